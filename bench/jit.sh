#!/usr/bin/env bash
# The JIT backend against the interpreter, same run: Prospero at 1024x1024 (warm re-render, 1 and
# 2 threads, each image checked against brute force by bench_eval), brute force (every pixel on
# the whole tape), batch throughput on Prospero and bear.vm, compile time per 1,000
# instructions, and the break-even: how many points a tape must be asked for before its
# compilation has paid for itself (compile time over the time saved per point); the same for
# the 16-box interval pass (break-even in passes). Last, the issue's "no regression elsewhere":
# bear.vm meshed at 256 cells (1 and 2 threads) and 3D renders of the shared 3D models (bear.vm,
# tanglecube.vm; 1024x1024, 1 thread), each run three times alternating the backends, medians.
#   bash bench/jit.sh
source "$(dirname "$0")/common.sh"
require_input ../shared/data/vm/prospero.vm
build_targets bench_eval bench_mesh bench_render3d
run() {  # backend, filter
  FREP_BACKEND=$1 ./build/bench/bench_eval --benchmark_filter="$2" --benchmark_min_time=1 --benchmark_repetitions=3 \
    --benchmark_report_aggregates_only=true 2>&1
}
interp=$(run interp 'ProsperoRender|ProsperoBruteForce')
jit=$(run jit 'ProsperoRender|ProsperoBruteForce')
parts=$(run interp 'BatchOn|GradOn|JitCompile|IntervalPassOn|JitIntervalCompile')
echo "$interp" | grep -E '^(check|BM_)'
echo "$jit" | grep -E '^(check|BM_)'
echo "$parts" | grep -E '^BM_'
median() { echo "$1" | awk -v n="$2" '$1 == n"_median" {print $2}'; }
counter() { echo "$1" | awk -v n="$2" -v c="$3" '$1 == n"_median" {for (i = 1; i <= NF; ++i) if (index($i, c"=") == 1) {split($i, kv, "="); v = kv[2]; m = 1; if (v ~ /k$/) {m = 1000; sub(/k$/, "", v)} print v * m}}'; }
echo
echo "Same run, median of 3 (ms; FREP_BACKEND=interp vs jit):"
for what in "ProsperoRender/1024/1/real_time" "ProsperoRender/1024/2/real_time" "ProsperoBruteForce/1024/real_time"; do
  i=$(median "$interp" "BM_$what"); j=$(median "$jit" "BM_$what")
  awk -v w="$what" -v i="$i" -v j="$j" 'BEGIN { printf "  %-36s interp %8.2f   jit %8.2f   jit speed-up %.2fx\n", w, i, j, i / j }'
done
awk -v a="$(median "$interp" BM_ProsperoRender/1024/1/real_time)" -v b="$(median "$interp" BM_ProsperoRender/1024/2/real_time)" \
    -v c="$(median "$jit" BM_ProsperoRender/1024/1/real_time)" -v d="$(median "$jit" BM_ProsperoRender/1024/2/real_time)" \
    'BEGIN { printf "  two threads over one: interp %.2fx, jit %.2fx\n", a / b, c / d }'
echo
echo "Batch evaluator, whole tapes (ns per point; break-even = compile time / time saved per point):"
for m in prospero bear; do
  for n in 256 4096; do
    i=$(median "$parts" "BM_BatchOn/${m}_interp/$n"); j=$(median "$parts" "BM_BatchOn/${m}_jit/$n")
    awk -v m="$m" -v n="$n" -v i="$i" -v j="$j" 'BEGIN { printf "  %-9s %5d points a call: interp %7.1f   jit %7.1f   %.2fx\n", m, n, i / n, j / n, i / j }'
  done
  i=$(median "$parts" "BM_GradOn/${m}_interp/4096"); j=$(median "$parts" "BM_GradOn/${m}_jit/4096")
  awk -v m="$m" -v i="$i" -v j="$j" 'BEGIN { printf "  %-9s gradients, 4096 points: interp %7.1f   jit %7.1f   %.2fx\n", m, i / 4096, j / 4096, i / j }'
  c=$(median "$parts" "BM_JitCompile/$m")
  per=$(counter "$parts" "BM_JitCompile/$m" compile_us_per_1000)
  ins=$(counter "$parts" "BM_JitCompile/$m" instructions)
  i=$(median "$parts" "BM_BatchOn/${m}_interp/4096"); j=$(median "$parts" "BM_BatchOn/${m}_jit/4096")
  awk -v m="$m" -v c="$c" -v per="$per" -v ins="$ins" -v i="$i" -v j="$j" 'BEGIN {
    saved = (i - j) / 4096; printf "  %-9s %d instructions: compile %.0f us (%.0f us per 1,000), break-even %.0f points\n", m, ins, c, per, c * 1000 / saved }'
done
echo
echo "Interval-batch evaluator, one pass of the whole tape over 16 boxes (us; break-even = compile time / time saved per pass):"
for m in prospero bear; do
  i=$(median "$parts" "BM_IntervalPassOn/${m}_interp"); j=$(median "$parts" "BM_IntervalPassOn/${m}_jit")
  c=$(median "$parts" "BM_JitIntervalCompile/$m")
  per=$(counter "$parts" "BM_JitIntervalCompile/$m" compile_us_per_1000)
  awk -v m="$m" -v i="$i" -v j="$j" -v c="$c" -v per="$per" 'BEGIN {
    printf "  %-9s pass: interp %7.1f   jit %7.1f   %.2fx; compile %.0f us (%.0f us per 1,000), break-even %.0f passes\n", m, i, j, i / j, c, per, c / (i - j) }'
done
echo
echo "Elsewhere, FREP_BACKEND=interp vs jit, alternating, median of 3 (ms):"
med3() { printf '%s\n' "$@" | sort -g | sed -n 2p; }
for what in "mesh BM_Bear/256/1/" "mesh BM_Bear/256/0/" "render3d bear.vm" "render3d tanglecube.vm"; do
  set -- $what
  ti=(); tj=()
  for rep in 1 2 3; do
    for b in interp jit; do
      if [ "$1" = mesh ]; then
        t=$(FREP_BACKEND=$b ./build/bench/bench_mesh --benchmark_filter="$2" 2>&1 | awk '$1 ~ /^BM_Bear/ {print $2}')
      else
        t=$(FREP_BACKEND=$b FREP_RENDER3D_MODEL=../shared/data/vm/$2 ./build/bench/bench_render3d \
            --benchmark_filter='BM_Render3D/1/' 2>&1 | awk '$1 ~ /^BM_Render3D/ {print $2}')
      fi
      if [ $b = interp ]; then ti+=("$t"); else tj+=("$t"); fi
    done
  done
  i=$(med3 "${ti[@]}"); j=$(med3 "${tj[@]}")
  label="$1 $2"; [ "$1" = mesh ] && label="mesh bear.vm 256 cells, $( [ "$2" = BM_Bear/256/1/ ] && echo 1 thread || echo all threads)"
  awk -v w="$label" -v i="$i" -v j="$j" 'BEGIN { printf "  %-36s interp %8.1f   jit %8.1f   jit speed-up %.2fx\n", w, i, j, i / j }'
done
