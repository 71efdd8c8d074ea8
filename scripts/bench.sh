#!/usr/bin/env bash
# glint's benchmark set. Renders each scene once and prints the wall time of
# the whole process, the render time, the rays, Mrays/s and the peak memory.
#
#   scripts/bench.sh                 the fixed set
#   scripts/bench.sh --povray [N]    glint and POV-Ray alternately on the
#                                    equivalent pairs, N rounds (default 3):
#                                    medians and the ratio
#   scripts/bench.sh --spheres [N]   100 and 1 000 000 spheres alternately,
#                                    N rounds (default 5) at 1, 4 and 16
#                                    samples per pixel: the best tracing
#                                    times (render - BVH) and their ratio;
#                                    then, if POV-Ray is installed, its
#                                    trace times and ratio on the same two
#                                    scenes at one ray per pixel
#
# Needs ../shared beside the repository (the framework's scenes and meshes;
# not for --spheres), GNU time at /usr/bin/time, and for --povray
# `apt-get install povray`.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
shared=${GLINT_SHARED:-$root/../shared}
cargo build --release --quiet --manifest-path "$root/Cargo.toml"
glint=$root/target/release/glint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# spheres N [pov]: the million-sphere family of scenes, into $work.
source "$root/scripts/spheres.sh"

# glint_render SCENE [glint options]: one render, its wall time and peak
# memory (GNU time) into $work/time, its summary line into $work/summary;
# fails, showing glint's output, when the render fails or prints no summary.
glint_render() {
  local scene=$1
  shift
  if /usr/bin/time -f '%e %M' -o "$work/time" "$glint" render "$scene" -o "$work/out.png" "$@" 2> "$work/log" &&
    grep 'Mrays/s' "$work/log" > "$work/summary"; then
    return 0
  fi
  cat "$work/log" >&2
  return 1
}

# The summary line's figures, each the group of a pattern.
SIZE_RE='^.*: ([0-9]+x[0-9]+),.*'
RENDER_RE='.*\(([0-9.]+) s render.*'
BVH_RE='.*, ([0-9.]+) s BVH\).*'
RAYS_RE='.*, ([0-9.]+) M rays.*'
MRAYS_RE='.*, ([0-9.]+) Mrays\/s.*'

# field PATTERN: the group of PATTERN in the last summary line; fails when
# the line does not match.
field() {
  local v
  v=$(sed -nE "s/$1/\1/p" "$work/summary")
  [[ -n $v ]] || { echo "no match for '$1' in: $(cat "$work/summary")" >&2; return 1; }
  echo "$v"
}

# tracing: the last render's tracing time, render - BVH.
tracing() {
  local render bvh
  render=$(field "$RENDER_RE") || return 1
  bvh=$(field "$BVH_RE") || return 1
  awk -v r="$render" -v b="$bvh" 'BEGIN {printf "%.3f", r - b}'
}

# run NAME SCENE [glint options]: one render; prints a table row.
run() {
  local name=$1 scene=$2
  shift 2
  glint_render "$scene" "$@" || return 1
  local size render bvh trace rays mrays wall kib
  size=$(field "$SIZE_RE") || return 1
  render=$(field "$RENDER_RE") || return 1
  bvh=$(field "$BVH_RE") || return 1
  trace=$(tracing) || return 1
  rays=$(field "$RAYS_RE") || return 1
  mrays=$(field "$MRAYS_RE") || return 1
  read -r wall kib < "$work/time"
  printf '| %-22s | %-9s | %7s | %8s | %6s | %7s | %8s | %7s | %8.0f |\n' "$name" "$size" "$wall" "$render" "$bvh" "$trace" "$rays" "$mrays" "$((kib / 1024))"
}

# pov_render DIR FILE WIDTH HEIGHT: POV-Ray renders DIR/FILE in DIR, no
# anti-aliasing, two threads; its wall time into $work/t, its statistics
# into $work/plog; fails, showing them, when POV-Ray does.
pov_render() {
  (cd "$1" && /usr/bin/time -f '%e' -o "$work/t" povray +W"$3" +H"$4" -A -D +WT2 File_Gamma=1.0 \
    +O"$work/p.png" "$2" > /dev/null 2> "$work/plog") || {
    cat "$work/plog" >&2
    return 1
  }
}

# median X...: the middle value (the lower one of an even count).
median() {
  printf '%s\n' "$@" | sort -n | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'
}

# least A B: the smaller number.
least() {
  awk -v a="$1" -v b="$2" 'BEGIN {print (b < a) ? b : a}'
}

header() {
  printf '| %-22s | %-9s | %7s | %8s | %6s | %7s | %8s | %7s | %8s |\n' scene size "wall s" "render s" "BVH s" "trace s" "M rays" "Mrays/s" "peak MiB"
  printf '|%s|%s|%s|%s|%s|%s|%s|%s|%s|\n' ------------------------ ----------- --------- ---------- -------- --------- ---------- --------- ----------
}

if [[ ${1:-} == --povray ]]; then
  rounds=${2:-3}
  command -v povray > /dev/null || { echo "povray is not installed (apt-get install povray)" >&2; exit 2; }
  pov=$shared/bench/povray
  # pair NAME GLINT_SCENE POV_FILE WIDTH HEIGHT
  pair() {
    local name=$1 scene=$2 povfile=$3 w=$4 h=$5 g=() p=() grays=""
    for ((k = 0; k < rounds; k++)); do
      glint_render "$scene" --spp 1 || return 1
      g+=("$(cut -d' ' -f1 "$work/time")")
      grays=$(field "$RAYS_RE") || return 1
      pov_render "$pov" "$povfile" "$w" "$h" || return 1
      p+=("$(cat "$work/t")")
    done
    local gm pm prays
    gm=$(median "${g[@]}")
    pm=$(median "${p[@]}")
    # POV-Ray's "Rays:" counts camera, reflected and refracted rays; shadow rays come apart.
    prays=$(awk '/^Rays:/ {r = $2} /^Shadow Ray Tests:/ {s = $4} END {printf "%.1f", (r + s) / 1e6}' "$work/plog")
    printf '| %-10s | %8s | %8s | %6.2fx | %8s | %8s | %8.1f | %8.1f |\n' "$name" "$gm" "$pm" "$(awk -v a="$pm" -v b="$gm" 'BEGIN {print a / b}')" \
      "$grays" "${prays:-?}" "$(awk -v r="$grays" -v t="$gm" 'BEGIN {print r / t}')" "$(awk -v r="${prays:-0}" -v t="$pm" 'BEGIN {print r / t}')"
  }
  echo "glint and POV-Ray 3.7, alternately, $rounds rounds, median wall seconds of the whole process (no anti-aliasing):"
  printf '| %-10s | %8s | %8s | %7s | %8s | %8s | %8s | %8s |\n' pair glint povray speed-up "glint Mr" "pov Mr" "glint Mr/s" "pov Mr/s"
  printf '|%s|%s|%s|%s|%s|%s|%s|%s|\n' ------------ ---------- ---------- --------- ---------- ---------- ---------- ----------
  pair scene1 "$root/bench/scene1.txt" scene1.pov 1280 760
  pair features "$root/bench/features.txt" features.pov 1280 720
  exit 0
fi

# trace SCENE SPP: the tracing time of one render on two cores.
trace() {
  glint_render "$1" --spp "$2" --threads 2 || return 1
  tracing
}

# ratio_row LABEL MEASURE: MEASURE 100 and MEASURE 1000000 (each printing
# a time) alternately, $rounds rounds; a table row of the best of each and
# their ratio.
ratio_row() {
  local label=$1 measure=$2 small=1e9 big=1e9 t k
  for ((k = 0; k < rounds; k++)); do
    t=$("$measure" 100)
    small=$(least "$small" "$t")
    t=$("$measure" 1000000)
    big=$(least "$big" "$t")
  done
  printf '| %3s | %11.3f | %17.3f | %5.2fx |\n' "$label" "$small" "$big" "$(awk -v a="$big" -v b="$small" 'BEGIN {print a / b}')"
}

if [[ ${1:-} == --spheres ]]; then
  rounds=${2:-5}
  [[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "--spheres takes a number of rounds, 1 or more" >&2; exit 2; }
  for n in 100 1000000; do spheres "$n"; done
  echo "100 and 1 000 000 spheres, alternately, $rounds rounds, best tracing seconds (render - BVH), 2 threads:"
  printf '| %3s | %11s | %17s | %6s |\n' spp "100 spheres" "1 000 000 spheres" ratio
  printf '|%s|%s|%s|%s|\n' ----- ------------- ------------------- --------
  # glint_trace N: the tracing time of spheres_N at $spp samples per pixel.
  glint_trace() { trace "$work/spheres_$1.txt" "$spp"; }
  for spp in 1 4 16; do
    ratio_row "$spp" glint_trace
  done
  command -v povray > /dev/null || { echo "(POV-Ray is not installed: no comparison of its ratio)"; exit 0; }
  # povtrace N: POV-Ray's trace time (its own figure, parsing and bounding
  # apart) for the twin of spheres_N, one ray per pixel, two threads.
  povtrace() {
    pov_render "$work" "spheres_$1.pov" 1024 768 || return 1
    local t
    t=$(sed -nE 's/^ *Trace Time:.*\(([0-9.]+) seconds\).*/\1/p' "$work/plog")
    [[ -n $t ]] || { echo "no trace time in POV-Ray's output" >&2; return 1; }
    echo "$t"
  }
  for n in 100 1000000; do spheres "$n" pov; done
  echo "POV-Ray 3.7 on the same two scenes, alternately, $rounds rounds, best trace seconds (its own figure), 2 threads, no anti-aliasing:"
  ratio_row 1 povtrace
  exit 0
fi

for n in 100 10000 1000000; do spheres "$n"; done
echo "glint benchmark set (one run each; wall = the whole process, parsing included):"
header
run "framework scene1" "$shared/scenes/framework/scene1.txt"
run "framework scene2" "$shared/scenes/framework/scene2.txt"
run "bunny 69k triangles" "$root/bench/bunny.txt" --spp 1
run "100 spheres" "$work/spheres_100.txt" --spp 1
run "10 000 spheres" "$work/spheres_10000.txt" --spp 1
run "1 000 000 spheres" "$work/spheres_1000000.txt" --spp 1
run "100 spheres, 4 spp" "$work/spheres_100.txt" --spp 4
run "1 000 000, 4 spp" "$work/spheres_1000000.txt" --spp 4
