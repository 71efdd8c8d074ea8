#!/usr/bin/env bash
# Renders every file of the lineages' repositories that selects photon
# mapping, at its own settings (its own emit_photons=, max_photons=,
# iterations= and size), from the folder its renderer ran in, and prints
# a Markdown row a file: its dialect and photon algorithm, the estimate
# glint states, the peak resident memory and the wall time (GNU time).
#
#   scripts/lineage-photons.sh LINEAGES [OUT]
#
# LINEAGES is a folder of the repositories' checkouts named OWNER+NAME
# (their licences keep them out of glint); the renders go to OUT (default:
# a temporary folder, removed). A file whose repository lacks a file it
# names is listed with the error, not rendered.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
lineages=${1:?usage: scripts/lineage-photons.sh LINEAGES [OUT]}
lineages=$(cd "$lineages" && pwd)
if [[ -n ${2:-} ]]; then
  out=$2
  mkdir -p "$out"
else
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
out=$(cd "$out" && pwd)
glint=${GLINT:-$here/target/release/glint}

# Repository, the file (from the repository's root) and the folder its
# renderer ran in (from the root).
files=(
  "zsyzgu+new_photon_mapping|scene.txt|."
  "zsyzgu+new_photon_mapping|picture/all.txt|."
  "zsyzgu+new_photon_mapping|picture/diff.txt|."
  "zsyzgu+new_photon_mapping|picture/refl.txt|."
  "zsyzgu+new_photon_mapping|picture/refr.txt|."
  "daibiaoxuwu+PM3|scene.txt|."
  "daibiaoxuwu+PM3|scene - 3个珠子.txt|."
  "daibiaoxuwu+PM3|scene - 3个珠子1龙亮.txt|."
  "daibiaoxuwu+PM3|scene - 321s.txt|."
  "daibiaoxuwu+PM3|scene - 副本.txt|."
  "daibiaoxuwu+PM3|scene2珠子1龙.txt|."
  "daibiaoxuwu+PM3|scene345s.txt|."
  "daibiaoxuwu+PM3|scene兔子.txt|."
  "daibiaoxuwu+PM3|scene兔龙.txt|."
  "daibiaoxuwu+PM3|scene玻璃.txt|."
  "daibiaoxuwu+PM3|scene玻璃2.txt|."
  "daibiaoxuwu+PM3|scene网格.txt|."
  "daibiaoxuwu+PM3|scene龙.txt|."
  "LuChengTHU+RayTracing-PPM-NormalMap|src/scene.txt|src"
  "lazycal+Progressive-Photon-Mapping|scenes/scene.txt|scenes"
  "lazycal+Progressive-Photon-Mapping|scenes/scene_bowling.txt|scenes"
  "lazycal+Progressive-Photon-Mapping|scenes/scene_example.txt|scenes"
  "lazycal+Progressive-Photon-Mapping|scenes/scene_flower.txt|scenes"
  "lazycal+Progressive-Photon-Mapping|scenes/scene_plate.txt|scenes"
)

echo "| file | dialect | photon passes × emitted | stored (kept) | hit points | estimate | peak | time |"
echo "|---|---|---|---|---|---|---|---|"
k=0
for entry in "${files[@]}"; do
  IFS='|' read -r repo file runs_in <<< "$entry"
  k=$((k + 1))
  root=$lineages/$repo
  if [[ ! -f $root/$file ]]; then
    echo "| $repo \`$file\` | | not there: skipped | | | | | |"
    continue
  fi
  log=$out/$k.log
  set +e
  (cd "$root/$runs_in" && /usr/bin/time -f 'TIME %e %M' "$glint" render "$root/$file" -v \
    -o "$out/$k.png" < /dev/null) > "$log" 2>&1
  status=$?
  set -e
  dialect=$(grep -m1 -a '^dialect ' "$log" | sed 's/^dialect \([a-z0-9]*\).*/\1/' || true)
  if [[ $status -ne 0 ]]; then
    why=$(grep -m1 -a '^error' "$log" | sed 's/^error: //; s/|/\\|/g' || true)
    echo "| $repo \`$file\` | $dialect | not rendered: ${why:-exit $status} | | | | | |"
    continue
  fi
  # glint -v: "photons: N of M passes of E emitted, S stored in the last
  # (of T traced), H hit points, ..." (PM: "one map of E emitted, ...").
  line=$(grep -m1 -a '^photons: ' "$log" || true)
  passes=off stored= points=
  if [[ $line =~ photons:\ (one\ map|[0-9]+\ of\ [0-9]+\ passes)\ of\ ([0-9]+)\ emitted,\ ([0-9]+)\ stored\ in\ the\ last\ \(of\ ([0-9]+)\ traced\),\ ([0-9]+)\ hit ]]; then
    passes="${BASH_REMATCH[1]/ of */} × ${BASH_REMATCH[2]}"
    [[ ${BASH_REMATCH[1]} == "one map" ]] && passes="1 × ${BASH_REMATCH[2]}"
    stored=${BASH_REMATCH[4]}
    [[ ${BASH_REMATCH[3]} != "${BASH_REMATCH[4]}" ]] && stored="$stored (${BASH_REMATCH[3]})"
    points=${BASH_REMATCH[5]}
  fi
  estimate=$(grep -m1 -a 'note: memory: at most' "$log" | sed 's/.*at most \([0-9.]*\) MiB at the peak.*/\1 MiB/' || true)
  read -r _ seconds kib < <(grep -a '^TIME ' "$log")
  printf '| %s `%s` | %s | %s | %s | %s | %s | %.0f MiB | %.0f s |\n' "$repo" "$file" "$dialect" \
    "$passes" "$stored" "$points" "$estimate" "$(echo "$kib / 1024" | bc -l)" "$seconds"
done
