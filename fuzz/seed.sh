#!/usr/bin/env bash
# fuzz/seed.sh: fills fuzz/corpus/<target>/ with the repository's files.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/scene corpus/diagnostics corpus/obj corpus/texture corpus/rays
# Every scene of the repository, named after its path (examples/photons/x.txt: examples_photons_x.txt).
find ../examples ../bench ../tests/data -name '*.txt' | while read -r f; do
    cp "$f" "corpus/scene/$(echo "${f#../}" | tr / _)"
    cp "$f" "corpus/diagnostics/$(echo "${f#../}" | tr / _)"
done
cp ../tests/data/*.obj corpus/obj/
find .. \( -path ../fuzz -o -path ../target -o -path ../.git \) -prune -o -name '*.obj' -print | head -20 | xargs -r -I{} cp {} corpus/obj/
cp ../tests/data/*.bmp corpus/texture/
find ../examples -name '*.bmp' -o -name '*.png' | xargs -r -I{} cp {} corpus/texture/
printf '0 0 0 0 0 1\n1 2 3 0 1 0 # c\n\n' > corpus/rays/basic
printf '1e308 7 -1e308 1e100 1 1e100\n' > corpus/rays/large
