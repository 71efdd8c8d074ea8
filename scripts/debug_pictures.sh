#!/bin/sh
# Makes the pictures and listings of docs/debugging.md from the showcase at
# 240x135: every pass (render --aov), the explain of a black pixel, the
# check of the scene, and the compare of a deliberately broken render (the
# mirror ball's intersection "forgets" its outer rim: its radius is cut to
# 0.25 in a copy of the scene, rendered as "yours").
# Run from anywhere: sh scripts/debug_pictures.sh (about 15 s on 2 cores).
set -eu
cd "$(dirname "$0")/.."
cargo build --release -q
glint="${CARGO_TARGET_DIR:-target}/release/glint"
out=docs/debugging
mkdir -p "$out"
size="--width 240"
passes=normal,depth,position,uv,primitive,albedo,rays,light:0,light:1,shade,why,clamp,cost
"$glint" render examples/showcase.txt -o "$out/showcase.png" $size -q --aov "$passes"
"$glint" explain examples/showcase.txt $size --pixel 161,82 > "$out/black-pixel.txt"
"$glint" check examples/showcase.txt > "$out/check.txt"

# The broken render, made beside the scene so that its textures resolve.
broken=examples/.broken-showcase.txt
trap 'rm -f "$broken" "$out/yours.png.tmp"' EXIT
awk 'NR == 193 { print "    R= 0.25"; next } { print }' examples/showcase.txt > "$broken"
"$glint" render "$broken" -o "$out/yours.png" $size -q
"$glint" compare examples/showcase.txt "$out/yours.png" $size -o "$out/heat.png" > "$out/compare.txt"
du -ch "$out"/*.png | tail -1
