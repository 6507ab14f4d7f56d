#!/usr/bin/env bash
# The slicing target of a field: a gyroid-filled 40 mm cube written in Rhai (examples/gyroid_cube.rhai:
# a 1.2 mm skin around a gyroid lattice of 8 mm period and 1.2 mm sheets), sliced directly by
# `frep slice`, against PrusaSlicer 2.5 (and CuraEngine, CURA=0 skips it) on the STL that `frep mesh`
# makes of it at a 0.05 mm cell, all in the same run: end-to-end seconds (meshing included for the
# mesh slicers), peak memory, and the outer walls of every G-code checked against the exact field by
# bench/slice_field_check.py (through the frep Python package in build/python).
#   bash bench/slice_gyroid.sh [EXPR]        (default examples/gyroid_cube.rhai)
# Settings, the same for all (as bench/slice_compare.sh, with 0% sparse infill: the lattice is the
# infill): 0.2 mm layers, 0.45 mm lines, 2 perimeters, 4 top and 4 bottom layers.
#   frep        $FREP slice EXPR -o OUT.gcode --layer-height 0.2 --line-width 0.45 --perimeters 2
#               --infill 0 --top-layers 4 --bottom-layers 4
#   mesh        $FREP mesh EXPR --cell CELL -o PART.stl  (CELL=0.05; if that is refused, fails or
#               passes the limits below, the next of FALLBACK_CELLS (0.075 0.1) is tried, and said)
#   PrusaSlicer prusa-slicer --export-gcode --load bench/slicer_configs/prusa.ini --fill-density 0%
#               --fill-pattern rectilinear --dont-arrange -o OUT.gcode PART.stl   (keeps the STL's
#               x and y on its bed centred at the origin, and drops it to z = 0); prusa.ini leaves
#               2.5's default Arachne perimeters (variable widths, so the outer wall's centre line is
#               not always w/2 inside), so it runs a second time with --perimeter-generator classic
#               (constant widths, gap fill) as well (PRUSA_CLASSIC=0 skips that)
#   CuraEngine  CuraEngine slice -j fdmprinter.def.json -s K=V... -e0 -s K=V... -l PART.stl -o OUT.gcode
#               with bench/slicer_configs/cura.txt and infill_sparse_density=0, infill_line_distance=0
#               (center_object: the STL's box centred at (110,110), bottom at z = 0)
# Placement for the check (printer = model + shift): frep's `; part: ... shift` header line; for
# the mesh slicers, computed here from the STL's bounding box as above. Each check also fits a
# residual xy shift (--fit-xy, on 100 points a layer): near 0 when the slicer put the part where
# this script says.
# Every slicer and mesher runs under a watchdog: stopped past TIME_LIMIT seconds (900) or
# MEM_LIMIT_MB of resident memory (20000; the kernel's high-water mark, VmHWM, polled every 0.25 s);
# peak memory is /usr/bin/time's maximum resident set. At a 0.05 mm cell the STL is 59 M triangles
# (2.9 GB; frep mesh peaks at 9.2 GB, PrusaSlicer at 12.1 GB, CuraEngine at 9.6 GB): WORK=DIR puts
# the scratch files there (default: a temporary folder, removed), KEEP=DIR keeps the G-code and STL.
# A run takes about 20 minutes on 2 cores, 9 of them checking (frep's 1.5 M outer-wall vertices: 5).
# Columns: s = wall seconds of the process (reading and writing included); end to end = meshing +
# slicing; peak MB; triangles (of the STL) or extrusion moves (of the G-code); outer pts = outer-wall
# path vertices checked (all of them); median / p95 / max = |d - w/2| in mm, d the distance of a
# vertex to the zero set of the exact field at its layer's mid-height, w/2 = 0.225; within 1% =
# |d - w/2| <= 0.0045; xy shift = the residual translation the check fits (mm).
#   CELL=0.05 FALLBACK_CELLS="0.075 0.1" CURA=0 FREP=binary TIME_LIMIT=900 MEM_LIMIT_MB=20000
#   CHECK_ARGS="--max-points 200000" (a sample, faster; default: every point)
args=()
for a in "$@"; do args+=("$(realpath -m -- "$a")"); done  # common.sh moves to the project root
[ -n "${FREP:-}" ] && FREP=$(realpath -m -- "$FREP")
[ -n "${KEEP:-}" ] && KEEP=$(realpath -m -- "$KEEP")
[ -n "${WORK:-}" ] && WORK=$(realpath -m -- "$WORK")
[ -n "${CURA_DEFS:-}" ] && CURA_DEFS=$(realpath -m -- "$CURA_DEFS")
source "$(dirname "$0")/common.sh"
set -- "${args[@]}"
PY=/usr/bin/python3
"$PY" -c "import numpy" 2>/dev/null || { echo "bench/slice_gyroid.sh: needs /usr/bin/python3 with numpy" >&2; exit 1; }
expr=${1:-examples/gyroid_cube.rhai}
require_input "$expr"
CELL=${CELL:-0.05}
FALLBACK_CELLS=${FALLBACK_CELLS-0.075 0.1}
TIME_LIMIT=${TIME_LIMIT:-900}
MEM_LIMIT_MB=${MEM_LIMIT_MB:-20000}
read -r -a check_args <<<"${CHECK_ARGS:-}"
notes=()

frep=${FREP:-}
if [ -z "$frep" ]; then
  for f in build/frep build/apps/frep/frep; do [ -x "$f" ] && { frep=$f; break; }; done
  if [ -z "$frep" ] && [ -z "${NO_BUILD:-}" ]; then build_targets frep && frep=build/frep; fi
fi
if [ -z "$frep" ] || ! "$frep" slice --help >/dev/null 2>&1; then
  echo "bench/slice_gyroid.sh: ${frep:-no frep binary} has no 'slice' command" >&2
  exit 1
fi
pydir=${FREP_PYTHON:-$(dirname "$(realpath "$frep")")/python}
[ -d "$pydir" ] || pydir=build/python
if ! FREP_PYTHON=$pydir PYTHONPATH=$pydir "$PY" -c "import frep" 2>/dev/null; then
  echo "bench/slice_gyroid.sh: the frep Python package is not in $pydir (build the python target, or FREP_PYTHON=DIR)" >&2
  exit 1
fi
export FREP_PYTHON=$pydir

prusa=${PRUSA:-prusa-slicer}
have_prusa=
if command -v "$prusa" >/dev/null; then have_prusa=1; else
  notes+=("$prusa not found (apt-get install --no-install-recommends prusa-slicer): PrusaSlicer skipped"); fi
cura=${CURA_ENGINE:-CuraEngine}
have_cura=
defs=
if [ "${CURA:-1}" != 0 ] && command -v "$cura" >/dev/null; then
  # Cura's definitions as bench/slice_compare.sh finds them (run it once to fetch them)
  for d in "${CURA_DEFS:-}" /usr/share/cura/resources/definitions "${XDG_CACHE_HOME:-$HOME/.cache}/frep-bench/cura-defs"; do
    [ -n "$d" ] && [ -f "$d/fdmprinter.def.json" ] && [ -f "$d/fdmextruder.def.json" ] && { defs=$d; break; }
  done
  if [ -n "$defs" ]; then have_cura=1; else
    notes+=("Cura's fdmprinter/fdmextruder.def.json not found (bench/slice_compare.sh fetches them; or CURA_DEFS=DIR): CuraEngine skipped"); fi
elif [ "${CURA:-1}" != 0 ]; then
  notes+=("$cura not found: CuraEngine skipped")
fi
cura_settings=()
while IFS= read -r l; do
  [[ -z "$l" || "$l" == \#* ]] && continue
  cura_settings+=(-s "$l")
done <bench/slicer_configs/cura.txt
cura_settings+=(-s infill_sparse_density=0 -s infill_line_distance=0 -s infill_overlap=10)

if [ -n "${WORK:-}" ]; then mkdir -p "$WORK"; work=$(mktemp -d -p "$WORK"); else work=$(mktemp -d); fi
trap 'rm -rf "$work"' EXIT
out=${KEEP:-$work}
mkdir -p "$out"

# run_limited NAME CMD...: runs CMD (output to $work/NAME.log) under the watchdog; sets sec (wall
# seconds, "-" if it failed or was stopped), peak_mb, and why ("" or the reason it was stopped).
run_limited() {
  local name=$1 pid child= t0 t1 rc=0 hwm=0 h
  shift
  why=
  rm -f "$work/$name.rss"
  t0=$EPOCHREALTIME
  /usr/bin/time -f "%M" -o "$work/$name.rss" "$@" >"$work/$name.log" 2>&1 &
  pid=$!
  while kill -0 "$pid" 2>/dev/null; do
    [ -z "$child" ] && child=$(pgrep -P "$pid" | head -1 || true)
    if [ -n "$child" ]; then
      h=$(awk '/^VmHWM:/ { print int($2 / 1024) }' "/proc/$child/status" 2>/dev/null || true)
      [ -n "$h" ] && [ "$h" -gt "$hwm" ] && hwm=$h
    fi
    if [ "$hwm" -gt "$MEM_LIMIT_MB" ]; then why="stopped at $hwm MB (MEM_LIMIT_MB=$MEM_LIMIT_MB)"; fi
    if awk -v a="$t0" -v b="$EPOCHREALTIME" -v l="$TIME_LIMIT" 'BEGIN { exit !(b - a > l) }'; then
      why="stopped after $TIME_LIMIT s (TIME_LIMIT)"
    fi
    if [ -n "$why" ]; then
      [ -n "$child" ] && { kill "$child" 2>/dev/null || true; }
      sleep 2
      [ -n "$child" ] && { kill -9 "$child" 2>/dev/null || true; }
      break
    fi
    sleep 0.25
  done
  wait "$pid" || rc=$?
  t1=$EPOCHREALTIME
  h=$(tail -1 "$work/$name.rss" 2>/dev/null | grep -E '^[0-9]+$' || true)
  peak_mb=$hwm
  [ -n "$h" ] && peak_mb=$((h / 1024))
  if [ -n "$why" ]; then
    sec=-
  elif [ "$rc" != 0 ]; then
    why="exit $rc: $(grep -v '^ *$' "$work/$name.log" | grep -v trace | tail -2 | tr '\n' ' ')"
    sec=-
  else
    sec=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
  fi
}

# check NAME GCODE SHIFT: slice_field_check.py's JSON in $work/NAME.json (nothing if it failed)
check() {
  [ -s "$2" ] || return 0
  local shift=()
  [ -n "$3" ] && shift=(--shift "$3")
  "$PY" bench/slice_field_check.py "$expr" "$2" --line-width 0.45 --layer-height 0.2 "${shift[@]}" --fit-xy \
    "${check_args[@]}" --json >"$work/$1.json" 2>"$work/$1.json.err" ||
    { notes+=("slice_field_check $1: $(tail -1 "$work/$1.json.err")"); rm -f "$work/$1.json"; }
}

# stl_info STL: "triangles xmin ymin zmin xmax ymax zmax" of a binary STL, read in chunks
stl_info() {
  "$PY" - "$1" <<'EOF'
import sys, numpy as np
path = sys.argv[1]
n = int.from_bytes(open(path, "rb").read(84)[80:84], "little")
rec = np.memmap(path, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), mode="r", offset=84, shape=(n,))
lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
for s in range(0, n, 4_000_000):
    v = np.asarray(rec["v"][s:s + 4_000_000]).reshape(-1, 3)
    lo, hi = np.minimum(lo, v.min(0)), np.maximum(hi, v.max(0))
print(n, *lo, *hi)
EOF
}

p_label=skipped c_label=skipped
[ -n "$have_prusa" ] && p_label=$("$prusa" --help 2>/dev/null | grep -m1 -o 'PrusaSlicer-[^ ]*' || true)
[ -n "$have_cura" ] && c_label="$("$cura" help 2>&1 | grep -m1 -o 'version [0-9.]*' || true)"
echo "$expr: 0.2 mm layers, 0.45 mm lines, 2 perimeters, 4 top / 4 bottom, 0% sparse infill ($(nproc) cores," \
     "load $(cut -d' ' -f1 /proc/loadavg)); frep: $frep; PrusaSlicer: $p_label; CuraEngine: $c_label"

declare -A S=() M=() N=() W=() J=()
# (a) frep slices the field
run_limited frep "$frep" slice "$expr" -o "$out/frep.gcode" --layer-height 0.2 --line-width 0.45 --perimeters 2 \
  --infill 0 --top-layers 4 --bottom-layers 4
S[frep]=$sec M[frep]=$peak_mb W[frep]=$why
# (b) frep meshes it at CELL (falling back to coarser cells), the mesh slicers slice the STL
stl=$out/part.stl
cell=
for c in $CELL $FALLBACK_CELLS; do
  rm -f "$stl"
  run_limited mesh "$frep" mesh "$expr" --cell "$c" -o "$stl"
  if [ "$sec" != - ] && [ -s "$stl" ]; then cell=$c; break; fi
  notes+=("frep mesh --cell $c: $why")
done
S[mesh]=$sec M[mesh]=$peak_mb W[mesh]=$why
if [ -n "$cell" ]; then
  [ "$cell" != "$CELL" ] && notes+=("meshed at --cell $cell instead of $CELL (see above)")
  read -r tris x0 y0 z0 x1 y1 z1 < <(stl_info "$stl")
  N[mesh]=$tris
  # PrusaSlicer keeps x and y (bed centred at the origin, --dont-arrange) and drops the part to z = 0;
  # Cura centres the box at (110,110) and drops it to z = 0
  J[prusa]=$(awk -v z="$z0" 'BEGIN { printf "0,0,%.9g", -z }')
  J[cura]=$(awk -v a="$x0" -v b="$x1" -v c="$y0" -v d="$y1" -v z="$z0" \
    'BEGIN { printf "%.9g,%.9g,%.9g", 110 - (a + b) / 2, 110 - (c + d) / 2, -z }')
  if [ -n "$have_prusa" ]; then
    run_limited prusa "$prusa" --export-gcode --load bench/slicer_configs/prusa.ini --fill-density 0% \
      --fill-pattern rectilinear --dont-arrange -o "$out/prusa.gcode" "$stl"
    S[prusa]=$sec M[prusa]=$peak_mb W[prusa]=$why
    if [ "${PRUSA_CLASSIC:-1}" != 0 ]; then
      run_limited prusa_classic "$prusa" --export-gcode --load bench/slicer_configs/prusa.ini --fill-density 0% \
        --fill-pattern rectilinear --perimeter-generator classic --dont-arrange -o "$out/prusa_classic.gcode" "$stl"
      S[prusa_classic]=$sec M[prusa_classic]=$peak_mb W[prusa_classic]=$why
    fi
  fi
  if [ -n "$have_cura" ]; then
    run_limited cura "$cura" slice -j "$defs/fdmprinter.def.json" "${cura_settings[@]}" -e0 "${cura_settings[@]}" \
      -l "$stl" -o "$out/cura.gcode"
    S[cura]=$sec M[cura]=$peak_mb W[cura]=$why
  fi
  [ -z "${KEEP:-}" ] && rm -f "$stl"  # 3 GB at 0.05 mm
fi
for k in frep mesh prusa prusa_classic cura; do [ -n "${W[$k]:-}" ] && notes+=("$k: ${W[$k]}"); done
# the checks, after every timed step (they take minutes each: 1.5 M outer-wall vertices on frep's)
check frep "$out/frep.gcode" ""
[ -n "$have_prusa" ] && [ -n "$cell" ] && check prusa "$out/prusa.gcode" "${J[prusa]}"
[ -n "${S[prusa_classic]:-}" ] && check prusa_classic "$out/prusa_classic.gcode" "${J[prusa]}"
[ -n "$have_cura" ] && [ -n "$cell" ] && check cura "$out/cura.gcode" "${J[cura]}"

echo
echo "| step | s | peak MB | triangles / moves | outer pts | median | p95 | max | within 1% w | xy shift |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
"$PY" - "$work" "${cell:-$CELL (failed)}" "${S[frep]:--}" "${M[frep]:--}" "${S[mesh]:--}" "${M[mesh]:--}" "${N[mesh]:--}" \
  "${S[prusa]:--}" "${M[prusa]:--}" "${S[prusa_classic]:--}" "${M[prusa_classic]:--}" "${S[cura]:--}" "${M[cura]:--}" \
  "$have_prusa" "${S[prusa_classic]:+1}" "$have_cura" <<'EOF'
import json, os, sys
work, cell, fs, fm, ms, mm, tris, ps, pm, qs, qm, cs, cm, have_p, have_q, have_c = sys.argv[1:]
f = lambda x, fmt="{:.4f}": "-" if x is None else fmt.format(x)

def load(name):
    p = os.path.join(work, name + ".json")
    return json.load(open(p)) if os.path.exists(p) else None

def cols(r):
    if not r or not r["outer_points"]:
        return ["-"] * 6
    sh = r["fitted_xy_shift"]
    return [str(r["outer_points"]), f(r["err_median"]), f(r["err_p95"]), f(r["err_max"]),
            f(100 * r["within_1pct"], "{:.1f}%"), "({:.4f}, {:.4f})".format(*sh) if sh else "-"]

def add(a, b):
    return "-" if "-" in (a, b) else f"{float(a) + float(b):.1f}"

def row(step, s, m, count, r=None):
    print(f"| {step} | {s} | {m} | {count} | " + " | ".join(cols(r)) + " |")

fr = load("frep")
row("frep slice (the field)", fs, fm, fr["extrusion_moves"] if fr else "-", fr)
row(f"frep mesh --cell {cell}", ms, mm, f"{int(tris):,} triangles" if tris != "-" else "-")
for who, label, s, m, have in (("prusa", "PrusaSlicer", ps, pm, have_p),
                               ("prusa_classic", "PrusaSlicer (classic perimeters)", qs, qm, have_q),
                               ("cura", "CuraEngine", cs, cm, have_c)):
    if not have:
        continue
    r = load(who)
    row(f"{label} on the STL", s, m, r["extrusion_moves"] if r else "-", r)
    e2e = add(ms, s)
    ratio = f" (frep {float(e2e) / float(fs):.1f}x faster)" if "-" not in (e2e, fs) else ""
    row(f"mesh + {label}, end to end{ratio}", e2e, max(int(mm), int(m)) if "-" not in (mm, m) else "-", "")
print()
for who in ("frep", "prusa", "prusa_classic", "cura"):
    r = load(who)
    if r and r.get("worst_point"):
        w = r["worst_point"]
        print(f"{who}: worst outer-wall vertex: layer {w['layer']} at printer ({w['printer_xyz'][0]:.3f}, "
              f"{w['printer_xyz'][1]:.3f}, {w['printer_xyz'][2]:.2f}), d = {w['d']:.4f}; "
              f"{r['outer_points']} of {r['outer_points_total']} points checked in {r['total_s']:.0f} s")
EOF
echo
for n in "${notes[@]}"; do echo "note: $n"; done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
[ -n "${KEEP:-}" ] && echo "G-code and JSON kept in $KEEP" && cp "$work"/*.json "$KEEP"/ 2>/dev/null
exit 0
