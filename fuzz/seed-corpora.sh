#!/usr/bin/env bash
# Builds the fuzzers' seed corpora from the shipped files (nothing here is committed):
#   corpus/scene  every shipped scene (the OBJ a scene names appended after a %%OBJ%% line)
#   corpus/trace  traces of shipped scenes saved by `raystep trace --save`
#   corpus/sheet  every shipped exercise sheet, with an answers file and a class CSV appended
#   corpus/student  `raystep trace --format student` of the pixels the target grades against and
#                 of two pixels of every shipped scene, and the starter kit's and the model
#                 student's Python tracers' output for the same pixels (when python3 is there)
#   corpus/gltf   the GLB and glTF test models (tests/gltf/; JSON ones with their buffers inline)
#   corpus/grade_sheet  the starter kit's grading sheet, a sheet per shipped scene, and one that
#                 varies scenes per student (scene paths as seen from lessons/starter/)
# Usage: fuzz/seed-corpora.sh [RAYSTEP]   (RAYSTEP: a raystep binary; default: cargo run)
set -euo pipefail
cd "$(dirname "$0")"
root=..
if [ $# -ge 1 ]; then raystep=("$1"); else raystep=(cargo run --quiet --manifest-path "$root/Cargo.toml" --); fi
mkdir -p corpus/scene corpus/trace corpus/sheet corpus/student corpus/grade_sheet corpus/gltf
cp "$root"/tests/gltf/*.glb "$root"/tests/gltf/*.gltf corpus/gltf/

# A fuzz input carries one OBJ file but no images: image textures become checkers.
images_as_checkers() { sed -e 's/^image *= *".*"/checker = [8, 8]/' -e '/^filter *=/d' -e '/^wrap *=/d' "$1"; }
for f in "$root"/scenes/*.toml; do
    out="corpus/scene/$(basename "$(dirname "$f")")-$(basename "$f" .toml)"
    obj=$(sed -n 's/^obj *= *"\(.*\)"/\1/p' "$f" | head -n1)
    if [ -n "$obj" ]; then
        { images_as_checkers "$f" | sed "s/^obj *= *\".*\"/obj = \"mesh.obj\"/"; printf '\n%%%%OBJ%%%%\n'; cat "$(dirname "$f")/$obj"; } > "$out"
    else
        images_as_checkers "$f" > "$out"
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
# The student target grades against these pixels (raystep::fuzzing::STUDENT_PIXELS); then two
# pixels of every shipped scene.
student_pixels="mirror-glass:240,160 triangles:100,150"
for f in "$root"/scenes/*.toml; do
    student_pixels="$student_pixels $(basename "$f" .toml):160,120 $(basename "$f" .toml):100,150"
done
for sp in $student_pixels; do
    name=${sp%%:*} px=${sp#*:}
    f="$root/scenes/$name.toml" out="corpus/student/$name-${px/,/-}"
    "${raystep[@]}" trace "$f" --pixel "$px" --format student > "$out-raystep" 2> /dev/null || rm -f "$out-raystep"
    if command -v python3 > /dev/null; then
        for tracer in lessons/starter tests/student_tracer; do
            python3 "$root/$tracer/tracer.py" "$f" "${px%,*}" "${px#*,}" > "$out-$(basename "$tracer")" 2> /dev/null || true
            [ -s "$out-$(basename "$tracer")" ] || rm -f "$out-$(basename "$tracer")"
        done
    fi
done

# Grading sheets stand where lessons/starter/sheet.toml does (raystep::fuzzing::grade_sheet_path).
cp "$root/lessons/starter/sheet.toml" corpus/grade_sheet/starter
for f in "$root"/scenes/*.toml; do
    name=$(basename "$f" .toml)
    printf 'title = "%s"\nupto = "color"\n[[scene]]\nfile = "../../scenes/%s.toml"\npixels = [[0, 0], [60, 40]]\nrandom_pixels = 3\n' \
        "$name" "$name" > "corpus/grade_sheet/$name"
done
cat > corpus/grade_sheet/vary <<'EOF'
title = "Variants"
id = "checkpoint-3"
upto = "shadows"
timeout_s = 2.5
tolerance = { rel = 1e-3, abs = 1e-4, color = 4e-3, offset = 2e-2 }
[[scene]]
file = "../../scenes/three-spheres.toml"
pixels = [[150, 110], [100, 160]]
random_pixels = 2
[[scene.vary]]
object = "middle"
key = "radius"
range = [0.8, 1.2]
[[scene.vary]]
object = "key"
key = "position"
index = 1
range = [6, 14]
decimals = 1
[[scene]]
file = "../../scenes/triangles.toml"
pixels = [[80, 130]]
[[scene.vary]]
object = "icosahedron"
key = "scale"
range = [0.9, 1.1]
EOF
echo "seeded: $(ls corpus/scene | wc -l) scenes, $(ls corpus/trace | wc -l) traces, $(ls corpus/sheet | wc -l) sheets," \
    "$(ls corpus/student | wc -l) student outputs, $(ls corpus/grade_sheet | wc -l) grading sheets"
