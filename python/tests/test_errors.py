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
