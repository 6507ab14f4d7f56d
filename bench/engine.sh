#!/usr/bin/env bash
# Engine benchmark: Prospero at 1024x1024 (1 and 2 threads) against brute force measured in the
# same run, plus evaluator throughput. Needs ../shared/data/vm and a Release build in build/.
# What is timed: a warm re-render (the renderer object, its threads and scratch are reused; file
# loading and tape compilation excluded). Every configuration timed is first checked against the
# brute-force image pixel for pixel; a mismatch aborts the benchmark.
#   bash bench/engine.sh            # builds bench_eval if needed, prints the table and ratios
source "$(dirname "$0")/common.sh"
require_input ../shared/data/vm/prospero.vm
build_targets bench_eval
out=$(./build/bench/bench_eval --benchmark_min_time=2 --benchmark_repetitions=3 \
      --benchmark_report_aggregates_only=true 2>&1)
echo "$out"
median() { echo "$out" | awk -v n="$1" '$1 == n"_median" {print $2}'; }
t1=$(median "BM_ProsperoRender/1024/1/real_time")
t2=$(median "BM_ProsperoRender/1024/2/real_time")
bf=$(median "BM_ProsperoBruteForce/1024/real_time")
echo
echo "Prospero 1024x1024, median of 3 (ms per warm re-render; each configuration checked against brute force):"
awk -v t1="$t1" -v t2="$t2" -v bf="$bf" 'BEGIN {
  printf "  1 thread:  %.2f ms   (%.0fx faster than brute force)\n", t1, bf / t1;
  printf "  2 threads: %.2f ms   (%.0fx faster than brute force, %.2fx over 1 thread)\n", t2, bf / t2, t1 / t2;
  printf "  brute force (every pixel, SIMD, 1 thread): %.1f ms\n", bf;
}'
