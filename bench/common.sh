# Sourced by the bench/*.sh scripts: run from the project root, and the shared steps.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# require_input PATH: stop with a message naming the calling script if PATH is missing.
require_input() {
  if [ ! -f "$1" ]; then
    echo "bench/$(basename "$0"): $1 not found; nothing to measure" >&2
    exit 1
  fi
}

# build_targets TARGET...: a Release build with the benchmarks, quietly.
build_targets() {
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DFREP_BUILD_BENCH=ON >/dev/null
  cmake --build build --target "$@" >/dev/null
}
