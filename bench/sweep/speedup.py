"""Speed-up of gmslab.sweep from 1 to 2 Dask workers (LocalCluster, one thread each) on the grid
of fig2c_grid.json (12 simulations of 30 s of Fig. 2C). The cluster is started before the clock
runs; 1 and 2 workers alternate 3 times; the median of each is reported, with the load average
(the machine may be shared). Usage: PYTHONPATH=build/python python3 bench/sweep/speedup.py"""
import os
import statistics
import sys
import tempfile
import time


def main():
    from dask.distributed import Client, LocalCluster

    from gmslab import sweep

    spec = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fig2c_grid.json")
    times = {1: [], 2: []}
    for _ in range(3):
        for workers in (1, 2):
            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client, \
                    tempfile.TemporaryDirectory() as d:
                sweep.run_sweep(spec, os.path.join(d, "warm.csv"), client=client, progress=False)  # imports
                os.remove(os.path.join(d, "warm.csv.partial.jsonl"))
                t0 = time.perf_counter()
                rows = sweep.run_sweep(spec, os.path.join(d, "r.csv"), client=client, progress=False)
                dt = time.perf_counter() - t0
                assert all(r["status"] == "ok" for r in rows)
                times[workers].append(dt)
                print(f"{workers} worker(s): {len(rows)} points in {dt:.2f} s "
                      f"(sum of job times {sum(r['seconds'] for r in rows):.2f} s)", file=sys.stderr)
    m1, m2 = statistics.median(times[1]), statistics.median(times[2])
    print(f"1 worker {m1:.2f} s, 2 workers {m2:.2f} s (medians of 3): speed-up {m1 / m2:.2f}x; "
          f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")


if __name__ == "__main__":  # the workers are spawned processes that import this file
    main()
