"""The Python module against the C++ command line on the same inputs, and against independent
expectations (polynomial roots, steady-state friction, values written to files), over random
parameters with fixed seeds."""
import json
import os

import numpy as np
import pytest

import gmslab
from conftest import PRESETS


def read_csv(path):
    """A CSV with one header row as a dict of columns."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {h: data[:, i] for i, h in enumerate(header)}


def random_scenario(rng):
    """fig2a's preset with a random plant mass, friction levels and a shorter run."""
    sc = gmslab.load_scenario(os.path.join(PRESETS, "fig2c_periodic_1hz.json"))
    sc.plant.mass = float(rng.uniform(0.5, 3.0))
    sc.friction["Fc"] = float(rng.uniform(0.5, 1.2))
    sc.friction["Fs"] = sc.friction["Fc"] * float(rng.uniform(1.1, 1.8))
    sc.run.duration = float(rng.uniform(0.2, 0.6))
    sc.run.record_every = int(rng.integers(5, 50))
    return sc


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_simulate_matches_cli_trace(cli, tmp_path, seed):
    rng = np.random.default_rng(seed)
    sc = random_scenario(rng)
    preset = tmp_path / "sc.json"
    gmslab.save_scenario(sc, str(preset))
    assert gmslab.load_scenario(str(preset)) == sc  # edited fields survive the file
    tr = gmslab.simulate(sc)
    out = tmp_path / "trace.csv"
    cli("simulate", str(preset), "--out", str(out))
    ref = read_csv(out)
    assert len(tr) == len(ref["t_s"]) > 10
    for mine, theirs in [(tr.t, "t_s"), (tr.x, "x_m"), (tr.v, "v_mps"), (tr.friction, "F_friction_N"),
                         (tr.applied, "F_applied_N")]:
        np.testing.assert_allclose(mine, ref[theirs], rtol=1e-9, atol=1e-12 * max(1.0, np.abs(ref[theirs]).max()))
    n = tr.element_force.shape[1]
    assert n == len(sc.friction.elements)
    for i in range(n):
        np.testing.assert_allclose(tr.element_force[:, i], ref[f"F{i + 1}_N"], rtol=1e-9, atol=1e-12)
        np.testing.assert_array_equal(tr.element_slip[:, i], ref[f"slip{i + 1}"] != 0)


def test_errors_carry_the_core_message_as_the_cli_prints_it(cli, tmp_path):
    sc = gmslab.load_scenario(os.path.join(PRESETS, "fig2a_presliding.json"))
    d = sc.to_dict()
    d["plant"]["mass"] = -2.0
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))
    with pytest.raises(gmslab.InputError) as e:
        gmslab.load_scenario(str(bad))
    assert "plant.mass" in str(e.value)
    p = cli("simulate", str(bad), "--out", str(tmp_path / "x.csv"), check=False)
    assert p.returncode == 2
    assert str(e.value) in p.stderr
    with pytest.raises(ValueError):  # InputError is a ValueError
        sc.plant.mass = -1.0
        sc.validate()
    with pytest.raises(KeyError):
        sc.friction["no_such_parameter"] = 1.0


@pytest.mark.parametrize("seed", [11, 12, 13, 14])
def test_design_matches_cli(cli, seed):
    rng = np.random.default_rng(seed)
    num = [float(rng.uniform(0.5, 10))]
    den = [1.0, float(rng.uniform(0.5, 5)), 0.0]
    zeta, wn = float(rng.uniform(0.3, 0.8)), float(rng.uniform(2, 10))
    mine = gmslab.design(zeta, wn, num=num, den=den)
    p = cli("design", "--num", " ".join(repr(c) for c in num), "--den", " ".join(repr(c) for c in den),
            "--zeta", repr(zeta), "--wn", repr(wn), "--json", "-")
    theirs = json.loads(p.stdout)
    assert mine.keys() == theirs.keys()
    assert isinstance(mine["s_d"], complex)
    if theirs["closed_loop_poles"] is not None:  # null when no design applies
        assert mine["closed_loop_poles"].dtype == complex
        np.testing.assert_array_equal(mine["closed_loop_poles"], [complex(*r) for r in theirs["closed_loop_poles"]])
    assert json.dumps(gmslab.to_json(mine), sort_keys=True) == json.dumps(theirs, sort_keys=True)


@pytest.mark.parametrize("seed", [21, 22, 23, 24, 25])
@pytest.mark.parametrize("compensator", ["lead", "lag", "lead_lag", "pi", "pid"])
def test_design_of_each_compensator_type(cli, compensator, seed):
    """gmslab.design(compensator=...) is the Design view's compensator of that type: its closed-loop
    poles are the roots of den_G den_C + num_G num_C (numpy.roots on the exported polynomials, an
    independent method), and the whole dict equals `gmslab design --compensator` for the same
    arguments. Random type-1 plants b/(s (s + a)) (the lag and PI need the plant's own locus to cross
    the zeta line, at wn = a / (2 zeta)), K random or none."""
    rng = np.random.default_rng(seed)
    a, b = float(rng.uniform(1, 6)), float(rng.uniform(0.5, 10))
    num, den = [b], [1.0, a, 0.0]
    zeta = float(rng.uniform(0.4, 0.8))
    wn = float(rng.uniform(1.5, 4)) * a / (2 * zeta)
    K = None if seed % 2 else float(b / a * rng.uniform(5, 20))
    mine = gmslab.design(zeta, wn, num=num, den=den, K=K, compensator=compensator)
    args = ["design", "--num", " ".join(repr(c) for c in num), "--den", " ".join(repr(c) for c in den),
            "--zeta", repr(zeta), "--wn", repr(wn), "--compensator", compensator, "--json", "-"]
    if K is not None:
        args += ["--K", repr(K)]
    theirs = json.loads(cli(*args).stdout)
    assert json.dumps(gmslab.to_json(mine), sort_keys=True) == json.dumps(theirs, sort_keys=True)
    t = mine["typed_compensator"]
    assert t["type"] == compensator
    assert t["error"] == "", t["error"]
    c = t["compensator"]
    alone = "the lead alone reaches K" in t["kind"]  # a lead-lag whose lead reaches K needs no lag
    assert len(c["sections"]) == (1 if compensator in ("lead", "lag", "pi") or alone else 2)
    if compensator in ("pi", "pid"):
        assert c["sections"][-1]["p"] == 0.0  # an integrator
    char = np.polyadd(np.polymul(den, c["den"]), np.polymul(num, c["num"]))
    expect = np.roots(char)
    got = t["closed_loop_poles"]  # complex, as root_locus gives roots
    assert isinstance(got, np.ndarray) and got.dtype == complex
    assert len(got) == len(expect)
    for p in expect:  # every root found, to the polynomial's conditioning
        assert np.min(np.abs(got - p)) < 1e-6 * max(1.0, abs(p)), (p, got)
    if compensator in ("lag", "pi", "pid") or (compensator == "lead_lag" and not alone):
        assert "lag" in t
        slow = t["lag"]["slow_pole"]
        assert isinstance(slow, complex)
        assert np.min(np.abs(expect - slow)) < 1e-6 * max(1.0, abs(slow))
        z_lag = c["sections"][-1]["z"]
        assert abs(slow + z_lag) < abs(slow)  # the slow pole sits next to the lag / integral zero


def test_design_compensator_errors(cli):
    with pytest.raises(gmslab.InputError) as e:
        gmslab.design(0.5, 4.0, num=[4], den=[1, 2, 0], compensator="pd")
    assert "lead, lag, lead_lag, pi or pid" in str(e.value)


@pytest.mark.parametrize("seed", [31, 32])
def test_design_of_a_scenario_with_a_compensator_matches_cli(cli, seed):
    """A scenario's plant (Fig. 4, sliding): the same dict as the CLI, with the describing-function
    limit cycles of the lead loop and of the typed compensator's loop."""
    rng = np.random.default_rng(seed)
    preset = os.path.join(PRESETS, "fig4_stick_slip.json")
    zeta, wn = float(rng.uniform(0.5, 0.8)), float(rng.uniform(40, 80))
    comp = ["pi", "pid"][seed % 2]
    mine = gmslab.design(zeta, wn, scenario=preset, regime="sliding", compensator=comp)
    theirs = json.loads(cli("design", "--preset", preset, "--regime", "sliding", "--zeta", repr(zeta), "--wn",
                            repr(wn), "--compensator", comp, "--json", "-").stdout)
    assert json.dumps(gmslab.to_json(mine), sort_keys=True) == json.dumps(theirs, sort_keys=True)
    assert "limit_cycles" in mine and "limit_cycles" in mine["typed_compensator"]


@pytest.mark.parametrize("name", ["two_mass_drive", "three_body_chain"])
def test_simulate_an_assembled_preset_matches_cli_trace(cli, tmp_path, name):
    """An assembled plant (schema 2) simulates on the same engine as `gmslab simulate`: every output."""
    preset = os.path.join(PRESETS, name + ".json")
    tr = gmslab.simulate(preset)
    assert isinstance(tr, gmslab.PlantTrace)
    out = tmp_path / "trace.csv"
    cli("simulate", preset, "--out", str(out))
    ref = read_csv(out)
    assert len(tr) == len(ref["t_s"]) > 10
    np.testing.assert_array_equal(tr.t, ref["t_s"])
    unit = {"x": "m", "v": "mps", "F": "N"}
    for output in tr.outputs:  # CSV columns NAME_UNIT: x.motor_m, v.motor_mps, F.shaft_N
        np.testing.assert_array_equal(tr.output(output), ref[output + "_" + unit[output[0]]])
    for contact, slip in tr.contact_slip.items():
        np.testing.assert_array_equal(slip, ref["slip." + contact] != 0)
    with pytest.raises(gmslab.InputError, match="no such output"):
        tr.output("x.nothing")


@pytest.mark.parametrize("output", ["x.motor", "x.load"])
def test_design_on_the_assembled_plant_matches_cli(cli, output):
    """The assembled two-mass train from its force drive to a body: the same plant and design as the CLI."""
    preset = os.path.join(PRESETS, "two_mass_drive.json")
    mine = gmslab.design(0.7, 10.0, scenario=preset, regime="sliding", output=output)
    p = cli("design", "--preset", preset, "--regime", "sliding", "--output", output,
            "--zeta", "0.7", "--wn", "10", "--json", "-")
    theirs = json.loads(p.stdout)
    assert json.dumps(gmslab.to_json(mine), sort_keys=True) == json.dumps(theirs, sort_keys=True)
    assert mine["plant"]["plant_source"] == "assembly"
    assert mine["plant"]["output"] == output
    # Collocated: two zeros (the anti-resonance pair); non-collocated: only the shaft damper's -k/c.
    assert len(np.roots(mine["plant"]["num"])) == (2 if output == "x.motor" else 1)


@pytest.mark.parametrize("seed", range(41, 47))
def test_design_job_agrees_with_the_cli(cli, seed):
    """gmslab.design and `gmslab design --json` are views of one design job: for random designs over
    the accepted ranges (a typed plant b(s) / (s^k a(s)), Fig. 4's one body or the assembled two-mass
    train; zeta, wn, K, the p/z bound, the compensator type and a sample time random) the dict equals
    the CLI's JSON, key for key, or both fail with the same message. The Design panel's side:
    tests/control/design_job_agreement_test.cpp."""
    rng = np.random.default_rng(seed)
    source = seed % 3
    kwargs, args = {}, []
    if source == 0:
        n, k = int(rng.integers(1, 4)), int(rng.integers(0, 3))
        den = [1.0] + [float(10 ** rng.uniform(-1, 2)) for _ in range(n)] + [0.0] * k
        num = [float(10 ** rng.uniform(-1, 2)) for _ in range(int(rng.integers(0, n)) + 1)]
        kwargs.update(num=num, den=den)
        args += ["--num", " ".join(repr(c) for c in num), "--den", " ".join(repr(c) for c in den)]
        wn = float(10 ** rng.uniform(-1, 3))
    else:
        preset = os.path.join(PRESETS, "fig4_stick_slip.json" if source == 1 else "two_mass_drive.json")
        kwargs.update(scenario=preset)
        args += ["--preset", preset]
        if source == 2:
            output = ["x.motor", "x.load"][int(rng.integers(0, 2))]
            kwargs.update(output=output)
            args += ["--output", output]
        wn = float(10 ** rng.uniform(0.5, 2.5))
    regime = ["presliding", "sliding"][int(rng.integers(0, 2))]
    zeta = float(rng.uniform(0.02, 0.98))
    max_ratio = float(rng.uniform(1.5, 100))
    K = float(10 ** rng.uniform(-1, 4)) if rng.uniform() < 0.5 else None
    compensator = ["lead", "lag", "lead_lag", "pi", "pid"][int(rng.integers(0, 5))]
    T = float(10 ** rng.uniform(-4, -2)) if rng.uniform() < 0.3 else 0.0
    kwargs.update(regime=regime, K=K, max_ratio=max_ratio, compensator=compensator, sample_time=T)
    args += ["--regime", regime, "--zeta", repr(zeta), "--wn", repr(wn), "--max-ratio", repr(max_ratio),
             "--compensator", compensator, "--sample-time", repr(T), "--json", "-"]
    if K is not None:
        args += ["--K", repr(K)]
    p = cli("design", *args, check=False)
    try:
        mine = gmslab.design(zeta, wn, **kwargs)
    except gmslab.InputError as e:
        assert p.returncode == 2, p.stderr
        assert str(e) in p.stderr
        return
    assert p.returncode == 0, p.stderr
    theirs = json.loads(p.stdout)
    assert json.dumps(gmslab.to_json(mine), sort_keys=True) == json.dumps(theirs, sort_keys=True)
    assert mine["typed_compensator"]["type"] == compensator


@pytest.mark.parametrize("seed", [21, 22, 23])
def test_root_locus_points_are_closed_loop_roots(seed):
    rng = np.random.default_rng(seed)
    num = [1.0, float(rng.uniform(1, 5))]
    den = [1.0, float(rng.uniform(1, 4)), float(rng.uniform(1, 9)), 0.0]
    r = gmslab.root_locus(num, den)
    np.testing.assert_allclose(np.sort_complex(r["poles"]), np.sort_complex(np.roots(den)), atol=1e-9)
    gains = r["gains"]
    assert r["branches"].shape == (3, len(gains))
    for k_index in rng.integers(1, len(gains), size=10):
        k = gains[k_index]
        expect = np.roots(np.polyadd(den, k * np.array(num)))
        got = list(r["branches"][:, k_index])
        tol = 1e-6 * max(1.0, abs(expect).max())
        # Each expected root matched by the nearest unused locus point (sorting alone would pair a
        # conjugate pair crosswise when their real parts differ in the last digit).
        for e in expect:
            i = int(np.argmin([abs(g - e) for g in got]))
            assert abs(got[i] - e) <= tol + 1e-6 * abs(e), (k, e, got)
            got.pop(i)


@pytest.mark.parametrize("tag", [m["tag"] for m in gmslab.models()])
def test_every_registry_model_steps_to_its_steady_state(tag):
    m = gmslab.Model(tag)
    rng = np.random.default_rng(abs(hash(tag)) % 1000)
    v = float(rng.uniform(0.002, 0.02)) * (1 if rng.uniform() < 0.5 else -1)
    f = m.run(np.full(20000, v), 1e-5)  # 0.2 s at constant velocity
    assert f.shape == (20000,)
    assert f[-1] == pytest.approx(m.steady_state(v), rel=1e-3, abs=1e-6)
    m.reset()
    assert m.step(v, 1e-5) == pytest.approx(f[0])
    assert len(m.elements()) == len(m.params.elements)


def test_figure_2a_is_the_preset_simulated():
    fig = gmslab.figure("fig2a_presliding")
    s = fig["panels"][0]["series"][0]
    tr = gmslab.simulate(os.path.join(PRESETS, "fig2a_presliding.json"))
    assert "um" in fig["panels"][0]["x_label"]
    # The figure plots F_f against x [um] from the same run: every figure point is a trace point.
    xs, fs = tr.x * 1e6, tr.friction
    for i in np.linspace(0, len(s["x"]) - 1, 25).astype(int):
        j = np.argmin(np.abs(xs - s["x"][i]) + np.abs(fs - s["y"][i]))
        assert abs(xs[j] - s["x"][i]) < 1e-6 and abs(fs[j] - s["y"][i]) < 1e-9
    assert "fig2a_presliding" in gmslab.figure_ids()
    with pytest.raises(gmslab.InputError):
        gmslab.figure("no_such_figure")


def test_identify_report_matches_cli(cli, tmp_path):
    rng = np.random.default_rng(5)
    sc = gmslab.load_scenario(os.path.join(PRESETS, "fig2c_periodic_1hz.json"))
    sc.run.duration = 2.0
    sc.run.record_every = 100
    tr = gmslab.simulate(sc)
    data = tmp_path / "rec.txt"  # whitespace-separated, no header, decimal comma: columns by position
    F = tr.friction + rng.normal(0, 0.01, len(tr.t))
    rows = [" ".join(f"{v:.17g}".replace(".", ",") for v in r) for r in zip(tr.t, tr.x, F)]
    data.write_text("\n".join(rows) + "\n")
    opts = dict(columns="t=1,x=2,F=3", model="gms", elements="2", starts=1, max_evals=60, effects="offset")
    rec = gmslab.load_record(str(data), "t=1,x=2,F=3")
    np.testing.assert_array_equal(rec["x"], tr.x)  # 17 digits round-trip exactly
    np.testing.assert_array_equal(rec["F"], F)
    mine = gmslab.identify(str(data), **opts)
    report = tmp_path / "rep.json"
    cli("identify", "--data", str(data), "--columns", "t=1,x=2,F=3", "--model", "gms", "--elements", "2",
        "--starts", "1", "--max-evals", "60", "--effects", "offset", "--report", str(report))
    theirs = json.loads(report.read_text())
    assert mine["rms_after"] == pytest.approx(theirs["rms_after"], rel=1e-12)
    assert mine["effects_added"] == theirs["effects_added"]
    assert mine["discovery"]["summary"] == theirs["discovery"]["summary"]  # said, never silently absent
    assert mine["discovery"]["summary"].startswith(("not run", "nothing discovered", "discovered"))
    assert [p["value"] for p in mine["parameters"]] == pytest.approx([p["value"] for p in theirs["parameters"]], rel=1e-12)
    assert isinstance(mine["scenario"], dict)  # the report is JSON as the CLI's is
    json.dumps(mine)
    assert gmslab.Scenario.from_dict(mine["scenario"]) == gmslab.load_scenario(theirs["scenario_file"])
