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
