#!/usr/bin/env bash
# `frep slice` against PrusaSlicer 2.5 and CuraEngine 4.13 on the same STL with the same settings,
# in the same run, each output checked independently by bench/slice_check.py against the mesh.
#   bash bench/slice_compare.sh [MESH...]   (default: fandisk, plate_holes, armadillo, thingi10k_73416
#                                            from ../shared/data/meshes, and a speed row on scallop)
# Each mesh is scaled uniformly to SIZE mm (40) on its largest side and written as one binary STL,
# its bounding box centred at the origin with its bottom at z = 0 (bench/slice_scale.py; float32
# is most precise there: moved to (110,110), needle triangles of thingi10k_73416 fold). The three
# slicers get that same file. frep (its default) and Cura (center_object=true) centre the box on the
# 220 x 220 bed at (110,110); PrusaSlicer keeps the file's coordinates (--dont-arrange, on a bed
# declared centred at the origin), as its own --center 110,110 puts fandisk 0.009 mm off in y. So
# slice_check.py knows each placement exactly; its --fit-xy shift is shown (near 0: the slicer put
# the part where it says).
# The settings (bench/slicer_configs/prusa.ini and cura.txt; frep's flags below): 0.4 mm nozzle,
# every line 0.45 mm wide, 0.2 mm layers (first layer too), 2 perimeters, rectilinear / lines
# infill at 20% (and 100% for the volume column), 4 top and 4 bottom solid layers, no
# skirt/brim/support, 1.75 mm filament, 220 x 220 bed, no elephant-foot / XY compensation, 1 mm
# retraction and no wipe. Both references slice at mid-layer (print z - 0.1), as slice_check.py does.
#   frep       $FREP slice IN.stl -o OUT.gcode --layer-height 0.2 --line-width 0.45 --perimeters 2
#              --infill D --top-layers 4 --bottom-layers 4
#   PrusaSlicer prusa-slicer --export-gcode --load bench/slicer_configs/prusa.ini --fill-density D%
#              --fill-pattern rectilinear --dont-arrange -o OUT.gcode IN.stl   (the pattern is
#              repeated on the command line: 2.5 checks a command-line --fill-density 100% against
#              the default pattern, before the loaded file applies)
#   CuraEngine CuraEngine slice -j fdmprinter.def.json -s K=V... -e0 -s K=V... -l IN.stl -o OUT.gcode
#              with every line of cura.txt as -s K=V, plus infill_sparse_density=D,
#              infill_line_distance=0.45*100/D and infill_overlap (10, or 0 at 100%); given again
#              after -e0 because the extruder's own definition (fdmextruder.def.json) otherwise
#              puts back material_diameter 2.85. CuraEngine evaluates none of the definitions'
#              formulas: every derived setting is in cura.txt.
# Cura's definitions: $CURA_DEFS (a folder with fdmprinter.def.json and fdmextruder.def.json), else
# /usr/share/cura/resources/definitions (package `cura`, the Qt GUI), else
# ${XDG_CACHE_HOME:-~/.cache}/frep-bench/cura-defs, which this script fills from Debian's `cura`
# package by `apt-get download cura` + `dpkg -x` (the two JSON files only; nothing installed).
# Without them, or without a slicer, that slicer is skipped with a message; frep is skipped until
# its binary ($FREP, build/frep or build/apps/frep/frep) has a `slice` command.
# Columns: s = wall seconds of the whole 20% job (process start and G-code writing included; each
# slicer with its own default threads on this machine); vs Prusa = s / PrusaSlicer's s; outer pts =
# outer-wall path vertices checked; median / p95 / max = |d - w/2| in mm, d the distance of a vertex
# to the exact mesh section at its layer's mid-height, w/2 = 0.225; within 1% = |d - w/2| <= 0.0045;
# xy shift = the translation slice_check --fit-xy finds (mm); vol 100% = extruded filament volume of
# the 100% job / mesh volume.
#   SIZE=40 KEEP=DIR (keep the STL and G-code) FREP=binary SPEED_MESH=file (scallop; '' skips)
args=()
for a in "$@"; do args+=("$(realpath -m -- "$a")"); done  # common.sh moves to the project root
[ -n "${SPEED_MESH:-}" ] && SPEED_MESH=$(realpath -m -- "$SPEED_MESH")
[ -n "${FREP:-}" ] && FREP=$(realpath -m -- "$FREP")
[ -n "${CURA_DEFS:-}" ] && CURA_DEFS=$(realpath -m -- "$CURA_DEFS")
[ -n "${KEEP:-}" ] && KEEP=$(realpath -m -- "$KEEP")
source "$(dirname "$0")/common.sh"
set -- "${args[@]}"
PY=/usr/bin/python3
"$PY" -c "import numpy" 2>/dev/null || { echo "bench/slice_compare.sh: needs /usr/bin/python3 with numpy" >&2; exit 1; }
SIZE=${SIZE:-40}
data=../shared/data/meshes
if [ $# -gt 0 ]; then
  meshes=("$@")
  for m in "${meshes[@]}"; do require_input "$m"; done
  speed=${SPEED_MESH:-}
elif [ -d "$data" ]; then
  meshes=("$data/fandisk.obj" "$data/plate_holes.stl" "$data/armadillo_libigl.obj" "$data/thingi10k_73416.stl")
  for m in "${meshes[@]}"; do require_input "$m"; done
  speed=${SPEED_MESH-$data/scallop_manifold.obj}
else
  echo "bench/slice_compare.sh: $data not found (the shared meshes); skipping. Give mesh files as arguments." >&2
  exit 0
fi
notes=()

# frep: $FREP, else build/frep (built if missing), else build/apps/frep/frep; skipped without `slice`
frep=${FREP:-}
if [ -z "$frep" ]; then
  for f in build/frep build/apps/frep/frep; do [ -x "$f" ] && { frep=$f; break; }; done
  if [ -z "$frep" ] && [ -z "${NO_BUILD:-}" ]; then build_targets frep && frep=build/frep; fi
fi
if [ -n "$frep" ] && "$frep" slice --help >/dev/null 2>&1; then
  have_frep=1
else
  have_frep=
  echo "note: ${frep:-no frep binary} has no 'slice' command yet: frep skipped"
fi

prusa=${PRUSA:-prusa-slicer}
have_prusa=
if command -v "$prusa" >/dev/null; then have_prusa=1; else
  echo "note: $prusa not found (apt-get install --no-install-recommends prusa-slicer): PrusaSlicer skipped"; fi

cura=${CURA:-CuraEngine}
have_cura=
defs=
if ! command -v "$cura" >/dev/null; then
  echo "note: $cura not found (apt-get install --no-install-recommends cura-engine): CuraEngine skipped"
else
  cache=${XDG_CACHE_HOME:-$HOME/.cache}/frep-bench/cura-defs
  for d in "${CURA_DEFS:-}" /usr/share/cura/resources/definitions "$cache"; do
    [ -n "$d" ] && [ -f "$d/fdmprinter.def.json" ] && [ -f "$d/fdmextruder.def.json" ] && { defs=$d; break; }
  done
  if [ -z "$defs" ] && command -v apt-get >/dev/null && command -v dpkg >/dev/null; then
    echo "note: fetching Cura's printer definitions from Debian's cura package into $cache (nothing installed)"
    dl=$(mktemp -d)
    if (cd "$dl" && apt-get download cura >/dev/null 2>&1) && dpkg -x "$dl"/cura_*.deb "$dl/x" 2>/dev/null; then
      mkdir -p "$cache"
      cp "$dl"/x/usr/share/cura/resources/definitions/fdm{printer,extruder}.def.json "$cache"/ && defs=$cache
    fi
    rm -rf "$dl"
  fi
  if [ -n "$defs" ]; then have_cura=1; else
    echo "note: Cura's fdmprinter.def.json / fdmextruder.def.json not found (package cura, or CURA_DEFS=DIR): CuraEngine skipped"; fi
fi
cura_settings=()
while IFS= read -r l; do
  [[ -z "$l" || "$l" == \#* ]] && continue
  cura_settings+=(-s "$l")
done <bench/slicer_configs/cura.txt

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=${KEEP:-$work}
mkdir -p "$out"

# slice SLICER IN.stl OUT.gcode DENSITY: runs one slicer; sets sec to its wall seconds ("-" if it failed)
slice() {
  local who=$1 in=$2 gcode=$3 d=$4 t0 t1 rc=0
  rm -f "$gcode"
  t0=$EPOCHREALTIME
  case "$who" in
    frep) "$frep" slice "$in" -o "$gcode" --layer-height 0.2 --line-width 0.45 --perimeters 2 --infill "$d" \
            --top-layers 4 --bottom-layers 4 >"$gcode.log" 2>&1 || rc=$? ;;
    prusa) "$prusa" --export-gcode --load bench/slicer_configs/prusa.ini --fill-density "$d%" --fill-pattern rectilinear \
             --dont-arrange -o "$gcode" "$in" >"$gcode.log" 2>&1 || rc=$? ;;
    cura)
      local dens=(-s "infill_sparse_density=$d"
                  -s "infill_line_distance=$(awk -v d="$d" 'BEGIN { printf "%.6g", 0.45 * 100 / d }')"
                  -s "infill_overlap=$([ "$d" -ge 95 ] && echo 0 || echo 10)")
      "$cura" slice -j "$defs/fdmprinter.def.json" "${cura_settings[@]}" "${dens[@]}" -e0 "${cura_settings[@]}" "${dens[@]}" \
        -l "$in" -o "$gcode" >"$gcode.log" 2>&1 || rc=$? ;;
  esac
  t1=$EPOCHREALTIME
  if [ "$rc" != 0 ] || [ ! -s "$gcode" ]; then
    notes+=("$(basename "$in") $who ${d}%: exit $rc: $(grep -v '^ *$' "$gcode.log" | grep -v trace | tail -2 | tr '\n' ' ')")
    sec=-
  else
    sec=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
  fi
}

# check SLICER STL GCODE JSON: slice_check.py's numbers, or nothing if it failed
check() {
  [ -s "$3" ] || return 0
  local center=110,110
  [ "$1" = prusa ] && center=0,0
  "$PY" bench/slice_check.py "$2" "$3" --line-width 0.45 --layer-height 0.2 --filament 1.75 --center "$center" \
    --fit-xy --json >"$4" 2>"$4.err" || { notes+=("slice_check $(basename "$3"): $(tail -1 "$4.err")"); rm -f "$4"; }
}

slicers=()
[ -n "$have_frep" ] && slicers+=(frep)
[ -n "$have_prusa" ] && slicers+=(prusa)
[ -n "$have_cura" ] && slicers+=(cura)
[ ${#slicers[@]} -gt 0 ] || { echo "bench/slice_compare.sh: no slicer to run" >&2; exit 0; }

f_label=skipped p_label=skipped c_label=skipped
[ -n "$have_frep" ] && f_label=$frep
[ -n "$have_prusa" ] && p_label=$("$prusa" --help 2>/dev/null | grep -m1 -o 'PrusaSlicer-[^ ]*' || true)
[ -n "$have_cura" ] && c_label="$("$cura" help 2>&1 | grep -m1 -o 'version [0-9.]*' || true), definitions in $defs"
echo "slicing at 0.2 mm, meshes scaled to $SIZE mm ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg));" \
     "frep: $f_label; PrusaSlicer: $p_label; CuraEngine: $c_label"
echo
echo "| mesh | triangles | slicer | s | vs Prusa | outer pts | median | p95 | max | within 1% w | xy shift | vol 100% |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  stem=${name%.*}
  stl=$out/$stem.stl
  read -r tris _ < <("$PY" bench/slice_scale.py "$m" "$stl" --size "$SIZE")
  declare -A secs=()
  for s in "${slicers[@]}"; do
    slice "$s" "$stl" "$out/$stem.$s.20.gcode" 20
    secs[$s]=$sec
    slice "$s" "$stl" "$out/$stem.$s.100.gcode" 100
    check "$s" "$stl" "$out/$stem.$s.20.gcode" "$out/$stem.$s.20.json"
    check "$s" "$stl" "$out/$stem.$s.100.gcode" "$out/$stem.$s.100.json"
  done
  for s in "${slicers[@]}"; do
    "$PY" - "$name" "$tris" "$s" "${secs[$s]}" "${secs[prusa]:--}" "$out/$stem.$s.20.json" "$out/$stem.$s.100.json" \
      2>>"$work/notes" <<'EOF'
import json, os, sys
name, tris, who, s, sp, j20, j100 = sys.argv[1:]
label = {"frep": "frep", "prusa": "PrusaSlicer", "cura": "CuraEngine"}[who]
r = json.load(open(j20)) if os.path.exists(j20) else None
v = json.load(open(j100)) if os.path.exists(j100) else None
ratio = f"{float(s) / float(sp):.2f}" if "-" not in (s, sp) and float(sp) > 0 else "-"
f = lambda x, fmt="{:.4f}": "-" if x is None else fmt.format(x)
if r and r["outer_points"]:
    cols = [str(r["outer_points"]), f(r["err_median"]), f(r["err_p95"]), f(r["err_max"]),
            f(100 * r["within_1pct"], "{:.1f}%"), "({:.3f}, {:.3f})".format(*r["fitted_xy_shift"])]
else:
    cols = ["0" if r else "-"] + ["-"] * 5
print(f"| {name} | {tris} | {label} | {s} | {ratio} | " + " | ".join(cols) + f" | {f(v and v['volume_ratio'], '{:.3f}')} |")
q = r and r["fitted"]
if q and q["outer_points"] and max(map(abs, r["fitted_xy_shift"])) > 0.01:
    print(f"{name} {label}: placed ({r['fitted_xy_shift'][0]:.3f}, {r['fitted_xy_shift'][1]:.3f}) mm off the STL's "
          f"coordinates; after that shift: median {f(q['err_median'])} p95 {f(q['err_p95'])} max {f(q['err_max'])} "
          f"within 1% w {100 * q['within_1pct']:.1f}%", file=sys.stderr)
EOF
  done
  unset secs
done

if [ -n "$speed" ]; then
  require_input "$speed"
  name=$(basename "$speed")
  stem=${name%.*}
  read -r tris _ < <("$PY" bench/slice_scale.py "$speed" "$out/$stem.stl" --size "$SIZE")
  echo
  echo "speed, 20% infill at 0.2 mm layers:"
  echo
  echo "| mesh | triangles | slicer | s | vs Prusa | layers |"
  echo "| --- | --- | --- | --- | --- | --- |"
  declare -A secs=()
  for s in "${slicers[@]}"; do slice "$s" "$out/$stem.stl" "$out/$stem.$s.speed.gcode" 20; secs[$s]=$sec; done
  for s in "${slicers[@]}"; do
    layers=$(grep -cE '^;(LAYER_CHANGE|LAYER:)' "$out/$stem.$s.speed.gcode" 2>/dev/null || true)
    awk -v n="$name" -v t="$tris" -v w="$s" -v s="${secs[$s]}" -v p="${secs[prusa]:--}" -v l="${layers:--}" 'BEGIN {
      split("frep frep prusa PrusaSlicer cura CuraEngine", a, " "); for (i = 1; i < 6; i += 2) lab[a[i]] = a[i + 1]
      r = (s != "-" && p != "-" && p > 0) ? sprintf("%.2f", s / p) : "-"
      printf "| %s | %s | %s | %s | %s | %s |\n", n, t, lab[w], s, r, l }'
  done
fi
echo
for n in "${notes[@]}"; do echo "note: $n"; done
[ -s "$work/notes" ] && sed 's/^/note: /' "$work/notes"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
[ -n "${KEEP:-}" ] && echo "scaled STL and G-code kept in $KEEP"
exit 0
