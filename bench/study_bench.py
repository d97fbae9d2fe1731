"""Wall time, per-task overhead and driver peak RSS of a study run (issue 14 acceptance).

    nice -n 5 .venv/bin/python bench/study_bench.py [--spec bench/studies/grid12k.toml] [--out out/grid12k]
                                                    [--workers 2 | --dask local:2] [--max-tasks N]

Runs the spec (resuming if OUT has results: use a fresh OUT for a timing), samples the load average
every 10 s, then prints: tasks, wall time, tasks/s, the sum of the task functions' own time (t_task:
load + embed + attack + extract + measure, measured inside the worker), the per-task overhead
``(wall x workers - sum t_task) / tasks`` beside the mean bare task time, the driver's peak RSS
(getrusage of this process) and the load averages seen.
"""
import argparse
import json
import os
import pathlib
import resource
import sys
import threading
import time

import numpy as np

loads, stop = [], threading.Event()

from meshmark.study import engine

def main():
    global loads, stop
    ap = argparse.ArgumentParser()
    ap.add_argument("--spec", default=str(pathlib.Path(__file__).parent / "studies" / "grid12k.toml"))
    ap.add_argument("--out", default="out/grid12k")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dask", default=None)
    ap.add_argument("--max-tasks", type=int, default=None)
    a = ap.parse_args()



    def sample():
        while not stop.is_set():
            loads.append(os.getloadavg()[0])
            stop.wait(10)


    th = threading.Thread(target=sample, daemon=True)
    th.start()
    t0 = time.perf_counter()
    S = engine.run(a.spec, a.out, workers=None if a.dask else a.workers, dask=a.dask, progress=False,
                   max_tasks=a.max_tasks)
    wall = time.perf_counter() - t0
    stop.set()
    t = engine.load_results(a.out)
    n = S.ran
    tt = np.asarray(t.column("t_task").to_numpy(zero_copy_only=False), float)
    n_workers = int(a.dask.split(":")[1]) if a.dask and a.dask.startswith("local:") else a.workers
    # only the rows of this run: the last S.ran rows by time are not identifiable, so use all when fresh
    bare = float(tt.sum()) if S.skipped == 0 else float("nan")
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    st = t.column("status").to_pylist()
    rep = {"tasks_planned": S.planned, "tasks_run": n, "ok": S.ok, "mesh_error": S.mesh_error, "failed": S.failed,
           "wall_s": round(wall, 1), "plan_s": round(S.plan_seconds, 2), "tasks_per_s": round(n / wall, 2),
           "workers": n_workers, "sum_task_s": round(bare, 1), "mean_task_ms": round(1000 * bare / max(n, 1), 1),
           "overhead_per_task_ms": round(1000 * (wall * n_workers - bare) / max(n, 1), 1),
           "driver_peak_rss_mb": round(rss, 1), "load_avg_min": min(loads), "load_avg_mean": round(float(np.mean(loads)), 2),
           "load_avg_max": max(loads), "by_status": {s: st.count(s) for s in set(st)}}
    print(json.dumps(rep, indent=1))
    pathlib.Path(a.out, "bench.json").write_text(json.dumps(rep, indent=1))


if __name__ == "__main__":
    main()
