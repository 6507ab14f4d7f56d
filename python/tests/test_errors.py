"""Errors are Python exceptions saying where the problem is: frep.InputError (a ValueError) with
the file, the line and the byte offset."""

import numpy as np
import pytest

import frep


def test_input_error_is_a_value_error():
    assert issubclass(frep.InputError, ValueError)


def test_malformed_vm_names_file_and_line(tmp_path):
    path = tmp_path / "bad.vm"
    path.write_text("_0 var-x\n_1 var-y\n_2 frobnicate _0 _1\n")
    with pytest.raises(frep.InputError) as e:
        frep.load(path)
    assert e.value.file == str(path)
    assert e.value.line == 3
    assert "bad.vm" in str(e.value) and e.value.detail


def test_broken_ascii_stl_names_file_and_line(tmp_path):
    path = tmp_path / "broken.stl"
    path.write_text("solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 nonsense\n"
                    "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n")
    with pytest.raises(frep.InputError) as e:
        frep.check(path)
    assert e.value.file == str(path) and e.value.line == 5


def test_broken_binary_mesh_names_the_byte(tmp_path):
    path = tmp_path / "broken.ply"
    header = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" \
             b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    path.write_bytes(header + np.zeros(9, np.float32).tobytes() + b"\x03\x00")  # the face is cut short
    with pytest.raises(frep.InputError) as e:
        frep.read_mesh(path)
    assert e.value.file == str(path) and e.value.byte > 0


def test_script_errors_name_the_line():
    with pytest.raises(frep.InputError) as e:
        frep.parse("let a = sphere([0, 0, 0], 1);\nlet b = ;\n", name="model.rhai")
    assert e.value.file == "model.rhai" and e.value.line == 2


def test_refused_meshes_and_missing_files(mesh_path, tmp_path):
    with pytest.raises(frep.InputError) as e:
        frep.load(mesh_path("soup_random.stl"))
    assert "not a solid" in str(e.value)
    with pytest.raises(frep.InputError) as e:
        frep.load(tmp_path / "missing.stl")
    assert e.value.file.endswith("missing.stl")
    with pytest.raises(frep.InputError):
        frep.sphere().save(tmp_path / "x.unknown")


def test_bad_arguments_are_value_errors():
    s = frep.sphere()
    with pytest.raises(ValueError):
        s.sdf(np.zeros((4, 2)))
    with pytest.raises(ValueError):
        s.sample_points(10, kind="gaussian")
    with pytest.raises(ValueError):
        s.sample_points(10, kind="near-surface")  # no sigma
    with pytest.raises(ValueError):
        s.sample_grid(8, bounds=((1, 0, 0), (0, 1, 1)))
    with pytest.raises(frep.InputError):
        s.sample_grid(1)
