#!/usr/bin/env bash
# Renders the pictures of docs/photons.md into docs/photons/: the glass
# ball's caustic without photons and with PM, PPM and SPPM; PPM's
# convergence over iterations; depth of field; and, when the shared corpus
# is beside the clone, the caustics under scene1's and scene2's glass spheres.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
glint=./target/release/glint
out=docs/photons
mkdir -p "$out"
for mode in off pm ppm sppm; do
    $glint render examples/photons/caustic.txt --photons "$mode" --iterations 40 -o "$out/caustic-$mode.png"
done
for n in 1 4 16 64; do
    $glint render examples/photons/caustic.txt --photons ppm --iterations "$n" -o "$out/ppm-$n.png"
done
$glint render examples/photons/dof.txt -o "$out/dof.png"
shared=${GLINT_SCENES:-../shared/scenes}/framework
if [ -d "$shared" ]; then
    for scene in scene1 scene2; do
        $glint render "$shared/$scene.txt" --width 320 --photons pm --emit 100000 -o "$out/$scene-pm.png"
        $glint render "$shared/$scene.txt" --width 320 --photons ppm --emit 100000 --iterations 8 -o "$out/$scene-ppm.png"
    done
else
    echo "photon-pictures: SKIPPED scene1 and scene2 (no shared corpus at $shared)"
fi
