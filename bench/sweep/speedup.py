"""Speed-up of gmslab.sweep from 1 to 2 Dask workers (LocalCluster, one thread each) on the grid
of fig2c_grid.json (12 simulations of 30 s). Usage: PYTHONPATH=build/python python3 bench/sweep/speedup.py"""
import os
import sys
import tempfile
import time

from gmslab import sweep


def main():
    spec = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fig2c_grid.json")
    times = {}
    for workers in (1, 2, 1, 2):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            rows = sweep.run_sweep(spec, os.path.join(d, "r.csv"), workers=workers, progress=False)
            dt = time.perf_counter() - t0
            assert all(r["status"] == "ok" for r in rows)
            job = sum(r["seconds"] for r in rows)
            times.setdefault(workers, []).append(dt)
            print(f"{workers} worker(s): {len(rows)} points, wall {dt:.2f} s (cluster start included), "
                  f"sum of job times {job:.2f} s", file=sys.stderr)
    best = {w: min(t) for w, t in times.items()}
    print(f"speed-up 1 -> 2 workers: {best[1] / best[2]:.2f}x (best of 2 runs each)")


if __name__ == "__main__":  # the workers are spawned processes that import this file
    main()
