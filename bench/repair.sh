#!/usr/bin/env bash
# `frep repair` against CGAL's own repair calls on the same meshes, in the same run:
#   before   `frep check FILE`: solid, not solid, or unreadable
#   frep     `frep repair FILE -o OUT.stl --json`, the whole process timed (wall clock, and its
#            peak memory by /usr/bin/time), and `frep check OUT.stl` (after)
#   CGAL     bench/bench_repair_cgal: repair_polygon_soup, orient_polygon_soup,
#            polygon_soup_to_polygon_mesh, remove_degenerate_faces,
#            experimental::autorefine_and_remove_self_intersections, does_self_intersect and
#            orient_to_bound_a_volume on exact points (Epeck), in a child under the same time
#            limit; its outcome, and `frep check` on its result written the same way (after)
# Both results are written as binary STL, as users ask for them: coordinates rounded to floats,
# which can itself create crossings. FORMAT=obj writes both as OBJ (%.17g: doubles) instead.
# Seconds are whole jobs: reading included on both sides (CGAL: its child's work, reading and the
# conversion to exact points included). us/tri = microseconds per input triangle; MB = peak
# resident memory. ratio = frep s / CGAL s, where CGAL's outcome is ok. Until `frep repair`
# exists, the CGAL columns only. Why a job failed is printed under the table.
#   bash bench/repair.sh [MESH...]      (default: every mesh in ../shared/data/meshes)
# TIME_LIMIT=S per job (120); FORMAT=stl|obj (stl); TSV=FILE appends CGAL's full per-stage
# lines; FREP=another frep binary (default build/frep); NO_BUILD=1 skips the build.
args=()
for a in "$@"; do args+=("$(realpath -m -- "$a")"); done  # common.sh moves to the project root
source "$(dirname "$0")/common.sh"
set -- "${args[@]}"
data=../shared/data/meshes
limit=${TIME_LIMIT:-120}
ext=${FORMAT:-stl}
case "$ext" in stl) stl_flag=(--stl) ;; obj) stl_flag=() ;; *) echo "bench/repair.sh: FORMAT is stl or obj" >&2; exit 2 ;; esac
if [ $# -gt 0 ]; then
  meshes=("$@")
  for m in "${meshes[@]}"; do require_input "$m"; done
elif [ -d "$data" ]; then
  mapfile -t meshes < <(find "$data" -maxdepth 1 -type f \( -iname '*.stl' -o -iname '*.obj' -o -iname '*.ply' \
                          -o -iname '*.off' \) | sort)
else
  echo "bench/repair.sh: $data not found (the shared meshes); skipping. Give mesh files as arguments." >&2
  exit 0
fi
[ -n "${NO_BUILD:-}" ] || build_targets frep bench_repair_cgal
cgal=./build/bench/bench_repair_cgal
frep=${FREP:-./build/frep}
if "$frep" repair --help >/dev/null 2>&1; then
  has_repair=1
else
  has_repair=
  echo "note: $frep has no 'repair' command yet: CGAL columns only"
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tsv=${TSV:-$tmp/cgal.tsv}
notes=()
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); time limit ${limit} s per job; results written as .$ext"

# verdict FILE: "TRIANGLES solid", "TRIANGLES not solid" or "- unreadable", by `frep check --json`.
verdict() {
  local out
  out=$("$frep" check "$1" --json 2>/dev/null || true)
  python3 -c '
import json, sys
try:
    d = json.loads(sys.argv[1])
    print(d.get("triangles", "-"), "solid" if d.get("solid") else "not solid")
except ValueError:
    print("- unreadable")' "$out"
}

printf '%-28s %8s %-10s | %8s %7s %6s %-10s | %8s %7s %6s %-18s %-10s | %6s\n' \
  file tris before "frep s" "us/tri" MB after "CGAL s" "us/tri" MB "CGAL outcome" after ratio
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  read -r tris before <<<"$(verdict "$m")"
  # frep repair, whole process.
  fs=- fmb=- fafter=-
  if [ -n "$has_repair" ]; then
    rm -f "$tmp/out.$ext"
    rc=0
    t0=$EPOCHREALTIME
    /usr/bin/time -o "$tmp/time" -f "%M" timeout "$limit" "$frep" repair "$m" -o "$tmp/out.$ext" --json \
      >"$tmp/repair.json" 2>"$tmp/repair.err" || rc=$?
    t1=$EPOCHREALTIME
    fs=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
    fmb=$(awk 'END { printf "%.0f", $1 / 1024 }' "$tmp/time")
    if [ "$rc" = 124 ]; then
      fafter=timeout
      notes+=("$name: frep repair: timeout after $limit s")
    elif [ -f "$tmp/out.$ext" ]; then
      read -r _ fafter <<<"$(verdict "$tmp/out.$ext")"
    else
      fafter="failed($rc)"
      notes+=("$name: frep repair exit $rc: $(grep -v '^ *$' "$tmp/repair.err" | tail -2 | tr '\n' ' ')")
    fi
  fi
  # CGAL, in its own child under the same limit; its result written as NAME.cgal.$ext.
  rm -f "$tmp"/*.cgal.*
  out=$("$cgal" --time-limit "$limit" -o "$tmp" "${stl_flag[@]}" "$m" || true)
  [ -s "$tsv" ] || head -1 <<<"$out" >>"$tsv"
  line=$(tail -n +2 <<<"$out")
  echo "$line" >>"$tsv"
  IFS=$'\t' read -r -a h <<<"$(head -1 <<<"$out")"
  IFS=$'\t' read -r -a f <<<"$line"
  declare -A col=()
  for i in "${!h[@]}"; do col[${h[$i]}]=${f[$i]:-}; done
  cs=${col[total_s]:--} cmb=${col[peak_MB]:--} coutcome=${col[outcome]:-none}
  [ "$coutcome" != ok ] && notes+=("$name: CGAL $coutcome: ${col[message]:-}")
  cafter=-
  stem=${name%.*}
  [ -f "$tmp/$stem.cgal.$ext" ] && read -r _ cafter <<<"$(verdict "$tmp/$stem.cgal.$ext")"
  awk -v n="$name" -v t="$tris" -v b="$before" -v fs="$fs" -v fm="$fmb" -v fa="$fafter" -v cs="$cs" -v cm="$cmb" \
      -v co="$coutcome" -v ca="$cafter" '
    function us(s, v) { return (s == "-" || t == "-" || t == 0 || v == "timeout") ? "-" : sprintf("%.2f", 1e6 * s / t) }
    BEGIN {
      ratio = (fs != "-" && cs != "-" && co == "ok" && cs > 0) ? sprintf("%.2f", fs / cs) : "-"
      printf "%-28s %8s %-10s | %8s %7s %6s %-10s | %8s %7s %6s %-18s %-10s | %6s\n", n, t, b, fs, us(fs, fa), fm, fa,
             cs, us(cs, co), cm, co, ca, ratio
    }'
done
for n in "${notes[@]}"; do echo "$n"; done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
[ -n "${TSV:-}" ] && echo "CGAL's per-stage lines (see bench/bench_repair_cgal.cpp for the columns): $TSV"
exit 0
