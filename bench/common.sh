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

# meshes_or_defaults [MESH...]: sets `meshes` to the arguments, or to the real-world meshes the
# mesh benchmarks share (CAD parts and scans of 13k to 120k triangles), each checked to exist.
meshes_or_defaults() {
  local data=../shared/data/meshes
  if [ $# -gt 0 ]; then
    meshes=("$@")
  else
    meshes=("$data/fandisk.obj" "$data/menger_sponge_l3.obj" "$data/thingi10k_73416.stl" "$data/armadillo_libigl.obj"
            "$data/scallop_manifold.obj")
  fi
  local m
  for m in "${meshes[@]}"; do require_input "$m"; done
}
