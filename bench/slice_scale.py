#!/usr/bin/env python3
"""Write a mesh (STL, OBJ or OFF) as a binary STL scaled uniformly so that its largest bounding-box
side is SIZE mm, with its bounding-box centre at (CX, CY) (default the origin, where float32
keeps the most precision: moved to (110,110) in float32, thin triangles of thingi10k_73416 fold)
and its bottom at z = 0. Prints the triangle count and the volume (mm^3).

  /usr/bin/python3 bench/slice_scale.py IN OUT.stl [--size 40] [--center 0,0]
"""
import argparse
import os
import sys

sys.dont_write_bytecode = True  # no bench/__pycache__ in the work tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from slice_check import centred_translation, mesh_volume, read_mesh, write_stl  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--size", type=float, default=40.0)
    ap.add_argument("--center", default="0,0")
    a = ap.parse_args(argv)
    tris = read_mesh(a.mesh)
    flat = tris.reshape(-1, 3)
    side = float((flat.max(0) - flat.min(0)).max())
    tris = tris * (a.size / side)
    if mesh_volume(tris) < 0:  # inside out: flip every triangle
        tris = tris[:, ::-1]
    cx, cy = (float(v) for v in a.center.split(","))
    tris = tris + centred_translation(tris, cx, cy)
    write_stl(a.out, tris)
    print(len(tris), f"{mesh_volume(tris):.6g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
