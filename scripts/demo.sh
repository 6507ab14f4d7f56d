#!/usr/bin/env bash
# Installs what is missing, builds the frep tool, and runs the main job on the shipped mesh
# examples/bracket.obj: check it, convert it to its exact signed-distance expression, draw a
# distance slice and a 3D view of that expression, and mesh it back. Pictures and files go to
# build/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target frep
out=build/demo
mkdir -p "$out"
start=$(date +%s%N)
echo
echo "== frep check examples/bracket.obj"
./build/frep check examples/bracket.obj
echo
echo "== frep convert examples/bracket.obj -o $out/bracket.frep"
./build/frep convert examples/bracket.obj -o "$out/bracket.frep"
./build/frep convert examples/bracket.obj -o "$out/bracket.vm" --quiet
echo
echo "== frep eval: the expression at the hole's centre, inside the plate, and 1 above it"
printf '%s\n' "-0.35 0 0" "0.6 0 0" "0.6 0 1.12" > "$out/points.txt"
./build/frep eval "$out/bracket.frep" --points "$out/points.txt"
echo "   (exact: the hole is a 48-sided polygon of radius 0.3, so its centre is 0.3 cos(pi/48) ="
echo "    0.29936 from its flat walls; the plate is 0.24 thick, so -0.12 at its mid-plane; the"
echo "    point above is 1 from the top face)"
echo
echo "== frep render: a distance slice through the plate's mid-plane and a 3D view"
./build/frep render "$out/bracket.frep" --slice z=0 --size 640 -o "$out/bracket_slice.png"
./build/frep render "$out/bracket.frep" --3d --up z --view iso --ao --size 640 -o "$out/bracket_3d.png"
echo
echo "== frep mesh: the expression back to a mesh, with its sharp edges"
./build/frep mesh "$out/bracket.frep" -o "$out/bracket_remeshed.stl" --resolution 128
./build/frep check "$out/bracket_remeshed.stl" | tail -n 1
ms=$((($(date +%s%N) - start) / 1000000))
echo
echo "frep demo: done in $((ms / 1000)).$(printf '%03d' $((ms % 1000))) s after the build; files in $(pwd)/$out/"
ls -l "$out"
