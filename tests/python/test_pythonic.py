"""Python as a Python user expects it: paths as os.PathLike, numbers where numbers are meant,
Model.run validating its inputs as the command line does, preset names resolved from any folder,
and gmslab's own trace read back as it is (the friction force as F, force="applied" the applied)."""
import json
import os
import pathlib

import numpy as np
import pytest

import gmslab
from conftest import PRESETS


def test_paths_may_be_pathlike(tmp_path):
    """Path arguments: load_scenario, save_scenario, simulate, design (load_record and identify below)."""
    preset = pathlib.Path(PRESETS) / "fig2a_presliding.json"
    sc = gmslab.load_scenario(preset)
    assert sc == gmslab.load_scenario(str(preset))
    out = tmp_path / "copy.json"
    gmslab.save_scenario(sc, out)  # a pathlib.Path
    assert gmslab.load_scenario(out) == sc
    sc.run.duration = 0.5
    tr = gmslab.simulate(sc)
    tr_path = gmslab.simulate(preset)
    assert len(tr_path) > len(tr)
    d = gmslab.design(0.7, 60.0, scenario=pathlib.Path(PRESETS) / "fig4_stick_slip.json", regime="sliding")
    assert gmslab.to_json(d) == gmslab.to_json(
        gmslab.design(0.7, 60.0, scenario=os.path.join(PRESETS, "fig4_stick_slip.json"), regime="sliding"))
    with pytest.raises(TypeError, match="path: expected a path"):
        gmslab.load_scenario(42)


def test_bare_preset_names_resolve_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # not the repository root
    want = gmslab.load_scenario(os.path.join(PRESETS, "fig2a_presliding.json"))
    assert gmslab.load_scenario("fig2a_presliding") == want
    assert gmslab.load_scenario("fig2a_presliding.json") == want
    assert gmslab.load_scenario("presets/fig2a_presliding.json") == want
    assert len(gmslab.simulate("fig2a_presliding")) == len(gmslab.simulate(want))
    # A file of that name in the working folder comes first.
    local = gmslab.load_scenario("fig2c_periodic_1hz")
    local.name = "my local copy"
    gmslab.save_scenario(local, tmp_path / "fig2a_presliding.json")
    assert gmslab.load_scenario("fig2a_presliding.json").name == "my local copy"
    with pytest.raises(gmslab.InputError, match=r"no preset 'fig9_nothing' in .*presets: .*fig2a_presliding"):
        gmslab.load_scenario("fig9_nothing")


def test_model_run_rejects_nan_and_bad_steps_as_the_cli_does():
    m = gmslab.Model("gms")
    v = np.full(100, 0.01)
    f = m.run(v, 1e-4)
    assert np.all(np.isfinite(f))
    state = m.state.copy()
    for h in (0.0, -1e-4, float("nan"), float("inf"), 2.0):
        with pytest.raises(gmslab.InputError, match=r"run: h = .* must be in \(0, 1\] s"):
            m.run(v, h)
    bad = v.copy()
    bad[37] = np.nan
    with pytest.raises(gmslab.InputError, match=r"run: v\[37\] = nan: every velocity must be finite"):
        m.run(bad, 1e-4)
    bad[37] = np.inf
    with pytest.raises(gmslab.InputError, match=r"v\[37\]"):
        m.run(bad, 1e-4)
    np.testing.assert_array_equal(m.state, state)  # a rejected call stepped nothing
    with pytest.raises(gmslab.InputError, match="step: h = "):
        m.step(0.01, 0.0)
    with pytest.raises(gmslab.InputError, match="the velocity must be finite"):
        m.step(float("nan"), 1e-4)


def simulate_trace(tmp_path, cli):
    """fig2d (a force drive: applied differs from friction), shortened, written by `gmslab simulate`."""
    sc = gmslab.load_scenario("fig2d_nondrifting")
    sc.run.duration = 1.0
    preset = tmp_path / "short.json"
    gmslab.save_scenario(sc, preset)
    out = tmp_path / "rec.csv"
    cli("simulate", str(preset), "--out", str(out))
    return gmslab.simulate(sc), out


def test_simulate_trace_is_read_as_it_is(cli, tmp_path):
    tr, out = simulate_trace(tmp_path, cli)
    rec = gmslab.load_record(out)  # a pathlib.Path, no columns
    np.testing.assert_allclose(rec["t"], tr.t, rtol=1e-9)
    np.testing.assert_allclose(rec["x"], tr.x, rtol=1e-9)
    np.testing.assert_allclose(rec["F"], tr.friction, rtol=1e-9, atol=1e-12)
    applied = gmslab.load_record(out, force="applied")
    np.testing.assert_allclose(applied["F"], tr.applied, rtol=1e-9, atol=1e-12)
    assert np.max(np.abs(tr.applied - tr.friction)) > 1e-3
    with pytest.raises(gmslab.InputError, match="--force 'motor': expected friction or applied"):
        gmslab.load_record(out, force="motor")


def test_identify_takes_an_int_element_count_and_a_path(cli, tmp_path):
    sc = gmslab.load_scenario("fig2c_periodic_1hz")
    sc.run.record_every = 100
    preset = tmp_path / "short.json"
    gmslab.save_scenario(sc, preset)
    out = tmp_path / "rec.csv"
    cli("simulate", str(preset), "--out", str(out))
    opts = dict(starts=1, max_evals=60, effects="offset")
    as_int = gmslab.identify(out, elements=2, **opts)
    as_str = gmslab.identify(str(out), elements="2", **opts)
    assert as_int["rms_after"] == as_str["rms_after"]
    assert gmslab.identify(out, elements=2.0, **opts)["rms_after"] == as_int["rms_after"]  # a sweep's range value
    # The report is JSON (as the CLI writes it); its scenario a preset dict that makes a Scenario again.
    text = json.dumps(as_int)
    assert json.loads(text)["scenario"] == as_int["scenario"]
    sc = gmslab.Scenario.from_dict(as_int["scenario"])
    assert sc.to_dict() == as_int["scenario"]
    assert len(gmslab.simulate(sc)) > 1
    for bad in (True, 2.5, [2]):
        with pytest.raises(gmslab.InputError, match="elements: expected a whole number 1..64"):
            gmslab.identify(out, elements=bad, **opts)
    with pytest.raises(gmslab.InputError, match="elements"):
        gmslab.identify(out, elements=0, **opts)


@pytest.mark.parametrize("ext", [".csv", ".h5", ".mat"])
def test_trace_files_in_every_format(cli, tmp_path, ext):
    """gmslab simulate --out by extension; load_trace gives the columns by name, load_record reads it as is."""
    sc = gmslab.load_scenario("fig2d_nondrifting")
    sc.run.duration = 0.5
    preset = tmp_path / "short.json"
    gmslab.save_scenario(sc, preset)
    out = tmp_path / ("trace" + ext)
    cli("simulate", str(preset), "--out", str(out))
    tr = gmslab.simulate(sc)
    cols = gmslab.load_trace(out)
    rtol = 1e-9 if ext == ".csv" else 0  # CSV: 10 significant digits; HDF5 and .mat: the doubles
    for name, want in (("t_s", tr.t), ("x_m", tr.x), ("v_mps", tr.v), ("F_friction_N", tr.friction),
                       ("F_applied_N", tr.applied), ("F2_N", tr.element_force[:, 1])):
        np.testing.assert_allclose(cols[name], want, rtol=rtol, atol=0, err_msg=name)
    np.testing.assert_array_equal(cols["slip3"], tr.element_slip[:, 2].astype(float))
    if ext == ".csv":
        assert list(cols)[:5] == ["t_s", "x_m", "v_mps", "F_friction_N", "F_applied_N"]
    rec = gmslab.load_record(out, force="applied")
    np.testing.assert_allclose(rec["F"], tr.applied, rtol=rtol, atol=0)
    bad = cli("simulate", str(preset), "--out", str(tmp_path / "trace.txt"), check=False)
    assert bad.returncode == 2 and "unknown extension '.txt'" in bad.stderr
