"""Identification from Python: a record the model makes with another load is fitted back
with a deviation that covers the error, the fitted Scene and the residuals come back as
the CLI reports them, and a bad record is refused naming its column and row."""

import tomllib

import numpy as np
import pytest

import telescopic


def _record(load: float, seed: int, sigma: float = 1e-4):
    """A 1 s record of adams-linear (its paper's 5 modes) with ``load``: t, F and the tip and
    strain gauge with noise ``sigma``."""
    import pandas as pd

    scene = telescopic.Scene.load("scenes/adams-linear.toml",
                                  set={"time.end": 1.0, "masses.load": load})
    sim = telescopic.simulate(scene, error_estimate=False)
    rng = np.random.default_rng(seed)
    return pd.DataFrame({
        "t": sim.t,
        "F": np.full(len(sim.t), 100.0),
        "tip_rel": sim["tip_rel"] + rng.normal(0, sigma, len(sim.t)),
        "kappa_1_0": sim["kappa_1_0"] + rng.normal(0, sigma, len(sim.t)),
    })


def test_a_load_is_fitted_back_with_an_honest_deviation(cli, tmp_path):
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 1.0})
    fit = telescopic.identify(scene, _record(24.0, 1), free=["masses.load"], size="5",
                              validate=_record(24.0, 2), progress=False)
    row = fit.values.iloc[0]
    assert row["key"] == "masses.load"
    assert abs(row["value"] - 24.0) <= 4 * row["std"], fit.values
    assert row["std"] < 0.01 * 24.0
    # the residuals are fitted minus measured at every sample, as the report's RMS says
    tip = fit.sensors[fit.sensors["sensor"] == "tip_rel"].iloc[0]
    assert abs(fit.residuals["tip_rel"].std(ddof=0) - tip["rms_residual"]) < 1e-3 * tip["rms_residual"]
    assert set(fit.validation["sensor"]) == {"tip_rel", "kappa_1_0"}
    assert (fit.validation["relative"] < 0.03).all(), fit.validation
    fitted_load = tomllib.loads(fit.scene.to_toml())["masses"]["load"]
    assert abs(fitted_load - row["value"]) < 1e-9 * row["value"]
    # the CLI fits the same record to the same value
    data = tmp_path / "run.csv"
    _record(24.0, 1).to_csv(data, index=False)
    printed = cli("identify", "scenes/adams-linear.toml", "--set", "time.end=1", "--data",
                  str(data), "--free", "masses.load", "--size", "5").stdout
    line = next(l for l in printed.splitlines() if l.strip().startswith("masses.load"))
    assert abs(float(line.split()[1]) - row["value"]) < 1e-6 * row["value"], printed


def test_a_bad_record_is_refused_naming_its_column_and_row():
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 1.0})
    data = _record(20.0, 3)
    data.loc[7, "tip_rel"] = np.nan
    with pytest.raises(telescopic.TelescopicError, match="row 7, column tip_rel"):
        telescopic.identify(scene, data, free=["masses.load"], progress=False)
    with pytest.raises(telescopic.OptionError, match="offsets"):
        telescopic.identify(scene, _record(20.0, 3), free=["masses.load"], offsets="mean",
                            progress=False)
    both = _record(20.0, 3)
    both["s"] = 0.0
    with pytest.raises(telescopic.TelescopicError, match="not both"):
        telescopic.identify(scene, both, free=["masses.load"], progress=False)


def test_a_record_that_starts_in_motion_is_fitted_with_start_moving():
    import pandas as pd

    truth = telescopic.Scene.load("scenes/adams-linear.toml",
                                  set={"time.end": 1.0, "masses.load": 24.0})
    sim = telescopic.simulate(truth, error_estimate=False)
    rng = np.random.default_rng(5)
    first = int(np.searchsorted(sim.t, 0.3 - 1e-9))
    rows = slice(first, None)
    data = pd.DataFrame({
        "t": sim.t[rows] - sim.t[first],
        "F": np.full(len(sim.t) - first, 100.0),
        "vehicle": sim["vehicle"][rows] + rng.normal(0, 1e-5, len(sim.t) - first),
        "tip_rel": sim["tip_rel"][rows] + rng.normal(0, 1e-4, len(sim.t) - first),
    })
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 1.0})
    fit = telescopic.identify(scene, data, free=["masses.load"], size="5", start="moving",
                              progress=False)
    row = fit.values.iloc[0]
    assert abs(row["value"] - 24.0) <= 4 * row["std"], fit.values
    vehicle = np.asarray(sim["vehicle"])
    speed = (vehicle[first + 1] - vehicle[first - 1]) / (sim.t[first + 1] - sim.t[first - 1])
    assert abs(fit.start_vehicle_speed - speed) < 1e-2 * abs(speed), (fit.start_vehicle_speed, speed)
    assert "start in motion" in str(fit)
    with pytest.raises(telescopic.OptionError, match="start"):
        telescopic.identify(scene, data, free=["masses.load"], start="walking", progress=False)
