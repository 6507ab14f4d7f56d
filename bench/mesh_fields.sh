#!/usr/bin/env bash
# Everyday jobs on meshes, timed as a user runs them (whole processes: reading, checking and
# indexing the mesh included), with peak memory:
#   frep render MESH --3d --size 1024      a ray per pixel through the mesh
#   frep mesh MESH -r 256                  remeshing by dual contouring
#   frep clearance MESH COPY               the exact gap to a copy moved by 1.3 widths along x
#   frep sample PART.frep --near-surface   10,000 points from the .frep frep convert wrote
#   frep sample MESH --grid 256 --truncate (3 voxels)
# With OTHER=path/to/another/frep, the same commands run with that build too, alternating, and
# the ratio is printed (for example a build of an earlier commit: the ratio is the speed-up).
#   bash bench/mesh_fields.sh [MESH...]
source "$(dirname "$0")/common.sh"
build_targets frep
meshes_or_defaults "$@"
other=${OTHER:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
# time_of BINARY ARGS...: "seconds megabytes" of one run.
time_of() {
  local bin=$1
  shift
  /usr/bin/time -o "$tmp/time" -f "%e %M" "$bin" "$@" >/dev/null 2>"$tmp/err" || { cat "$tmp/err" >&2; }
  tail -1 "$tmp/time"
}
printf '%-26s %-10s | %8s %8s' mesh job "s" "MB"
[ -n "$other" ] && printf ' | %8s %8s %7s' "other s" "other MB" "ratio"
echo
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  # A copy 1.3 widths along x (a script moving the mesh), and the converted .frep.
  w=$(./build/frep info "$m" 2>/dev/null | awk '/^bounds:/ { gsub(/,/, ""); print 1.3 * ($5 - $2) }')
  printf 'let p = mesh("%s");\nmove(p, [%s, 0.0, 0.0])\n' "$(realpath "$m")" "$w" > "$tmp/copy.rhai"
  ./build/frep convert "$m" -q -o "$tmp/part.frep"
  voxel=$(./build/frep info "$m" 2>/dev/null | awk '/^bounds:/ { gsub(/,/, ""); dx = $5 - $2; dy = $6 - $3; dz = $7 - $4;
      m = dx > dy ? dx : dy; m = m > dz ? m : dz; printf "%.6g", 3 * 1.1 * m / 255 }')
  jobs=("render|render $m --3d --size 1024 -q -o $tmp/r.png"
        "mesh|mesh $m -r 256 -q -o $tmp/m.stl"
        "clearance|clearance $m $tmp/copy.rhai -q"
        "near-surf|sample $tmp/part.frep --near-surface 10000 --sigma 0.01 -q -o $tmp/s.npy"
        "truncated|sample $m --grid 256 --truncate $voxel -q -o $tmp/t.npy")
  for j in "${jobs[@]}"; do
    label=${j%%|*}
    read -r -a args <<<"${j#*|}"
    read -r s kb <<<"$(time_of ./build/frep "${args[@]}")"
    printf '%-26s %-10s | %8.2f %8.0f' "$name" "$label" "$s" "$((kb / 1024))"
    if [ -n "$other" ]; then
      read -r os okb <<<"$(time_of "$other" "${args[@]}")"
      awk -v s="$s" -v os="$os" -v okb="$okb" 'BEGIN { printf " | %8.2f %8.0f %7.2f", os, okb / 1024, os / s }'
    fi
    echo
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
