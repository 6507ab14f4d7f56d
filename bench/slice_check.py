#!/usr/bin/env python3
"""An independent check of a G-code file against the mesh it was sliced from (Python 3 + numpy).

  /usr/bin/python3 bench/slice_check.py MESH.stl OUT.gcode --line-width 0.45 --layer-height 0.2
      [--filament 1.75] [--center 110,110 | --translate X,Y,Z] [--fit-xy] [--sample 0.1] [--json]

What it measures, with nothing taken from the slicer but the G-code:
  layers      the distinct Z of extrusion moves (a G1 that moves in XY and pushes filament); first
              and last layer z.
  sections    for each layer, the exact cross-section of the mesh (every triangle cut by the plane,
              numpy) at the slicing height: print z minus half the layer's height by default
              (PrusaSlicer and CuraEngine's default slicing_tolerance=middle both slice mid-layer);
              the first layer's height is its z. A vertex on the plane counts as above it
              (symbolic perturbation), so every cut triangle gives exactly one segment.
  perimeter   every vertex of the outer-wall extrusion paths (--sample S adds points every S mm
              along them): the unsigned in-plane distance d to the section, whose target is w/2
              (the outer wall's centre line runs half a line width inside the surface). Reported:
              count, mean / median / p95 / max of |d - w/2|, the fraction with |d - w/2| <= 1% of
              w, and how many of the points lie outside the section (side of the nearest segment).
  volume      the filament pushed by extrusion moves (retractions and primes without XY motion
              excluded) times the filament's cross-section, over the mesh volume (signed
              tetrahedra); near 1 at 100% infill.
  placement   the mesh goes to the printer by a translation: --translate X,Y,Z, or by default the
              one that puts the bounding box's centre at --center (110,110) and its bottom at z = 0.
              --fit-xy also fits a residual XY translation (Gauss-Newton, L1-reweighted, on |d - w/2|
              over the outer-wall points) and reports it with the statistics after it, beside the
              nominal ones: a slicer that places parts differently shows here.

Move types come from the `;TYPE:` comments: Cura's and frep's WALL-OUTER, WALL-INNER, SKIN, FILL
and PrusaSlicer's External perimeter, Perimeter, Solid infill, Top solid infill, Bridge infill,
Internal infill (Overhang perimeter, Gap fill, skirt, support ... count as other).
"""
import argparse
import json
import math
import re
import sys
import time

import numpy as np

KINDS = ("outer", "inner", "skin", "fill", "other", "none")
_TYPE_MAP = {
    # Cura, frep
    "WALL-OUTER": "outer", "WALL-INNER": "inner", "SKIN": "skin", "FILL": "fill",
    # PrusaSlicer 2.x
    "EXTERNAL PERIMETER": "outer", "PERIMETER": "inner", "SOLID INFILL": "skin",
    "TOP SOLID INFILL": "skin", "BRIDGE INFILL": "skin", "INTERNAL INFILL": "fill",
}


def type_kind(name):
    """The kind (outer, inner, skin, fill, other) of a `;TYPE:` comment's name."""
    return _TYPE_MAP.get(name.strip().upper(), "other")


# ---------------------------------------------------------------------------------------------
# meshes

def read_stl(path):
    """Triangles (T x 3 x 3, float64) of a binary or ASCII STL."""
    data = open(path, "rb").read()
    if len(data) >= 84:
        n = int.from_bytes(data[80:84], "little")
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=n, offset=84)
            return rec["v"].astype(np.float64)
    text = data.decode("ascii", errors="replace")
    nums = re.findall(r"^\s*vertex\s+(\S+)\s+(\S+)\s+(\S+)", text, flags=re.M)
    if not nums or len(nums) % 3:
        raise ValueError(f"{path}: not a binary STL and no ASCII facets")
    return np.array(nums, dtype=np.float64).reshape(-1, 3, 3)


def read_mesh(path):
    """Triangles (T x 3 x 3) of an STL, OBJ or OFF file (polygons fan-triangulated)."""
    low = path.lower()
    if low.endswith(".stl"):
        return read_stl(path)
    verts, faces = [], []
    if low.endswith(".obj"):
        for line in open(path, errors="replace"):
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) for t in line.split()[1:]]
                faces.append([i - 1 if i > 0 else len(verts) + i for i in idx])
    elif low.endswith(".off"):
        tokens = [ln.split("#")[0].split() for ln in open(path, errors="replace")]
        tokens = [t for t in tokens if t]
        head = tokens[0]
        if head[0].upper().endswith("OFF"):
            head = head[1:] or tokens[1]
            rest = tokens[1:] if tokens[0][1:] else tokens[2:]
        else:
            rest = tokens[1:]
        nv, nf = int(head[0]), int(head[1])
        verts = [[float(x) for x in t[:3]] for t in rest[:nv]]
        faces = [[int(x) for x in t[1:1 + int(t[0])]] for t in rest[nv:nv + nf]]
    else:
        raise ValueError(f"{path}: reads STL, OBJ and OFF")
    v = np.array(verts, dtype=np.float64)
    tris = [(f[0], f[i], f[i + 1]) for f in faces for i in range(1, len(f) - 1)]
    return v[np.array(tris, dtype=np.int64)]


def write_stl(path, tris):
    """Binary STL of triangles (T x 3 x 3); facet normals from the vertex order."""
    tris = np.asarray(tris, dtype=np.float64)
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    ln = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.divide(n, ln, out=np.zeros_like(n), where=ln > 0)
    rec = np.zeros(len(tris), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    rec["n"], rec["v"] = n, tris
    with open(path, "wb") as f:
        f.write(b"frep bench".ljust(80, b" "))
        f.write(len(tris).to_bytes(4, "little"))
        f.write(rec.tobytes())


def mesh_volume(tris):
    """Signed volume (sum of the tetrahedra to the origin, taken about the centroid for accuracy)."""
    c = tris.reshape(-1, 3).mean(0)
    a, b, d = tris[:, 0] - c, tris[:, 1] - c, tris[:, 2] - c
    return float(np.einsum("ij,ij->i", a, np.cross(b, d)).sum() / 6.0)


def centred_translation(tris, cx=110.0, cy=110.0):
    """The translation that puts the mesh's bounding-box centre at (cx, cy) and its bottom at z = 0."""
    lo, hi = tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0)
    return np.array([cx - (lo[0] + hi[0]) / 2, cy - (lo[1] + hi[1]) / 2, -lo[2]])


def section(tris, z):
    """The mesh's cross-section at height z: segments A, B (S x 2 each) and each segment's outward
    in-plane normal (S x 2, unit, perpendicular to the segment). A vertex exactly at z counts as
    above the plane, so each triangle the plane cuts gives exactly one segment."""
    above = tris[:, :, 2] >= z
    na = above.sum(1)
    t = tris[(na == 1) | (na == 2)]
    ab = above[(na == 1) | (na == 2)]
    if len(t) == 0:
        e = np.zeros((0, 2))
        return e, e, e
    # the lone vertex (the one on its own side) and the two others, in cyclic order
    lone = np.where(ab.sum(1) == 1, np.argmax(ab, 1), np.argmin(ab, 1))
    r = np.arange(len(t))
    p0, p1, p2 = t[r, lone], t[r, (lone + 1) % 3], t[r, (lone + 2) % 3]

    def cut(p, q):
        s = (z - p[:, 2]) / (q[:, 2] - p[:, 2])
        return p[:, :2] + s[:, None] * (q[:, :2] - p[:, :2])

    a, b = cut(p0, p1), cut(p0, p2)
    n3 = np.cross(p1 - p0, p2 - p0)
    d = b - a
    perp = np.stack([d[:, 1], -d[:, 0]], 1)
    flip = np.einsum("ij,ij->i", perp, n3[:, :2]) < 0
    perp[flip] *= -1
    ln = np.linalg.norm(perp, axis=1, keepdims=True)
    perp = np.divide(perp, ln, out=np.zeros_like(perp), where=ln > 0)
    return a, b, perp


# ---------------------------------------------------------------------------------------------
# distances from points to a set of segments (uniform grid, numpy)

def _pair_dist(P, A, B):
    """Distance from each P to its segment A-B, and the nearest point."""
    d = B - A
    dd = np.einsum("ij,ij->i", d, d)
    s = np.einsum("ij,ij->i", P - A, d)
    s = np.clip(np.divide(s, dd, out=np.zeros_like(s), where=dd > 0), 0.0, 1.0)
    q = A + s[:, None] * d
    return np.hypot(P[:, 0] - q[:, 0], P[:, 1] - q[:, 1]), q


def _reduce_nearest(pt, dist, side, n):
    """Per point (pt sorted ascending): the smallest distance, and its side (+1 outside, -1 inside),
    ties broken by the segment whose line is farthest (the right side at a shared vertex)."""
    best = np.full(n, np.inf)
    sgn = np.zeros(n)
    which = np.full(n, -1)
    if len(pt) == 0:
        return best, sgn, which
    starts = np.flatnonzero(np.r_[True, pt[1:] != pt[:-1]])
    owners = pt[starts]
    dmin = np.minimum.reduceat(dist, starts)
    best[owners] = dmin
    counts = np.diff(np.r_[starts, len(pt)])
    near = dist <= np.repeat(dmin, counts) + 1e-9
    score = np.where(near, np.abs(side), -1.0)
    smax = np.maximum.reduceat(score, starts)
    pick = np.flatnonzero(near & (score >= np.repeat(smax, counts)))
    _, first = np.unique(pt[pick], return_index=True)
    sel = pick[first]
    sgn[pt[sel]] = np.where(side[sel] > 0, 1.0, -1.0)
    which[pt[sel]] = sel
    return best, sgn, which


def distances(P, A, B, N, cell=0.25, radius=0.75, chunk=20000, nearest=False):
    """Unsigned distance from each point P (n x 2) to the nearest segment A-B, and the side of that
    segment (+1 outside, by the outward normals N; -1 inside). Segments are split into pieces no
    longer than `cell` and binned by midpoint; a point searches the cells that can hold a piece
    within `radius`; the few points with nothing that near are searched by brute force.
    With nearest=True, also the nearest point of the segments to each point (n x 2)."""
    n = len(P)
    best, sgn, near = np.full(n, np.inf), np.zeros(n), np.full((n, 2), np.nan)
    if n == 0 or len(A) == 0:
        return (best, sgn, near) if nearest else (best, sgn)
    L = np.hypot(*(B - A).T)
    k = np.maximum(1, np.ceil(L / cell).astype(np.int64))
    par = np.repeat(np.arange(len(A)), k)
    j = np.arange(len(par)) - np.repeat(np.cumsum(k) - k, k)
    f0, f1 = (j / k[par])[:, None], ((j + 1) / k[par])[:, None]
    PA = A[par] + f0 * (B[par] - A[par])
    PB = A[par] + f1 * (B[par] - A[par])
    PN = N[par]
    mid = (PA + PB) / 2
    ring = int(math.ceil((radius + cell / 2) / cell))
    lo = mid.min(0) - (ring + 1) * cell
    nx, ny = (np.floor((mid.max(0) + (ring + 1) * cell - lo) / cell).astype(np.int64) + 1)
    mc = np.floor((mid - lo) / cell).astype(np.int64)
    key = mc[:, 0] * ny + mc[:, 1]
    order = np.argsort(key, kind="stable")
    cstart = np.zeros(nx * ny + 1, dtype=np.int64)
    np.cumsum(np.bincount(key, minlength=nx * ny), out=cstart[1:])
    offs = np.arange(-ring, ring + 1)
    dx, dy = [o.ravel() for o in np.meshgrid(offs, offs, indexing="ij")]
    for s in range(0, n, chunk):
        Q = P[s:s + chunk]
        m = len(Q)
        pc = np.floor((Q - lo) / cell).astype(np.int64)
        cx, cy = pc[:, 0:1] + dx, pc[:, 1:2] + dy
        ok = (cx >= 0) & (cx < nx) & (cy >= 0) & (cy < ny)
        keys = np.where(ok, cx * ny + cy, 0)
        st = cstart[keys]
        cnt = np.where(ok, cstart[keys + 1] - st, 0).ravel()
        tot = int(cnt.sum())
        pt = np.repeat(np.repeat(np.arange(m), len(dx)), cnt)
        within = np.arange(tot) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        piece = order[np.repeat(st.ravel(), cnt) + within]
        dist, qn = _pair_dist(Q[pt], PA[piece], PB[piece])
        side = np.einsum("ij,ij->i", Q[pt] - PA[piece], PN[piece])
        b, g, w = _reduce_nearest(pt, dist, side, m)
        nq = np.full((m, 2), np.nan)
        nq[w >= 0] = qn[w[w >= 0]]
        far = np.flatnonzero(b > radius)
        if len(far):  # brute force: nothing within the radius searched
            for f in range(0, len(far), 64):
                ids = far[f:f + 64]
                pt2 = np.repeat(np.arange(len(ids)), len(PA))
                pc2 = np.tile(np.arange(len(PA)), len(ids))
                d2, q2 = _pair_dist(Q[ids][pt2], PA[pc2], PB[pc2])
                s2 = np.einsum("ij,ij->i", Q[ids][pt2] - PA[pc2], PN[pc2])
                b2, g2, w2 = _reduce_nearest(pt2, d2, s2, len(ids))
                b[ids], g[ids], nq[ids] = b2, g2, q2[w2]
        best[s:s + m], sgn[s:s + m], near[s:s + m] = b, g, nq
    return (best, sgn, near) if nearest else (best, sgn)


# ---------------------------------------------------------------------------------------------
# G-code

_WORD = re.compile(r"([A-Za-z])\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")


def parse_gcode(path):
    """Extrusion moves of a G-code file: dict of arrays x0, y0, x1, y1, z, e (filament pushed, mm),
    kind (index into KINDS), and layer (the `;LAYER:` number in force, -1 before any); plus counts.
    Handles G0/G1 (and G2/G3 arcs, linearised), G90/G91, M82/M83, G92, and `;TYPE:` comments."""
    x = y = z = e = 0.0
    absolute, abs_e = True, True
    kind = KINDS.index("none")
    layer = -1
    out = {k: [] for k in ("x0", "y0", "x1", "y1", "z", "e", "kind", "layer")}
    retract = 0.0
    lines = 0
    kinds = {k: KINDS.index(k) for k in KINDS}

    def emit(nx, ny, de):
        out["x0"].append(x); out["y0"].append(y); out["x1"].append(nx); out["y1"].append(ny)
        out["z"].append(z); out["e"].append(de); out["kind"].append(kind); out["layer"].append(layer)

    with open(path, "r", errors="replace") as fh:
        for raw in fh:
            lines += 1
            semi = raw.find(";")
            if semi >= 0:
                comment = raw[semi + 1:].strip()
                if comment.startswith("TYPE:"):
                    kind = kinds[type_kind(comment[5:])]
                elif comment.startswith("LAYER:"):
                    try:
                        layer = int(comment[6:].split()[0])
                    except (ValueError, IndexError):
                        pass
                code = raw[:semi]
            else:
                code = raw
            code = code.strip()
            if not code:
                continue
            c0 = code[0].upper()
            if c0 not in "GM":
                continue
            words = _WORD.findall(code)
            if not words:
                continue
            cmd = words[0][0].upper() + str(int(float(words[0][1])))
            if cmd in ("G0", "G1", "G2", "G3"):
                v = {w.upper(): float(val) for w, val in words[1:]}
                nx, ny, nz = x, y, z
                if "X" in v: nx = v["X"] if absolute else x + v["X"]
                if "Y" in v: ny = v["Y"] if absolute else y + v["Y"]
                if "Z" in v: nz = v["Z"] if absolute else z + v["Z"]
                de = 0.0
                if "E" in v:
                    de = v["E"] - e if abs_e else v["E"]
                    e = v["E"] if abs_e else e + v["E"]
                z = nz
                moved = nx != x or ny != y
                if de > 0 and moved:
                    if cmd in ("G2", "G3") and ("I" in v or "J" in v):
                        cxa, cya = x + v.get("I", 0.0), y + v.get("J", 0.0)
                        a0 = math.atan2(y - cya, x - cxa)
                        a1 = math.atan2(ny - cya, nx - cxa)
                        r = math.hypot(x - cxa, y - cya)
                        sweep = a1 - a0
                        if cmd == "G2" and sweep >= 0: sweep -= 2 * math.pi
                        if cmd == "G3" and sweep <= 0: sweep += 2 * math.pi
                        steps = max(1, int(abs(sweep) * r / 0.1))
                        for i in range(1, steps + 1):
                            a = a0 + sweep * i / steps
                            px, py = (cxa + r * math.cos(a), cya + r * math.sin(a)) if i < steps else (nx, ny)
                            emit(px, py, de / steps)
                            x, y = px, py
                    else:
                        emit(nx, ny, de)
                elif de < 0:
                    retract -= de
                x, y = nx, ny
            elif cmd == "G90":
                absolute = True
                abs_e = True
            elif cmd == "G91":
                absolute = False
                abs_e = False
            elif cmd == "M82":
                abs_e = True
            elif cmd == "M83":
                abs_e = False
            elif cmd == "G92":
                v = {w.upper(): float(val) for w, val in words[1:]}
                x, y, z, e = v.get("X", x), v.get("Y", y), v.get("Z", z), v.get("E", e)
    res = {k: np.array(val, dtype=np.int64 if k in ("kind", "layer") else np.float64) for k, val in out.items()}
    res["lines"] = lines
    res["retracted"] = retract
    return res


# ---------------------------------------------------------------------------------------------
# the check

def outer_points(moves, sel, sample):
    """Points on the outer-wall paths of the moves `sel` (indices, in file order): every polyline
    vertex once, plus points every `sample` mm along each move when sample > 0."""
    x0, y0, x1, y1 = moves["x0"][sel], moves["y0"][sel], moves["x1"][sel], moves["y1"][sel]
    # a move starts a new polyline unless the previous selected move ended where it starts
    cont = np.r_[False, (sel[1:] == sel[:-1] + 1) & (x1[:-1] == x0[1:]) & (y1[:-1] == y0[1:])]
    pts = [np.stack([x0[~cont], y0[~cont]], 1), np.stack([x1, y1], 1)]
    if sample > 0:
        L = np.hypot(x1 - x0, y1 - y0)
        k = np.floor(L / sample).astype(np.int64)
        k = np.where(np.isclose(k * sample, L), k - 1, k).clip(0)
        idx = np.repeat(np.arange(len(L)), k)
        j = np.arange(len(idx)) - np.repeat(np.cumsum(k) - k, k) + 1
        f = np.divide(j * sample, L[idx], out=np.zeros(len(idx)), where=L[idx] > 0)
        pts.append(np.stack([x0[idx] + f * (x1[idx] - x0[idx]), y0[idx] + f * (y1[idx] - y0[idx])], 1))
    return np.concatenate(pts)


def layer_table(moves, layer_height, first_layer_height=None):
    """Distinct print heights of the extrusion moves, and the slicing height of each: z minus half
    the layer's height (the first layer's height is its z unless given)."""
    zs = np.unique(np.round(moves["z"], 5))
    h = np.full(len(zs), float(layer_height))
    if len(zs):
        h[0] = first_layer_height if first_layer_height else (zs[0] if 0 < zs[0] <= 2 * layer_height else layer_height)
    return zs, zs - h / 2


def _perimeter_stats(layers, shift, target, line_width):
    """|d - w/2| statistics of the outer-wall points of `layers` moved by -shift."""
    D, S, worst = [], [], (None, -1.0)
    for zp, zc, P, A, B, N in layers:
        d, s = distances(P - shift, A, B, N)
        D.append(d); S.append(s)
        e = np.abs(d[np.isfinite(d)] - target)
        if len(e) and e.max() > worst[1]:
            worst = (float(zp), float(e.max()))
    D = np.concatenate(D) if D else np.zeros(0)
    S = np.concatenate(S) if S else np.zeros(0)
    lost = ~np.isfinite(D)  # points on a layer whose slicing plane misses the mesh
    D, S = D[~lost], S[~lost]
    err = np.abs(D - target)
    some = len(err) > 0
    return {
        "outer_points": int(len(D)),
        "err_mean": float(err.mean()) if some else None,
        "err_median": float(np.median(err)) if some else None,
        "err_p95": float(np.percentile(err, 95)) if some else None,
        "err_max": float(err.max()) if some else None,
        "within_1pct": float((err <= 0.01 * line_width + 1e-12).mean()) if some else None,
        "outside_points": int((S > 0).sum()), "points_without_section": int(lost.sum()),
        "worst_layer_z": worst[0],
    }


def check(mesh_path, gcode_path, line_width=0.45, layer_height=0.2, filament=1.75, center=(110.0, 110.0),
          translate=None, fit_xy=False, sample=0.0, first_layer_height=None, slice_offset=None):
    t0 = time.perf_counter()
    moves = parse_gcode(gcode_path)
    t_parse = time.perf_counter() - t0
    tris = read_mesh(mesh_path)
    vol = mesh_volume(tris)
    if vol < 0:
        tris = tris[:, ::-1]
        vol = -vol
    T = np.asarray(translate, dtype=np.float64) if translate is not None else centred_translation(tris, *center)
    tris = tris + T
    zs, slice_z = layer_table(moves, layer_height, first_layer_height)
    if slice_offset is not None:
        slice_z = zs - slice_offset
    zkey = np.round(moves["z"], 5)
    li = np.searchsorted(zs, zkey)
    outer = moves["kind"] == KINDS.index("outer")
    target = line_width / 2

    # per layer: sections and outer-wall points
    layers = []
    for i, (zp, zc) in enumerate(zip(zs, slice_z)):
        sel = np.flatnonzero(outer & (li == i))
        if len(sel) == 0:
            continue
        P = outer_points(moves, sel, sample)
        A, B, N = section(tris, zc)
        layers.append((zp, zc, P, A, B, N))
    shift = np.zeros(2)
    if fit_xy and layers:
        # initial guess: bbox centre of the outer-wall points against the section's
        allp = np.concatenate([l[2] for l in layers])
        alls = np.concatenate([np.concatenate([l[3], l[4]]) for l in layers if len(l[3])])
        shift = (allp.min(0) + allp.max(0)) / 2 - (alls.min(0) + alls.max(0)) / 2
        rng = np.random.default_rng(0)
        picks = [rng.permutation(len(l[2]))[:400] for l in layers]  # up to 400 points a layer
        for _ in range(12):
            U, R = [], []
            for (zp, zc, P, A, B, N), pick in zip(layers, picks):
                if len(A) == 0:
                    continue
                Q = P[pick] - shift
                d, _, q = distances(Q, A, B, N, nearest=True)
                ok = np.isfinite(d) & (d > 1e-9)
                U.append((Q[ok] - q[ok]) / d[ok, None]); R.append(d[ok] - target)  # the gradient of d
            U, R = np.concatenate(U), np.concatenate(R)
            keep = np.abs(R) < 1.0
            if keep.sum() < 3:
                break
            # L1 by reweighting (mean |d - w/2|, not squares: a few corner points must not pull)
            wgt = 1.0 / np.sqrt(np.maximum(np.abs(R[keep]), 1e-4))
            U, R = U[keep] * wgt[:, None], R[keep] * wgt
            step = np.linalg.lstsq(U, R, rcond=None)[0]  # d(Q - shift) ~ d - U.dshift
            shift = shift + step
            if np.hypot(*step) < 1e-5:
                break
    t1 = time.perf_counter()
    nominal = _perimeter_stats(layers, np.zeros(2), target, line_width)
    fitted = _perimeter_stats(layers, shift, target, line_width) if fit_xy else None
    t_dist = time.perf_counter() - t1
    fil_area = math.pi * (filament / 2) ** 2
    e_total = float(moves["e"].sum())
    counts = {k: int((moves["kind"] == i).sum()) for i, k in enumerate(KINDS)}
    ext_by_kind = {k: float(moves["e"][moves["kind"] == i].sum() * fil_area) for i, k in enumerate(KINDS)}
    res = {
        "mesh": mesh_path, "gcode": gcode_path, "gcode_lines": moves["lines"],
        "translation": [float(t) for t in T], "fitted_xy_shift": [float(t) for t in shift] if fit_xy else None,
        "layers": int(len(zs)), "first_layer_z": float(zs[0]) if len(zs) else None,
        "last_layer_z": float(zs[-1]) if len(zs) else None,
        "mesh_height": float(tris[:, :, 2].max() - tris[:, :, 2].min()),
        "extrusion_moves": int(len(moves["e"])), "moves_by_kind": counts, "target": target,
        **nominal,
        "fitted": fitted,
        "filament_mm": e_total, "extruded_mm3": e_total * fil_area, "mesh_volume_mm3": vol,
        "volume_ratio": e_total * fil_area / vol if vol > 0 else None,
        "extruded_mm3_by_kind": ext_by_kind, "retracted_mm": moves["retracted"],
        "parse_s": t_parse, "distance_s": t_dist, "total_s": time.perf_counter() - t0,
    }
    return res


def _fmt(r):
    p = lambda v, f="{:.4f}": "n/a" if v is None else f.format(v)
    mk = r["moves_by_kind"]

    def wall(q, label):
        return (f"outer wall{label}: {q['outer_points']} points, |d - w/2| (w/2 = {r['target']:.4f}) mean "
                f"{p(q['err_mean'])} median {p(q['err_median'])} p95 {p(q['err_p95'])} max {p(q['err_max'])} "
                f"(worst layer z {p(q['worst_layer_z'], '{:.3f}')}); within 1% of w: "
                f"{p(q['within_1pct'] and 100 * q['within_1pct'], '{:.1f}')}%; outside the section: "
                f"{q['outside_points']}"
                + (f"; on layers with no section: {q['points_without_section']}" if q["points_without_section"] else ""))

    lines = [
        f"{r['gcode']}: {r['gcode_lines']} lines, parsed in {r['parse_s']:.2f} s; "
        f"{r['extrusion_moves']} extrusion moves ({', '.join(f'{k} {mk[k]}' for k in KINDS if mk[k])})",
        f"layers: {r['layers']}, z {p(r['first_layer_z'], '{:.3f}')} .. {p(r['last_layer_z'], '{:.3f}')} "
        f"(mesh height {r['mesh_height']:.3f})",
        f"placement: mesh + ({', '.join(f'{t:.4f}' for t in r['translation'])})",
        wall(r, ""),
    ]
    if r["fitted"]:
        sx, sy = r["fitted_xy_shift"]
        lines.append(wall(r["fitted"], f" after the fitted xy shift ({sx:.4f}, {sy:.4f})"))
    lines += [
        f"volume: extruded {r['extruded_mm3']:.1f} mm^3 ({r['filament_mm']:.1f} mm of filament), mesh "
        f"{r['mesh_volume_mm3']:.1f} mm^3, ratio {p(r['volume_ratio'])}",
        f"time: distances {r['distance_s']:.2f} s, total {r['total_s']:.2f} s",
    ]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("mesh", help="the mesh sliced (STL; OBJ and OFF also read)")
    ap.add_argument("gcode")
    ap.add_argument("--line-width", type=float, default=0.45, help="outer-wall line width w (mm)")
    ap.add_argument("--layer-height", type=float, default=0.2)
    ap.add_argument("--first-layer-height", type=float, default=None, help="default: the first layer's z")
    ap.add_argument("--slice-offset", type=float, default=None,
                    help="slice every layer at print z minus this (default: half the layer height)")
    ap.add_argument("--filament", type=float, default=1.75, help="filament diameter (mm)")
    ap.add_argument("--center", default="110,110", help="bed point the mesh's bbox centre goes to")
    ap.add_argument("--translate", default=None, help="X,Y,Z: mesh to printer translation (instead of --center)")
    ap.add_argument("--fit-xy", action="store_true", help="fit and report a residual XY translation")
    ap.add_argument("--sample", type=float, default=0.0, help="also points every S mm along the outer walls")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    center = tuple(float(v) for v in a.center.split(","))
    translate = tuple(float(v) for v in a.translate.split(",")) if a.translate else None
    r = check(a.mesh, a.gcode, a.line_width, a.layer_height, a.filament, center, translate, a.fit_xy, a.sample,
              a.first_layer_height, a.slice_offset)
    print(json.dumps(r, indent=1) if a.json else _fmt(r))
    return 0


if __name__ == "__main__":
    sys.exit(main())
