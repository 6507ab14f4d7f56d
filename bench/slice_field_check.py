#!/usr/bin/env python3
"""An independent check of a G-code file's outer walls against the exact field it was sliced from.

  PYTHONPATH=build/python /usr/bin/python3 bench/slice_field_check.py EXPR OUT.gcode
      [--line-width 0.45] [--layer-height 0.2] [--shift SX,SY,SZ] [--fit-xy] [--max-points N] [--json]

The model is a frep expression (.rhai, .vm, .frep; anything frep.load reads), evaluated through the
frep Python package (build/python, or $FREP_PYTHON, or whatever `import frep` finds); nothing of the
slicer is used but the G-code. bench/slice_check.py does the same against a mesh; this reads the
G-code with its parse_gcode / outer_points / layer_table and reports the same statistics.

  placement   printer (x, y, z) = model (x, y, z) + shift: --shift SX,SY,SZ, or by default the
              `; part: ... shift SX SY SZ` header line frep slice writes. --fit-xy also fits a
              residual XY translation (Gauss-Newton, L1-reweighted, on |d - w/2| over up to 100
              outer-wall points a layer) and reports the statistics over those points before and
              after it (--fit-full: after it over every point, which doubles the time).
  layers      the distinct z of extrusion moves; each layer is checked at its mid-height, print z
              minus half the layer's height (the first layer's height is its z), minus SZ.
  distance    for every outer-wall vertex p (model coordinates), the in-plane distance d from p to
              the zero set of f(., ., z_slice), by sign changes only (f need not be a distance; a
              sample is "across" when its sign is opposite to f(p)'s: f >= 0 for p inside):
              1. local search: p projected on the zero set along the gradient (Newton), a crossing
                 c along that direction (bisection), the samples across on the circle of radius c
                 within 30 degrees (every 0.5 degree) as a window; then the band [0.97 c, c] x the
                 window is refined by a polar grid (5 radii x 20 angles) to its lowest row across,
                 again and again (the window follows the samples across, widened by their drift
                 from one row to the next, so oblique edges and corners are followed), to 1e-6 mm.
              2. check: a circle of --angles (720) samples at (1 - 1e-3) d and one of 180 at d / 2
                 must have nothing across; else (about 4% of the gyroid cube's points: the gradient
                 points at the wrong side, or a nearer part of the zero set lies elsewhere)
              3. circles: a ladder of full circles of radii 0.0005 * 2^k mm (to 16 mm) brackets the
                 smallest radius with a sample across, bisection on r narrows it to 4%, and each
                 run of samples across on the outer circle (one spacing added either side) is a
                 window refined as in 1; d is the smallest.
              d is an upper bound (a sample across lies at that radius); it is exact to about 1e-6
              mm where the sampling resolves the zero set (a box's walls and corners: 0.225 to
              1e-6; a meshed cylinder at 0.02 mm: within 8e-6 of slice_check.py point by point;
              150 random points of the gyroid cube: never more than 1e-6 above a brute-force
              scan of 3600 rays x 0.5 um steps, up to 2e-4 below it at grazing corners).
  reported    count, mean / median / p95 / max of |d - w/2| (w/2 the outer wall's target), the
              fraction with |d - w/2| <= 1% of w, the points outside the section (f(p) > 0), the
              worst point (layer, printer x y z, d), and per-layer worst errors in --json.
              --max-points N checks a seeded random sample of N points instead of all (the maximum
              is then the sample's).
"""
import argparse
import json
import math
import os
import re
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import slice_check as sc  # noqa: E402


def load_field(path):
    """The frep field of an expression file, through the frep Python package."""
    here = os.path.dirname(os.path.abspath(__file__))
    for p in (os.environ.get("FREP_PYTHON"), os.path.join(here, "..", "build", "python")):
        if p and os.path.isdir(p) and p not in sys.path:
            sys.path.insert(0, p)
            break
    import frep
    return frep.load(path)


def header_shift(gcode_path):
    """SX, SY, SZ of frep's `; part: ... shift SX SY SZ` header line, or None."""
    with open(gcode_path, "r", errors="replace") as fh:
        for i, line in enumerate(fh):
            if i > 200:
                break
            m = re.match(r"^;\s*part:.*\bshift\s+(\S+)\s+(\S+)\s+(\S+)", line)
            if m:
                return np.array([float(v) for v in m.groups()])
    return None


class Field2D:
    """f and its gradient at (x, y, z) points, float64 in and out, counting evaluations."""

    def __init__(self, field, threads=None):
        self.field, self.threads, self.evals = field, threads, 0

    def __call__(self, xy, z):
        pts = np.empty((len(xy), 3), dtype=np.float32)
        pts[:, :2], pts[:, 2] = xy, z
        self.evals += len(pts)
        return np.asarray(self.field.sdf(pts, threads=self.threads), dtype=np.float64)

    def gradient(self, xy, z):
        pts = np.empty((len(xy), 3), dtype=np.float32)
        pts[:, :2], pts[:, 2] = xy, z
        self.evals += len(pts)
        return np.asarray(self.field.gradient(pts, threads=self.threads), dtype=np.float64)


def _hit(F, Q, z, inside):
    """Whether f at Q (n x 2) has the sign opposite to the points': f >= 0 for a point inside."""
    v = F(Q, z)
    return np.where(inside, v >= 0, v <= 0)


def _circle(F, P, z, inside, r, cs):
    """Hit mask (n x A) of the circles of radii r (n) around P (n x 2) at the angles' (cos, sin) cs."""
    n, A = len(P), len(cs)
    Q = P[:, None, :] + r[:, None, None] * cs[None, :, :]
    v = F(Q.reshape(-1, 2), np.repeat(z, A)).reshape(n, A)
    return np.where(inside[:, None], v >= 0, v <= 0)


def _cross(F, P, U, z, inside, rl, rh, tol):
    """Bisection along the rays P + t U between rl (p's side) and rh (across) to width tol: rh."""
    if len(P) == 0:
        return rh
    rl, rh = rl.copy(), rh.copy()
    width = float(np.max(rh - rl))
    for _ in range(max(1, int(math.ceil(math.log2(max(width, tol) / tol))))):
        mid = (rl + rh) / 2
        h = _hit(F, P + mid[:, None] * U, z, inside)
        rh, rl = np.where(h, mid, rh), np.where(h, rl, mid)
    return rh


def _unit(a):
    return np.stack([np.cos(a), np.sin(a)], 1)


def _arc(F, P, z, inside, lo, hi, a1, a2, tol, K=20, rows=4):
    """Refine the nearest crossing of each item (point P, height z) within the radial band
    [lo, hi] and the angular window [a1, a2]: a polar grid of rows + 1 radii (lo to hi) by K
    angles; the lowest row with a sample across becomes the new hi and the row under it the new
    lo, the window shrinks to that row's samples across, widened by two spacings and by how far
    they moved from the row above (an oblique edge or corner of the zero set moves the arc across
    as r falls). A sample across at lo lowers the band. Returns hi (a radius at which a sample is
    across: d <= hi) and the angle of the middle sample across there."""
    lo, hi, a1, a2 = lo.copy(), hi.copy(), a1.copy(), a2.copy()
    m = len(P)
    ang = (a1 + a2) / 2
    out = np.full(m, np.inf)
    jr = np.arange(rows + 1) / rows
    ja = (np.arange(K) + 0.5) / K
    live = np.arange(m)
    for _ in range(80):
        if len(live) == 0:
            break
        n = len(live)
        R = lo[live, None] + jr[None, :] * (hi - lo)[live, None]               # n x rows+1
        T = a1[live, None] + ja[None, :] * (a2 - a1)[live, None]               # n x K
        C = np.stack([np.cos(T), np.sin(T)], 2)                                 # n x K x 2
        Q = P[live, None, None, :] + R[:, :, None, None] * C[:, None, :, :]   # n x rows+1 x K x 2
        v = F(Q.reshape(-1, 2), np.repeat(z[live], (rows + 1) * K)).reshape(n, rows + 1, K)
        H = np.where(inside[live, None, None], v >= 0, v <= 0)
        rowhit = H.any(2)
        anyh = rowhit.any(1)
        k = np.argmax(rowhit, 1)
        r = np.arange(n)
        # nothing across anywhere in the grid: keep the last hi (known to be across)
        none = live[~anyh]
        out[none] = np.where(np.isfinite(out[none]), out[none], hi[none])
        # across already at lo: lower the band, keep the window
        low = anyh & (k == 0)
        w = live[low]
        span = hi[w] - lo[w]
        hi[w], lo[w] = lo[w], np.maximum(0.0, lo[w] - 2 * span)
        # otherwise narrow the band to the rows k-1, k and the window to row k's samples across
        go = np.flatnonzero(anyh & (k > 0))
        w = live[go]
        if len(w):
            kk = k[go]
            Hk = H[go, kk]
            Tg = T[go]
            first, last = np.argmax(Hk, 1), K - 1 - np.argmax(Hk[:, ::-1], 1)
            rg = np.arange(len(go))
            cen = (Tg[rg, first] + Tg[rg, last]) / 2
            up = np.minimum(kk + 1, rows)
            Hu = H[go, up]
            has_up = Hu.any(1) & (kk < rows)
            fu, lu = np.argmax(Hu, 1), K - 1 - np.argmax(Hu[:, ::-1], 1)
            drift = np.where(has_up, np.abs(cen - (Tg[rg, fu] + Tg[rg, lu]) / 2), 0.0)
            s = (a2[w] - a1[w]) / K
            pad = 2 * s + 1.5 * drift
            hi[w], lo[w] = R[go, kk], R[go, kk - 1]
            ang[w], out[w] = cen, R[go, kk]
            a1[w], a2[w] = Tg[rg, first] - pad, Tg[rg, last] + pad
            wide = a2[w] - a1[w] > 2 * math.pi
            a1[w[wide]], a2[w[wide]] = cen[wide] - math.pi, cen[wide] + math.pi
        live = live[anyh & (hi[live] - lo[live] > tol)]
    return out, ang


def _local(F, p, z, f0, g, inside, tol):
    """The nearest crossing by a local search: project p onto the zero set along the gradient
    (4 Newton steps); cross along that direction (bisection) to a radius c; the samples across
    on the circle of radius c within 30 degrees of that direction (every 0.5 degree) give the
    window for _arc, from c down to 0.97 c. Returns the distance (inf where the search failed) and
    the angle."""
    m = len(p)
    best, ang = np.full(m, np.inf), np.zeros(m)
    q, fq, gq = p.copy(), f0.copy(), g.copy()
    for it in range(4):
        gl2 = (gq ** 2).sum(1)
        ok = np.isfinite(gl2) & (gl2 > 1e-20) & np.isfinite(fq)
        q = q - np.where(ok, fq / np.where(ok, gl2, 1.0), 0.0)[:, None] * np.where(ok[:, None], gq, 0.0)
        if it < 3:
            fq, gq = F(q, z), F.gradient(q, z)[:, :2]
    r0 = np.hypot(q[:, 0] - p[:, 0], q[:, 1] - p[:, 1])
    good = np.flatnonzero(np.isfinite(r0) & (r0 > 1e-7) & (r0 < 16.0))
    if len(good) == 0:
        return best, ang
    th = np.arctan2(q[good, 1] - p[good, 1], q[good, 0] - p[good, 0])
    U = _unit(th)
    ts = np.array([0.5, 0.9, 1.02, 1.2, 1.6, 2.5])
    H = np.stack([_hit(F, p[good] + (t * r0[good])[:, None] * U, z[good], inside[good]) for t in ts], 1)
    s = np.flatnonzero(H.any(1))
    good, th, H = good[s], th[s], H[s]
    kh = np.argmax(H, 1)
    rh = ts[kh] * r0[good]
    rl = np.where(kh > 0, ts[np.maximum(kh - 1, 0)], 0.0) * r0[good]
    c = _cross(F, p[good], U[s], z[good], inside[good], rl, rh, tol)
    # the window: the samples across on the circle of radius c, 0.5 degree apart within 30 degrees
    step = math.radians(0.5)
    k = np.arange(-60, 61)
    ta = th[:, None] + k[None, :] * step
    Q = p[good, None, :] + c[:, None, None] * np.stack([np.cos(ta), np.sin(ta)], 2)
    v = F(Q.reshape(-1, 2), np.repeat(z[good], len(k))).reshape(len(good), len(k))
    Hc = np.where(inside[good, None], v >= 0, v <= 0)
    Hc[:, 60] = True  # the ray's own crossing (rh is across)
    first, last = np.argmax(Hc, 1), len(k) - 1 - np.argmax(Hc[:, ::-1], 1)
    a1, a2 = th + (k[first] - 1) * step, th + (k[last] + 1) * step
    b, a = _arc(F, p[good], z[good], inside[good], 0.97 * c, c, a1, a2, tol)
    best[good], ang[good] = b, a
    return best, ang


def _circles(F, p, z, inside, cs, th, tol):
    """The nearest crossing by circles, for the points the local search leaves in doubt: a ladder
    of radii 0.0005 * 2^k mm (to 16 mm) brackets the smallest radius at which some sample is
    across, bisection on r narrows it to 4%, and each run of samples across on the outer circle
    (one spacing added either side) is a window for _arc. Distance (inf: nothing within 16 mm) and
    angle."""
    m = len(p)
    lo, hi = np.zeros(m), np.full(m, np.nan)
    todo, prev = np.arange(m), np.zeros(m)
    for r in 0.0005 * 2.0 ** np.arange(16):
        if len(todo) == 0:
            break
        h = _circle(F, p[todo], z[todo], inside[todo], np.full(len(todo), r), cs).any(1)
        lo[todo[h]], hi[todo[h]] = prev[h], r
        todo, prev = todo[~h], np.full((~h).sum(), r)
    wide = np.flatnonzero(np.isfinite(hi) & (hi > 1.04 * lo) & (hi - lo > tol))
    for _ in range(40):
        if len(wide) == 0:
            break
        mid = np.where(lo[wide] > 0, np.sqrt(lo[wide] * hi[wide]), hi[wide] / 2)
        h = _circle(F, p[wide], z[wide], inside[wide], mid, cs).any(1)
        hi[wide[h]], lo[wide[~h]] = mid[h], mid[~h]
        wide = wide[(hi[wide] > 1.04 * lo[wide]) & (hi[wide] - lo[wide] > tol)]
    best, ang = np.full(m, np.inf), np.zeros(m)
    br = np.flatnonzero(np.isfinite(hi))
    if len(br) == 0:
        return best, ang
    H = _circle(F, p[br], z[br], inside[br], hi[br], cs)
    A, s = len(cs), 2 * math.pi / len(cs)
    item, a1, a2 = [], [], []
    for i in range(len(br)):
        h = H[i]
        if h.all():
            item.append(i); a1.append(0.0); a2.append(2 * math.pi)
            continue
        starts = np.flatnonzero(h & ~np.roll(h, 1))
        ends = np.flatnonzero(h & ~np.roll(h, -1))
        if ends[0] < starts[0]:
            ends = np.r_[ends[1:], ends[0] + A]
        for a, b in zip(starts, ends):
            item.append(i); a1.append(th[a] - s); a2.append(th[b % A] + (b // A) * 2 * math.pi + s)
    item = np.array(item)
    d, a = _arc(F, p[br][item], z[br][item], inside[br][item], lo[br][item], hi[br][item], np.array(a1),
                np.array(a2), tol)
    b = np.full(len(br), np.inf)
    np.minimum.at(b, item, d)
    win = np.flatnonzero(d <= b[item])
    best[br] = b
    ang[br[item[win]]] = a[win]
    return best, ang


def measure(F, P, z, angles=720, chunk=4000, tol=1e-6, stats=None):
    """In-plane distance from each P (n x 2, model coordinates) at height z (n) to the zero set of
    f(., ., z), the unit direction (n x 2) from P to the nearest crossing found, and f(P).
    d = inf where no sign change lies within 16 mm; d = 0 where f(P) = 0.
    The local search (_local) answers where a circle of `angles` samples at (1 - 1e-3) d, and one
    of angles / 4 samples at d / 2, have no sample across; the others go to _circles."""
    n = len(P)
    D, U, F0 = np.full(n, np.inf), np.full((n, 2), np.nan), np.zeros(n)
    th = (np.arange(angles) + 0.5) * (2 * math.pi / angles)
    cs = _unit(th)
    guard = _unit((np.arange(max(8, angles // 4)) + 0.5) * (2 * math.pi / max(8, angles // 4)))
    for s in range(0, n, chunk):
        p, zz = P[s:s + chunk], z[s:s + chunk]
        m = len(p)
        f0 = F(p, zz)
        F0[s:s + m] = f0
        g = F.gradient(p, zz)[:, :2]
        inside = f0 < 0
        todo = np.flatnonzero(f0 != 0)
        best, ang = np.full(m, np.inf), np.zeros(m)
        b, a = _local(F, p[todo], zz[todo], f0[todo], g[todo], inside[todo], tol)
        best[todo], ang[todo] = b, a
        ok = np.isfinite(b)
        c = np.flatnonzero(ok)
        ok[c] = ~_circle(F, p[todo[c]], zz[todo[c]], inside[todo[c]], (1 - 1e-3) * b[c], cs).any(1)
        c = np.flatnonzero(ok)
        ok[c] = ~_circle(F, p[todo[c]], zz[todo[c]], inside[todo[c]], 0.5 * b[c], guard).any(1)
        rest = todo[~ok]
        if stats is not None:
            stats["local"] = stats.get("local", 0) + int(ok.sum())
            stats["circles"] = stats.get("circles", 0) + len(rest)
        if len(rest):
            best[rest], ang[rest] = _circles(F, p[rest], zz[rest], inside[rest], cs, th, tol)
        best[f0 == 0] = 0.0
        u = _unit(ang)
        u[~np.isfinite(best) | (best == 0)] = np.nan
        D[s:s + m], U[s:s + m] = best, u
    return D, U, F0


def _stats(D, F0, where, target, line_width):
    """|d - w/2| statistics (slice_check.py's keys), the worst point, and per-layer worst errors."""
    lost = ~np.isfinite(D)
    ok = ~lost
    err = np.abs(D[ok] - target)
    some = len(err) > 0
    res = {
        "outer_points": int(ok.sum()),
        "err_mean": float(err.mean()) if some else None,
        "err_median": float(np.median(err)) if some else None,
        "err_p95": float(np.percentile(err, 95)) if some else None,
        "err_max": float(err.max()) if some else None,
        "within_1pct": float((err <= 0.01 * line_width + 1e-12).mean()) if some else None,
        "outside_points": int((F0 > 0).sum()), "points_without_section": int(lost.sum()),
        "worst_layer_z": None, "worst_point": None,
    }
    if some:
        i = np.flatnonzero(ok)[int(np.argmax(err))]
        layer, x, y, zp = where[i]
        res["worst_layer_z"] = float(zp)
        res["worst_point"] = {"layer": int(layer), "printer_xyz": [float(x), float(y), float(zp)],
                              "d": float(D[i]), "f": float(F0[i])}
    return res


def check(expr_path, gcode_path, line_width=0.45, layer_height=0.2, shift=None, fit_xy=False, sample=0.0,
          first_layer_height=None, slice_offset=None, angles=720, max_points=0, threads=None, seed=0,
          fit_full=False):
    t0 = time.perf_counter()
    moves = sc.parse_gcode(gcode_path)
    t_parse = time.perf_counter() - t0
    if shift is None:
        shift = header_shift(gcode_path)
        if shift is None:
            raise SystemExit(f"{gcode_path}: no '; part: ... shift' header line; give --shift SX,SY,SZ")
    shift = np.asarray(shift, dtype=np.float64)
    F = Field2D(load_field(expr_path), threads)
    zs, slice_z = sc.layer_table(moves, layer_height, first_layer_height)
    if slice_offset is not None:
        slice_z = zs - slice_offset
    li = np.searchsorted(zs, np.round(moves["z"], 5))
    outer = moves["kind"] == sc.KINDS.index("outer")
    target = line_width / 2
    Ps, Zs, W = [], [], []
    for i, (zp, zc) in enumerate(zip(zs, slice_z)):
        sel = np.flatnonzero(outer & (li == i))
        if len(sel) == 0:
            continue
        P = sc.outer_points(moves, sel, sample)
        Ps.append(P)
        Zs.append(np.full(len(P), zc - shift[2]))
        W.append(np.stack([np.full(len(P), i), P[:, 0], P[:, 1],
                           np.full(len(P), zp)], 1))
    P = np.concatenate(Ps) if Ps else np.zeros((0, 2))
    Z = np.concatenate(Zs) if Zs else np.zeros(0)
    where = np.concatenate(W) if W else np.zeros((0, 4))
    total_points = len(P)
    if max_points and len(P) > max_points:
        keep = np.sort(np.random.default_rng(seed).choice(len(P), max_points, replace=False))
        P, Z, where = P[keep], Z[keep], where[keep]
    t1 = time.perf_counter()
    xy = np.zeros(2)
    fit_s = 0.0
    fitted = None
    if fit_xy and len(P):
        # up to 100 points a layer; Gauss-Newton on d(p - s) ~ d(p) - u . s, u the unit vector from
        # the crossing found to p (the gradient of the unsigned distance), L1 by reweighting
        rng = np.random.default_rng(seed)
        layer_of = where[:, 3]
        pick = np.sort(np.concatenate([rng.permutation(np.flatnonzero(layer_of == lz))[:100]
                                       for lz in np.unique(layer_of)]))
        sample_nominal = None
        for _ in range(10):
            d, u, f = measure(F, P[pick] - shift[:2] - xy, Z[pick], angles)
            if sample_nominal is None:
                sample_nominal = _stats(d, f, where[pick], target, line_width)
            ok = np.isfinite(d) & (d > 1e-9)
            R = d[ok] - target
            G = -u[ok]
            keep = np.abs(R) < 1.0
            if keep.sum() < 3:
                break
            wgt = 1.0 / np.sqrt(np.maximum(np.abs(R[keep]), 1e-4))
            step = np.linalg.lstsq(G[keep] * wgt[:, None], R[keep] * wgt, rcond=None)[0]
            xy = xy + step
            if np.hypot(*step) < 1e-5:
                break
        if not fit_full:
            d, _, f = measure(F, P[pick] - shift[:2] - xy, Z[pick], angles)
            fitted = _stats(d, f, where[pick], target, line_width)
            fitted["nominal_on_these_points"] = sample_nominal
        fit_s = time.perf_counter() - t1
    t2 = time.perf_counter()
    D, _, F0 = measure(F, P - shift[:2], Z, angles)
    nominal = _stats(D, F0, where, target, line_width)
    per_layer = {}
    if len(P):
        err = np.abs(D - target)
        for lz in np.unique(where[:, 3]):
            e = err[(where[:, 3] == lz) & np.isfinite(D)]
            if len(e):
                per_layer[f"{lz:.3f}"] = float(e.max())
    if fit_xy and fit_full and len(P):
        D2, _, F2 = measure(F, P - shift[:2] - xy, Z, angles)
        fitted = _stats(D2, F2, where, target, line_width)
    t_dist = time.perf_counter() - t2
    counts = {k: int((moves["kind"] == i).sum()) for i, k in enumerate(sc.KINDS)}
    return {
        "expression": expr_path, "gcode": gcode_path, "gcode_lines": moves["lines"],
        "shift": [float(v) for v in shift], "fitted_xy_shift": [float(v) for v in xy] if fit_xy else None,
        "layers": int(len(zs)), "first_layer_z": float(zs[0]) if len(zs) else None,
        "last_layer_z": float(zs[-1]) if len(zs) else None,
        "extrusion_moves": int(len(moves["e"])), "moves_by_kind": counts, "target": target,
        "outer_points_total": int(total_points), "sampled": bool(max_points and total_points > max_points),
        **nominal, "fitted": fitted, "layer_max_err": per_layer,
        "evaluations": int(F.evals), "parse_s": t_parse, "fit_s": fit_s, "distance_s": t_dist,
        "total_s": time.perf_counter() - t0,
    }


def _fmt(r):
    p = lambda v, f="{:.4f}": "n/a" if v is None else f.format(v)
    mk = r["moves_by_kind"]

    def wall(q, label):
        w = q["worst_point"]
        worst = (f"; worst: layer {w['layer']} at printer ({w['printer_xyz'][0]:.3f}, {w['printer_xyz'][1]:.3f}, "
                 f"{w['printer_xyz'][2]:.3f}), d {w['d']:.4f}" if w else "")
        return (f"outer wall{label}: {q['outer_points']} points, |d - w/2| (w/2 = {r['target']:.4f}) mean "
                f"{p(q['err_mean'])} median {p(q['err_median'])} p95 {p(q['err_p95'])} max {p(q['err_max'])}"
                f"{worst}; within 1% of w: {p(q['within_1pct'] and 100 * q['within_1pct'], '{:.1f}')}%; "
                f"outside the section: {q['outside_points']}"
                + (f"; with no zero set within 16 mm: {q['points_without_section']}" if q["points_without_section"] else ""))

    lines = [
        f"{r['gcode']}: {r['gcode_lines']} lines, parsed in {r['parse_s']:.2f} s; "
        f"{r['extrusion_moves']} extrusion moves ({', '.join(f'{k} {mk[k]}' for k in sc.KINDS if mk[k])})",
        f"layers: {r['layers']}, z {p(r['first_layer_z'], '{:.3f}')} .. {p(r['last_layer_z'], '{:.3f}')}",
        f"placement: printer = model + ({', '.join(f'{t:.4f}' for t in r['shift'])})"
        + (f"; {r['outer_points']} of {r['outer_points_total']} outer-wall points sampled" if r["sampled"] else ""),
        wall(r, ""),
    ]
    if r["fitted"]:
        sx, sy = r["fitted_xy_shift"]
        q = r["fitted"].get("nominal_on_these_points")
        lines.append(wall(r["fitted"], f" after the fitted xy shift ({sx:.4f}, {sy:.4f})"
                          + (" (the fit's points)" if q else "")))
        if q:
            lines.append(wall(q, " on the fit's points before the shift"))
    lines.append(f"time: fit {r['fit_s']:.1f} s, distances {r['distance_s']:.1f} s ({r['evaluations']} evaluations), "
                 f"total {r['total_s']:.1f} s")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("expr", help="the expression sliced (.rhai, .vm, .frep)")
    ap.add_argument("gcode")
    ap.add_argument("--line-width", type=float, default=0.45, help="outer-wall line width w (mm)")
    ap.add_argument("--layer-height", type=float, default=0.2)
    ap.add_argument("--first-layer-height", type=float, default=None, help="default: the first layer's z")
    ap.add_argument("--slice-offset", type=float, default=None,
                    help="check every layer at print z minus this (default: half the layer height)")
    ap.add_argument("--shift", default=None, help="SX,SY,SZ: printer = model + shift (default: frep's header)")
    ap.add_argument("--fit-xy", action="store_true", help="fit and report a residual XY translation")
    ap.add_argument("--fit-full", action="store_true",
                    help="with --fit-xy: the statistics after the shift over every point, not the fit's")
    ap.add_argument("--sample", type=float, default=0.0, help="also points every S mm along the outer walls")
    ap.add_argument("--angles", type=int, default=720, help="samples on each circle")
    ap.add_argument("--max-points", type=int, default=0, help="check a random sample of N points (0: all)")
    ap.add_argument("-j", "--threads", type=int, default=None, help="evaluation threads (default: frep's)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    shift = tuple(float(v) for v in a.shift.split(",")) if a.shift else None
    r = check(a.expr, a.gcode, a.line_width, a.layer_height, shift, a.fit_xy, a.sample, a.first_layer_height,
              a.slice_offset, a.angles, a.max_points, a.threads, fit_full=a.fit_full)
    print(json.dumps(r, indent=1) if a.json else _fmt(r))
    return 0


if __name__ == "__main__":
    sys.exit(main())
