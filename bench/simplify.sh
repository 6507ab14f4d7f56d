#!/usr/bin/env bash
# Simplification (`frep mesh --max-error`) against the uniform mesh (`--max-error 0`), in the same
# run, on the demo bracket and real meshes (their exact distance is the field): the default
# (`flat`: flat regions merged) and a bound (ERR); triangles, time, and the maximum error measured
# independently of the simplification's own samples: the exact distance of the input mesh
# (`frep eval` on it) at every output vertex and at 4 random points of each triangle.
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

# seconds of a `frep mesh` run: the best of $2 runs (the short ones are noisy)
run() {
  local in=$1 out=$2 err=$3 reps=${4:-1} best="" t0 t1 t
  for ((i = 0; i < reps; ++i)); do
    t0=$(date +%s.%N)
    build/frep mesh "$in" -r "$RES" --max-error "$err" -o "$out" -q
    t1=$(date +%s.%N)
    t=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
    best=$(awk -v a="$best" -v b="$t" 'BEGIN { print (a == "" || b < a) ? b : a }')
  done
  echo "$best"
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
echo "| mesh | input triangles | uniform | flat | $ERR | ratio | uniform s | flat s | $ERR s | flat time ratio | $ERR time ratio | uniform max error | flat max error | $ERR max error |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  su=$(run "$m" "$work/u.stl" 0 3)
  sf=$(run "$m" "$work/f.stl" flat 3)
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
  ef=$(max_error "$m" "$work/f.stl")
  es=$(max_error "$m" "$work/s.stl")
  "$PY" - "$name" "$tin" "$work/u.stl" "$work/f.stl" "$work/s.stl" "$su" "$sf" "$ss" "$eu" "$ef" "$es" "$diag" <<'EOF'
import sys
name, tin, u, f, s, su, sf, ss, eu, ef, es, diag = sys.argv[1:]
count = lambda p: int.from_bytes(open(p, 'rb').read()[80:84], 'little')
nu, nf, ns = count(u), count(f), count(s)
e = lambda x: f"{float(x) / float(diag):.2g}"
print(f"| {name} | {tin} | {nu} | {nf} | {ns} | {nu / ns:.1f}x | {su} | {sf} | {ss} | {float(sf) / float(su):.2f}x "
      f"| {float(ss) / float(su):.1f}x | {e(eu)} | {e(ef)} | {e(es)} |")
EOF
done
echo
echo "max error: the largest |d| of the input mesh's exact signed distance at each output's vertices and 4"
echo "random points per triangle, over the input's diagonal (the uniform mesh's own error included; a cell is"
echo "1/$RES of the longest side)"
