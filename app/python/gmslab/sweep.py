"""Parameter sweeps and Monte Carlo studies of gmslab jobs on Dask distributed.

A sweep runs one independent job per point of a grid or of a random sample, on a LocalCluster
using every core (default) or on a running scheduler (``--scheduler tcp://host:8786``). Results
are gathered in one table (CSV and JSON) with each point's parameters, its metrics, its status
and, for a failed point, the error; a failed point does not stop the others. Every finished point
is appended to ``OUT.partial.jsonl`` as it arrives, so an interrupted sweep started again with the
same spec and output skips the points already done (failed points are tried again).

Spec (JSON)::

    {
      "job": "simulate" | "design" | "identify",
      "scenario": "presets/fig2c_periodic_1hz.json",     # simulate, design: the base scenario
      "design": {"zeta": 0.7, "wn": 60, "regime": "sliding"},   # design: fixed arguments
      "identify": {"data": "rec.csv", "starts": 1},     # identify: fixed arguments
      "sample": "grid" | "random",  "samples": 20,  "seed": 1,
      "parameters": {
        "friction.Fs":   {"values": [1.2, 1.5, 1.8]},           # a list
        "plant.mass":    {"range": [0.5, 2.0, 4]},              # lo, hi, count (grid)
        "friction.elements.0.k": {"uniform": [5e4, 1e5]},       # random sample
        "friction.Fc":   {"normal": [1.0, 0.05]},               # mean, standard deviation
        "zeta":          {"values": [0.5, 0.7]}                 # a design / identify argument
      },
      "from_report": "report.json"   # optional: every base-model parameter of an identification
                                     # report drawn from normal(value, std_error) (Monte Carlo)
    }

Scenario parameters are key paths into the preset JSON ("friction.Fs", "plant.mass",
"run.duration", "drive.signal.frequency", "friction.elements.2.alpha"); other names are
arguments of gmslab.design / gmslab.identify. Metrics per point:
  simulate: samples, friction_max_N, friction_rms_N, x_final_m, x_max_abs_m, v_max_abs_mps, seconds
  design: applicable, K, Kc, z, p, K_max, K_max_usable, phi_deg, design_kind, seconds
  identify: rms_before_validation, rms_after_validation, effects_added, elements, seconds

Command line: python3 -m gmslab.sweep SPEC.json --out results.csv [--scheduler ADDR [--connect-timeout S]]
[--workers N]
(also ``gmslab sweep``).
"""
import argparse
import copy
import csv
import difflib
import itertools
import json
import math
import os
import sys
import time

import numpy as np

SCENARIO_ROOTS = ("friction", "plant", "drive", "run", "name", "description")


class SpecError(ValueError):
    """A bad sweep spec: names the key and what is accepted."""


SPEC_KEYS = ("job", "scenario", "design", "identify", "sample", "samples", "seed", "parameters", "from_report")
# The arguments of gmslab.design (besides scenario) and gmslab.identify a spec may fix or vary.
JOB_ARGS = {
    "simulate": (),
    "design": ("zeta", "wn", "num", "den", "regime", "velocity", "K", "max_ratio", "margin", "drive", "output",
               "compensator", "sample_time"),
    "identify": ("data", "validate", "columns", "model", "elements", "mask", "validate_mask", "mask_edges", "holdout",
                 "method", "starts", "max_evals", "min_gain", "effects", "compare", "compare_seconds", "force"),
}
REQUIRED_ARGS = {"simulate": (), "design": ("zeta", "wn"), "identify": ("data",)}


def _did_you_mean(word, known):
    m = difflib.get_close_matches(word, list(known), n=1, cutoff=0.5)
    return f"; did you mean '{m[0]}'?" if m else ""


def _paths(node, prefix=""):
    """Every key path of a scenario dict ("friction.Fs", "friction.elements.0.k", "plant.mass")."""
    out = []
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for k, v in items:
        p = f"{prefix}{k}"
        out.append(p)
        out += _paths(v, p + ".")
    return out


def check_spec(spec, pts):
    """Every key, argument and parameter path of the spec, checked before any cluster starts.

    Raises SpecError naming the key, what is accepted and the closest known name."""
    job = spec.get("job", "simulate")
    if job not in JOB_ARGS:
        raise SpecError(f"job: '{job}'; accepted: simulate, design, identify{_did_you_mean(str(job), JOB_ARGS)}")
    for k in spec:
        if k in SPEC_KEYS:
            continue
        hint = next((f"; did you mean '{sec}.{k}'?" for sec in ("identify", "design") if k in JOB_ARGS[sec]), "")
        raise SpecError(f"unknown key '{k}'; accepted: {', '.join(SPEC_KEYS)}{hint or _did_you_mean(k, SPEC_KEYS)}")
    args = JOB_ARGS[job]
    for section in ("design", "identify"):
        if section not in spec:
            continue
        if section != job:
            raise SpecError(f"{section}: arguments of the {section} job, but the job is '{job}'")
        if not isinstance(spec[section], dict):
            raise SpecError(f"{section}: expected an object of arguments ({', '.join(args)})")
        for k in spec[section]:
            if k == "scenario" and section == "design":
                raise SpecError("design.scenario: the scenario is the spec's top-level 'scenario'")
            if k not in args:
                raise SpecError(f"{section}.{k}: unknown argument; accepted: {', '.join(args)}{_did_you_mean(k, args)}")
    paths = []
    if spec.get("scenario"):
        import gmslab
        paths = _paths(gmslab.load_scenario(spec["scenario"]).to_dict())
    names = list(pts[0]) if pts else list(spec.get("parameters", {}))
    for name in names:
        if name.split(".")[0] in SCENARIO_ROOTS:
            if paths and name not in paths:
                raise SpecError(f"parameters.{name}: no such key path in the scenario{_did_you_mean(name, paths)}")
        elif name not in args:
            what = "a scenario key path (friction.*, plant.*, drive.*, run.*)" + (
                f" or an argument of gmslab.{job} ({', '.join(args)})" if args else "")
            raise SpecError(f"parameters.{name}: not {what}{_did_you_mean(name, list(paths) + list(args))}")
    given = set(spec.get(job, {})) | set(names)
    missing = [a for a in REQUIRED_ARGS[job] if a not in given]
    if missing:
        raise SpecError(f"{job}: missing argument{'s' if len(missing) > 1 else ''} {', '.join(missing)} "
                        f"(in \"{job}\": {{...}} or as a parameter)")


def _load_json(path, what):
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        raise SpecError(f"{path}: cannot read the {what}: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise SpecError(f"{path}:{e.lineno}: not valid JSON ({e.msg})") from None


def _axis(name, d, sample):
    """The values of one parameter: a list for a grid, or a draw function for a random sample."""
    if not isinstance(d, dict) or len(d) != 1:
        raise SpecError(f"parameters.{name}: expected one of {{values: [...]}}, {{range: [lo, hi, n]}}, "
                        "{uniform: [lo, hi]}, {normal: [mean, std]}")
    (kind, arg), = d.items()
    if kind == "values":
        if not isinstance(arg, list) or not arg:
            raise SpecError(f"parameters.{name}.values: expected a non-empty list")
        return list(arg)
    if kind == "range":
        if not (isinstance(arg, list) and len(arg) == 3 and int(arg[2]) >= 1):
            raise SpecError(f"parameters.{name}.range: expected [lo, hi, count >= 1]")
        return [float(v) for v in np.linspace(float(arg[0]), float(arg[1]), int(arg[2]))]
    if kind in ("uniform", "normal"):
        if sample != "random":
            raise SpecError(f"parameters.{name}.{kind}: a distribution needs \"sample\": \"random\"")
        if not (isinstance(arg, list) and len(arg) == 2):
            raise SpecError(f"parameters.{name}.{kind}: expected [{'lo, hi' if kind == 'uniform' else 'mean, std'}]")
        a, b = float(arg[0]), float(arg[1])
        return (lambda rng: float(rng.uniform(a, b))) if kind == "uniform" else (lambda rng: float(rng.normal(a, b)))
    raise SpecError(f"parameters.{name}: unknown kind '{kind}'; accepted: values, range, uniform, normal")


def points(spec):
    """The sweep's points (dicts name -> value), deterministic for a spec (seeded)."""
    sample = spec.get("sample", "grid")
    if sample not in ("grid", "random"):
        raise SpecError(f"sample: '{sample}'; accepted: grid, random")
    params = spec.get("parameters", {})
    if not isinstance(params, dict):
        raise SpecError("parameters: expected an object {name: {values|range|uniform|normal: ...}}")
    axes = {k: _axis(k, v, sample) for k, v in params.items()}
    if spec.get("from_report"):
        if sample != "random":
            raise SpecError("from_report: draws parameters at random; needs \"sample\": \"random\"")
        rep = _load_json(spec["from_report"], "identification report")
        conv = rep.get("converged", {})
        if conv and not conv.get("verified_minimum", True):
            raise SpecError("from_report: %s is not at a verified minimum (%s): it has no standard errors "
                            "to draw from; identify again with a larger budget" % (spec["from_report"], conv.get("reason", "")))
        for p in rep.get("parameters", []):
            if p.get("effect") != "base":
                continue
            key = "friction." + p["name"].replace("[", ".").replace("]", "")
            if p.get("std_error") and math.isfinite(p["std_error"]):
                mean, sd = float(p["value"]), float(p["std_error"])
                axes.setdefault(key, (lambda m, s: (lambda rng: float(rng.normal(m, s))))(mean, sd))
            elif key not in axes:
                print("gmslab sweep: from_report: %s kept at %g (no standard error: %s)"
                      % (key, float(p["value"]), p.get("no_error") or "none given"), file=sys.stderr)
    if sample == "grid":
        names = list(axes)
        for k in names:
            if callable(axes[k]):
                raise SpecError(f"parameters.{k}: a distribution in a grid sweep")
        return [dict(zip(names, combo)) for combo in itertools.product(*(axes[k] for k in names))]
    n = int(spec.get("samples", 0))
    if n < 1:
        raise SpecError("samples: a random sweep needs \"samples\" >= 1")
    rng = np.random.default_rng(int(spec.get("seed", 0)))
    out = []
    for i in range(n):
        out.append({k: (a(rng) if callable(a) else a[int(rng.integers(len(a)))]) for k, a in axes.items()})
    return out


def _set_path(d, path, value):
    keys = path.split(".")
    node = d
    for i, k in enumerate(keys[:-1]):
        nxt = node[int(k)] if isinstance(node, list) else node.get(k)
        if nxt is None:
            raise KeyError(f"'{path}': no key '{'.'.join(keys[:i + 1])}' in the scenario")
        node = nxt
    last = keys[-1]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value  # an unknown key is rejected by the scenario's validation, by name


def _scenario(spec, point):
    import gmslab
    sc = gmslab.load_scenario(spec["scenario"])
    d = sc.to_dict()
    for k, v in point.items():
        if k.split(".")[0] in SCENARIO_ROOTS:
            _set_path(d, k, v)
    return gmslab.Scenario(d)  # validated: a bad value fails this point with the core's message


def run_point(spec, point):
    """Runs one point's job; returns its metrics (raises on failure: the caller records it)."""
    import gmslab
    t0 = time.perf_counter()
    job = spec.get("job", "simulate")
    args = {k: v for k, v in point.items() if k.split(".")[0] not in SCENARIO_ROOTS}
    if job == "simulate":
        if args:
            raise SpecError(f"parameters {sorted(args)}: not scenario key paths (friction.*, plant.*, drive.*, run.*)")
        tr = gmslab.simulate(_scenario(spec, point))
        f, x = tr.friction, tr.x
        m = {"samples": len(tr), "friction_max_N": float(np.abs(f).max()),
             "friction_rms_N": float(np.sqrt(np.mean(f * f))), "x_final_m": float(x[-1]),
             "x_max_abs_m": float(np.abs(x).max()), "v_max_abs_mps": float(np.abs(tr.v).max())}
    elif job == "design":
        kw = dict(spec.get("design", {}))
        kw.update(args)
        r = gmslab.design(scenario=_scenario(spec, point), **kw)
        m = {k: r.get(k) for k in ("applicable", "K", "Kc", "z", "p", "K_max", "K_max_usable", "phi_deg",
                                   "design_kind")}
    elif job == "identify":
        kw = dict(spec.get("identify", {}))
        kw.update(args)
        r = gmslab.identify(**kw)
        m = {"rms_before_validation": r["rms_before"]["validation"], "rms_after_validation": r["rms_after"]["validation"],
             "effects_added": " ".join(r.get("effects_added", [])), "elements": r.get("elements")}
    else:
        raise SpecError(f"job: '{job}'; accepted: simulate, design, identify")
    m["seconds"] = time.perf_counter() - t0
    return m


def _guarded(spec, index, point):
    """A point's table row: never raises (a failure is recorded with its error)."""
    row = {"point": index, **{f"param:{k}": v for k, v in point.items()}}
    try:
        row.update(run_point(spec, point))
        row["status"] = "ok"
        row["error"] = ""  # every table has the column, empty for a point that ran
    except Exception as e:  # noqa: BLE001 - every failure is reported in the table
        row["status"] = "failed"
        row["error"] = f"{type(e).__name__}: {e}"
    return row


def _write_atomic(path, text):
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def _progress(done, total, failed, t0, stream):
    """A bar rewritten in place on a terminal; one line per finished point in a log file or pipe."""
    if not (hasattr(stream, "isatty") and stream.isatty()):
        stream.write(f"sweep: {done}/{total} points, {failed} failed, {time.time() - t0:.1f} s\n")
        stream.flush()
        return
    width = 30
    filled = int(width * done / max(total, 1))
    stream.write(f"\rsweep [{'#' * filled}{'.' * (width - filled)}] {done}/{total} points, {failed} failed, "
                 f"{time.time() - t0:.1f} s")
    stream.flush()


class SchedulerError(OSError):
    """The Dask scheduler cannot be reached (the message names its address and the time waited)."""


def run_sweep(spec, out, scheduler=None, workers=None, progress=True, client=None, connect_timeout=10.0):
    """Runs the sweep; writes OUT (.csv) and OUT's .json twin; returns the rows (one per point).

    spec: a dict or a path to the spec JSON. out: the CSV table to write. scheduler: a Dask
    scheduler address (tcp://host:8786); else a LocalCluster of `workers` processes (default: every
    core), one thread each. client: an existing dask.distributed.Client (tests).
    """
    if isinstance(spec, (str, os.PathLike)):
        base = os.path.dirname(os.path.abspath(spec))
        spec = _load_json(spec, "sweep spec")
        for key in ("scenario", "from_report"):  # relative to the spec's folder
            if isinstance(spec.get(key), str) and not os.path.isabs(spec[key]):
                spec[key] = os.path.join(base, spec[key])
        ident = spec.get("identify", {})
        for key in ("data", "validate"):
            if isinstance(ident.get(key), str) and ident[key] and not os.path.isabs(ident[key]):
                ident[key] = os.path.join(base, ident[key])
    spec = copy.deepcopy(spec)
    if spec.get("job", "simulate") in ("simulate", "design") and not spec.get("scenario"):
        raise SpecError("scenario: the simulate and design jobs need a base scenario preset")
    pts = points(spec)
    if spec.get("scenario"):  # a bad base scenario is the spec's error, found before any job runs
        import gmslab
        try:
            gmslab.load_scenario(spec["scenario"])
        except gmslab.InputError as e:
            raise SpecError(f"scenario: {e}") from None
    check_spec(spec, pts)  # unknown keys, parameter paths and arguments: before any cluster starts
    partial = f"{out}.partial.jsonl"
    done = {}
    if os.path.exists(partial):
        with open(partial) as f:
            for line in f:
                try:
                    row = json.loads(line)
                except json.JSONDecodeError:
                    continue  # a line cut by the interruption
                if row.get("status") == "ok" and row.get("point") is not None and row["point"] < len(pts) and \
                        all(row.get(f"param:{k}") == v for k, v in pts[row["point"]].items()):
                    done[row["point"]] = row
    todo = [i for i in range(len(pts)) if i not in done]
    stream = sys.stderr
    t0 = time.time()
    if done and progress:
        stream.write(f"sweep: resuming, {len(done)} of {len(pts)} points already done\n")
    rows = dict(done)
    own = None
    if todo:
        from dask.distributed import Client, LocalCluster, as_completed
        if client is None:
            if scheduler:
                try:
                    own = Client(scheduler, timeout=connect_timeout)
                except (OSError, TimeoutError) as e:
                    raise SchedulerError(f"cannot reach the Dask scheduler at {scheduler} within {connect_timeout:g} s "
                                         f"(--connect-timeout): {type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}"
                                         ) from None
            else:
                own = Client(LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1,
                                          processes=True, dashboard_address=None))
            client = own
        try:
            futures = [client.submit(_guarded, spec, i, pts[i], key=f"gmslab-sweep-{i}-{time.time_ns()}",
                                     pure=False) for i in todo]
            failed = 0
            with open(partial, "a") as log:
                for fut in as_completed(futures):
                    row = fut.result()
                    rows[row["point"]] = row
                    failed += row["status"] != "ok"
                    log.write(json.dumps(row) + "\n")
                    log.flush()
                    if progress:
                        _progress(len(rows), len(pts), failed, t0, stream)
            if progress and hasattr(stream, "isatty") and stream.isatty():
                stream.write("\n")  # ends the bar
        finally:
            if own is not None:
                cluster = own.cluster
                own.close()
                if cluster is not None:
                    cluster.close()
    table = [rows[i] for i in range(len(pts))]
    columns = []
    for r in table:
        for k in r:
            if k not in columns:
                columns.append(k)
    import io
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=columns, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in table:
        w.writerow(r)
    _write_atomic(out, buf.getvalue())
    _write_atomic(os.path.splitext(out)[0] + ".json", json.dumps(table, indent=1) + "\n")
    nfail = sum(r["status"] != "ok" for r in table)
    if progress:
        stream.write(f"sweep: {len(table)} points ({nfail} failed) in {time.time() - t0:.1f} s; wrote {out}\n")
        for r in table:
            if r["status"] != "ok":
                stream.write(f"  point {r['point']}: {r['error']}\n")
    return table


def main(argv=None):
    ap = argparse.ArgumentParser(prog="gmslab sweep", description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", help="sweep spec (JSON)")
    ap.add_argument("--out", "-o", default=None, help="results table CSV (default: SPEC stem + .results.csv)")
    ap.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://host:8786")
    ap.add_argument("--workers", type=int, default=None, help="LocalCluster worker processes (default: every core)")
    ap.add_argument("--connect-timeout", type=float, default=10.0,
                    help="seconds to wait for --scheduler before giving up (default: 10)")
    a = ap.parse_args(argv)
    out = a.out or os.path.splitext(a.spec)[0] + ".results.csv"
    if a.workers is not None and a.workers < 1:
        ap.error("--workers: must be >= 1")
    if not (a.connect_timeout > 0):
        ap.error("--connect-timeout: must be > 0 s")
    try:
        table = run_sweep(a.spec, out, scheduler=a.scheduler, workers=a.workers, connect_timeout=a.connect_timeout)
    except (SpecError, SchedulerError) as e:
        print(f"gmslab sweep: {e}", file=sys.stderr)
        return 2
    return 0 if all(r["status"] == "ok" for r in table) else 1


if __name__ == "__main__":
    sys.exit(main())
