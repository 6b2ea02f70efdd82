#!/usr/bin/env bash
# Builds the fuzzers' seed corpora from the shipped files (nothing here is committed):
#   corpus/scene  every shipped scene (the OBJ a scene names appended after a %%OBJ%% line)
#   corpus/trace  traces of shipped scenes saved by `raystep trace --save`
#   corpus/sheet  every shipped exercise sheet, with an answers file and a class CSV appended
# Usage: fuzz/seed-corpora.sh [RAYSTEP]   (RAYSTEP: a raystep binary; default: cargo run)
set -euo pipefail
cd "$(dirname "$0")"
root=..
if [ $# -ge 1 ]; then raystep=("$1"); else raystep=(cargo run --quiet --manifest-path "$root/Cargo.toml" --); fi
mkdir -p corpus/scene corpus/trace corpus/sheet

for f in "$root"/scenes/*.toml; do
    out="corpus/scene/$(basename "$(dirname "$f")")-$(basename "$f" .toml)"
    obj=$(sed -n 's/^obj *= *"\(.*\)"/\1/p' "$f" | head -n1)
    if [ -n "$obj" ]; then
        { sed "s/^obj *= *\".*\"/obj = \"mesh.obj\"/" "$f"; printf '\n%%%%OBJ%%%%\n'; cat "$(dirname "$f")/$obj"; } > "$out"
    else
        cp "$f" "$out"
    fi
done

# Two pixels per scene: the middle one and one off-centre; depth 3 keeps the traces small.
for f in "$root"/scenes/*.toml; do
    name=$(basename "$f" .toml)
    for px in 160,120 100,150; do
        "${raystep[@]}" trace "$f" --pixel "$px" --max-depth 3 --save "corpus/trace/$name-${px/,/-}.json" > /dev/null 2>&1 || true
    done
done

for f in "$root"/lessons/exercises/0*.toml; do
    ids=$(sed -n '/^\[\[question\]\]/,/^id *=/s/^id *= *"\(.*\)"/\1/p' "$f")
    {
        cat "$f"
        printf '\n%%%%ANSWERS%%%%\n'
        for id in $ids; do echo "$id = 1"; done
        printf '%%%%CSV%%%%\n'
        echo "student,$(echo $ids | tr ' ' ',')"
        echo "ann,$(for id in $ids; do printf '1,'; done | sed 's/,$//')"
    } > "corpus/sheet/$(basename "$f" .toml)"
done
echo "seeded: $(ls corpus/scene | wc -l) scenes, $(ls corpus/trace | wc -l) traces, $(ls corpus/sheet | wc -l) sheets"
