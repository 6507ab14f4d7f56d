#!/usr/bin/env bash
# Simplification (`frep mesh --max-error`) against the uniform mesh, in the same run, on the demo
# bracket and real meshes (their exact distance is the field): triangles, time, and the maximum
# error measured independently of the simplification's own samples: the exact distance of the
# input mesh (`frep eval` on it) at every output vertex and at 4 random points of each triangle.
#   bash bench/simplify.sh [MESH...]            (default: the bracket and the shared meshes)
#   RES=128 ERR=0.05c bash bench/simplify.sh
source "$(dirname "$0")/common.sh"
RES=${RES:-128}
ERR=${ERR:-0.05c}
[ -x build/frep ] || build_targets frep
PY=/usr/bin/python3
"$PY" -c "import numpy" 2>/dev/null || { echo "bench/simplify.sh: needs /usr/bin/python3 with numpy" >&2; exit 1; }
if [ $# -gt 0 ]; then
  meshes=("$@")
else
  meshes_or_defaults
  meshes=(examples/bracket.obj "${meshes[@]}")
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# seconds and triangles of one `frep mesh` run (the mesher's own report line)
run() {
  local in=$1 out=$2 err=$3 t0 t1
  t0=$(date +%s.%N)
  build/frep mesh "$in" -r "$RES" --max-error "$err" -o "$out" -q
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }'
}

# the largest |d| of the input mesh's exact distance at a mesh's vertices and 4 random points
# per triangle (stl_probe_points)
max_error() {
  local in=$1 stl=$2
  stl_probe_points "$stl" "$work/pts.txt"
  build/frep eval "$in" --points "$work/pts.txt" 2>/dev/null | "$PY" -c "
import sys
print(max(abs(float(l)) for l in sys.stdin))"
}

echo "frep mesh -r $RES, uniform against --max-error $ERR (same run, $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
echo
echo "| mesh | input triangles | uniform | simplified | ratio | uniform s | simplified s | time ratio | uniform max error | simplified max error |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  su=$(run "$m" "$work/u.stl" 0)
  ss=$(run "$m" "$work/s.stl" "$ERR")
  read -r tin diag < <(build/frep check "$m" 2>/dev/null | "$PY" -c "
import re, sys
t = s = None
for line in sys.stdin:
    m = re.match(r'.*?: (\d+) triangles', line)
    if m and t is None: t = int(m.group(1))
    b = re.search(r'box: \(([^)]*)\) - \(([^)]*)\)', line)
    if b:
        lo = [float(x) for x in b.group(1).split(',')]; hi = [float(x) for x in b.group(2).split(',')]
        s = sum((h - l) ** 2 for l, h in zip(lo, hi)) ** 0.5
print(t, s)")
  eu=$(max_error "$m" "$work/u.stl")
  es=$(max_error "$m" "$work/s.stl")
  "$PY" - "$name" "$tin" "$work/u.stl" "$work/s.stl" "$su" "$ss" "$eu" "$es" "$diag" <<'EOF'
import sys
name, tin, u, s, su, ss, eu, es, diag = sys.argv[1:]
count = lambda p: int.from_bytes(open(p, 'rb').read()[80:84], 'little')
nu, ns = count(u), count(s)
print(f"| {name} | {tin} | {nu} | {ns} | {nu / ns:.1f}x | {su} | {ss} | {float(ss) / float(su):.1f}x "
      f"| {float(eu) / float(diag):.2g} | {float(es) / float(diag):.2g} |")
EOF
done
echo
echo "max error: the largest |d| of the input mesh's exact signed distance at each output's vertices and 4"
echo "random points per triangle, over the input's diagonal (the uniform mesh's own error included; a cell is"
echo "1/$RES of the longest side)"
