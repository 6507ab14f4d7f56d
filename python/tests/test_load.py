"""Loading fields from files, and the mesh tools: check, repair, convert, reading and writing."""

import numpy as np
import pytest

import frep
from conftest import edges_shared_twice


def test_load_mesh_is_its_exact_distance(mesh_path):
    f = frep.load(mesh_path("sphere_icosa_1280.stl"))
    assert f.is_mesh
    assert f.info.lipschitz == 1
    assert f.info.growth == "distance"
    (lo, hi) = f.info.bounds
    vertices, _ = frep.read_mesh(mesh_path("sphere_icosa_1280.stl"))
    assert np.allclose(lo, vertices.min(axis=0)) and np.allclose(hi, vertices.max(axis=0))


def test_load_expression_and_script(data_path):
    vm = frep.load(data_path("vm", "hi.vm"))
    assert not vm.is_mesh
    values = vm.sdf(np.zeros((1, 3), np.float32))
    assert values.shape == (1,) and values.dtype == np.float32
    script = frep.parse("sphere([0, 0, 0], 0.5)")
    assert script.sdf(np.array([[0.0, 0.0, 0.0]]))[0] == pytest.approx(-0.5)


def test_check_reports_as_dicts(mesh_path):
    good = frep.check(mesh_path("sphere_icosa_1280.stl"))
    assert good["is_solid"] and good["summary"].startswith("valid solid")
    assert good["triangles"] == 1280
    bad = frep.check(mesh_path("wallhole.obj"))
    assert not bad["is_solid"] and bad["summary"].startswith("not a solid")
    # Arrays work as well as files.
    v, f = frep.read_mesh(mesh_path("sphere_icosa_1280.stl"))
    assert frep.check((v, f))["is_solid"]


def test_repair_to_arrays_and_file(mesh_path, tmp_path):
    v, f, report = frep.repair(mesh_path("wallhole.obj"))
    assert v.dtype == np.float64 and v.shape[1] == 3 and f.shape[1] == 3
    assert frep.check((v, f))["is_solid"] and edges_shared_twice(f)
    assert isinstance(report, dict)
    out = tmp_path / "fixed.stl"
    frep.repair(mesh_path("wallhole.obj"), out)
    assert frep.check(out)["is_solid"]
    # load(repair=True) repairs on the way in; without it the broken mesh is refused.
    with pytest.raises(frep.InputError):
        frep.load(mesh_path("wallhole.obj"))
    assert frep.load(mesh_path("wallhole.obj"), repair=True).info.lipschitz == 1


def test_convert_and_save_round_trip(mesh_path, tmp_path, rng):
    src = mesh_path("cube_unit_bin.stl")
    points = rng.uniform(-0.5, 1.5, (500, 3)).astype(np.float32)
    direct = frep.load(src).sdf(points)
    stats = frep.convert(src, tmp_path / "cube.vm")
    assert stats["triangles"] == 12
    closed_form = frep.load(tmp_path / "cube.vm")
    assert closed_form.info.lipschitz == 1
    np.testing.assert_allclose(closed_form.sdf(points), direct, atol=1e-5)
    frep.convert(src, tmp_path / "cube.frep")
    assert frep.load(tmp_path / "cube.frep").is_mesh
    # Field.save keeps the facts.
    shape = frep.ugf.offset(frep.sphere((0, 0, 0), 1), 0.25)
    shape.save(tmp_path / "s.vm")
    again = frep.load(tmp_path / "s.vm")
    assert again.info.bounds == shape.info.bounds and again.info.lipschitz == 1
    np.testing.assert_array_equal(again.sdf(points), shape.sdf(points))


def test_mesh_arrays_round_trip(mesh_path, tmp_path):
    v, f = frep.read_mesh(mesh_path("cube_quads.off"))
    assert f.dtype == np.uint32 and len(f) == 12
    frep.write_mesh(tmp_path / "c.ply", v, f)
    v2, f2 = frep.read_mesh(tmp_path / "c.ply")
    np.testing.assert_array_equal(v, v2)
    np.testing.assert_array_equal(f, f2)
    field = frep.mesh_field(v, f)
    assert field.is_mesh and field.sdf(np.zeros((1, 3), np.float32))[0] < 0


def test_importing_frep_needs_no_dask():
    import subprocess
    import sys

    code = "import sys, frep; assert callable(frep.dataset); assert 'dask' not in sys.modules; print('ok')"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"
