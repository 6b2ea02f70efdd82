#!/bin/sh
# raystep and Embree side by side on the same rays (see README.md beside this script).
#
#   tools/embree-compare/run.sh [WORKDIR] [ROUNDS]
#
# Needs Debian's libembree-dev and a C compiler; run from the repository root after
# `cargo build --release`. Makes the three SPD scenes of the comparison (sphereflake size 4,
# tetra size 9, mount size 8) in WORKDIR (default /tmp/raystep-embree), exports their rays once,
# prints both tracers' build qualities, then alternates the two tracers ROUNDS times
# (default 2), each printing medians of 5.
set -eu
work=${1:-/tmp/raystep-embree}
rounds=${2:-2}
here=$(dirname "$0")
raystep=${RAYSTEP:-target/release/raystep}
# Embree's device configuration (e.g. isa=avx2), passed on when set: see README.md.
config=${EMBREE_CONFIG:+--config $EMBREE_CONFIG}
mkdir -p "$work"
cc -O2 -o "$work/embree_compare" "$here/embree_compare.c" -lembree3 -lpthread -lm
for spec in "balls 4" "tetra 9" "mount 8"; do
  set -- $spec
  name="$1$2"
  "$raystep" scene spd "$1" --size "$2" -o "$work/$name.toml" > /dev/null
  echo "### SPD $1 $2"
  "$raystep" bench "$work/$name.toml" --section rays --reps 1 --export "$work/$name.bin" | grep -E '^- (build|wrote)'
  "$work/embree_compare" "$work/$name.bin" --reps 1 --quality high $config | head -1
  "$work/embree_compare" "$work/$name.bin" --reps 1 --quality low $config | head -1
  "$raystep" bench "$work/$name.toml" --section build --reps 3 | grep -E '^\| (low|medium|high) '
  round=1
  while [ "$round" -le "$rounds" ]; do
    echo "round $round"
    "$raystep" bench "$work/$name.toml" --section rays --reps 5 | grep -E '^- (build|primary|shadow)'
    "$work/embree_compare" "$work/$name.bin" --reps 5 $config
    round=$((round + 1))
  done
done
