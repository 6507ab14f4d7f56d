"""Shared fixtures: the real test meshes (../shared/data beside the source tree, skipped when
absent), the frep CLI to compare against (FREP_CLI, set by ctest), and small helpers."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("FREP_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA_DIR = SOURCE_DIR.parent / "shared" / "data"


def data_file(*parts):
    """A file of the shared test data, or skip the test saying what is missing."""
    path = DATA_DIR.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"{path} is absent (the shared test data, ../shared/data beside the source tree); skipping")
    return path


@pytest.fixture
def mesh_path():
    return lambda name: data_file("meshes", name)


@pytest.fixture
def data_path():
    return data_file


def _find_cli():
    env = os.environ.get("FREP_CLI")
    if env:
        return pathlib.Path(env)
    for build in ("build-py", "build"):
        candidate = SOURCE_DIR / build / "frep"
        if candidate.exists():
            return candidate
    return None


@pytest.fixture
def cli():
    """Runs the frep CLI with the given arguments (checking success), or skips without it."""
    path = _find_cli()
    if path is None or not path.exists():
        pytest.skip("the frep CLI was not found (set FREP_CLI to the built binary); skipping the comparison")

    def run(*args):
        return subprocess.run([str(path), *map(str, args)], check=True, capture_output=True, text=True)

    return run


@pytest.fixture
def rng():
    return np.random.default_rng(1234)


def edges_shared_twice(faces):
    """True if every directed edge appears once and its reverse once: a closed, consistently
    oriented, edge-manifold surface."""
    f = np.asarray(faces, dtype=np.int64)
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    keys = directed[:, 0] * (f.max() + 1) + directed[:, 1]
    reverse = directed[:, 1] * (f.max() + 1) + directed[:, 0]
    return len(np.unique(keys)) == len(keys) and np.array_equal(np.sort(keys), np.sort(reverse))


def winding_numbers(vertices, faces, points):
    """The generalized winding number of a triangle mesh at points (van Oosterom and Strackee's
    solid angles), independent of frep."""
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(faces)]
    w = np.zeros(len(points))
    for i, p in enumerate(np.asarray(points, dtype=np.float64)):
        a, b, c = tri[:, 0] - p, tri[:, 1] - p, tri[:, 2] - p
        la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la
               + np.einsum("ij,ij->i", c, a) * lb)
        w[i] = np.sum(2 * np.arctan2(det, den)) / (4 * np.pi)
    return w

