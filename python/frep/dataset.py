"""frep dataset: signed-distance training data for a whole folder of meshes, on one machine or a cluster.

Each mesh is one Dask task, and each task runs the ``frep`` program itself (``frep sample ... --json``)
as child processes: a timeout can stop it, a crash cannot take the worker down, and the files are
those ``frep sample`` writes alone. The client appends one manifest line per mesh as results arrive.

Pure Python (standard library, Dask distributed; numpy is not needed here): it runs without the
compiled ``frep._core`` module. Usable as ``frep.dataset(...)``, ``python -m frep.dataset`` and
``frep dataset``.
"""

import argparse
import hashlib
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import types

MESH_EXTENSIONS = (".stl", ".obj", ".ply", ".off")
NORMALIZATIONS = ("unit-cube", "unit-sphere", "none")
MANIFEST = "manifest.jsonl"


# ---------------------------------------------------------------------------------------------
# Inputs


def list_meshes(src):
    """(source, path) pairs: `source` as the manifest names it (relative to the folder or to the list
    file's folder), `path` the file to read. SRC is a folder (searched recursively) or a list file."""
    src = os.path.abspath(src)
    if os.path.isdir(src):
        found = []
        for root, dirs, files in os.walk(src):
            dirs.sort()
            for f in sorted(files):
                if f.lower().endswith(MESH_EXTENSIONS):
                    p = os.path.join(root, f)
                    found.append((os.path.relpath(p, src), p))
        return found
    if not os.path.isfile(src):
        raise FileNotFoundError(f"{src}: no such folder or list file")
    base = os.path.dirname(src)
    found = []
    with open(src, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            found.append((line, os.path.normpath(os.path.join(base, line))))
    return found


def sha256_of(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def output_dir_name(source, sha):
    """DST/<source with separators replaced>-<first 8 hex of the sha256>: readable, and two files
    whose paths flatten alike (a/b.stl, a__b.stl) or whose content changed never share a folder."""
    flat = source.replace("\\", "/").strip("/").replace("../", "up__").replace("/", "__")
    return f"{flat}-{sha[:8]}"


# ---------------------------------------------------------------------------------------------
# One mesh: runs on a worker. Only the standard library, so that it pickles by value.


def _run_frep(cmd, deadline):
    """Runs one frep command; returns (returncode, stdout, stderr). At the deadline: SIGTERM (frep
    then removes its temporary file), SIGKILL 5 s later, and TimeoutError."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace")
    try:
        out, err = proc.communicate(timeout=None if deadline is None else max(0.0, deadline - time.monotonic()))
    except subprocess.TimeoutExpired:
        proc.terminate()
        try:
            proc.communicate(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
        raise TimeoutError
    return proc.returncode, out, err


def process_mesh(job):
    """Samples one mesh as `job` says and returns its manifest record (never raises)."""
    t0 = time.monotonic()
    opts = job["options"]
    rec = {
        "source": job["source"],
        "path": job["path"],
        "sha256": job["sha256"],
        "status": "ok",
        "error": None,
        "triangles": None,
        "solid": None,
        "check": None,
        "repair": None,
        "normalize": opts["normalize"],
        "scale": None,
        "offset": None,
        "bounds": None,
        "outputs": {},
        "counts": {},
        "seconds": None,
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "options": opts,
    }
    deadline = None if opts.get("timeout") is None else t0 + opts["timeout"]
    frep = job["frep"]
    if not os.path.exists(frep):  # a cluster node may have frep elsewhere
        frep = os.environ.get("FREP_CLI") or shutil.which("frep") or frep
    try:
        if job.get("delay"):  # testing only: keeps tasks running long enough to kill a worker
            time.sleep(job["delay"])
        outdir = os.path.join(job["dst"], job["name"])
        os.makedirs(outdir, exist_ok=True)
        common = ["--normalize", opts["normalize"], "--seed", str(opts["seed"]), "--threads", "1", "-q", "--json"]
        if opts.get("repair"):
            common.append("--repair")
        if opts.get("bounds"):
            common += ["--bounds", ",".join(repr(float(v)) for v in opts["bounds"])]
        steps = []
        if opts.get("grid"):
            extra = ["--grid", str(opts["grid"])]
            if opts.get("truncate") is not None:
                extra += ["--truncate", repr(float(opts["truncate"]))]
            steps.append(("grid", extra, common))
        if opts.get("points"):
            steps.append(("points", ["--points", str(opts["points"])], common))
        if opts.get("near_surface"):
            # Its own seed (seed + 1): the uniform and the near-surface points draw different numbers.
            near_common = list(common)
            near_common[near_common.index("--seed") + 1] = str(opts["seed"] + 1)
            steps.append(("near_surface", ["--near-surface", str(opts["near_surface"]), "--sigma",
                                           repr(float(opts["sigma"]))], near_common))
        for kind, extra, args in steps:
            rel = os.path.join(job["name"], kind + ".npy")
            cmd = [frep, "sample", job["path"], *extra, *args, "-o", os.path.join(job["dst"], rel)]
            try:
                code, out, err = _run_frep(cmd, deadline)
            except TimeoutError:
                raise RuntimeError(f"timeout: stopped after {opts['timeout']:g} s (--timeout), during the {kind}")
            if code != 0:
                msg = " ".join(line.strip() for line in err.strip().splitlines()[-3:]) or f"exit code {code}"
                raise RuntimeError(msg if code > 0 else f"frep sample died of signal {-code}")
            summary = json.loads(out.strip().splitlines()[-1])
            for key in ("triangles", "solid", "check", "repair", "scale", "offset", "bounds"):
                if rec[key] is None:
                    rec[key] = summary.get(key)
            rec["outputs"][kind] = rel
            rec["counts"][kind] = summary["count"]
    except Exception as e:  # the record says what went wrong; the run goes on
        rec["status"] = "failed"
        rec["error"] = str(e) or type(e).__name__
    rec["seconds"] = round(time.monotonic() - t0, 3)
    return rec


# ---------------------------------------------------------------------------------------------
# The manifest


def read_manifest(path):
    """The last record per source (later lines supersede earlier ones)."""
    records = {}
    if not os.path.exists(path):
        return records
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            try:
                rec = json.loads(line)
            except ValueError:  # a line cut short by a crash: that mesh is simply redone
                continue
            records[rec.get("source")] = rec
    return records


def _same_work(rec, sha, options):
    """True when `rec` is about this very file (by hash) sampled with these options (the timeout aside:
    it changes no output)."""
    def sampling(o):
        return {k: v for k, v in (o or {}).items() if k != "timeout"}
    return rec.get("sha256") == sha and sampling(rec.get("options")) == sampling(options)


def _done(rec, sha, options, dst):
    """True when `rec` is an ok result of this very work, its outputs all there."""
    return (rec.get("status") == "ok" and _same_work(rec, sha, options)
            and all(os.path.exists(os.path.join(dst, p)) for p in rec.get("outputs", {}).values()))


def _write_compacted(path, records, order):
    """Rewrites the manifest atomically: one line per source, this run's inputs first, in input order."""
    keys = [k for k in order if k in records] + [k for k in records if k not in set(order)]
    fd, tmp = tempfile.mkstemp(prefix=".manifest.", dir=os.path.dirname(path))
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        for k in keys:
            f.write(json.dumps(records[k]) + "\n")
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


# ---------------------------------------------------------------------------------------------
# Progress


class _Progress:
    """A bar on stderr with the rate and the time left; on a terminal it redraws one line, else it
    prints a line at most every 10 s."""

    def __init__(self, total, quiet):
        self.total, self.quiet = total, quiet
        self.done = self.failed = 0
        self.t0 = time.monotonic()
        self.last = 0.0
        self.tty = sys.stderr.isatty()

    def update(self, failed):
        self.done += 1
        self.failed += failed
        self.show(self.done == self.total)

    def show(self, final=False):
        if self.quiet or self.total == 0:
            return
        now = time.monotonic()
        if not final and not self.tty and now - self.last < 10:
            return
        self.last = now
        elapsed = now - self.t0
        rate = self.done / elapsed * 60 if elapsed > 0 else 0.0
        left = (self.total - self.done) / (rate / 60) if rate > 0 else None
        width = 30
        fill = int(width * self.done / self.total)
        eta = "--" if left is None else _duration(left)
        line = (f"[{'#' * fill}{'.' * (width - fill)}] {self.done}/{self.total} meshes, {rate:.1f}/min, "
                f"{eta} left" + (f", {self.failed} failed" if self.failed else ""))
        sys.stderr.write(("\r" + line + ("\n" if final else "")) if self.tty else line + "\n")
        sys.stderr.flush()


def _duration(s):
    s = int(round(s))
    return f"{s // 3600}h{s % 3600 // 60:02d}m" if s >= 3600 else f"{s // 60}m{s % 60:02d}s"


# ---------------------------------------------------------------------------------------------
# The run


def _find_frep(frep):
    # Given, then $FREP_CLI, then the program beside the package in a build folder
    # (build/python/frep -> build/frep), then the one on PATH (an installed frep).
    beside = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "frep")
    for cand in (frep, os.environ.get("FREP_CLI"), beside if os.path.isfile(beside) else None, shutil.which("frep")):
        if cand:
            if not os.path.exists(cand):
                raise FileNotFoundError(f"the frep program was not found at {cand}")
            return os.path.abspath(cand)
    raise FileNotFoundError("the frep program was not found: pass frep=PATH (--frep), set FREP_CLI, or put frep on PATH")


def _register_by_value():
    """Workers need not import this module (the frep package needs the compiled _core): the task
    function travels by value."""
    try:
        import cloudpickle
        if __name__ != "__main__" and __name__ in sys.modules:
            cloudpickle.register_pickle_by_value(sys.modules[__name__])
    except Exception:  # older cloudpickle: workers then import frep.dataset themselves
        pass


def dataset(src, dst, *, grid=None, points=None, near_surface=None, sigma=None, truncate=None,
            normalize="unit-cube", bounds=None, seed=0, repair=False, timeout=None, workers=1, scheduler=None,
            client=None, retry_failed=False, quiet=False, frep=None, on_result=None, _task_delay=0.0):
    """Samples every mesh of `src` (a folder searched recursively, or a list file) into `dst`.

    Writes dst/<name>/grid.npy, points.npy, near_surface.npy as asked and dst/manifest.jsonl (one
    JSON object per mesh). Runs on a LocalCluster of `workers` processes (1 thread each), on the
    Dask scheduler at `scheduler` ("tcp://host:port"), or on the given dask `client`. Meshes
    already done with the same options are skipped; failed ones are retried only with
    `retry_failed`. `on_result(record)` is called as each result arrives. Returns a summary dict:
    {"ok", "failed", "skipped", "total", "seconds", "manifest"}.
    """
    if not (grid or points or near_surface):
        raise ValueError("give grid=N, points=N or near_surface=N (with sigma)")
    if near_surface and sigma is None:
        raise ValueError("near_surface needs sigma")
    if truncate is not None and not grid:
        raise ValueError("truncate applies to grid")
    if normalize not in NORMALIZATIONS:
        raise ValueError(f"normalize must be one of {', '.join(NORMALIZATIONS)}")
    t0 = time.monotonic()
    frep = _find_frep(frep)
    dst = os.path.abspath(dst)
    os.makedirs(dst, exist_ok=True)
    options = {"grid": grid or None, "points": points or None, "near_surface": near_surface or None,
               "sigma": sigma if near_surface else None, "truncate": truncate, "normalize": normalize,
               "bounds": list(bounds) if bounds else None, "seed": int(seed), "repair": bool(repair),
               "timeout": timeout}
    manifest = os.path.join(dst, MANIFEST)
    previous = read_manifest(manifest)
    records = dict(previous)
    inputs = list_meshes(src)
    order = [s for s, _ in inputs]
    jobs, skipped, early = [], 0, []
    for source, path in inputs:
        try:
            sha = sha256_of(path)
        except OSError as e:
            early.append({"source": source, "path": path, "sha256": None, "status": "failed",
                          "error": f"cannot read: {e.strerror or e}", "outputs": {}, "counts": {},
                          "options": options})
            continue
        old = previous.get(source)
        if old is not None and _done(old, sha, options, dst):
            skipped += 1
            continue
        if old is not None and old.get("status") == "failed" and _same_work(old, sha, options) and not retry_failed:
            skipped += 1
            continue
        jobs.append({"source": source, "path": path, "sha256": sha, "name": output_dir_name(source, sha),
                     "dst": dst, "frep": frep, "options": options, "delay": _task_delay,
                     "size": os.path.getsize(path)})
    progress = _Progress(len(jobs) + len(early), quiet)
    if not quiet:
        sys.stderr.write(f"frep dataset: {len(inputs)} meshes, {len(jobs) + len(early)} to do, {skipped} done before\n")
    with open(manifest, "a", encoding="utf-8") as out:
        def record(rec):
            out.write(json.dumps(rec) + "\n")
            out.flush()  # a crash of the client loses at most the line being written
            records[rec["source"]] = rec
            progress.update(rec["status"] != "ok")
            if on_result:
                on_result(rec)

        for rec in early:
            record(rec)
        if jobs:
            _run_jobs(jobs, record, workers, scheduler, client, quiet)
    _write_compacted(manifest, records, order)
    current = [records[s] for s in order if s in records]
    ok = sum(r.get("status") == "ok" for r in current)
    return {"ok": ok, "failed": len(current) - ok, "skipped": skipped, "total": len(inputs),
            "seconds": round(time.monotonic() - t0, 3), "manifest": manifest}


def _run_jobs(jobs, record, workers, scheduler, client, quiet):
    import logging

    from distributed import Client, LocalCluster, as_completed

    _register_by_value()
    own_cluster = own_client = None
    try:
        if client is None:
            if scheduler:
                client = own_client = Client(scheduler)
            else:
                # Processes of one thread: each runs one frep child at a time, which uses one core.
                # No memory limit: the work happens in the children, which the nanny does not see.
                own_cluster = LocalCluster(n_workers=max(1, int(workers)), threads_per_worker=1, processes=True,
                                           memory_limit=0, dashboard_address=None,
                                           silence_logs=logging.ERROR if quiet else logging.WARNING)
                client = own_client = Client(own_cluster)
        # Biggest files first: the long tasks start early and the last ones to finish are short.
        futures = {}
        for job in sorted(jobs, key=lambda j: -j["size"]):
            fut = client.submit(process_mesh, job, key=f"frep-dataset-{job['sha256'][:16]}-{os.urandom(4).hex()}",
                                pure=False, priority=job["size"])
            futures[fut] = job
        for fut in as_completed(list(futures)):
            job = futures[fut]
            try:
                rec = fut.result()
            except Exception as e:  # the task's worker died too often (KilledWorker), or the cluster failed
                rec = {"source": job["source"], "path": job["path"], "sha256": job["sha256"], "status": "failed",
                       "error": f"{type(e).__name__}: {e}", "outputs": {}, "counts": {}, "options": job["options"]}
            record(rec)
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()


# ---------------------------------------------------------------------------------------------
# Command line


def _parser():
    p = argparse.ArgumentParser(
        prog=os.environ.get("FREP_DATASET_PROG", "python -m frep.dataset"),
        description="Sample exact signed distances of every mesh in SRC (a folder searched recursively for "
                    ".stl .obj .ply .off, or a text file listing meshes one per line, relative to its folder) "
                    "into DST, with DST/manifest.jsonl recording each mesh. Reruns skip meshes already done.",
        epilog="Exit codes: 0 all meshes ok, 1 some failed (the manifest says why), 2 usage error.")
    p.add_argument("src", metavar="SRC", help="folder of meshes, or a list file")
    p.add_argument("-o", "--output", required=True, metavar="DST", help="output folder (shared by all workers)")
    p.add_argument("--grid", type=int, metavar="N", help="dense N^3 grid of signed distances: grid.npy")
    p.add_argument("--points", type=int, metavar="N", help="N points uniform in the bounds: points.npy rows (x,y,z,d)")
    p.add_argument("--near-surface", type=int, metavar="N", help="N points near the surface: near_surface.npy")
    p.add_argument("--sigma", type=float, metavar="S", help="noise deviation of --near-surface (normalized units)")
    p.add_argument("--truncate", type=float, metavar="D", help="with --grid: clamp distances to [-D, D]")
    p.add_argument("--normalize", choices=NORMALIZATIONS, default="unit-cube",
                   help="unit-cube (default): the mesh's box centred at the origin, longest side 1, bounds "
                        "[-0.55,0.55]^3; unit-sphere: box centre at the origin, farthest vertex at distance 1, "
                        "bounds [-1.1,1.1]^3; none: as frep sample. original = normalized / scale + offset")
    p.add_argument("--bounds", metavar="x0,y0,z0,x1,y1,z1", help="sampling box (default: by --normalize)")
    p.add_argument("--seed", type=int, default=0, help="seed of the points (near-surface ones use seed + 1)")
    p.add_argument("--repair", action="store_true", help="repair meshes that are not valid solids first")
    p.add_argument("--timeout", type=float, metavar="S", help="stop a mesh after S seconds and record it as failed")
    p.add_argument("--workers", type=int, default=1, metavar="N", help="local worker processes (default 1)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="run on this Dask scheduler's workers instead")
    p.add_argument("--retry-failed", action="store_true", help="retry meshes that failed in an earlier run")
    p.add_argument("--frep", metavar="PATH", help="the frep program (default: $FREP_CLI, else frep on PATH)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return p


def main(argv=None):
    p = _parser()
    a = p.parse_args(argv)
    for name in ("grid", "points", "near_surface", "workers"):
        v = getattr(a, name)
        if v is not None and v < (1 if name == "workers" else 0):
            p.error(f"--{name.replace('_', '-')} must be a whole number >= {1 if name == 'workers' else 0}")
    if not (a.grid or a.points or a.near_surface):
        p.error("give --grid N, --points N or --near-surface N --sigma S")
    if a.grid is not None and not 2 <= a.grid <= 4096:
        p.error("--grid must be from 2 to 4096")
    if bool(a.near_surface) != (a.sigma is not None):
        p.error("--near-surface and --sigma go together")
    if a.truncate is not None and (not a.grid or not a.truncate > 0):
        p.error("--truncate needs --grid and a length > 0")
    if a.timeout is not None and not a.timeout > 0:
        p.error("--timeout must be > 0")
    bounds = None
    if a.bounds:
        try:
            bounds = [float(v) for v in a.bounds.split(",")]
        except ValueError:
            bounds = []
        if len(bounds) != 6 or not all(bounds[i] < bounds[i + 3] for i in range(3)):
            p.error("--bounds needs six numbers x0,y0,z0,x1,y1,z1 with x0 < x1, y0 < y1, z0 < z1")
    if not os.path.exists(a.src):
        p.error(f"{a.src}: no such folder or list file")
    try:
        import distributed  # noqa: F401
    except ImportError:
        sys.stderr.write(f"frep dataset: this Python ({sys.executable}) has no Dask distributed: "
                         "install python3-distributed (Debian, Ubuntu) or pip install distributed\n")
        return 1
    try:
        s = dataset(a.src, a.output, grid=a.grid, points=a.points, near_surface=a.near_surface, sigma=a.sigma,
                    truncate=a.truncate, normalize=a.normalize, bounds=bounds, seed=a.seed, repair=a.repair,
                    timeout=a.timeout, workers=a.workers, scheduler=a.scheduler, retry_failed=a.retry_failed,
                    quiet=a.quiet, frep=a.frep)
    except (OSError, ValueError) as e:
        sys.stderr.write(f"frep dataset: error: {e}\n")
        return 1
    if not a.quiet:
        sys.stderr.write(f"frep dataset: {s['ok']} ok, {s['failed']} failed, {s['skipped']} done before, "
                         f"{s['seconds']:.1f} s; manifest {s['manifest']}\n")
    return 0 if s["failed"] == 0 else 1


class _CallableModule(types.ModuleType):
    """Lets `frep.dataset(...)` call dataset() even once `import frep.dataset` has bound this module
    to the package's attribute of that name (a submodule import does that)."""

    def __call__(self, *args, **kwargs):
        return dataset(*args, **kwargs)


if __name__ == "__main__":
    sys.exit(main())
elif __name__ in sys.modules:
    sys.modules[__name__].__class__ = _CallableModule
