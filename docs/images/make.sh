#!/usr/bin/env bash
# Renders every picture in docs/ (docs/rendering.md, docs/ugf.md, README.md) with `frep render`,
# from the shared models (../shared/data) and the fields of examples/ugf_example and
# examples/ugf_pictures. Needs a Release build in build/ (it builds what it uses).
#   bash docs/images/make.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
data=../shared/data
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target frep ugf_example ugf_pictures >/dev/null
frep() { ./build/frep "$@" -q; }
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The demo mesh (examples/bracket.obj), converted on the way in: a 3D view and its distance slice.
frep render examples/bracket.obj --3d --up z --view iso --ao --size 320 -o $out/bracket_3d.png
frep render examples/bracket.obj --slice z=0 --size 320 -o $out/bracket_slice.png
# A big converted mesh (86,482 triangles, 6.6M nodes), framed by its own bounding box.
frep render $data/meshes/armadillo_libigl.obj --3d --view iso --ao --size 320 -o $out/armadillo_iso.png
# Fidget's bear head, seen from (-1, 1, 1) so that the face shows, framed by its bounds.
bear="$data/vm/bear.vm --3d --view iso --rotate -90,0 --bounds -0.7,-0.65,-0.7,1,0.85,0.65"
frep render $bear --size 300 --ao -o $out/bear_shaded.png
frep render $bear --size 220 --mode normals -o $out/bear_normals.png
frep render $bear --size 160 --mode depth -o $out/bear_depth.png
# Its field on z = 0: not a distance (contours crowd about five times).
frep render $data/vm/bear.vm --slice z=0 --size 180 -o $out/bear_slice.png
# Fidget's Menger sponge (Rhai), sphere-ified.
frep render $data/rhai/sponge.rhai --3d --view iso --rotate -10,-10 --bounds -0.96,-0.96,-0.96,0.96,0.96,0.96 \
  --size 200 --ao -o $out/sponge.png
# Prospero's first line, as a distance slice.
frep render $data/vm/prospero.vm --slice z=0 --bounds -0.92,0.58,-1,0.12,0.95,1 --size 300 -o $out/prospero_slice.png
# The UGF example part (z up): rounded block with a chamfered top, and its shell and gyroid
# infill cut open at z = 0.2.
./build/examples/ugf_example "$tmp" >/dev/null
frep render "$tmp/ugf_part.vm" --3d --up z --size 240 --ao -o $out/ugf_part.png
frep render "$tmp/ugf_infill.vm" --3d --up z --bounds -0.85,-0.65,-0.45,0.85,0.65,0.2 --size 220 --ao \
  -o $out/ugf_infill.png
# docs/ugf.md: one slice z = 0 per field of examples/ugf_pictures.
./build/examples/ugf_pictures "$tmp" >/dev/null
for f in offset shell shell_biased shell_variable intersect blend_quadratic blend_cubic blend_exponential \
         blend_root frame_sn frame_dn chamfer_inset chamfer_setback chamfer_width chamfer_setbacks chamfer_exact \
         round_intersection_45 round_union_45 round_intersection_135 round_union_135 pencils two_body_xi \
         two_body_between two_body_clearance gyroid_network gyroid_sheet medial_m; do
  frep render "$tmp/ugf_$f.vm" --slice z=0 --size 150 -o "$out/ugf/$f.png"
done
du -ch $out/*.png $out/ugf/*.png | tail -1

# Slicing (docs/slicing.md): one layer of the demo bracket scaled to 72 mm, as SVG, and a layer of
# the gyroid-filled cube of examples/ as PNG.
frep slice examples/bracket.obj --scale 40 -o $out/slice_bracket.svg --svg-layers 10 --preview-layer 10
frep slice examples/gyroid_cube.rhai --infill 0 -o /dev/null --preview $out/slice_gyroid_cube.png --preview-layer 60 --preview-size 480
