"""Planning a move from Python: the table as a DataFrame, the best plan as a Scene that
simulates to the table's cycle time, the CLI's table."""

import tomllib

import numpy as np

import telescopic


def test_plan_returns_the_table_and_a_scene_that_reproduces_it(cli, capsys):
    scene = telescopic.Scene.load("scenes/adams-linear.toml")
    plan = telescopic.plan(scene, 2.0, v_max=1.0, a_max=1.0, j_max=5.0, tolerance=0.002,
                           settle=4.0, optimize=False)
    # what the planner does is on stderr as it goes, with the share done, as the CLI's log
    said = capsys.readouterr().err
    assert "evaluating 6 candidates on 1 plants, side by side" in said, said
    assert "%]" in said
    assert abs(plan.rigid_limit_s - 3.2) < 1e-12
    assert set(plan.table["candidate"]) >= {"s-curve", "zv", "zvd", "ei", "2ei"}
    best = plan.table[(plan.table["candidate"] == plan.best) & (plan.table["plant"] == "nominal")]
    cycle = float(best["cycle_time_s"].iloc[0])
    assert cycle == plan.worst_cycle_s
    # the best is ranked on its pick: within the tolerance less the margin, never earlier
    assert float(best["pick_cycle_time_s"].iloc[0]) == plan.worst_pick_s >= cycle
    sim = telescopic.simulate(plan.scene, error_estimate=False)
    rest = sim["tip_rel"][sim.t >= sim.t[-1] - 1.0].mean()
    outside = (np.abs(sim["tip_rel"] - rest) > 0.002) | (np.abs(sim["vehicle"] - 2.0) > 1e-3)
    last = np.nonzero(outside)[0][-1]
    move = float(best["move_time_s"].iloc[0])
    assert abs(max(sim.t[last + 1], move) - cycle) < 1e-9
    assert float(best["settling_time_s"].iloc[0]) >= 0.0
    # each plant of the table is defined: the nominal scene, and its neighbours 1 % away
    assert set(plan.table["plant"]) == set(plan.plants)
    assert plan.plants["nominal"] == {}
    with open("scenes/adams-linear.toml", "rb") as file:
        load = tomllib.load(file)["masses"]["load"]
    assert plan.plants["load +1%"].keys() == {"masses.load"}
    assert abs(plan.plants["load +1%"]["masses.load"] / load - 1.01) < 1e-12
    printed = cli("plan", "scenes/adams-linear.toml", "--distance", "2", "--v-max", "1",
                  "--a-max", "1", "--j-max", "5", "--tolerance", "0.002", "--settle", "4",
                  "--no-optimize").stdout
    assert printed == str(plan)


def test_a_plan_with_feedback_runs_from_python_as_the_cli_reports(cli, tmp_path):
    flags = ["--distance", "2", "--v-max", "1", "--a-max", "1", "--j-max", "5",
             "--tolerance", "0.002", "--settle", "6", "--no-optimize", "--feedback", "0.2"]
    out = tmp_path / "plan.toml"
    printed = cli("plan", "scenes/adams-linear.toml", *flags, "--pick", "s-curve + feedback",
                  "--out", str(out)).stdout
    row = next(line for line in printed.splitlines()
               if line.startswith(f"{'s-curve + feedback':<52} nominal"))
    reported = float(row[52:].split()[3])
    scene = telescopic.Scene.load(str(out))
    controller = telescopic.Controller.load(str(out.with_suffix(".json")))
    assert "velocity feedback" in repr(controller)
    sim = telescopic.simulate(scene, controller=controller, error_estimate=False)
    rest = sim["tip_rel"][sim.t >= sim.t[-1] - 1.0].mean()
    outside = (np.abs(sim["tip_rel"] - rest) > 0.002) | (np.abs(sim["vehicle"] - 2.0) > 1e-3)
    last = np.nonzero(outside)[0][-1]
    assert abs(sim.t[last + 1] - reported) < 0.006
    # the same plan from Python: the same table, feedback rows among its candidates
    plan = telescopic.plan(telescopic.Scene.load("scenes/adams-linear.toml"), 2.0, v_max=1.0,
                           a_max=1.0, j_max=5.0, tolerance=0.002, settle=6.0, optimize=False,
                           feedback=0.2)
    assert "s-curve + feedback" in set(plan.table["candidate"])
    assert str(plan) == printed
    assert (plan.controller is None) == ("feedback" not in plan.best)


def test_a_load_scheduled_feedback_is_told_the_weighed_load_as_the_cli_tells_it(cli, tmp_path):
    import pytest

    out = tmp_path / "plan.toml"
    cli("plan", "scenes/adams-linear.toml", "--distance", "2", "--v-max", "1", "--a-max", "1",
        "--j-max", "5", "--tolerance", "0.002", "--settle", "4", "--no-optimize", "--checks",
        "0", "--robust", "masses.load=12:24", "--feedback", "0.2", "--pick",
        "s-curve + feedback", "--out", str(out))
    scene = telescopic.Scene.load(str(out))
    controller = telescopic.Controller.load(str(out.with_suffix(".json")))
    assert "loads 12.0 to 24.0 kg" in repr(controller)
    carried = telescopic.simulate(scene, controller=controller, error_estimate=False)
    same = telescopic.simulate(scene, controller=controller, error_estimate=False,
                               weighed_load=17.897)
    other = telescopic.simulate(scene, controller=controller, error_estimate=False,
                                weighed_load=24.0)
    assert np.array_equal(carried["vehicle"], same["vehicle"])
    assert not np.array_equal(carried["vehicle"], other["vehicle"])
    # the CLI's run told the same load writes the same samples
    csv = tmp_path / "other.csv"
    cli("simulate", str(out), "--controller", str(out.with_suffix(".json")),
        "--no-error-estimate", "--weighed-load", "24", "--out", str(csv))
    data = np.genfromtxt(csv, delimiter=",", names=True, comments="#")
    assert np.array_equal(data["vehicle"], other["vehicle"])
    for bad in (float("nan"), -1.0):
        with pytest.raises(telescopic.OptionError) as caught:
            telescopic.simulate(scene, controller=controller, weighed_load=bad)
        assert "weighed_load" in str(caught.value)


def test_a_plan_too_large_is_refused_before_any_work_naming_the_argument():
    import pytest

    scene = telescopic.Scene.load("scenes/adams-linear.toml")
    for arguments, name in [({"checks": 10**9, "robust": {"masses.load": (10, 30)}}, "checks"),
                            ({"v_max": 0.003}, "v_max/a_max/j_max")]:
        with pytest.raises(telescopic.OptionError) as caught:
            telescopic.plan(scene, 23.0, **arguments)
        assert caught.value.option == name, (arguments, caught.value)


def test_an_exception_of_the_progress_callable_ends_the_plan_with_it():
    # the plan stops at its next run or eigen analysis (tests/plan.rs shows where); here the
    # exception reaches Python as raised, once
    import pytest

    scene = telescopic.Scene.load("scenes/case-study.toml")
    calls = []

    def progress(fraction):
        calls.append(fraction)
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        telescopic.plan(scene, 23.0, robust={"masses.load": (10, 30), "contact.clearance": (0.005, 0.02),
                                             "sections.youngs_modulus": (1.9e11, 2.3e11)},
                        progress=progress)
    assert len(calls) == 1


def test_a_bad_margin_is_refused_naming_it():
    import pytest

    scene = telescopic.Scene.load("scenes/adams-linear.toml")
    with pytest.raises(telescopic.OptionError, match="margin.*0 to 0.9"):
        telescopic.plan(scene, 2.0, margin=1.5)
