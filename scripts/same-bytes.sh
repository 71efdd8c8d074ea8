#!/usr/bin/env bash
# Renders a fixed set of scenes (every example, the shared corpus when it is
# beside the repository) with one glint binary into a folder, so that two
# builds can be compared byte for byte: a refactoring must not move a pixel.
#
#   scripts/same-bytes.sh BINARY OUTDIR          # render the set
#   diff -r OUTDIR_OLD OUTDIR_NEW                # nothing printed: same bytes
#
# Each scene is rendered small (--width 160) with every pass, at 1 and 2
# threads, and the photon examples with their photon algorithms.
set -euo pipefail
bin=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")/.." && pwd)
shared=${GLINT_SCENES:-$here/../shared/scenes}
mkdir -p "$out"
scenes=("$here"/examples/showcase.txt "$here"/examples/lineages/*.txt "$here"/examples/photons/*.txt)
if [ -d "$shared" ]; then
    scenes+=("$shared"/framework/*.txt "$shared"/community/*.txt)
fi
aovs=normal,depth,position,uv,primitive,albedo,rays,light:0,shade,why,clamp,cost
for s in "${scenes[@]}"; do
    name=$(basename "$s" .txt)
    for t in 1 2; do
        "$bin" render "$s" --quiet --width 160 --threads "$t" --seed 7 \
            --aov "$aovs" -o "$out/$name.t$t.exr"
        "$bin" render "$s" --quiet --width 160 --threads "$t" --seed 7 \
            --aov "$aovs" -o "$out/$name.t$t.png"
    done
    "$bin" render "$s" --quiet --width 120 --spp 3 --seed 3 -o "$out/$name.spp3.bmp"
    "$bin" render "$s" --quiet --width 120 --region 10,20,90,60 -o "$out/$name.region.hdr"
    "$bin" explain "$s" --width 120 --pixel 60,40 --json >"$out/$name.explain.json"
done
for s in "$here"/examples/photons/*.txt; do
    name=$(basename "$s" .txt)
    for mode in pm ppm sppm; do
        "$bin" render "$s" --quiet --width 96 --photons "$mode" --iterations 3 --emit 20000 \
            --seed 5 -o "$out/$name.$mode.png"
    done
done
echo "rendered ${#scenes[@]} scenes into $out"
