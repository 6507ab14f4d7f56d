#!/usr/bin/env python3
"""Signed distances at points, per second: frep's Python package against Open3D's
RaycastingScene.compute_signed_distance and CGAL (bench_sdf_points_cgal), on the same points and
the same thread count, in one run. Accuracy is measured against an oracle computed here:
CGAL's double-precision closest point for the magnitude, and the generalized winding number
(numpy, solid angles summed over every triangle) for the sign wherever any two tools disagree
and on a random subset.

  /usr/bin/python3 bench/sdf_points.py [--threads 2] [--points 500000] [MESH...]

Needs the built package (PYTHONPATH=build/python), python3-open3d (optional, skipped if absent)
and build/bench/bench_sdf_points_cgal (optional). Prints a Markdown table.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.join(HERE, "..", "..", "shared", "data", "meshes")
DEFAULT = ["armadillo_libigl.obj", "fandisk.obj", "spot.obj", "thingi10k_73416.stl"]


def points_for(vertices, faces, n, rng):
    """Half uniform in the box grown by 5% of its diagonal, half near the surface (Gaussian,
    1% of the diagonal), as learning pipelines sample them."""
    lo, hi = vertices.min(0), vertices.max(0)
    diag = float(np.linalg.norm(hi - lo))
    lo, hi = lo - 0.05 * diag, hi + 0.05 * diag
    uniform = lo + rng.random((n // 2, 3)) * (hi - lo)
    tri = vertices[faces[rng.integers(0, len(faces), n - n // 2)]]
    a, b = rng.random((2, n - n // 2, 1))
    flip = (a + b) > 1
    a, b = np.where(flip, 1 - a, a), np.where(flip, 1 - b, b)
    near = tri[:, 0] + a * (tri[:, 1] - tri[:, 0]) + b * (tri[:, 2] - tri[:, 0])
    near += rng.normal(0, 0.01 * diag, near.shape)
    return np.concatenate([uniform, near]).astype(np.float32), diag


def winding_numbers(vertices, faces, points, chunk=64):
    """Generalized winding number (sum of signed solid angles / 4 pi), in double, brute force."""
    v = vertices[faces].astype(np.float64)  # T x 3 x 3
    out = np.empty(len(points))
    for s in range(0, len(points), chunk):
        p = points[s:s + chunk, None, None, :].astype(np.float64)  # P x 1 x 1 x 3
        r = v[None] - p  # P x T x 3 x 3
        n = np.linalg.norm(r, axis=3)
        a, b, c = r[:, :, 0], r[:, :, 1], r[:, :, 2]
        det = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
        la, lb, lc = n[:, :, 0], n[:, :, 1], n[:, :, 2]
        den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc + np.einsum("ptk,ptk->pt", b, c) * la
               + np.einsum("ptk,ptk->pt", c, a) * lb)
        out[s:s + chunk] = 2 * np.arctan2(det, den).sum(1) / (4 * np.pi)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("meshes", nargs="*")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--points", type=int, default=500000)
    ap.add_argument("--cgal", default=os.path.join(HERE, "..", "build", "bench", "bench_sdf_points_cgal"))
    args = ap.parse_args()
    import frep
    frep.set_threads(args.threads)
    try:
        import open3d as o3d
    except ImportError:
        o3d = None
        print("open3d not installed (python3-open3d): its column is skipped", file=sys.stderr)
    meshes = args.meshes or [os.path.join(SHARED, m) for m in DEFAULT]
    meshes = [m for m in meshes if os.path.exists(m)]
    if not meshes:
        print("no meshes (the shared data folder is absent): nothing to measure", file=sys.stderr)
        return 0
    rng = np.random.default_rng(2026)
    print(f"threads: {args.threads}, points per mesh: {args.points}\n")
    print("| mesh | triangles | frep pts/s | Open3D pts/s | CGAL pts/s | frep / Open3D | frep / CGAL "
          "| frep max err / diag | frep sign errors | Open3D sign errors | CGAL sign errors | Open3D disagree |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for path in meshes:
        field = frep.load(path)
        vertices, faces = frep.read_mesh(path)
        pts, diag = points_for(vertices, faces, args.points, rng)
        field.sdf(pts[:1000])  # the first call builds the distance structure: not timed
        t = time.perf_counter()
        d_frep = field.sdf(pts)
        frep_rate = len(pts) / (time.perf_counter() - t)

        d_o3d, o3d_rate = None, float("nan")
        if o3d is not None:
            scene = o3d.t.geometry.RaycastingScene(nthreads=args.threads)
            scene.add_triangles(o3d.core.Tensor(vertices.astype(np.float32)), o3d.core.Tensor(faces.astype(np.uint32)))
            q = o3d.core.Tensor(pts)
            scene.compute_signed_distance(q[:1000], nthreads=args.threads)  # builds the BVH: not timed
            t = time.perf_counter()
            d_o3d = scene.compute_signed_distance(q, nthreads=args.threads).numpy()
            o3d_rate = len(pts) / (time.perf_counter() - t)

        d_cgal, cgal_rate = None, float("nan")
        if os.path.exists(args.cgal):
            with tempfile.TemporaryDirectory() as tmp:
                np.save(os.path.join(tmp, "p.npy"), pts)
                r = subprocess.run([args.cgal, path, os.path.join(tmp, "p.npy"), os.path.join(tmp, "d.npy"), str(args.threads)],
                                   capture_output=True, text=True)
                if r.returncode == 0:
                    cgal_rate = json.loads(r.stdout)["points_per_s"]
                    d_cgal = np.load(os.path.join(tmp, "d.npy"))

        # The oracle: CGAL's magnitude (double precision), the winding number's sign where the
        # tools disagree and on a random sample.
        signs = [np.signbit(d) for d in (d_frep, d_o3d, d_cgal) if d is not None]
        disputed = np.flatnonzero(np.any([s != signs[0] for s in signs[1:]], axis=0)) if len(signs) > 1 else np.array([], int)
        disputed = disputed[rng.permutation(len(disputed))[:4000]]  # the oracle is brute force: a sample of them
        sample = np.union1d(disputed, rng.choice(len(pts), 1000, replace=False))
        inside = winding_numbers(vertices, faces, pts[sample]) > 0.5
        sign_errors = lambda d: None if d is None else int(np.sum((d[sample] < 0) != inside))
        disagree = "" if d_o3d is None else f"{np.mean(np.signbit(d_o3d) != np.signbit(d_frep)):.2%}"
        err = float(np.max(np.abs(np.abs(d_frep) - np.abs(d_cgal))) / diag) if d_cgal is not None else float("nan")
        name = os.path.basename(path)
        print(f"| {name} | {len(faces)} | {frep_rate:,.0f} | {o3d_rate:,.0f} | {cgal_rate:,.0f} | {frep_rate / o3d_rate:.2f} "
              f"| {frep_rate / cgal_rate:.2f} | {err:.2g} | {sign_errors(d_frep)} | {sign_errors(d_o3d)} | {sign_errors(d_cgal)} "
              f"| {disagree} |",
              flush=True)
    print("\nsign errors: among the points checked by the winding number (up to 4000 where the tools disagree, plus 1000 "
          "random ones); disagree: points whose sign differs from frep's, of all; max err: |frep| against CGAL's "
          "double-precision distance, over the diagonal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
