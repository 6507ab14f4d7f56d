"""Signed distances at points, grids and point samples: properties of the values, and the same
numbers as the frep CLI."""

import numpy as np
import pytest

import frep
from conftest import winding_numbers


def test_sphere_mesh_distance_is_close_to_the_sphere(mesh_path, rng):
    f = frep.load(mesh_path("sphere_icosa_1280.stl"))  # radius 1, vertices on the sphere
    p = rng.uniform(-2, 2, (20000, 3))
    d = f.sdf(p)
    analytic = np.linalg.norm(p, axis=1) - 1
    # The polyhedron lies within its sagitta (< 0.01 for 1280 faces) inside the sphere.
    assert np.all(d >= analytic - 1e-5)
    assert np.all(d <= analytic + 0.01)


def test_signs_agree_with_the_winding_number(mesh_path, rng):
    path = mesh_path("bunny_closed_libigl.off")
    f = frep.load(path)
    v, faces = frep.read_mesh(path)
    (lo, hi) = np.array(f.info.bounds)
    p = rng.uniform(lo, hi, (300, 3))
    d = f.sdf(p)
    w = winding_numbers(v, faces, p)
    # Away from the surface (where float32 rounding cannot flip the sign).
    far = np.abs(d) > 1e-4 * np.linalg.norm(hi - lo)
    assert far.sum() > 250
    np.testing.assert_array_equal(d[far] < 0, w[far] > 0.5)


def test_float32_and_float64_inputs_give_the_same_values(mesh_path, rng):
    f = frep.load(mesh_path("spot.obj"))
    p64 = rng.uniform(-1, 1, (5000, 3))
    p32 = p64.astype(np.float32)
    np.testing.assert_array_equal(f.sdf(p64), f.sdf(p32))
    # Strided views and integer arrays are read too.
    np.testing.assert_array_equal(f.sdf(np.asfortranarray(p32)), f.sdf(p32))
    assert f.sdf(np.zeros((3, 3), np.int64)).shape == (3,)
    np.testing.assert_array_equal(f.sdf(p64[:4].tolist()), f.sdf(p32[:4]))  # lists too
    assert f(p32).dtype == np.float32


def test_gradients_and_intervals():
    s = frep.sphere((0, 0, 0), 1)
    p = np.array([[2.0, 0, 0], [0, -3, 0], [1, 1, 1]], np.float32)
    g = s.gradient(p)
    np.testing.assert_allclose(g, p / np.linalg.norm(p, axis=1)[:, None], atol=1e-6)
    lo, hi = s.interval(((1, 1, 1), (2, 2, 2)))
    # Holds the true range (up to float32 rounding of its ends).
    assert lo <= np.sqrt(3) - 1 + 1e-6 and hi >= np.sqrt(12) - 1 - 1e-6
    assert lo > 0  # the box is outside


def _npy(path):
    return np.load(path, allow_pickle=False)


@pytest.mark.parametrize("extra", [[], ["--truncate", "0.05"]])
def test_mesh_grid_equals_the_cli_byte_for_byte(mesh_path, cli, tmp_path, extra):
    path = mesh_path("spot.obj")
    out = tmp_path / "grid.npy"
    cli("sample", path, "-o", out, "--grid", 24, "-q", *extra)
    truncate = float(extra[1]) if extra else 0
    grid = frep.load(path).sample_grid(24, truncate=truncate)
    assert grid.shape == (24, 24, 24) and grid.dtype == np.float32
    assert grid.tobytes() == _npy(out).tobytes()


def test_expression_grid_and_points_equal_the_cli(data_path, cli, tmp_path):
    path = data_path("vm", "hi.vm")
    f = frep.load(path)
    cli("sample", path, "-o", tmp_path / "g.npy", "--grid", 32, "--bounds", "-1,-1,-1,1,1,1", "-q")
    assert f.sample_grid(32, bounds=((-1, -1, -1), (1, 1, 1))).tobytes() == _npy(tmp_path / "g.npy").tobytes()
    cli("sample", path, "-o", tmp_path / "p.npy", "--points", 1000, "--seed", 7, "-q")
    pts = f.sample_points(1000, seed=7)
    assert pts.shape == (1000, 4) and pts.tobytes() == _npy(tmp_path / "p.npy").tobytes()


def test_mesh_points_equal_the_cli(mesh_path, cli, tmp_path):
    path = mesh_path("bunny_closed_libigl.off")
    f = frep.load(path)
    cli("sample", path, "-o", tmp_path / "u.npy", "--points", 2000, "--seed", 3, "-q")
    assert f.sample_points(2000, seed=3).tobytes() == _npy(tmp_path / "u.npy").tobytes()
    cli("sample", path, "-o", tmp_path / "n.npy", "--near-surface", 1500, "--sigma", 0.01, "--seed", 5, "-q")
    near = f.sample_points(1500, kind="near-surface", sigma=0.01, seed=5)
    assert near.tobytes() == _npy(tmp_path / "n.npy").tobytes()
    # The rows' distances are the field's at the rows' points.
    np.testing.assert_array_equal(f.sdf(near[:, :3]), near[:, 3])


def test_threads_do_not_change_results(mesh_path):
    f = frep.load(mesh_path("spot.obj"))
    one = f.sample_points(3000, seed=1, threads=1)
    frep.set_threads(2)
    try:
        assert frep.get_threads() == 2
        np.testing.assert_array_equal(f.sample_points(3000, seed=1), one)
    finally:
        frep.set_threads(0)
    with pytest.raises(ValueError):
        frep.set_threads(-1)
