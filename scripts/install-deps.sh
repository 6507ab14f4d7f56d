#!/usr/bin/env bash
# Installs what frep needs to build on Debian 12 (run as root). Safe to run again.
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config
      libhwy-dev libcli11-dev libfmt-dev libstb-dev
      libgtest-dev libgmock-dev libbenchmark-dev
      lib3mf-dev    # 3MF output (-o part.3mf): the format slicers open directly
      libasmjit-dev  # the JIT backend (FREP_BACKEND=jit): tapes compiled to x86-64 code
      libpolyclipping-dev  # Clipper: frep slice's perimeters (exact polygon offsets) and infill clipping
      libcgal-dev libeigen3-dev  # CGAL (header-only; with GMP, MPFR) and Eigen: frep repair's exact cuts and hole filling
      tetgen        # frep convert --sign tets runs the separate tetgen program (AGPL: never linked)
      python3 python3-numpy  # scripts/make_example_mesh.py; tests check that numpy reads frep's .npy
      python3-dev python3-pybind11 pybind11-dev python3-pytest  # the Python package (python/) and its tests
      python3-distributed  # Dask: frep dataset's scheduling (its tests run a local cluster)
      glslang-tools        # tests validate the GLSL export with glslangValidator
      texlive-latex-base)  # pdflatex: tests compile the LaTeX export's documents (article, amsmath, geometry)
# Optional: libopenvdb-dev (the OpenVDB baselines of the sampling and meshing benchmarks).
# Optional, for the fuzz build (-DFREP_BUILD_FUZZ=ON, see fuzz/CMakeLists.txt): clang-14 libclang-rt-14-dev
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "frep: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update
  apt-get install -y --no-install-recommends "${missing[@]}"
fi
