"""gmslab.sweep on a Dask LocalCluster of 2 workers and on a real dask-scheduler with two dask-worker
processes on 127.0.0.1: a grid of scenario parameters gathered into
one table whose metrics equal the jobs run directly, a failed point reported with its error while
the others finish, resumption that redoes only what is missing, a random sample reproducible from
its seed, and the `gmslab sweep` command."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

import gmslab
from gmslab import sweep
from conftest import PRESETS

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def spec(tmp_path):
    return {
        "job": "simulate",
        "scenario": os.path.join(PRESETS, "fig2c_periodic_1hz.json"),
        "sample": "grid",
        "parameters": {
            "friction.Fs": {"values": [1.3, 1.6]},
            "plant.mass": {"values": [1.0, -1.0, 2.0]},  # -1 kg: that point fails, the others run
            "run.duration": {"values": [0.3]},
            "run.record_every": {"values": [20]},
        },
    }


def test_grid_sweep_gathers_metrics_reports_failures_and_resumes(client, tmp_path):
    s = spec(tmp_path)
    out = str(tmp_path / "res.csv")
    rows = sweep.run_sweep(s, out, client=client, progress=False)
    assert len(rows) == 6
    assert [r["point"] for r in rows] == list(range(6))
    for r in rows:
        if r["param:plant.mass"] < 0:
            assert r["status"] == "failed"
            assert "plant.mass" in r["error"] and "InputError" in r["error"]
            continue
        assert r["status"] == "ok" and r["error"] == ""
        sc = gmslab.load_scenario(s["scenario"])
        sc.friction["Fs"] = r["param:friction.Fs"]
        sc.plant.mass = r["param:plant.mass"]
        sc.run.duration, sc.run.record_every = 0.3, 20
        tr = gmslab.simulate(sc)
        assert r["samples"] == len(tr)
        assert r["friction_max_N"] == np.abs(tr.friction).max()
        assert r["x_final_m"] == tr.x[-1]
    with open(out) as f:
        table = list(csv.DictReader(f))
    assert [t["status"] for t in table] == [r["status"] for r in rows]
    assert json.load(open(str(tmp_path / "res.json")))[0]["point"] == 0

    # Interrupted after 3 logged points: the rerun computes only the points not logged as ok.
    partial = out + ".partial.jsonl"
    lines = open(partial).read().splitlines()[:3]
    kept_ok = sum(json.loads(x)["status"] == "ok" for x in lines)
    open(partial, "w").write("\n".join(lines) + "\n")
    again = sweep.run_sweep(s, out, client=client, progress=False)
    added = open(partial).read().splitlines()[3:]
    assert len(added) == 6 - kept_ok
    assert {json.loads(x)["point"] for x in added}.isdisjoint(
        {json.loads(x)["point"] for x in lines if json.loads(x)["status"] == "ok"})
    for a, b in zip(rows, again):
        assert a.get("friction_max_N") == b.get("friction_max_N")


def test_random_sample_is_reproducible_and_checks_the_spec(tmp_path):
    s = {"job": "design", "scenario": os.path.join(PRESETS, "fig2a_presliding.json"), "sample": "random",
         "samples": 5, "seed": 3, "parameters": {"zeta": {"uniform": [0.4, 0.8]}, "plant.mass": {"normal": [1.0, 0.1]}}}
    a, b = sweep.points(s), sweep.points(s)
    assert a == b and len(a) == 5
    assert all(0.4 <= p["zeta"] <= 0.8 for p in a)
    assert len({p["zeta"] for p in a}) == 5
    with pytest.raises(sweep.SpecError, match="parameters.zeta.uniform"):
        sweep.points({**s, "sample": "grid"})
    with pytest.raises(sweep.SpecError, match="scenario: .*nope.json: cannot open file"):
        sweep.run_sweep({**s, "scenario": str(tmp_path / "nope.json")}, str(tmp_path / "r.csv"), progress=False)
    with pytest.raises(sweep.SpecError, match="unknown kind 'between'"):
        sweep.points({**s, "parameters": {"zeta": {"between": [0, 1]}}})
    # A design point run directly equals gmslab.design on the same scenario.
    m = sweep.run_point({**s, "design": {"wn": 60.0}}, a[0])
    sc = gmslab.load_scenario(s["scenario"])
    sc.plant.mass = a[0]["plant.mass"]
    d = gmslab.design(a[0]["zeta"], 60.0, scenario=sc)
    assert m["K_max"] == d["K_max"] and m["phi_deg"] == d["phi_deg"]


def test_gmslab_sweep_command(tmp_path):
    exe = os.environ.get("GMSLAB_EXE", "")
    if not exe:
        pytest.skip("gmslab executable not built")
    s = spec(tmp_path)
    s["parameters"]["plant.mass"] = {"values": [1.0]}
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(s))
    p = subprocess.run([exe, "sweep", str(path), "--workers", "2"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "2/2 points, 0 failed" in p.stderr
    # stderr is a pipe here: progress as lines ("sweep: 1/2 points, ..."), no carriage returns.
    assert "\r" not in p.stderr
    lines = [line for line in p.stderr.splitlines() if line.startswith("sweep: ")]
    assert [line.split(",")[0] for line in lines[:2]] == ["sweep: 1/2 points", "sweep: 2/2 points"], p.stderr
    assert lines[2].startswith("sweep: 2 points (0 failed) in "), p.stderr  # the summary
    with open(str(tmp_path / "spec.results.csv")) as f:
        table = list(csv.DictReader(f))
    assert len(table) == 2
    assert all(r["status"] == "ok" and r["error"] == "" for r in table)  # the column exists with no failure


def test_unreachable_scheduler_is_one_line_and_exit_2_within_the_timeout(tmp_path):
    """No scheduler listens on 127.0.0.1:1: one line naming the address, exit 2, within --connect-timeout."""
    import sys
    import time
    s = spec(tmp_path)
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(s))
    t0 = time.time()
    p = subprocess.run([sys.executable, "-m", "gmslab.sweep", str(path), "--scheduler", "tcp://127.0.0.1:1",
                        "--connect-timeout", "2"], capture_output=True, text=True, timeout=120)
    elapsed = time.time() - t0
    assert p.returncode == 2, p.stderr
    assert p.stderr.count("\n") == 1 and "Traceback" not in p.stderr, p.stderr
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:1 within 2 s" in p.stderr
    assert elapsed < 2 + 8  # the timeout plus interpreter and Dask start-up
    assert not (tmp_path / "spec.results.csv").exists()


def test_spec_errors_are_found_before_any_cluster_starts(tmp_path):
    """Misspelled parameter paths, keys at the wrong level, unknown arguments and missing ones: a
    SpecError naming the key and the closest known name, raised before a cluster is made (no
    client is given and none is started: the call returns at once), and exit 2 from the command."""
    import sys
    import time
    base = spec(tmp_path)
    out = str(tmp_path / "r.csv")
    cases = [
        ({**base, "parameters": {"friction.Fss": {"values": [1.0]}}},
         "parameters.friction.Fss: no such key path in the scenario; did you mean 'friction.Fs'?"),
        ({"job": "identify", "data": "rec.csv", "parameters": {"starts": {"values": [1]}}},
         "unknown key 'data'; accepted: job, scenario, design, identify, sample, samples, seed, parameters, "
         "from_report; did you mean 'identify.data'?"),
        ({**base, "paramters": {}}, "unknown key 'paramters'; accepted: .*; did you mean 'parameters'?"),
        ({**base, "job": "design", "design": {"zeta": 0.7, "wm": 60}},
         "design.wm: unknown argument; accepted: zeta, wn, .*; did you mean 'wn'?"),
        ({**base, "job": "design", "design": {"zeta": 0.7}}, r"design: missing argument wn \(in \"design\""),
        ({**base, "parameters": {"zeta": {"values": [0.5]}}},
         r"parameters.zeta: not a scenario key path \(friction.\*, plant.\*, drive.\*, run.\*\)"),
        ({**base, "identify": {"data": "x.csv"}}, "identify: arguments of the identify job, but the job is 'simulate'"),
    ]
    for s, message in cases:
        t0 = time.time()
        with pytest.raises(sweep.SpecError, match=message):
            sweep.run_sweep(s, out, progress=False)
        assert time.time() - t0 < 5, s  # no LocalCluster was started
    assert not os.path.exists(out)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(cases[0][0]))
    p = subprocess.run([sys.executable, "-m", "gmslab.sweep", str(path)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2
    assert p.stderr.strip() == "gmslab sweep: " + cases[0][1], p.stderr


@pytest.fixture(scope="module")
def real_cluster(tmp_path_factory):
    """A real dask-scheduler and two dask-worker processes on 127.0.0.1 (not a LocalCluster)."""
    import shutil
    import socket
    import sys
    import time
    sched, worker = shutil.which("dask-scheduler"), shutil.which("dask-worker")
    if not sched or not worker:
        pytest.skip("dask-scheduler / dask-worker not installed (Debian: python3-distributed)")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    addr = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ)  # the workers import gmslab from the same PYTHONPATH as this test
    logdir = tmp_path_factory.mktemp("dask")
    procs = [subprocess.Popen([sys.executable, sched, "--host", "127.0.0.1", "--port", str(port),
                               "--dashboard-address", ":0"], env=env, stdout=subprocess.DEVNULL,
                              stderr=open(logdir / "scheduler.log", "w"))]
    try:
        for i in range(2):
            procs.append(subprocess.Popen([sys.executable, worker, addr, "--nworkers", "1", "--nthreads", "1",
                                           "--no-dashboard"], env=env, stdout=subprocess.DEVNULL,
                                          stderr=open(logdir / f"worker{i}.log", "w")))
        c = distributed.Client(addr, timeout=30)
        t0 = time.time()
        while len(c.scheduler_info()["workers"]) < 2:
            if time.time() - t0 > 60:
                pytest.fail("the two dask-worker processes did not connect within 60 s")
            time.sleep(0.2)
        c.close()
        yield addr
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


def test_sweep_on_a_real_scheduler_with_two_workers(real_cluster, tmp_path):
    """`gmslab sweep --scheduler` on dask-scheduler + 2 dask-worker processes: the same table as the
    jobs run directly, the failed point reported, both workers still there afterwards."""
    exe = os.environ.get("GMSLAB_EXE", "")
    if not exe:
        pytest.skip("gmslab executable not built")
    s = spec(tmp_path)
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(s))
    p = subprocess.run([exe, "sweep", str(path), "--scheduler", real_cluster], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 1, p.stderr  # one point (plant.mass -1) fails by design
    with open(str(tmp_path / "spec.results.csv")) as f:
        table = list(csv.DictReader(f))
    assert len(table) == 6
    for r in table:
        if float(r["param:plant.mass"]) < 0:
            assert r["status"] == "failed" and "plant.mass" in r["error"]
            continue
        assert r["status"] == "ok" and r["error"] == ""
        sc = gmslab.load_scenario(s["scenario"])
        sc.friction["Fs"] = float(r["param:friction.Fs"])
        sc.plant.mass = float(r["param:plant.mass"])
        sc.run.duration, sc.run.record_every = 0.3, 20
        tr = gmslab.simulate(sc)
        assert int(r["samples"]) == len(tr)
        assert float(r["friction_max_N"]) == pytest.approx(float(np.abs(tr.friction).max()), rel=1e-15)
    c = distributed.Client(real_cluster, timeout=30)
    try:  # the scheduler still has its two worker processes (none was lost to a failed point)
        assert len(c.scheduler_info()["workers"]) == 2
    finally:
        c.close()
