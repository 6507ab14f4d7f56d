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

# stl_probe_points STL OUT: the points where an output mesh's error is measured, one "x y z" per
# line in OUT: its distinct vertices and 4 random points of each triangle (seeded: the same
# points every run). Needs /usr/bin/python3 with numpy.
stl_probe_points() {
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import sys, numpy as np
d = open(sys.argv[1], 'rb').read()
n = int.from_bytes(d[80:84], 'little')
rec = np.frombuffer(d[84:84 + 50 * n], dtype=np.dtype([('n', '<f4', 3), ('v', '<f4', (3, 3)), ('a', '<u2')]))
v = rec['v'].astype(np.float64)
rng = np.random.default_rng(1)
a, b = rng.random((2, n, 4, 1))
flip = a + b > 1
a, b = np.where(flip, 1 - a, a), np.where(flip, 1 - b, b)
inner = v[:, None, 0] + a * (v[:, None, 1] - v[:, None, 0]) + b * (v[:, None, 2] - v[:, None, 0])
pts = np.concatenate([np.unique(v.reshape(-1, 3), axis=0), inner.reshape(-1, 3)])
np.savetxt(sys.argv[2], pts, fmt='%.9g')
EOF
}
