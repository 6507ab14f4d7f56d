#!/usr/bin/env python3
"""Writes examples/bracket.obj, the mesh the demo converts: a plate with a round hole, as a
closed, consistently oriented triangle mesh (made by this script; run it again to
regenerate). Everything fits in [-1, 1]^3, where `frep render` draws by default."""
import math

N = 48  # segments around the hole
W, H, T = 0.9, 0.6, 0.12  # half width, half height, half thickness
HX, HR = -0.35, 0.3  # hole centre x, radius

def outline(a):
    """Where the ray from the hole's centre at angle a leaves the plate's outline."""
    dx, dy = math.cos(a), math.sin(a)
    best = math.inf
    for bound, d, o in ((W, dx, HX), (-W, dx, HX), (H, dy, 0.0), (-H, dy, 0.0)):
        if d != 0:
            t = (bound - o) / d
            if t > 0:
                best = min(best, t)
    return (HX + dx * best, dy * best)

verts, faces = [], []
def v(x, y, z):
    verts.append((x, y, z))
    return len(verts)  # OBJ is 1-based

# Both rings are sampled at the same angles around the hole's centre (the outline is star-shaped
# from there, so the ring's quads never overlap), and the rectangle's corners are among them.
corners = [math.atan2(cy, cx - HX) % (2 * math.pi) for cx, cy in ((W, H), (-W, H), (-W, -H), (W, -H))]
angles = sorted(set([2 * math.pi * i / N for i in range(N)] + corners))
outer = [outline(a) for a in angles]
inner = [(HX + HR * math.cos(a), HR * math.sin(a)) for a in angles]
n = len(angles)
top_o = [v(x, y, T) for x, y in outer]
bot_o = [v(x, y, -T) for x, y in outer]
top_i = [v(x, y, T) for x, y in inner]
bot_i = [v(x, y, -T) for x, y in inner]
for k in range(n):
    j = (k + 1) % n
    # top face (normal +z): ring between outline and hole, counter-clockwise seen from above
    faces.append((top_o[k], top_o[j], top_i[j])); faces.append((top_o[k], top_i[j], top_i[k]))
    # bottom face (normal -z)
    faces.append((bot_o[k], bot_i[j], bot_o[j])); faces.append((bot_o[k], bot_i[k], bot_i[j]))
    # outer wall (normal outward)
    faces.append((bot_o[k], bot_o[j], top_o[j])); faces.append((bot_o[k], top_o[j], top_o[k]))
    # hole wall (normal toward the hole's axis)
    faces.append((bot_i[k], top_i[j], bot_i[j])); faces.append((bot_i[k], top_i[k], top_i[j]))

with open("examples/bracket.obj", "w") as f:
    f.write("# A plate with a round hole: frep's demo mesh (scripts/make_example_mesh.py)\n")
    for x, y, z in verts:
        f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
    for a, b, c in faces:
        f.write(f"f {a} {b} {c}\n")
print(f"examples/bracket.obj: {len(verts)} vertices, {len(faces)} triangles")
