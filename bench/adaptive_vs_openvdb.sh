#!/usr/bin/env bash
# Adaptive meshing at the same maximum error: `frep mesh --max-error` against OpenVDB's
# volumeToMesh adaptivity (build/bench/adaptive_vdb: the field sampled on the grid frep mesh -r RES
# starts from), on Fidget's bear.vm and converted scans. (libfive, the other baseline the issue
# names, has no Debian package: not measured.) Per output: triangles, wall seconds (load included),
# the maximum error measured independently of either mesher (as bench/simplify.sh: the input's exact
# field, `frep eval`, at every output vertex and 4 random points per triangle), and `frep check`'s
# verdict. One table per model, sorted by that error, so triangles at the same error read off.
# bear.vm is not a distance field: its error is |f| in the field's units, and |f|/|grad f| (a
# first-order distance estimate) beside it; the meshes' |f| is their exact distance.
#   bash bench/adaptive_vs_openvdb.sh [MODEL...]          (default: bear.vm, armadillo, bunny)
#   RES=128 ERRS="0.1c 0.5c" ADAPT="0 0.5" bash bench/adaptive_vs_openvdb.sh
source "$(dirname "$0")/common.sh"
RES=${RES:-256}
ERRS=${ERRS:-0.05c 0.1c 0.25c 0.5c}
ADAPT=${ADAPT:-0 0.1 0.25 0.5 0.75 1.0}
PY=/usr/bin/python3
"$PY" -c "import numpy" 2>/dev/null || { echo "bench/adaptive_vs_openvdb.sh: needs /usr/bin/python3 with numpy" >&2; exit 1; }
[ -x build/frep ] || build_targets frep
[ -x build/bench/adaptive_vdb ] || build_targets adaptive_vdb
[ -x build/bench/adaptive_vdb ] || { echo "bench/adaptive_vs_openvdb.sh: build/bench/adaptive_vdb not built (OpenVDB, libopenvdb-dev, not found?)" >&2; exit 1; }
if [ $# -gt 0 ]; then
  models=("$@")
else
  models=(../shared/data/vm/bear.vm ../shared/data/meshes/armadillo_libigl.obj ../shared/data/meshes/bunny_closed_libigl.off)
fi
present=()
for m in "${models[@]}"; do
  if [ -f "$m" ]; then present+=("$m"); else echo "bench/adaptive_vs_openvdb.sh: $m not found (../shared absent?): skipped" >&2; fi
done
[ ${#present[@]} -gt 0 ] || { echo "bench/adaptive_vs_openvdb.sh: no model found; nothing to measure" >&2; exit 0; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The measured error of one STL against the input's exact field: prints max |f|, max |f|/|grad f|,
# and their 99th percentiles.
max_error() {
  stl_probe_points "$2" "$work/pts.txt"
  build/frep eval "$1" --points "$work/pts.txt" -g 2>/dev/null | "$PY" -c "
import sys, numpy as np
a = np.array(sys.stdin.read().split(), dtype=np.float64).reshape(-1, 4)
f = np.abs(a[:, 0]); g = np.linalg.norm(a[:, 1:], axis=1)
d = f / np.maximum(g, 1e-30)
print(f'{f.max():.6g} {d.max():.6g} {np.percentile(f, 99):.6g} {np.percentile(d, 99):.6g}')"
}

# frep check's verdict: "valid solid" or what is wrong (its last line, shortened)
verdict() {
  build/frep check "$1" 2>&1 | tail -1 | sed -e 's/^valid solid:.*/valid solid/' -e 's/^not a solid: //'
}

triangles() { "$PY" -c "import sys; print(int.from_bytes(open(sys.argv[1], 'rb').read()[80:84], 'little'))" "$1"; }

seconds_since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }'; }

echo "frep mesh -r $RES --max-error E against OpenVDB volumeToMesh(adaptivity) on the same grid ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
for m in "${present[@]}"; do
  name=$(basename "$m")
  rows="$work/rows.tsv"
  : >"$rows"
  log="$work/log.txt"
  for e in 0 $ERRS; do
    out="$work/frep_$e.stl"
    t0=$(date +%s.%N)
    build/frep mesh "$m" -r "$RES" --max-error "$e" -o "$out" >"$log" 2>&1 || { echo "frep mesh $name --max-error $e failed:" >&2; cat "$log" >&2; continue; }
    s=$(seconds_since "$t0")
    cell=$(sed -n 's/^grid: .* cells of \([0-9.e+-]*\) over .*/\1/p' "$log")
    note=""
    grep -q "failed validation" "$log" && note=" (simplified mesh rejected: uniform kept)"
    printf 'frep\t--max-error %s%s\t%s\t%s\t%s\t%s\n' "$e" "$note" "$(triangles "$out")" "$s" "$(max_error "$m" "$out" | tr ' ' '\t')" \
      "$(verdict "$out")" >>"$rows"
  done
  for ad in $ADAPT; do
    out="$work/vdb_$ad.stl"
    t0=$(date +%s.%N)
    build/bench/adaptive_vdb "$m" "$RES" "$ad" "$out" >"$log" 2>&1 || { echo "adaptive_vdb $name $ad failed:" >&2; cat "$log" >&2; continue; }
    s=$(seconds_since "$t0")
    split=$(awk '{ for (i = 1; i < NF; ++i) if ($i == "sample_s") a = $(i + 1); else if ($i == "vdb_s") b = $(i + 1); print a " sampling + " b " vdb" }' "$log")
    printf 'OpenVDB\tadaptivity %s\t%s\t%s (%s)\t%s\t%s\n' "$ad" "$(triangles "$out")" "$s" "$split" "$(max_error "$m" "$out" | tr ' ' '\t')" \
      "$(verdict "$out")" >>"$rows"
  done
  "$PY" - "$name" "$cell" "$rows" <<'EOF'
import sys
name, cell, path = sys.argv[1], float(sys.argv[2]), sys.argv[3]
rows = [l.rstrip('\n').split('\t') for l in open(path) if l.strip()]
distance = not name.endswith(('.vm', '.rhai', '.frep'))
err = lambda r: float(r[4] if distance else r[5])  # bear.vm: |f|/|grad f|
print(f"\n### {name} (cell {cell:.4g})\n")
head = "| mesher | setting | triangles | seconds | " + \
       ("max error (exact distance) | " if distance else "max abs f | max abs f / abs grad f | ") + \
       "in cells | 99th percentile, cells | frep check | fewest frep triangles at <= this max error (OpenVDB / frep) |"
print(head)
print("|" + " --- |" * (head.count("|") - 1))
frep_rows = [r for r in rows if r[0] == "frep"]
for r in sorted(rows, key=err):
    tool, setting, tris, sec, f, fg, f99, fg99, check = r
    best = ""
    if tool != "frep":
        ok = [int(q[2]) for q in frep_rows if err(q) <= err(r)]
        best = f"{min(ok):,} ({int(tris) / min(ok):.2g})" if ok else "none"
    cols = [tool, setting, f"{int(tris):,}", sec, f"{float(f):.3g}"] + ([] if distance else [f"{float(fg):.3g}"]) + \
           [f"{err(r) / cell:.3g}", f"{float(f99 if distance else fg99) / cell:.2g}", check, best]
    print("| " + " | ".join(cols) + " |")
EOF
done
echo
echo "max error: over each output's vertices and 4 random points per triangle, of the input's exact field (frep eval);"
echo "the uniform mesh's own error included; in cells and its 99th percentile: bear.vm's |f|/|grad f|. Sorted by it."
echo "seconds: wall, load and writing included (OpenVDB: its sampling of the field and volumeToMesh in parentheses)."
