"""Tests of frep.dataset (and `frep dataset`): a Dask LocalCluster of 2 worker processes over shared
meshes, broken ones included; a worker killed mid-run; reruns that resume; timeouts.

Needs numpy, Dask distributed, the frep program (FREP_CLI) and the shared meshes (../shared/data
beside the source tree); skips with a message when one is missing.
"""

import importlib
import importlib.util
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

np = pytest.importorskip("numpy", reason="numpy is not installed")
pytest.importorskip("distributed", reason="Dask distributed is not installed (Debian: python3-distributed)")
from distributed import Client, LocalCluster  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MESHES = os.path.normpath(os.path.join(ROOT, "..", "shared", "data", "meshes"))
FREP = os.environ.get("FREP_CLI", "")

try:
    ds = importlib.import_module("frep.dataset")
    PY_CMD = [sys.executable, "-m", "frep.dataset"]
except ImportError:
    # The package's __init__ needs the compiled _core, which this pure-Python module does not:
    # load the file by path, and run it as a script.
    _file = os.path.join(ROOT, "python", "frep", "dataset.py")
    _spec = importlib.util.spec_from_file_location("frep_dataset", _file)
    ds = sys.modules["frep_dataset"] = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(ds)
    PY_CMD = [sys.executable, _file]

pytestmark = [
    pytest.mark.skipif(not FREP or not os.path.exists(FREP), reason="set FREP_CLI to the frep program"),
    pytest.mark.skipif(not os.path.isdir(MESHES), reason=f"the shared meshes are absent ({MESHES})"),
]

GOOD = ["cube_unit_bin.stl", "sphere_icosa_1280.stl", "plate_holes.stl", "bunny_closed_libigl.off"]
# Not solids (sampled with winding-number signs), and files no reader accepts.
BROKEN = ["tetrahedra_joined.obj", "soup_random.stl", "suzanne.obj"]
OPTS = dict(grid=16, points=1000, near_surface=500, sigma=0.01)


def make_src(tmp_path, good=GOOD, broken=BROKEN, garbage=True):
    """A folder of meshes with a subfolder, unreadable files and a file that is not a mesh."""
    src = tmp_path / "src"
    (src / "sub").mkdir(parents=True)
    for i, name in enumerate(good + broken):
        shutil.copy(os.path.join(MESHES, name), src / ("sub" if i % 2 else "") / name)
    if garbage:
        (src / "garbage.stl").write_bytes(b"this is not a mesh\n")
        (src / "sub" / "empty.obj").write_bytes(b"")
    (src / "README.txt").write_text("not a mesh: ignored\n")
    return src


def manifest(dst):
    with open(os.path.join(dst, "manifest.jsonl"), encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]


def frep_sample(mesh, out, *args):
    subprocess.run([FREP, "sample", str(mesh), *args, "-q", "-o", str(out)], check=True)
    return np.load(out)


def test_local_cluster_two_workers(tmp_path):
    src, dst = make_src(tmp_path), tmp_path / "dst"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        s = ds.dataset(str(src), str(dst), client=client, quiet=True, frep=FREP, **OPTS)
    recs = manifest(dst)
    sources = sorted(r["source"] for r in recs)
    inputs = sorted(p for p, _ in ds.list_meshes(str(src)))
    assert sources == inputs and len(inputs) == len(GOOD) + len(BROKEN) + 2  # every input once, no README
    by_name = {os.path.basename(r["source"]): r for r in recs}
    for bad in ("garbage.stl", "empty.obj"):
        assert by_name[bad]["status"] == "failed" and by_name[bad]["error"], by_name[bad]
    assert s["failed"] == 2 and s["ok"] == len(GOOD) + len(BROKEN)
    for name in GOOD + BROKEN:
        r = by_name[name]
        assert r["status"] == "ok", r
        assert r["solid"] is (name in GOOD), r
        assert r["triangles"] > 0 and r["scale"] > 0 and len(r["offset"]) == 3
        assert set(r["outputs"]) == {"grid", "points", "near_surface"}
        assert r["counts"] == {"grid": 16 ** 3, "points": 1000, "near_surface": 500}
        mesh = src / r["source"]
        # The same bits as frep sample run alone.
        grid = np.load(dst / r["outputs"]["grid"])
        assert grid.shape == (16, 16, 16) and grid.dtype == np.float32
        assert np.array_equal(grid, frep_sample(mesh, tmp_path / "g.npy", "--grid", "16", "--normalize", "unit-cube"))
        if name in ("bunny_closed_libigl.off", "suzanne.obj"):
            pts = np.load(dst / r["outputs"]["points"])
            near = np.load(dst / r["outputs"]["near_surface"])
            assert pts.shape == (1000, 4) and near.shape == (500, 4)
            assert np.array_equal(pts, frep_sample(mesh, tmp_path / "p.npy", "--points", "1000", "--normalize",
                                                   "unit-cube", "--seed", "0"))
            assert np.array_equal(near, frep_sample(mesh, tmp_path / "n.npy", "--near-surface", "500", "--sigma",
                                                    "0.01", "--normalize", "unit-cube", "--seed", "1"))
            # Normalized to the unit cube: every point within the fixed bounds.
            assert np.abs(pts[:, :3]).max() <= 0.55
    # No temporary file left anywhere.
    left = [f for _, _, files in os.walk(dst) for f in files if not f.endswith((".npy", ".jsonl"))]
    assert left == []


def test_killed_worker_loses_nothing(tmp_path):
    src, dst = make_src(tmp_path, good=GOOD + ["spot.obj", "fandisk.obj"], broken=[], garbage=False), tmp_path / "dst"
    killed = {}
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        pids = client.run(os.getpid)

        def kill_one(rec):
            # The worker that sent the first result has just started another mesh (1.5 s of sleep
            # first): kill it then, well before that mesh can finish.
            if killed:
                return
            pid = int(rec["worker"].rsplit(":", 1)[1])
            worker = next(w for w, p in pids.items() if p == pid)
            for _ in range(100):
                keys = client.processing().get(worker)
                if keys:
                    break
                time.sleep(0.01)
            killed.update(worker=worker, pid=pid, keys=list(keys or []))
            os.kill(pid, signal.SIGKILL)

        s = ds.dataset(str(src), str(dst), grid=8, client=client, quiet=True, frep=FREP, on_result=kill_one,
                       _task_delay=1.5)
    assert killed["keys"], "the worker had no mesh when it was killed"
    recs = manifest(dst)
    assert len(recs) == 6 and all(r["status"] == "ok" for r in recs), recs
    assert s == {**s, "ok": 6, "failed": 0}
    # The meshes the killed worker was on were done again, elsewhere.
    redone = [r for r in recs if any(k.startswith(f"frep-dataset-{r['sha256'][:16]}") for k in killed["keys"])]
    assert redone and all(not r["worker"].endswith(f":{killed['pid']}") for r in redone), (killed, recs)


def test_rerun_resumes(tmp_path):
    src, dst = make_src(tmp_path, good=GOOD[:3], broken=[], garbage=True), tmp_path / "dst"
    cmd = [*PY_CMD, str(src), "-o", str(dst), "--grid", "8", "--workers", "2", "--frep", FREP, "-q"]
    first = subprocess.run(cmd, capture_output=True, text=True)
    assert first.returncode == 1, first.stderr  # two unreadable files
    recs1 = {r["source"]: r for r in manifest(dst)}
    assert [r["status"] for r in recs1.values()].count("ok") == 3
    stamps = {p: os.stat(dst / r["outputs"]["grid"]).st_mtime_ns for p, r in recs1.items() if r["status"] == "ok"}

    # Nothing new: nothing is redone, the failed ones are not retried, the manifest is the same.
    again = subprocess.run([*cmd[:-1]], capture_output=True, text=True)
    assert again.returncode == 1 and "0 to do, 5 done before" in again.stderr, again.stderr
    assert {r["source"]: r for r in manifest(dst)} == recs1
    assert {p: os.stat(dst / recs1[p]["outputs"]["grid"]).st_mtime_ns for p in stamps} == stamps

    # A new mesh is done alone; a changed file gets a new hash and is redone; --retry-failed retries.
    shutil.copy(os.path.join(MESHES, "spot.obj"), src / "spot.obj")
    (src / "garbage.stl").write_bytes(b"still not a mesh, but other bytes\n")
    third = subprocess.run([*cmd[:-1]], capture_output=True, text=True)
    assert "2 to do, 4 done before" in third.stderr, third.stderr
    recs3 = {r["source"]: r for r in manifest(dst)}
    assert len(recs3) == 6 and recs3["spot.obj"]["status"] == "ok"
    assert recs3["sub/empty.obj"] == recs1["sub/empty.obj"]
    fourth = subprocess.run([*cmd, "--retry-failed"], capture_output=True, text=True)
    assert fourth.returncode == 1
    recs4 = {r["source"]: r for r in manifest(dst)}
    assert recs4["sub/empty.obj"]["status"] == "failed" and recs4["sub/empty.obj"]["worker"] != \
        recs1["sub/empty.obj"]["worker"]
    assert {p: os.stat(dst / recs1[p]["outputs"]["grid"]).st_mtime_ns for p in stamps} == stamps
    # Other options: everything is redone.
    fifth = subprocess.run([*cmd[:-1], "--normalize", "unit-sphere"], capture_output=True, text=True)
    assert "6 to do, 0 done before" in fifth.stderr, fifth.stderr


def test_timeout_and_list_file(tmp_path):
    (tmp_path / "lists").mkdir()
    lst = tmp_path / "lists" / "meshes.txt"
    rel = os.path.relpath(MESHES, lst.parent)
    lst.write_text(f"# two meshes\n\n{rel}/armadillo_libigl.obj\n{rel}/cube_unit_bin.stl\n{rel}/no_such_mesh.stl\n")
    dst = tmp_path / "dst"
    s = ds.dataset(str(lst), str(dst), grid=64, workers=1, timeout=0.3, quiet=True, frep=FREP)
    recs = {os.path.basename(r["source"]): r for r in manifest(dst)}
    assert len(recs) == 3 and s["failed"] == 2
    assert recs["armadillo_libigl.obj"]["status"] == "failed"
    assert recs["armadillo_libigl.obj"]["error"].startswith("timeout"), recs["armadillo_libigl.obj"]
    assert recs["cube_unit_bin.stl"]["status"] == "ok"
    assert "cannot read" in recs["no_such_mesh.stl"]["error"]
    left = [f for _, _, files in os.walk(dst) for f in files if not f.endswith((".npy", ".jsonl"))]
    assert left == []  # the stopped frep removed its temporary file


def test_command_lines(tmp_path):
    h = subprocess.run([*PY_CMD, "--help"], capture_output=True, text=True)
    assert h.returncode == 0 and "--scheduler" in h.stdout
    bad = subprocess.run([*PY_CMD, str(tmp_path), "-o", str(tmp_path / "d")], capture_output=True, text=True)
    assert bad.returncode == 2 and "--grid" in bad.stderr
    if PY_CMD[1] != "-m":
        pytest.skip("frep dataset needs the frep package importable (its _core is not built here)")
    h = subprocess.run([FREP, "dataset", "--help"], capture_output=True, text=True)
    assert h.returncode == 0 and "--workers" in h.stdout
    src = make_src(tmp_path, good=GOOD[:1], broken=[], garbage=True)
    env = dict(os.environ, FREP_PYTHONPATH=os.path.dirname(os.path.dirname(ds.__file__)), FREP_PYTHON=sys.executable)
    r = subprocess.run([FREP, "dataset", str(src), "-o", str(tmp_path / "d"), "--points", "100", "--workers", "2"],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 1, r.stderr  # the unreadable files
    recs = manifest(tmp_path / "d")
    assert len(recs) == 3 and sum(r["status"] == "ok" for r in recs) == 1
