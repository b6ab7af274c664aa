"""The package against the CLI and against itself: the same numbers by another path."""

import json
import re
import threading

import numpy as np
import pandas as pd
import pytest

import telescopic


def test_simulate_equals_the_cli_csv(cli, tmp_path):
    scene = telescopic.Scene.load("scenes/case-study.toml", set={"time.end": 2.0})
    sim = telescopic.simulate(scene)
    csv = tmp_path / "run.csv"
    out = cli("simulate", "scenes/case-study.toml", "--set", "time.end=2", "--out", str(csv), "--json")
    theirs = pd.read_csv(csv, comment="#")
    assert list(theirs.columns) == ["t", *sim.columns]
    for name in theirs.columns:
        assert np.max(np.abs(sim[name] - theirs[name].to_numpy())) <= 1e-12, name
    frame = sim.to_pandas()
    assert frame.index.name == "t" and list(frame.columns) == sim.columns
    assert sim.summary["method"] == "dop853-imex" and sim.summary["switches"] > 0
    # the error budget: the same numbers as the CSV's `#` header, both parts
    error = sim.summary["error"]
    assert error["window_end"] == "first-switch" and 0 < error["window_end_s"] < 2.0
    assert error["refined_modes"] == [6, 6] and sim.summary["modes"] == [4, 4]
    assert 0 < error["integration_m"] < error["truncation_m"] < 1e-2
    # with clearance the statistics lead the header; then tip_rel, then the other outputs
    lines = csv.read_text().splitlines()
    assert lines[0].startswith("# error of the statistics beyond"), lines[0]
    header = next(line for line in lines if line.startswith("# error of tip_rel"))
    # the companion is integrated finer: its difference holds this run's integration too
    assert error["integration_included"], error
    written = float(re.search(r"truncation and this run's integration ([0-9.e+-]+) m",
                              header).group(1))
    assert abs(written - error["truncation_m"]) <= 0.05 * error["truncation_m"], header
    assert set(error["statistics"]) >= {"rms-tip-rel", "peak-tip-rel", "contact-switches"}
    assert all(isinstance(v, tuple) and len(v) == 2 for v in error["statistics"].values())
    # every other output's truncation, by column, in its own unit
    assert {"top1_rel", "xi_2_0", "f_2_0", "kappa_1_0"} <= set(error["outputs"])
    assert all(v >= 0 for v in error["outputs"].values())
    # one summary behind both faces: the command's JSON has the same keys and the same run
    theirs_summary = json.loads(out.stdout)
    assert set(theirs_summary) == set(sim.summary)
    for key in ("method", "steps", "rhs_evaluations", "switches", "samples", "modes", "basis"):
        assert theirs_summary[key] == sim.summary[key], key


def test_a_repeated_simulate_reuses_the_budget_and_the_cli_reads_the_same_record(
        cli, tmp_path, monkeypatch):
    records = tmp_path / "records"
    monkeypatch.setenv("TELESCOPIC_CACHE_DIR", str(records))
    scene = telescopic.Scene.load("scenes/adams-clearance.toml", set={"time.end": 0.5})
    first = telescopic.simulate(scene)
    assert first.summary["error"]["reused_from"] is None
    (record,) = records.iterdir()
    second = telescopic.simulate(scene)
    assert second.summary["error"]["reused_from"] == str(record)
    assert np.array_equal(first.to_numpy(), second.to_numpy())
    without = {k: v for k, v in second.summary["error"].items() if k != "reused_from"}
    assert without == {k: v for k, v in first.summary["error"].items() if k != "reused_from"}
    # the command names a run by the same scene and options: it reuses Python's record
    out = cli("simulate", "scenes/adams-clearance.toml", "--set", "time.end=0.5",
              "--out", str(tmp_path / "run.csv"), "--json")
    assert json.loads(out.stdout)["error"]["reused_from"] == str(record)
    afresh = telescopic.simulate(scene, reuse=False)
    assert afresh.summary["error"]["reused_from"] is None
    assert afresh.summary["error"]["total_m"] == first.summary["error"]["total_m"]


def test_a_scene_from_text_and_from_its_file_agree():
    path = "scenes/adams-clearance.toml"
    with open(path, encoding="utf-8") as f:
        text = f.read()
    a = telescopic.Scene.load(path, set={"time.end": 0.3})
    b = telescopic.Scene.from_toml(text, set={"time.end": 0.3})
    c = telescopic.Scene.load(path).with_set({"time.end": 0.3})
    runs = [telescopic.simulate(s)["tip_rel"] for s in (a, b, c)]
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[0], runs[2])
    # to_toml reads back as the same scene
    d = telescopic.Scene.from_toml(a.to_toml())
    assert np.array_equal(telescopic.simulate(d)["tip_rel"], runs[0])
    assert "adams-clearance" in repr(a) and "time.end" in repr(a)


def test_linearize_poles_are_the_modes_and_its_response_is_the_json_exports(cli, tmp_path):
    scene = telescopic.Scene.load("scenes/test-rig.toml")
    sys = telescopic.linearize(scene)
    modes = telescopic.modes(scene)
    poles = sys.poles()
    oscillating = np.sort(np.abs(poles[poles.imag > 1e-6])) / (2 * np.pi)
    assert np.allclose(oscillating, modes.frequencies_hz, rtol=1e-6)
    assert list(sys.state_labels)[:2] == ["u", "q_1_2"] and list(sys.input_labels) == ["F"]
    out = tmp_path / "model.json"
    cli("linearize", "scenes/test-rig.toml", "--out", str(out))
    doc = json.loads(out.read_text())
    p = doc["points"][0]
    a, b, c, d = (np.array(p[k]) for k in "ABCD")
    for w in [0.5, 3.0, 30.0, 300.0]:
        ours = sys(1j * w)
        theirs = c @ np.linalg.solve(1j * w * np.eye(a.shape[0]) - a, b) + d
        assert np.allclose(ours, theirs, rtol=1e-9, atol=0), w
    assert [s["name"] for s in doc["outputs"]] == list(sys.output_labels)


def test_a_grid_and_the_disturbance_and_discrete_models():
    scene = telescopic.Scene.load("scenes/case-study.toml")
    grid = telescopic.linearize(scene, grid={"a2": (0.35, 1.15, 3)})
    assert [p for p, _ in grid] == [{"a2": 0.35}, {"a2": 0.75}, {"a2": 1.15}]
    sysd = telescopic.linearize(scene, positions={"a2": 0.8}, disturbance=True, discrete=1e-3)
    assert list(sysd.input_labels) == ["F", "F_load"] and sysd.dt == 1e-3
    arrays = telescopic.linearize(scene, as_arrays=True)
    assert arrays["points"][0]["A"].shape == (16, 16)


def test_a_sweep_frame_equals_the_cli_sweeps_csv(cli, tmp_path):
    spec = {
        "scene": "scenes/adams-clearance.toml",
        "set": ["time.end=0.5"],
        "grid": {"contact.clearance": [0.005, 0.01], "masses.load": [10.0, 17.897]},
    }
    ours = telescopic.sweep(spec, jobs=2)
    path = tmp_path / "sweep.toml"
    path.write_text(
        'scene = "%s"\nset = ["time.end=0.5"]\n[grid]\n"contact.clearance" = [0.005, 0.01]\n'
        '"masses.load" = [10.0, 17.897]\n' % (telescopic.Scene.load(spec["scene"]).path.resolve())
    )
    out = tmp_path / "result.csv"
    cli("sweep", str(path), "--out", str(out))
    theirs = pd.read_csv(out, comment="#")
    assert list(ours.columns) == list(theirs.columns)
    assert len(ours) == 4
    numbers = [c for c in ours.columns if c not in ("wall_s", "status", "error")]
    for column in numbers:
        a, b = ours[column].to_numpy(), theirs[column].to_numpy()
        if a.dtype.kind == "f":
            assert np.allclose(a, b, rtol=0, atol=0, equal_nan=True), column
        else:
            assert (a == b).all(), column


def test_two_threads_simulate_at_once_and_agree_with_one():
    scene = telescopic.Scene.load("scenes/case-study.toml", set={"time.end": 4.0})
    alone = telescopic.simulate(scene)["tip_rel"]
    results = [None, None]

    def work(i):
        results[i] = telescopic.simulate(scene)["tip_rel"]

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(r, alone) for r in results)


def test_progress_reaches_one_and_a_controller_round_trips():
    fractions = []
    scene = telescopic.Scene.load("scenes/case-study.toml")
    telescopic.simulate(scene, progress=fractions.append)
    assert fractions and fractions[-1] == 1.0
    assert all(b >= a for a, b in zip(fractions, fractions[1:]))
    c = telescopic.design(scene, controller="shaper")
    # the shaped force is back at zero by the profile's last change (12 s), and with the
    # delayed trains it is not
    within = json.loads(c.to_json())
    assert within["shaper_timing"] == "within"
    assert within["feedforward"]["times"][-1] <= 12.0 + 1e-9
    delayed = json.loads(
        telescopic.design(scene, controller="shaper", shaper_timing="delayed").to_json()
    )
    assert delayed["shaper_timing"] == "delayed"
    assert delayed["feedforward"]["times"][-1] > 13.0
    # the design's settings reach the file as the CLI's flags do
    ekf = json.loads(
        telescopic.design(
            scene,
            sensors=["vehicle", "kappa_1_0"],
            estimator="extended",
            tip_scale=0.05,
            process_noise_floor=3e-10,
        ).to_json()
    )
    assert ekf["tip_scale_m"] == 0.05
    assert ekf["sampled"]["estimator"] == "extended"
    assert ekf["sampled"]["process_noise_floor"] == 3e-10
    again = telescopic.Controller.from_json(c.to_json())
    assert again.to_json() == c.to_json()
    with_controller = telescopic.simulate(scene, controller=again)
    without = telescopic.simulate(scene)
    assert not np.array_equal(with_controller["vehicle"], without["vehicle"])


def test_modes_and_equations():
    m = telescopic.modes(telescopic.Scene.load("scenes/test-rig.toml"))
    assert abs(m.frequencies_hz[0] - 0.4983) < 1e-4
    assert m.kinds[0] == "structural" and "contact" in m.kinds
    assert len(m.shapes[0]) == 2 and m.shapes[0][0].shape == (51,)
    assert "f1" in str(m)
    latex = m._repr_latex_()
    assert latex.startswith("$\\begin{array}") and "0.498275" in latex and "contact" in latex
    latex = telescopic.equations(telescopic.Scene.load("scenes/adams-linear.toml"))
    assert latex.startswith("\\documentclass") or "\\begin" in latex
