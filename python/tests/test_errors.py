"""Each documented exception, with the field or argument it names; a Ctrl-C in a long sweep."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

import telescopic


def test_a_scene_error_names_the_field_and_the_rule():
    with pytest.raises(telescopic.SceneError) as e:
        telescopic.Scene.load("scenes/adams-linear.toml", set={"contact.clearance": -1})
    assert ("contact.clearance", "must be a finite number >= 0 (got -1)") in e.value.errors
    with pytest.raises(telescopic.SceneError, match="no-such-scene"):
        telescopic.Scene.load("scenes/no-such-scene.toml")
    with pytest.raises(telescopic.SceneError, match="nonsense"):
        telescopic.Scene.load("scenes/adams-linear.toml", set={"contact.nonsense": 1})
    with pytest.raises(telescopic.SceneError):
        telescopic.Scene.from_toml("this is not toml")
    assert issubclass(telescopic.SceneError, telescopic.TelescopicError)


def test_set_values_are_bounded_and_take_numpy():
    import numpy as np

    deep = 1.0
    for _ in range(10_000):
        deep = [deep]
    with pytest.raises(telescopic.OptionError, match="nest deeper than 8"):
        telescopic.Scene.load("scenes/adams-linear.toml", set={"sections.modes": deep})
    with pytest.raises(telescopic.OptionError, match="holds no `=`"):
        telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end=0.1": 0.2})
    with pytest.raises(telescopic.OptionError, match="not a finite number"):
        telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": np.float64("nan")})
    # NumPy scalars and arrays give the same scene as Python's numbers and lists
    plain = telescopic.Scene.load(
        "scenes/adams-linear.toml", set={"sections.modes": [3, 4], "time.end": 0.25}
    )
    numpy = telescopic.Scene.load(
        "scenes/adams-linear.toml",
        set={"sections.modes": np.array([3, 4]), "time.end": np.float64(0.25)},
    )
    assert numpy.to_toml() == plain.to_toml()
    assert numpy.time == plain.time == (0.0, 0.25, plain.time[2])
    ints = telescopic.Scene.load(
        "scenes/adams-linear.toml", set={"sections.modes": [np.int64(3), np.int32(4)]}
    )
    assert ints.to_toml() == telescopic.Scene.load(
        "scenes/adams-linear.toml", set={"sections.modes": [3, 4]}
    ).to_toml()


@pytest.mark.parametrize(
    "kwargs, argument",
    [
        ({"method": "nonsense"}, "method"),
        ({"rtol": -1e-6}, "rtol"),
        ({"atol": 0.0}, "atol"),
        ({"model": "other"}, "model"),
        ({"stations": [(3, 0.0)]}, "stations"),
    ],
)
def test_a_bad_argument_is_an_option_error_naming_it(kwargs, argument):
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.1})
    with pytest.raises(telescopic.OptionError, match=argument):
        telescopic.simulate(scene, **kwargs)


def test_a_solver_error_has_the_time_and_the_method():
    scene = telescopic.Scene.load("scenes/adams-clearance.toml", set={"time.end": 0.5})
    with pytest.raises(telescopic.SolverError) as e:
        telescopic.simulate(scene, method="rk4", dt=1e-3)
    assert e.value.method == "rk4" and 0 < e.value.time < 0.5
    assert "stable" in str(e.value)


def test_other_arguments_are_checked():
    scene = telescopic.Scene.load("scenes/case-study.toml")
    with pytest.raises(telescopic.OptionError, match="contacts"):
        telescopic.linearize(scene, contacts="half")
    with pytest.raises(telescopic.OptionError, match="positions"):
        telescopic.linearize(scene, positions={"b2": 0.8})
    for count in (-3, 1, 2.5, 2**70):
        with pytest.raises(telescopic.OptionError, match="^grid: "):
            telescopic.linearize(scene, grid={"a2": (0.35, 1.15, count)})
    # counts and section numbers that are no whole number >= 0 name their argument (PyO3's
    # own conversion would raise an OverflowError naming none)
    for call, argument in [
        (lambda: telescopic.modes(scene, count=-1), "count"),
        (lambda: telescopic.modes(scene, points=2**70), "points"),
        (lambda: telescopic.modes(scene, points=2.5), "points"),
        (lambda: telescopic.simulate(scene, stations=[(-1, 0.0)]), "stations"),
        (lambda: telescopic.sweep({"scene": "scenes/case-study.toml",
                                   "grid": {"masses.load": [1.0]}}, jobs=-2), "jobs"),
    ]:
        with pytest.raises(telescopic.OptionError, match=f"^{argument}: must be a whole number"):
            call()
    with pytest.raises(telescopic.OptionError, match="controller"):
        telescopic.design(scene, controller="pid")
    with pytest.raises(telescopic.OptionError, match="shaper_timing"):
        telescopic.design(scene, shaper_timing="early")
    with pytest.raises(telescopic.OptionError, match="^process_noise_floor: must be"):
        telescopic.design(scene, sensors=["vehicle", "kappa_1_0"], estimator="extended",
                          process_noise_floor=-1.0)
    with pytest.raises(telescopic.OptionError, match="^tip_scale: must be"):
        telescopic.design(scene, tip_scale=0.0)
    with pytest.raises(telescopic.OptionError, match="format"):
        telescopic.equations(scene, format="pdf")
    with pytest.raises(telescopic.OptionError, match="jobs"):
        telescopic.sweep({"scene": "scenes/case-study.toml", "grid": {"masses.load": [1.0]}}, jobs=0)
    with pytest.raises(telescopic.TelescopicError):
        telescopic.Controller.from_json("{}")
    with pytest.raises(KeyError, match="columns"):
        telescopic.simulate(telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.1}))["nope"]


def test_ctrl_c_in_a_long_sweep_raises_keyboard_interrupt_and_leaves_no_file(tmp_path):
    # the signal goes out once the sweep has finished its first run (the progress callback
    # says so), while 399 runs of about 0.25 s each remain: it cannot have ended first
    script = textwrap.dedent(
        """
        import sys, telescopic
        announced = []
        def progress(fraction):
            if fraction > 0 and not announced:
                announced.append(fraction)
                print("first run done", flush=True)
        try:
            telescopic.sweep({"scene": "scenes/case-study.toml",
                              "grid": {"masses.load": [10.0 + 0.05 * i for i in range(400)]}},
                             jobs=1, progress=progress)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(7)
        print("finished", flush=True)
        """
    )
    env = dict(os.environ, TMPDIR=str(tmp_path))
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, env=env)
    assert p.stdout.readline().strip() == "first run done"
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=300)
    waited = time.monotonic() - sent
    assert p.returncode == 7 and "interrupted" in out and "finished" not in out, out
    # it stops after the run in progress (measured 0.23-0.37 s), not after the 399 left
    assert waited < 20.0, waited
    assert list(tmp_path.iterdir()) == [], "no file left behind"


# a single run of some 50 s: dopri5 at a tight tolerance over 600 s of case-study
LONG_RUN = (
    'telescopic.simulate(telescopic.Scene.load("scenes/case-study.toml", set={"time.end": 600.0}), '
    'method="dopri5", rtol=1e-10, atol=1e-13, error_estimate=False, progress=progress)'
)


def test_ctrl_c_stops_a_single_run():
    script = textwrap.dedent(
        f"""
        import sys, telescopic
        announced = []
        def progress(fraction):
            if fraction > 0 and not announced:
                announced.append(fraction)
                print("running", flush=True)
        try:
            {LONG_RUN}
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(7)
        print("finished", flush=True)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "running"
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=300)
    assert p.returncode == 7 and "interrupted" in out and "finished" not in out, out
    # the run stops at its next progress report (1 % of the span), not at its end
    assert time.monotonic() - sent < 20.0


def test_an_exception_in_the_progress_callable_stops_its_own_call_only():
    import threading

    # a sweep in another thread runs on while this thread's run is stopped by its callable
    sweep_started = threading.Event()
    results = {}

    def sweep():
        def progress(fraction):
            sweep_started.set()

        results["sweep"] = telescopic.sweep(
            {
                "scene": "scenes/case-study.toml",
                "grid": {"masses.load": [10.0 + 0.5 * i for i in range(8)]},
            },
            jobs=1,
            progress=progress,
        )

    worker = threading.Thread(target=sweep)
    worker.start()
    assert sweep_started.wait(timeout=120)

    class Refused(Exception):
        pass

    def progress(fraction):
        if fraction > 0:
            raise Refused("enough")

    started = time.monotonic()
    with pytest.raises(Refused):
        eval(LONG_RUN, {"telescopic": telescopic, "progress": progress})
    assert time.monotonic() - started < 20.0
    worker.join(timeout=300)
    frame = results["sweep"]
    assert len(frame) == 8 and (frame["status"] == "ok").all(), frame


def test_exceptions_carry_their_attributes_on_every_path():
    with pytest.raises(telescopic.SceneError) as e:
        telescopic.Scene.load("scenes/adams-linear.toml", set={"contact.nonsense": 1})
    assert [field for field, _ in e.value.errors] == ["contact.nonsense"], e.value.errors
    with pytest.raises(telescopic.SceneError) as e:
        telescopic.Scene.from_toml("this is not toml")
    assert len(e.value.errors) == 1
    # the binding's own argument errors name the argument too
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.1})
    with pytest.raises(telescopic.OptionError) as e:
        telescopic.modes(scene, count=-1)
    assert e.value.option == "count"
    # a run refused before it starts has no time or method, but has the attributes
    with pytest.raises(telescopic.SolverError) as e:
        telescopic.simulate(scene, method="rk4", dt=1e-9)
    assert e.value.time is None and e.value.method is None


def test_scene_text_is_capped_and_a_long_line_is_not_quoted_whole():
    with pytest.raises(telescopic.SceneError, match="at most 16777216 bytes"):
        telescopic.Scene.from_toml("# " + "x" * (17 << 20))
    with pytest.raises(telescopic.SceneError) as e:
        telescopic.Scene.from_toml("a = " + "[" * 100 + "1" * 1_000_000)
    assert len(str(e.value)) < 10_000


def test_a_scene_pickles():
    import pickle

    # a float, a list, a string and an inline table, each kept as the value it is
    scene = telescopic.Scene.load("scenes/case-study.toml", set={
        "contact.clearance": 0.004,
        "sections.length": [1.35, 1.2],
        "gravity.force_flow": "none",
        "drive.force": {"kind": "constant", "value": 50.0},
    })
    import tomllib

    written = tomllib.loads(scene.to_toml())
    assert written["contact"]["clearance"] == 0.004
    assert written["sections"]["length"] == [1.35, 1.2]
    assert written["gravity"]["force_flow"] == "none"
    assert written["drive"]["force"]["value"] == 50.0
    back = pickle.loads(pickle.dumps(scene))
    assert back.to_toml() == scene.to_toml()
    assert back.overrides == scene.overrides and back.path == scene.path


def test_a_controller_file_is_read_with_the_input_cap():
    with pytest.raises(telescopic.OptionError, match="more than the 16777216 bytes"):
        telescopic.Controller.load("/dev/zero")


def test_an_integer_too_large_names_its_argument():
    # PyO3's own conversion would raise an OverflowError naming no argument
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.2})
    calls = [
        (lambda: telescopic.plan(scene, 2.0, checks=10**30), "checks"),
        (lambda: telescopic.plan(scene, 2.0, checks=-1), "checks"),
        (lambda: telescopic.simulate(scene).animate(size=(2**40, 100)), "size"),
        (lambda: telescopic._telescopic.animate_modes_of(scene, count=2**70), "count"),
    ]
    for call, name in calls:
        with pytest.raises(telescopic.OptionError) as caught:
            call()
        assert caught.value.option == name, (name, caught.value)
