#!/usr/bin/env bash
# 3D render benchmark: the pruned column search at 1024x1024 (1 and 2 threads, warm renderer)
# against brute-force per-pixel column search in the same run, with the ratios.
#   bash bench/render3d.sh                       # ../shared/data/vm/bear.vm, front view
#   FREP_RENDER3D_MODEL=path.vm bash bench/render3d.sh   # any .vm or .rhai (a converted mesh)
#   FREP_RENDER3D_VIEW=iso FREP_RENDER3D_SIZE=512 FREP_RENDER3D_ROWS=4 bash bench/render3d.sh
# Brute force samples every FREP_RENDER3D_ROWS-th row (default 16) and is scaled to the whole
# image (rows cost independently); FREP_RENDER3D_ROWS=1 renders it all (minutes for the bear).
# The pruned depth map is checked bit for bit against brute force on those rows first.
source "$(dirname "$0")/common.sh"
model=${FREP_RENDER3D_MODEL:-../shared/data/vm/bear.vm}
require_input "$model"
build_targets bench_render3d
out=$(FREP_RENDER3D_MODEL="$model" ./build/bench/bench_render3d 2>&1)
echo "$out"
field() { echo "$out" | awk -v n="$1" -v c="$2" '$1 == n {print $c}'; }
t1=$(field "BM_Render3D/1/process_time/real_time" 2)
c1=$(field "BM_Render3D/1/process_time/real_time" 4)
t2=$(field "BM_Render3D/2/process_time/real_time" 2)
c2=$(field "BM_Render3D/2/process_time/real_time" 4)
bf=$(field "BM_Render3DBruteForce/iterations:1/manual_time" 2)
bfc=$(echo "$out" | sed -n 's/.*BM_Render3DBruteForce.*cpu_ms=\([0-9.e+k]*\).*/\1/p' | sed 's/k$/e3/')
echo
echo "$(basename "$model"), ${FREP_RENDER3D_SIZE:-1024}x${FREP_RENDER3D_SIZE:-1024}, view ${FREP_RENDER3D_VIEW:-front} (ms per warm re-render; CPU = all threads):"
awk -v t1="$t1" -v c1="$c1" -v t2="$t2" -v c2="$c2" -v bf="$bf" -v bfc="$bfc" 'BEGIN {
  printf "  1 thread:  %.0f ms (CPU %.0f ms)   %.0fx faster than brute force (CPU %.0fx)\n", t1, c1, bf / t1, bfc / c1;
  printf "  2 threads: %.0f ms (CPU %.0f ms)   %.0fx faster than brute force, %.2fx over 1 thread\n", t2, c2, bf / t2, t1 / t2;
  printf "  brute force (every column on the full tape, SIMD, 1 thread): %.0f ms (CPU %.0f ms)\n", bf, bfc;
}'
echo "  (load average when measured: $(cut -d' ' -f1-3 /proc/loadavg); on a busy machine, compare CPU times)"
