"""Batches release the GIL, and fits spread over a Dask cluster equal one process's."""

import pathlib
import sys
import threading
import time

import numpy as np

import stfit

from conftest import EXAMPLE


def test_long_calls_release_the_gil():
    """While one thread is inside a long random-walk estimate, another runs Python code: it
    finds the estimate unfinished after its own short sleep. With the GIL held, the second
    thread could not run until the estimate had returned."""
    sys.setswitchinterval(1e-4)
    walk = stfit.Microsurface(stfit.Ggx(0.4), 1.5)
    started, result = threading.Event(), []

    def work():
        started.set()
        result.append(walk.albedo([0.0, 0.0, 1.0], walks=4_000_000, seed=1))

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    time.sleep(0.05)
    seen_during_call = len(result)
    worker.join()
    assert seen_during_call == 0
    assert len(result) == 1 and result[0].walks == 4_000_000


def test_threads_get_the_results_of_one_thread():
    """Concurrent calls from several threads are independent: same inputs, same outputs."""
    glass = stfit.RoughDielectric(stfit.Ggx(0.3), 1.5)
    rng = np.random.default_rng(0)
    wi = rng.normal(size=(100_000, 3))
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    want = glass.sample(wi, seed=9).wo
    got = [None] * 4

    def work(k):
        got[k] = glass.sample(wi, seed=9).wo

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(g, want) for g in got)


def test_dask_cluster_fits_equal_one_process():
    """The example's samples fitted as parallel tasks on a local Dask cluster (two worker
    processes) return exactly the fits one process makes."""
    from dask.distributed import Client, LocalCluster

    path = str(pathlib.Path(EXAMPLE))
    samples = stfit.load(path).samples
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        # Each task calls stfit.fit on one sample, in a worker process.
        futures = [client.submit(stfit.fit, path, sample=s, model="all", pure=False)
                   for s in samples]
        distributed = [fit for part in client.gather(futures) for fit in part]
    local = stfit.fit(path, model="all")
    assert distributed == local
    assert [f.to_json() for f in distributed] == [f.to_json() for f in local]


def test_an_array_changed_by_another_thread_during_a_call_is_read_once():
    """A call copies its directions once, then checks and uses that copy: another Python
    thread writing NaN into the array while the GIL is released makes the call either refuse
    the NaN (ValueError naming the row) or evaluate the directions it checked, never a panic
    (the search for the bad row after a failed check found none) or NaN values (a direction
    changed after its check)."""
    sys.setswitchinterval(1e-6)
    glass = stfit.RoughDielectric(stfit.Ggx(0.3), 1.5)
    ndf = stfit.Ggx(0.3)
    n = 200_000
    wi = np.tile([0.0, 0.0, 1.0], (n, 1))
    wo = np.tile([0.0, 0.0, -1.0], (n, 1))
    stop = threading.Event()

    def spoil():
        row = wi[n - 1]
        while not stop.is_set():
            row[2] = np.nan
            row[2] = 1.0

    spoiler = threading.Thread(target=spoil)
    spoiler.start()
    try:
        for call in [lambda: glass.eval(wi, wo), lambda: ndf.d(wi)] * 100:
            try:
                values = call()
            except ValueError as e:
                assert str(e).startswith((f"wi[{n - 1}]", f"wm[{n - 1}]")), str(e)
                continue
            assert np.all(np.isfinite(values))
    finally:
        stop.set()
        spoiler.join()
        sys.setswitchinterval(0.005)
