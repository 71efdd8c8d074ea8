#!/usr/bin/env bash
# The parallel efficiency of a render cut into parts (issue #30's figures):
# CPU seconds (user + system, GNU time) of one whole render against the sum
# over its N parts (`render --tile I/N`, one after another, as many tasks
# of a job array would run them), for N = 4, 16, 64; then whether the
# merge is the same bytes. Each part's own summary line says what it pays
# again (reading the scene, the BVH, the photon map).
#
#   scripts/cluster-figures.sh [--quick]
#
# The configurations: scene1 at 1920x1140 and 3840x2280, the million-sphere
# scene at 1024x768, and a PPM render of examples/photons/caustic.txt.
# --quick: scene1 at 1920x1140 only. Needs ../shared beside the repository
# and GNU time at /usr/bin/time.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
shared=${GLINT_SHARED:-$root/../shared}
cargo build --release --quiet --manifest-path "$root/Cargo.toml"
glint=$root/target/release/glint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source "$root/scripts/spheres.sh"

# cpu COMMAND...: runs it, prints its user + system seconds.
cpu() {
  /usr/bin/time -f '%U %S' -o "$work/time" "$@" > /dev/null 2>> "$work/log" || {
    cat "$work/log" >&2
    return 1
  }
  awk '{ printf "%.2f", $1 + $2 }' "$work/time"
}

# figure NAME SCENE [options]: one line of the table.
figure() {
  local name=$1 scene=$2
  shift 2
  local one
  one=$(cpu "$glint" render "$scene" -o "$work/one.png" --quiet "$@")
  printf '| %-28s | %8s |' "$name" "$one"
  for n in 4 16 64; do
    rm -rf "$work/t" && mkdir "$work/t"
    local sum=0
    for ((i = 0; i < n; i++)); do
      local c
      c=$(cpu "$glint" render "$scene" --tile "$i/$n" --tiles-dir "$work/t" "$@")
      sum=$(awk -v a="$sum" -v b="$c" 'BEGIN { print a + b }')
    done
    "$glint" merge "$work/t" -o "$work/merged.png" --quiet
    cmp -s "$work/one.png" "$work/merged.png" || { echo "N=$n: the merge differs" >&2; exit 1; }
    printf ' %7.2f %4.0f%% |' "$sum" "$(awk -v a="$one" -v b="$sum" 'BEGIN { print 100 * a / b }')"
  done
  echo
}

echo "CPU seconds of one render, and of the sum of its N parts with the efficiency (one / sum); every merge the same bytes"
echo "| render                       | one      | N=4            | N=16           | N=64           |"
echo "|------------------------------|----------|----------------|----------------|----------------|"
scene1=$shared/scenes/framework/scene1.txt
figure "scene1 1920x1140" "$scene1" --width 1920 --height 1140
[[ ${1:-} == --quick ]] && exit 0
figure "scene1 3840x2280" "$scene1" --width 3840 --height 2280
spheres 1000000
figure "1 000 000 spheres 1024x768" "$work/spheres_1000000.txt"
figure "caustic PPM 640x480, 20 it" "$root/examples/photons/caustic.txt" --width 640 --height 480 --photons ppm --iterations 20
