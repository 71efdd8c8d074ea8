#!/bin/sh
# What every AOV costs over a plain render: alternates `glint render SCENE`
# and the same with every AOV (`--aov ...`, .png), N times each, and prints
# the medians of wall and CPU seconds (GNU time). Pause other work first.
# Usage: scripts/aovs-overhead.sh SCENE [N] [GLINT]
set -eu
scene=$1
n=${2:-5}
glint=${3:-target/release/glint}
all=normal,depth,position,uv,primitive,albedo,rays,light:0,shade,why,clamp,cost
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
i=0
while [ "$i" -lt "$n" ]; do
    /usr/bin/time -f "plain %e %U %S" -a -o "$out/t" "$glint" render "$scene" -o "$out/p.png" -q
    /usr/bin/time -f "aovs %e %U %S" -a -o "$out/t" "$glint" render "$scene" -o "$out/p.png" -q --aov "$all"
    i=$((i + 1))
done
python3 - "$out/t" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
med = {}
for kind in ("plain", "aovs"):
    wall = [float(r[1]) for r in rows if r[0] == kind]
    cpu = [float(r[2]) + float(r[3]) for r in rows if r[0] == kind]
    med[kind] = (statistics.median(wall), statistics.median(cpu))
    print(f"{kind:7} wall {med[kind][0]:.2f} s  CPU {med[kind][1]:.2f} s  (median of {len(wall)})")
w = med["aovs"][0] / med["plain"][0] - 1
c = med["aovs"][1] / med["plain"][1] - 1
print(f"every AOV: wall {100 * w:+.1f} %, CPU {100 * c:+.1f} %")
PY
