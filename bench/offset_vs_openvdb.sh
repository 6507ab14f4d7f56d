#!/usr/bin/env bash
# frep offset and frep shell of meshes against the OpenVDB pipeline at the same voxel size
# (bench/bench_offset_vdb.cpp: meshToSignedDistanceField in a band just wide enough, then
# volumeToMesh), side by side in one run: wall time and peak memory of each whole process (both
# read the mesh with frep's reader), and the mean distance of the output's vertices from the exact
# surface they stand for (the input's exact signed distance).
#   bash bench/offset_vs_openvdb.sh                     # every mesh below, -r 128 and 256
#   bash bench/offset_vs_openvdb.sh MESH...             # other meshes
#   RES="256" JOBS="offset" bash bench/offset_vs_openvdb.sh
# The offset and the wall are 2% of the mesh's bounding-box diagonal. Needs libopenvdb-dev and
# ../shared/data/meshes (or meshes given on the command line).
source "$(dirname "$0")/common.sh"
build_targets frep bench_offset_vdb
meshes_or_defaults "$@"
resolutions=${RES:-"128 256"}
jobs=${JOBS:-"offset shell"}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-26s %-6s %4s | %8s %8s %9s | %8s %8s %9s | %6s %6s %6s\n' mesh job res "frep s" "frep MB" "frep err" \
  "vdb s" "vdb MB" "vdb err" "time" "memory" "error"
for m in "${meshes[@]}"; do
  # 2% of the bounding box's diagonal, from frep info's bounds line.
  amount=$(./build/frep info "$m" 2>/dev/null | awk '/^bounds:/ {
      gsub(/,/, ""); dx = $5 - $2; dy = $6 - $3; dz = $7 - $4; printf "%.6g", 0.02 * sqrt(dx*dx + dy*dy + dz*dz) }')
  for job in $jobs; do
    for r in $resolutions; do
      f="$tmp/frep.stl" v="$tmp/vdb.stl"
      ft=$( { /usr/bin/time -f "%e %M" ./build/frep "$job" "$m" "$amount" -r "$r" -o "$f" -q; } 2>&1 | tail -1)
      vt=$( { /usr/bin/time -f "%e %M" ./build/bench/bench_offset_vdb "$job" "$m" "$amount" "$r" "$v" >/dev/null; } 2>&1 | tail -1)
      fe=$(./build/bench/bench_offset_vdb error "$m" "$job" "$amount" "$f" "$r" | sed -E 's/.*mean ([^,]+),.*/\1/')
      ve=$(./build/bench/bench_offset_vdb error "$m" "$job" "$amount" "$v" "$r" | sed -E 's/.*mean ([^,]+),.*/\1/')
      read -r fs fk <<<"$ft"
      read -r vs vk <<<"$vt"
      awk -v m="$(basename "$m")" -v j="$job" -v r="$r" -v fs="$fs" -v fk="$fk" -v fe="$fe" -v vs="$vs" -v vk="$vk" -v ve="$ve" \
        'BEGIN { printf "%-26s %-6s %4d | %8.2f %8.0f %9.3g | %8.2f %8.0f %9.3g | %6.2f %6.2f %6.2f\n",
                 m, j, r, fs, fk / 1024, fe, vs, vk / 1024, ve, fs / vs, fk / vk, fe / ve }'
    done
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "time, memory, error: frep / OpenVDB (below 1: frep is faster, smaller, more accurate)"
