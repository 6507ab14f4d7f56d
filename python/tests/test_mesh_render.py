"""Meshes and pictures of fields."""

import numpy as np
import pytest

import frep
from conftest import edges_shared_twice


def test_mesh_is_closed_and_on_the_surface(tmp_path):
    s = frep.sphere((0.1, 0, 0), 0.8)
    v, f = s.mesh(resolution=32)
    assert v.dtype == np.float64 and v.shape[1] == 3
    assert f.dtype == np.uint32 and f.shape[1] == 3 and len(f) > 500
    assert edges_shared_twice(f)
    r = np.linalg.norm(v - [0.1, 0, 0], axis=1)
    assert np.all(np.abs(r - 0.8) < 0.8 * 2 / 32)
    frep.write_mesh(tmp_path / "s.stl", v, f)
    assert frep.check(tmp_path / "s.stl")["is_solid"]


def test_mesh_of_a_loaded_mesh(mesh_path):
    f = frep.load(mesh_path("cube_unit_bin.stl"))
    v, faces = f.mesh(resolution=16)
    assert edges_shared_twice(faces)
    assert frep.check((v, faces))["is_solid"]
    # Dual contouring keeps the cube's sharp corners.
    assert np.allclose(np.abs(v).max(axis=0), 0.5, atol=1e-3)


def test_mesh_max_error_as_frep_mesh():
    box = frep.box((-0.3, -0.2, -0.1), (0.3, 0.25, 0.2))
    v0, f0 = box.mesh(resolution=32, max_error=0)  # the uniform mesh of the grid
    vf, ff = box.mesh(resolution=32)  # default: flat regions merged
    vs, fs = box.mesh(resolution=32, max_error="0.05c")
    assert len(f0) > 1000 and len(ff) <= 24 and len(fs) <= 24
    for v, f in ((v0, f0), (vf, ff), (vs, fs)):
        assert edges_shared_twice(f)
        assert frep.check((v, f))["is_solid"]
    with pytest.raises(ValueError, match="max_error"):
        box.mesh(resolution=8, max_error="-1")


def test_mesh_with_bounds_is_capped():
    v, f = frep.plane((0, 0, 1), 0).mesh(resolution=8, bounds=((-1, -1, -1), (1, 1, 1)))
    assert edges_shared_twice(f)
    assert v[:, 2].max() == pytest.approx(0, abs=1e-6)


def test_render_pictures():
    s = frep.sphere((0, 0, 0), 0.7)
    img = s.render(size=64)  # the iso view of a cube of space: 64 pixels along the longer side
    assert max(img.shape[:2]) == 64 and img.shape[2] == 3 and img.dtype == np.uint8
    background = np.array([72, 72, 76], np.uint8)
    hit = np.any(img != background, axis=2)
    assert hit[img.shape[0] // 2, img.shape[1] // 2] and not hit[0, 0]
    depth = s.render(size=48, view="front", mode="depth")
    assert depth.shape == (48, 48, 1) and depth[24, 24, 0] > 0
    assert s.render(size=32, mode="normals").shape == (32, 28, 3)
    sl = s.render_slice(axis="z", offset=0.0, size=40)
    assert sl.shape[2] == 3 and sl.shape[1] == 40
    pic = s.render_2d(size=50)
    assert pic.shape == (50, 50, 1) and pic[25, 25, 0] == 255 and pic[0, 0, 0] == 0
    with pytest.raises(ValueError):
        s.render(view="sideways")
