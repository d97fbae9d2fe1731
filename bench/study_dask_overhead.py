"""Per-task overhead of the Dask scheduler, and the cluster size at which it becomes the limit.

    .venv/bin/python bench/study_dask_overhead.py [--n 3000] [--workers 2]

Submits N no-op futures (one per call, as the engine submits one per chunk) to a LocalCluster and
times them to completion: the wall time per future is the driver + scheduler + worker round trip
when the work itself is nil. With tasks of mean time t (a study chunk: tasks per chunk x mean task
time), the scheduler keeps W workers busy while W x overhead < t, so W_max = t / overhead.
"""
import argparse
import time


def noop(x):
    return x


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=3000)
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args()
    from distributed import Client, LocalCluster, as_completed
    with LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cl, Client(cl) as c:
        c.submit(noop, 0).result()
        for rep in range(2):
            t0 = time.perf_counter()
            fs = [c.submit(noop, i, pure=False) for i in range(a.n)]
            for f in as_completed(fs):
                f.result()
            dt = time.perf_counter() - t0
            print(f"run {rep}: {a.n} no-op futures on {a.workers} workers in {dt:.2f} s: "
                  f"{1e3 * dt / a.n:.2f} ms per future ({a.n / dt:.0f} futures/s)")


if __name__ == "__main__":
    main()
