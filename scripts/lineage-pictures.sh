#!/usr/bin/env bash
# Renders the pictures of docs/lineages.md: one example scene per dialect
# (examples/lineages/*.txt, read by its markers) into docs/lineages/*.png.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
mkdir -p docs/lineages
for scene in examples/lineages/*.txt; do
    name=$(basename "$scene" .txt)
    ./target/release/glint render "$scene" -o "docs/lineages/$name.png"
done
