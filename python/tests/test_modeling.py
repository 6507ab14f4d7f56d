"""The modeling API and ugf operations: values against their formulas, facts, operators, fields
from different graphs, and the same expressions as a Rhai script run by the CLI."""

import numpy as np
import pytest

import frep

RHAI = """
let plate = box([-1, -0.6, -0.15], [1, 0.6, 0.15]);
let hole = sphere([0.2, 0, 0], 0.3);
let part = difference(plate, hole).move([0, 0, 0.1]);
let knob = sphere([0, 0, 0], 0.25).scale([1, 2, 1]).rotate("z", 30).move([0.6, 0.3, 0.2]);
let blended = blend(part, knob, 0.1);
offset(union(blended, circle([-0.7, 0], 0.2).extrude_z(-0.4, 0.4)), 0.02)
"""


def python_model():
    plate = frep.box((-1, -0.6, -0.15), (1, 0.6, 0.15))
    hole = frep.sphere((0.2, 0, 0), 0.3)
    part = frep.move(frep.subtract(plate, hole), (0, 0, 0.1))
    knob = frep.move(frep.rotate(frep.scale(frep.sphere((0, 0, 0), 0.25), (1, 2, 1)), (0, 0, 1), 30), (0.6, 0.3, 0.2))
    blended = frep.blend(part, knob, 0.1)
    return frep.ugf.offset(frep.union(blended, frep.extrude_z(frep.circle((-0.7, 0), 0.2), -0.4, 0.4)), 0.02)


BOUNDS = ((-1.2, -1, -0.6), (1.2, 1, 0.6))


def test_modeling_equals_the_cli_on_the_same_script(cli, tmp_path):
    script = tmp_path / "model.rhai"
    script.write_text(RHAI)
    out = tmp_path / "grid.npy"
    cli("sample", script, "-o", out, "--grid", 40, "--bounds", "-1.2,-1,-0.6,1.2,1,0.6", "-q")
    mine = python_model()
    assert mine.sample_grid(40, bounds=BOUNDS).tobytes() == np.load(out).tobytes()
    loaded = frep.load(script)
    assert (loaded.info.lipschitz, loaded.info.bounds, loaded.info.growth) == (
        mine.info.lipschitz, mine.info.bounds, mine.info.growth)


def test_shapes_follow_their_formulas(rng):
    p = rng.uniform(-2, 2, (2000, 3)).astype(np.float32)
    s = frep.sphere((0.5, 0, 0), 0.7)
    np.testing.assert_allclose(s.sdf(p), np.linalg.norm(p - [0.5, 0, 0], axis=1) - 0.7, atol=1e-5)
    b = frep.box((-1, -1, -1), (1, 1, 1))
    np.testing.assert_allclose(b.sdf(p), np.max(np.abs(p), axis=1) - 1, atol=1e-6)
    pl = frep.plane((0, 0, 1), 0.25)
    np.testing.assert_allclose(pl.sdf(p), p[:, 2] - 0.25, atol=1e-6)
    c = frep.circle((0, 0), 1)
    np.testing.assert_allclose(c.sdf(p), np.hypot(p[:, 0], p[:, 1]) - 1, atol=1e-5)
    np.testing.assert_allclose(frep.unite(s, b).sdf(p), np.minimum(s.sdf(p), b.sdf(p)))
    np.testing.assert_allclose(frep.intersect(s, b).sdf(p), np.maximum(s.sdf(p), b.sdf(p)))
    np.testing.assert_allclose(frep.subtract(b, s).sdf(p), np.maximum(b.sdf(p), -s.sdf(p)))
    np.testing.assert_allclose(frep.move(s, (1, 2, 3)).sdf(p + [1, 2, 3]), s.sdf(p), atol=1e-5)


def test_facts_follow_the_rules():
    s = frep.sphere((0, 0, 0), 1)
    assert (s.info.lipschitz, s.info.growth) == (1, "distance")
    assert s.info.bounds == ((-1, -1, -1), (1, 1, 1))
    grown = frep.ugf.offset(s, 0.5)
    assert grown.info.bounds == ((-1.5, -1.5, -1.5), (1.5, 1.5, 1.5))
    assert (s - 0.5).info.bounds == grown.info.bounds  # f - c is that offset
    assert (-s).info.bounds is None  # the complement is unbounded
    assert (s * s).info.lipschitz == 0  # nothing claimed where nothing is known


def test_operators_build_expressions(rng):
    p = rng.uniform(-1, 1, (500, 3)).astype(np.float32)
    x, y, z = frep.x(), frep.y(), frep.z()
    r = frep.sqrt(x * x + y * y + frep.square(z)) - 0.5
    np.testing.assert_allclose(r.sdf(p), np.linalg.norm(p, axis=1) - 0.5, atol=1e-6)
    np.testing.assert_allclose((2 * x / 4 + 1 - y).sdf(p), 2 * p[:, 0] / 4 + 1 - p[:, 1], atol=1e-6)
    np.testing.assert_allclose((1 / (x * x + 1)).sdf(p), 1 / (p[:, 0] ** 2 + 1), rtol=1e-6)
    np.testing.assert_allclose(abs(x).sdf(p), np.abs(p[:, 0]))
    np.testing.assert_allclose(frep.max(x, 0.25).sdf(p), np.maximum(p[:, 0], 0.25))
    np.testing.assert_allclose((x | y).sdf(p), np.minimum(p[:, 0], p[:, 1]))
    np.testing.assert_allclose((x & y).sdf(p), np.maximum(p[:, 0], p[:, 1]))


def test_fields_from_different_graphs_combine(mesh_path, rng):
    mesh = frep.load(mesh_path("sphere_icosa_1280.stl"))
    s = frep.sphere((1.5, 0, 0), 0.5)  # a graph of its own
    u = frep.unite(mesh, s)
    p = rng.uniform(-2, 2, (1000, 3)).astype(np.float32)
    np.testing.assert_array_equal(u.sdf(p), np.minimum(mesh.sdf(p), s.sdf(p)))
    both = frep.union([mesh, s, frep.box((0, 0, 0), (1, 1, 1))])
    assert both.info.lipschitz == 1
    # A chain of transforms still composes after a copy to another graph.
    moved = frep.move(frep.move(s, (0, 1, 0)), (0, -1, 0))
    np.testing.assert_allclose(frep.unite(mesh, moved).sdf(p), u.sdf(p), atol=1e-6)


def test_ugf_operations(rng):
    p = rng.uniform(-2, 2, (3000, 3)).astype(np.float32)
    s = frep.sphere((0, 0, 0), 1)
    d = np.linalg.norm(p, axis=1)
    np.testing.assert_allclose(frep.ugf.offset(s, 0.25).sdf(p), d - 1.25, atol=1e-5)
    np.testing.assert_allclose(frep.ugf.shell(s, 0.2).sdf(p), np.abs(d - 1) - 0.1, atol=1e-5)
    # Two half-spaces meeting at 90 degrees: the rounded and exact intersections are the wedge's
    # distances (the round's arc of radius r).
    a, b = frep.plane((1, 0, 0), 0), frep.plane((0, 1, 0), 0)
    exact = frep.ugf.intersect_exact(a, b).sdf(p)
    outside = (p[:, 0] > 0) & (p[:, 1] > 0)
    np.testing.assert_allclose(exact[outside], np.hypot(p[outside, 0], p[outside, 1]), atol=1e-5)
    rounded = frep.ugf.round_intersection(a, b, 0.3).sdf(np.array([[0.1, 0.1, 0]], np.float32))[0]
    assert rounded == pytest.approx(np.hypot(0.4, 0.4) - 0.3, abs=1e-5)
    su = frep.ugf.smooth_union(s, frep.sphere((1.5, 0, 0), 1), 0.5).sdf(p)
    assert np.all(su <= np.minimum(d - 1, np.linalg.norm(p - [1.5, 0, 0], axis=1) - 1) + 1e-6)
    ch = frep.ugf.chamfer_intersection(a, b, setback=0.2)
    assert ch.sdf(np.array([[0.0, 0.0, 0.0]], np.float32))[0] > 0  # the corner is cut away
    with pytest.raises(ValueError):
        frep.ugf.chamfer_intersection(a, b)
