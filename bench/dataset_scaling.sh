#!/usr/bin/env bash
# Dataset throughput: `frep dataset` over a folder of shared meshes at --grid 128 --points 250000,
# with 1 and then 2 local worker processes in the same run; prints meshes per minute and the ratio
# (target: at least 1.8x). The wall time timed is the whole command: cluster start, hashing, the
# samples, the manifest.
#   bash bench/dataset_scaling.sh                 # the clean shared meshes below, REPEAT=4 times each
#   FREP=build-x/frep bash bench/dataset_scaling.sh MESH...
# Needs ../shared/data/meshes (or meshes as arguments), a Python 3 with Dask distributed, and the
# frep program ($FREP, default build/frep, built if missing).
source "$(dirname "$0")/common.sh"
FREP=${FREP:-build/frep}
if [ ! -x "$FREP" ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build --target frep >/dev/null
fi
FREP=$(realpath "$FREP")
# A Python with Dask: $FREP_PYTHON, the system's, then python3 on PATH.
PY=""
for p in "${FREP_PYTHON:-}" /usr/bin/python3 python3; do
  if [ -n "$p" ] && "$p" -c "import distributed" 2>/dev/null; then PY=$p; break; fi
done
[ -n "$PY" ] || { echo "bench/dataset_scaling.sh: no Python with Dask distributed (install python3-distributed)" >&2; exit 1; }

data=../shared/data/meshes
if [ $# -gt 0 ]; then
  meshes=("$@")
else
  # The shared meshes that are valid solids, 4 to 120k triangles: CAD parts, scans, a high-genus
  # sponge, a sliver, a box at the float range's limit (normalized like the others).
  meshes=("$data/cube_unit_bin.stl" "$data/cube_quads.off" "$data/tet_sliver.ply" "$data/cray_right_fltmax.obj"
          "$data/sphere_icosa_1280.stl" "$data/plate_holes.stl" "$data/tray_bottom_ascii.stl" "$data/spot.obj"
          "$data/bunny_closed_libigl.off" "$data/fandisk.obj" "$data/menger_sponge_l3.obj"
          "$data/thingi10k_73416.stl" "$data/armadillo_libigl.obj" "$data/capsule_collapsed_poles.obj"
          "$data/scallop_manifold.obj")
fi
for m in "${meshes[@]}"; do require_input "$m"; done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# REPEAT copies of each mesh (symbolic links under other names: separate items of the dataset), so
# that the fixed cost of a run (Python, the cluster's start and stop) weighs as little as in a
# real dataset of thousands of meshes. REPEAT=1: each mesh once.
REPEAT=${REPEAT:-4}
mkdir -p "$work/in"
for ((r = 0; r < REPEAT; r++)); do
  for m in "${meshes[@]}"; do
    link="$work/in/r${r}_$(basename "$m")"
    ln -s "$(realpath "$m")" "$link"
    echo "$link"
  done
done >"$work/meshes.txt"

# run N: seconds for a fresh dataset with N workers
run() {
  local t0 t1
  t0=$(date +%s.%N)
  # The module as a script: it is pure Python and needs no built extension.
  "$PY" python/frep/dataset.py "$work/meshes.txt" -o "$work/out$1" \
    --grid 128 --points 250000 --workers "$1" --frep "$FREP" -q || {
      echo "bench/dataset_scaling.sh: some meshes failed:" >&2; grep '"failed"' "$work/out$1/manifest.jsonl" >&2; }
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }'
}
n=$(( ${#meshes[@]} * REPEAT ))
echo "frep dataset: $n meshes (${#meshes[@]} shared, each $REPEAT times), --grid 128 --points 250000, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
s1=$(run 1)
s2=$(run 2)
cmp -s <(cd "$work/out1" && find . -name '*.npy' | sort | xargs md5sum) \
       <(cd "$work/out2" && find . -name '*.npy' | sort | xargs md5sum) \
  || { echo "bench/dataset_scaling.sh: the two runs wrote different files" >&2; exit 1; }
echo "  (load average after: $(cut -d' ' -f1-3 /proc/loadavg); other processes on the machine distort the ratio)"
# A control in the same run: how much two cores give one frep sample (the CPT grid scales
# nearly linearly on an idle machine), so that a ratio below target can be told from a busy machine.
control() {
  local t0 t1
  t0=$(date +%s.%N)
  "$FREP" sample "${meshes[-1]}" --grid 160 --normalize unit-cube --threads "$1" -q -o "$work/control.npy"
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }'
}
c1=$(control 1)
c2=$(control 2)
awk -v c1="$c1" -v c2="$c2" 'BEGIN { printf "  control: frep sample --grid 160, 2 threads over 1: %.2fx\n", c1 / c2 }'
awk -v n="$n" -v s1="$s1" -v s2="$s2" 'BEGIN {
  printf "  1 worker:  %6.1f s  %6.2f meshes/min\n", s1, 60 * n / s1;
  printf "  2 workers: %6.1f s  %6.2f meshes/min\n", s2, 60 * n / s2;
  printf "  speedup:   %.2fx (target >= 1.8x); the files of both runs are identical\n", s1 / s2;
}'
