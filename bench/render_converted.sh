#!/usr/bin/env bash
# 3D renders of a converted mesh (default: the armadillo, 86,482 triangles, 6.6M nodes) at
# 1024x1024, front and iso, 2 threads, warm re-renders (the renderer reused; loading excluded).
# Brute force is left out: on millions of nodes it would take hours (bench/render3d.sh measures
# it on bear.vm). Compare builds by running this script on each, one after the other.
#   bash bench/render_converted.sh                     # ../shared/data/meshes/armadillo_libigl.obj
#   FREP_MESH=path.obj FREP_RENDER3D_SIZE=512 bash bench/render_converted.sh
source "$(dirname "$0")/common.sh"
mesh=${FREP_MESH:-../shared/data/meshes/armadillo_libigl.obj}
require_input "$mesh"
build_targets frep bench_render3d
mkdir -p build/bench_data
field="build/bench_data/$(basename "${mesh%.*}").frep"
./build/frep convert "$mesh" -o "$field" >/dev/null 2>build/bench_data/convert.log || { cat build/bench_data/convert.log >&2; exit 1; }
echo "$(basename "$mesh") converted to $field; ${FREP_RENDER3D_SIZE:-1024}x${FREP_RENDER3D_SIZE:-1024} over [-1,1]^3, 2 threads:"
for view in front iso; do
  out=$(FREP_RENDER3D_MODEL="$field" FREP_RENDER3D_VIEW=$view ./build/bench/bench_render3d \
        --benchmark_filter='BM_Render3D/2/' --benchmark_min_time=1 2>&1)
  echo "$out" | awk -v v="$view" '$1 ~ /^BM_Render3D\/2\// {printf "  %-5s %8.0f ms   (CPU %.0f ms)\n", v, $2, $4}'
done
echo "  (load average when measured: $(cut -d' ' -f1-3 /proc/loadavg))"
