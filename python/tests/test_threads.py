"""The GIL is released while frep works: another Python thread makes progress meanwhile."""

import threading
import time

import numpy as np

import frep


def test_other_threads_run_while_sdf_works(mesh_path, rng):
    f = frep.load(mesh_path("bunny_closed_libigl.off"))
    (lo, hi) = np.array(f.info.bounds)
    n = 200_000
    while True:
        points = rng.uniform(lo, hi, (n, 3)).astype(np.float32)
        done = {}

        def work():
            start = time.perf_counter()
            done["values"] = f.sdf(points, threads=1)
            done["seconds"] = time.perf_counter() - start

        t = threading.Thread(target=work)
        ticks = 0
        t.start()
        while t.is_alive():
            ticks += 1
            time.sleep(0.001)
        t.join()
        if done["seconds"] >= 0.2 or n >= 6_400_000:
            break
        n *= 4  # too quick to tell on this machine: more work
    assert done["values"].shape == (n,)
    # Holding the GIL would stall this loop for the whole call (a tick or two); without it, it
    # ticks about every millisecond.
    assert ticks >= 20, f"{ticks} ticks in {done['seconds']:.2f} s of sdf"
