"""Telescopic multi-section beams with clearance, in Python.

The Rust library of the ``telescopic`` project (Barthelis & Wauer's telescopic beams with
clearance: derived Galerkin equations, the clearance contact law, integrators, modes,
linear models, controllers, sweeps), with results as NumPy arrays, pandas DataFrames and
python-control state-space models. Long calls release the GIL, report progress to a callable
(``progress=``) and stop on Ctrl-C with ``KeyboardInterrupt``. See docs/python.md.

>>> import telescopic
>>> scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.5})
>>> sim = telescopic.simulate(scene)
>>> sim["tip_rel"].shape
(501,)
"""

from __future__ import annotations

import io
import os
import tempfile
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from . import _telescopic
from ._telescopic import (
    OptionError,
    Scene,
    SceneError,
    SolverError,
    TelescopicError,
    __version__,
)

__all__ = [
    "Scene",
    "Simulation",
    "Modes",
    "Controller",
    "Animation",
    "simulate",
    "modes",
    "plan",
    "Plan",
    "identify",
    "Identification",
    "linearize",
    "design",
    "sweep",
    "equations",
    "TelescopicError",
    "SceneError",
    "OptionError",
    "SolverError",
    "__version__",
]


def _progress(progress: Any) -> Callable[[float], None] | None:
    """A progress callable: the caller's, a tqdm bar for ``True`` (when tqdm is installed)."""
    if progress is None or progress is False:
        return None
    if progress is True:
        try:
            from tqdm.auto import tqdm  # type: ignore
        except ImportError:
            return None
        bar = tqdm(total=1.0, bar_format="{l_bar}{bar}| {n:.0%}")

        def update(fraction: float) -> None:
            bar.n = fraction
            bar.refresh()
            if fraction >= 1.0:
                bar.close()

        return update
    if not callable(progress):
        raise OptionError(f"progress: {progress!r} is not callable (or True for tqdm)")
    return progress


class Animation:
    """An animated view (``telescopic animate``): Jupyter shows it inline; ``save`` writes it.

    ``html`` is the self-contained page (the same document the CLI writes); ``frame_count``
    its frames (a run) or modes (a modes' view).
    """

    def __init__(self, movie: Any):
        self._movie = movie

    @property
    def html(self) -> str:
        """The self-contained HTML document."""
        return self._movie.html

    @property
    def frame_count(self) -> int:
        """Frames of a run's view, modes of a modes' view."""
        return self._movie.frame_count

    def save(self, path: str | os.PathLike) -> int:
        """Writes the view to ``path``: ``.html``, or ``.gif`` for a run (its frames at the
        view's rate); complete or not at all. Returns the file's size in bytes."""
        return self._movie.save(os.fspath(path))

    def _repr_html_(self) -> str:
        """The page in a sandboxed frame of its own, so its script runs in Jupyter."""
        import html

        return (
            '<iframe style="width: 100%; height: 640px; border: 0" sandbox="allow-scripts" '
            f'srcdoc="{html.escape(self.html, quote=True)}"></iframe>'
        )

    def __repr__(self) -> str:
        return f"Animation({self.frame_count} frames, {len(self.html)} bytes of HTML)"


class Simulation:
    """A finished simulation: ``t`` and every output column as NumPy arrays.

    ``sim["tip_rel"]`` is a column (m), ``sim.columns`` their names (the CLI's CSV columns
    after ``t``), ``sim.summary`` what ran (method, steps, switches, wall time, ...).
    """

    def __init__(self, columns: list[str], data: np.ndarray, summary: dict[str, Any],
                 request: dict[str, Any] | None = None):
        self.columns: list[str] = list(columns)
        self._data = data
        self.summary: dict[str, Any] = summary
        self._request = request

    def animate(self, fps: float | None = None, scale: float | None = None,
                size: tuple[int, int] | None = None, speed: float | None = None,
                compare: Scene | None = None, progress: Any = None) -> Animation:
        """The run as an animated view (``telescopic animate``): the scene is run again with
        the same options, its coordinates recorded (the same samples: runs are
        deterministic). ``fps`` frames per second of simulation (default 50), ``scale`` the
        deflection's exaggeration (default: readable), ``size`` and ``speed`` a GIF's,
        ``compare`` a second scene side by side."""
        if self._request is None:
            raise OptionError("animate: this simulation does not know how it was run")
        request = dict(self._request)
        scene = request.pop("scene")
        controller = request.pop("controller")
        weighed_load = request.pop("weighed_load")
        return Animation(_telescopic.animate(
            scene, request, controller=controller, compare=compare, fps=fps, scale=scale,
            size=size, speed=speed, progress=_progress(progress), weighed_load=weighed_load))

    @property
    def t(self) -> np.ndarray:
        """Sample times (s)."""
        return self._data[:, 0]

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "t":
            return self.t
        try:
            return self._data[:, 1 + self.columns.index(name)]
        except ValueError:
            raise KeyError(f"{name!r} is not a column; the columns are {self.columns}") from None

    def __contains__(self, name: str) -> bool:
        return name == "t" or name in self.columns

    def to_numpy(self) -> np.ndarray:
        """All samples: one row per time, ``t`` then the columns."""
        return self._data

    def to_pandas(self):
        """A pandas DataFrame of the columns, indexed by ``t`` (s)."""
        import pandas as pd

        frame = pd.DataFrame(self._data[:, 1:], columns=self.columns)
        frame.index = pd.Index(self.t, name="t")
        return frame

    def _repr_latex_(self) -> str:
        """A one-line summary as LaTeX (Jupyter shows it)."""
        s = self.summary
        return (
            f"$\\text{{{s['scene']}: {s['samples']} samples, method {s['method']}, "
            f"{s['steps']} steps, {s['switches']} contact switches}}$"
        )

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"Simulation({s['scene']!r}: {s['samples']} samples of {len(self.columns)} columns, "
            f"method {s['method']}, {s['steps']} steps, {s['switches']} contact switches, "
            f"{s['wall_s']:.3f} s)"
        )


class Modes:
    """Natural frequencies (Hz), damping and mode shapes of a scene, contacts closed."""

    def __init__(self, data: dict[str, Any], request: dict[str, Any] | None = None):
        self._request = request
        self.frequencies_hz: np.ndarray = data["frequencies_hz"]
        self.damped_frequencies_hz: np.ndarray = data["damped_frequencies_hz"]
        self.damping_ratios: np.ndarray = data["damping_ratios"]
        self.kinds: list[str] = data["kinds"]
        self.rigid_modes: int = data["rigid_modes"]
        #: per mode, per section: the deflection along the section, largest |w| = 1
        self.shapes: list[list[np.ndarray]] = data["shapes"]
        self.time_s: float = data["time_s"]
        self.model: str = data["model"]
        self._table: str = data["table"]

    def __len__(self) -> int:
        return len(self.frequencies_hz)

    def animate(self) -> Animation:
        """The modes as an animated view (``telescopic modes --animate``): each shape
        oscillating, with its frequency, damping ratio and kind."""
        if self._request is None:
            raise OptionError("animate: these modes do not know how they were computed")
        return Animation(_telescopic.animate_modes_of(**self._request))

    def __str__(self) -> str:
        return self._table

    def _repr_latex_(self) -> str:
        """The table as LaTeX (Jupyter shows it)."""
        rows = " \\\\ ".join(
            f"f_{{{i + 1}}} & {f:.6g} & {d:.6g} & {z:.3g} & \\text{{{k}}}"
            for i, (f, d, z, k) in enumerate(
                zip(self.frequencies_hz, self.damped_frequencies_hz, self.damping_ratios, self.kinds)
            )
        )
        return (
            "$\\begin{array}{lrrrl} & f\\ [\\mathrm{Hz}] & f_d\\ [\\mathrm{Hz}] & \\zeta & "
            f"\\text{{kind}} \\\\ \\hline {rows} \\end{{array}}$"
        )

    def __repr__(self) -> str:
        listed = ", ".join(f"{f:.4g}" for f in self.frequencies_hz[:5])
        more = ", ..." if len(self) > 5 else ""
        return f"Modes({len(self)} modes: [{listed}{more}] Hz, {self.rigid_modes} rigid)"


class Controller:
    """A controller of ``design`` (its JSON is the controller file of ``telescopic design``),
    or the velocity feedback of a ``plan`` (``Plan.controller``)."""

    def __init__(self, text: str):
        self._json = _telescopic.check_controller(text)

    @classmethod
    def from_json(cls, text: str) -> "Controller":
        """A controller from the JSON of a controller file (checked)."""
        return cls(text)

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Controller":
        """Reads a controller file (at most 16 MiB, as every input)."""
        return cls(_telescopic.read_input(os.fspath(path)))

    def to_json(self) -> str:
        """The controller file's JSON."""
        return self._json

    def __repr__(self) -> str:
        import json

        doc = json.loads(self._json)
        if doc.get("format") == "telescopic velocity feedback":
            loads = [t["load_kg"] for t in doc["tables"]]
            scheduled = f", loads {loads[0]} to {loads[-1]} kg" if len(loads) > 1 else ""
            return f"Controller(velocity feedback, zeta {doc['added_damping']}{scheduled})"
        return f"Controller({doc.get('kind', '?')!r}, force limit {doc.get('force_limit_n', '?')} N)"


def simulate(
    scene: Scene,
    method: str = "auto",
    rtol: float | None = None,
    atol: float | None = None,
    dt: float | None = None,
    accuracy: float | None = None,
    controller: Controller | None = None,
    stations: Iterable[tuple[int, float]] | None = None,
    model: str = "auto",
    progress: Any = None,
    modes_as_given: bool = False,
    error_estimate: bool = True,
    moment_tolerance: float | None = None,
    statistics_tolerance: float | None = None,
    reuse: bool = True,
    weighed_load: float | None = None,
) -> Simulation:
    """Integrates ``scene`` from rest with the clearance contact law (``telescopic simulate``).

    ``method`` is one of the CLI's (``auto``, ``exact``, ``dopri5``, ``dop853``, ``dop853-imex``,
    ``imex``, ...);
    ``accuracy`` (m) is the whole error of ``tip_rel`` against the beams: the run picks the
    basis, the modes per section, the method and the tolerance that reach it cheapest (a
    scene that states an ``accuracy`` gets it by default when no method, tolerance or model
    is given; with ``modes_as_given=True`` the scene's modes stay and ``accuracy`` bounds the
    integration only; ``moment_tolerance`` and ``statistics_tolerance`` bound the moments and, with
    clearance, the statistics, defaults 0.02 and 0.05). ``summary["error"]`` holds the run's
    error in two parts (integration and truncation; ``error_estimate=False`` skips the
    companion run that estimates the truncation; a repeated run of the same scene and
    arguments reuses the budget its first run kept, as the CLI does, and ``reuse=False``
    estimates afresh and keeps nothing); ``controller`` drives the scene
    with a designed controller or a plan's velocity feedback (``weighed_load``, kg: the load
    that feedback is told, default the scene's ``masses.load``); ``stations`` adds bending moments (and stresses) at
    ``(section, x)``; ``progress`` is a callable taking the fraction done (or ``True`` for a
    tqdm bar). Raises ``SolverError`` (with ``.time`` and ``.method``) when the integration
    fails, ``OptionError`` for a bad argument.
    """
    if not isinstance(scene, Scene):
        raise OptionError(f"scene: expected a telescopic.Scene, got {type(scene).__name__}")
    text = controller.to_json() if controller is not None else None
    columns, data, summary = _telescopic.simulate(
        scene,
        method=method,
        rtol=rtol,
        atol=atol,
        dt=dt,
        accuracy=accuracy,
        controller=text,
        stations=list(stations) if stations is not None else None,
        model=model,
        progress=_progress(progress),
        modes_as_given=modes_as_given,
        error_estimate=error_estimate,
        moment_tolerance=moment_tolerance,
        statistics_tolerance=statistics_tolerance,
        reuse=reuse,
        weighed_load=weighed_load,
    )
    request = dict(scene=scene, method=method, rtol=rtol, atol=atol, dt=dt, accuracy=accuracy,
                   controller=text, model=model, modes_as_given=modes_as_given,
                   weighed_load=weighed_load)
    return Simulation(columns, data, summary, request)


def modes(scene: Scene, at: float | None = None, count: int | None = None, points: int = 51,
          model: str = "auto") -> Modes:
    """Natural frequencies (Hz), damped frequencies, damping ratios, kinds (structural or
    contact) and mode shapes sampled at ``points`` per section, contacts closed, positions at
    time ``at`` (default the start)."""
    data = _telescopic.modes(scene, at=at, count=count, points=points, model=model)
    return Modes(data, dict(scene=scene, at=at, count=count, model=model))


def _state_space(point: dict[str, Any], names: dict[str, Any], discrete: bool = False):
    try:
        import control
    except ImportError:
        raise TelescopicError(
            "linearize returns python-control StateSpace models: pip install control "
            "(or call telescopic.linearize(..., as_arrays=True) for the NumPy matrices)"
        ) from None
    a, b = (point["Ad"], point["Bd"]) if discrete else (point["A"], point["B"])
    args = (a, b, point["C"], point["D"]) + ((point["dt"],) if discrete else ())
    return control.ss(*args, states=names["states"], inputs=names["inputs"],
                      outputs=names["outputs"])


def linearize(
    scene: Scene,
    positions: Mapping[str, float] | None = None,
    at_time: float | None = None,
    contacts: str = "closed",
    grid: Mapping[str, tuple[float, float, int]] | None = None,
    disturbance: bool = False,
    discrete: float | None = None,
    model: str = "auto",
    as_arrays: bool = False,
):
    """The linear model ``x' = A x + B u, y = C x + D u`` about the straight configuration
    (``telescopic linearize``), as a python-control ``StateSpace`` with the state, input and
    output names of the JSON export.

    ``positions={"a2": 0.8}`` sets positions at rest; ``grid={"a2": (0.35, 1.15, 5)}`` gives a
    list of ``(positions, StateSpace)``; ``disturbance=True`` adds the input ``F_load``;
    ``discrete=DT`` returns the zero-order-hold model instead. ``as_arrays=True`` returns the
    plain dict of NumPy matrices and names (no python-control needed).
    """
    if grid is not None and len(grid) != 1:
        raise OptionError("grid: give one position, e.g. {'a2': (0.35, 1.15, 5)}")
    data = _telescopic.linearize(
        scene,
        positions=list(positions.items()) if positions else None,
        at_time=at_time,
        contacts=contacts,
        grid=next(iter(grid.items())) if grid else None,
        disturbance=disturbance,
        discrete=discrete,
        model=model,
    )
    if as_arrays:
        return data
    systems = [_state_space(p, data, discrete is not None) for p in data["points"]]
    if grid is None:
        return systems[0]
    return [(p["positions"], s) for p, s in zip(data["points"], systems)]


def design(
    scene: Scene,
    controller: str | None = None,
    force_limit: float | None = None,
    sensors: Sequence[str] | None = None,
    rate_hz: float | None = None,
    law: str | None = None,
    shaper_timing: str | None = None,
    tip_scale: float | None = None,
    vehicle_scale: float | None = None,
    estimator: str | None = None,
    process_noise_floor: float | None = None,
    added_damping: float | None = None,
    model: str = "auto",
    progress: Any = None,
) -> Controller:
    """Designs a vibration-suppressing controller (``telescopic design``): ``lqr``,
    ``shaper``, ``lqr+shaper`` or ``lqr+shaper+kalman``; with ``sensors`` (e.g.
    ``["vehicle", "kappa_1_0"]``) a sampled output-feedback controller at ``rate_hz``;
    ``shaper_timing`` ``within`` (the default: the shaper's trains inside the profile's span) or
    ``delayed``; the rest as ``telescopic design``'s flags of the same names (``None``: their
    defaults), e.g. ``estimator="extended", tip_scale=0.05`` for the extended Kalman filter
    that models the clearance."""
    text = _telescopic.design(
        scene,
        controller=controller,
        force_limit=force_limit,
        sensors=list(sensors) if sensors is not None else None,
        rate_hz=rate_hz,
        law=law,
        shaper_timing=shaper_timing,
        tip_scale=tip_scale,
        vehicle_scale=vehicle_scale,
        estimator=estimator,
        process_noise_floor=process_noise_floor,
        added_damping=added_damping,
        model=model,
        progress=_progress(progress),
    )
    return Controller(text)


def sweep(spec: str | os.PathLike | Mapping[str, Any], jobs: int | None = None,
          progress: Any = None):
    """Runs a parameter study (``telescopic sweep``) and returns a pandas DataFrame with the
    result file's columns, one row per run.

    ``spec`` is a sweep file or a dict of its keys, e.g.
    ``{"scene": "scenes/case-study.toml", "grid": {"contact.clearance": [0.005, 0.01]}}``
    (a relative scene is taken from the current directory).
    Runs on ``jobs`` threads (default: every core). Ctrl-C stops between runs and raises
    ``KeyboardInterrupt``; no file is left.
    """
    import pandas as pd

    # a dict goes to the library as values; the result file is a temporary one
    spec = dict(spec) if isinstance(spec, Mapping) else os.fspath(spec)
    with tempfile.TemporaryDirectory(prefix="telescopic-sweep-") as directory:
        out = os.path.join(directory, "result.csv")
        columns, rows = _telescopic.sweep(spec, out, jobs=jobs, progress=_progress(progress))
    return pd.read_csv(io.StringIO("\n".join([columns, *rows])))


def equations(scene: Scene, format: str = "latex") -> str:
    """The derived equations of motion of the scene's generated model: ``text``, ``latex``,
    ``rust`` or ``json``."""
    return _telescopic.equations(scene, format=format)


class Plan:
    """A planned move (``telescopic plan``): ``table`` a DataFrame with a row per candidate
    and plant, ``scene`` the best plan as a Scene (its setpoint as ``drive.motion``),
    ``best`` its name, ``rigid_limit_s`` the time-optimal move of a rigid telescope,
    ``worst_cycle_s`` and ``worst_pick_s`` the best's worst cycle and worst pick (what it was
    ranked on: within the tolerance less the margin) over the evaluated plants, None if
    never, ``controller`` the best plan's velocity feedback (a Controller) when it uses one, else
    None: ``simulate(plan.scene, controller=plan.controller)`` runs the plan. ``plants`` says
    what each plant of the table is: its name to the scene values it sets (key to value;
    empty for the nominal plant)."""

    def __init__(self, rows: list[dict[str, Any]], scene_text: str, summary: dict[str, Any]):
        import pandas as pd

        self.table = pd.DataFrame(rows)
        self.scene: Scene = Scene.from_toml(scene_text)
        self.scene_toml: str = scene_text
        self.best: str = summary["best"]
        self.rigid_limit_s: float = summary["rigid_limit_s"]
        self.first_mode_hz: float = summary["first_mode_hz"]
        self.worst_cycle_s: float | None = summary["worst_cycle_s"]
        self.worst_pick_s: float | None = summary["worst_pick_s"]
        self._text: str = summary["table"]
        self.plants: dict[str, dict[str, float]] = summary["plants"]
        feedback = summary["feedback"]
        self.controller: Controller | None = None if feedback is None else Controller(feedback)

    def __str__(self) -> str:
        return self._text

    def __repr__(self) -> str:
        worst = "never" if self.worst_cycle_s is None else f"{self.worst_cycle_s:.2f} s"
        return (f"Plan(best {self.best!r}, worst cycle {worst}, rigid limit "
                f"{self.rigid_limit_s:.2f} s)")


def plan(scene: Scene, distance: float, v_max: float | None = None,
         a_max: float | None = None, j_max: float | None = None,
         tolerance: float | None = None, margin: float | None = None,
         robust: Mapping[str, tuple[float, float]] | None = None, settle: float | None = None,
         optimize: bool = True, checks: int | None = None, force_limit: float | None = None,
         feedback: float | None = None, method: str = "auto", progress: Any = None) -> Plan:
    """The shortest move over ``distance`` (m) that brings the load to rest within
    ``tolerance`` (m) (``telescopic plan``), picked with ``margin`` (a share of the tolerance,
    default 0.2) in reserve: the time-optimal S-curve within ``v_max``,
    ``a_max``, ``j_max``, shaped by ZV/ZVD/EI/2EI (fixed and scheduled on the first mode) and
    optimized, each on the nonlinear model and every plant of ``robust`` (``{"masses.load":
    (10, 30)}``: its corners and centre). ``feedback`` (a damping ratio, e.g. 0.3) adds the
    velocity feedback on top of the S-curve and of the best open-loop move. A limit left at
    ``None`` takes the library's default (``telescopic plan``'s). Returns a ``Plan``: the
    table as a DataFrame and the best plan as a Scene. What the planner does (``[ 40 %]
    evaluating ZVD on 10 plants``) goes to ``sys.stderr`` as it starts; ``progress=False``
    keeps it quiet."""
    ranges = None
    if robust is not None:
        ranges = [(k, *bounds) for k, bounds in robust.items()]
    options = dict(method=method, rtol=None, atol=None, dt=None, accuracy=None, model="auto",
                   modes_as_given=False)
    defaulted = dict(v_max=v_max, a_max=a_max, j_max=j_max, tolerance=tolerance, margin=margin,
                     settle=settle,
                     checks=checks)
    rows, scene_text, summary = _telescopic.plan(
        scene, distance, robust=ranges, optimize=optimize, force_limit=force_limit,
        feedback=feedback, options=options, progress=_progress(progress),
        notes=progress is not False,
        **{k: v for k, v in defaulted.items() if v is not None})
    return Plan(rows, scene_text, summary)



def _columns(data: Any, name: str) -> tuple[list[str], list[list[float]]]:
    """A DataFrame's (or a mapping's) column names and columns as floats."""
    try:
        names = [str(c) for c in data.keys()]
        columns = [np.asarray(data[c], dtype=float).tolist() for c in data.keys()]
    except (AttributeError, TypeError, ValueError) as e:
        raise OptionError(
            f"{name}: a DataFrame of numbers with columns t, F and sensors ({e})") from None
    return names, columns


class Identification:
    """A fit of scene values to a record (``telescopic identify``): ``scene`` the fitted
    Scene, ``values`` a DataFrame of the values with their standard deviations (``std``,
    None on a bound), ``sensors`` each sensor's noise, offset, residual RMS and the model's
    own error, ``residuals`` a DataFrame of fitted minus measured at each sample, ``validation``
    each sensor's error on the unseen record (or None), ``correlation`` a DataFrame of the
    values' correlations, ``start_vehicle_speed`` the vehicle's speed (m/s) at the first
    sample fitted with ``start="moving"`` (else None), ``force_noise`` the recorded force's
    noise (N) where it shows (else None); ``str()`` is the CLI's report."""

    def __init__(self, values, sensors, residuals, validation, scene_text, summary):
        import pandas as pd

        self.values = pd.DataFrame(values)
        self.sensors = pd.DataFrame(sensors)
        names, rows = residuals
        self.residuals = pd.DataFrame(rows, columns=names)
        self.validation = None if validation is None else pd.DataFrame(validation)
        keys = summary["correlated"]
        self.correlation = pd.DataFrame(summary["correlation"], index=keys, columns=keys)
        self.scene: Scene = Scene.from_toml(scene_text)
        self.scene_toml: str = scene_text
        self.size: str = summary["size"]
        self.runs: int = summary["runs"]
        self.wall_s: float = summary["wall_s"]
        self.start_vehicle_speed: float | None = summary["start_vehicle_speed"]
        self.force_noise: float | None = summary["force_noise"]
        self._text: str = summary["text"]

    def __str__(self) -> str:
        return self._text

    def __repr__(self) -> str:
        parts = ", ".join(f"{k} {v:.6g}" for k, v in zip(self.values["key"], self.values["value"]))
        return f"Identification({parts}; model {self.size}, {self.runs} runs)"


def identify(scene: Scene, data: Any, free: Sequence[str] | Mapping[str, Any],
             noise: Mapping[str, float] | None = None, offsets: str = "fitted",
             size: str | None = None, until: float | None = None, validate: Any = None,
             progress: Any = None, start: str = "rest") -> Identification:
    """Fits the ``free`` scene values (keys, or a mapping of key to ``(low, high)`` or None)
    of ``scene`` to the record ``data`` (a DataFrame with ``t``, the drive force ``F`` or the
    prescribed position ``s``, and sensor columns by output name) (``telescopic identify``, docs/identify.md). ``noise``
    gives sensors' noise instead of the estimate; ``offsets`` is ``"fitted"`` or ``"zero"``;
    ``size`` the model's (``"static:9"``); ``validate`` a second record the fitted scene
    predicts; ``start`` is ``"rest"`` or ``"moving"`` (a record that starts in motion: the
    free motion of the slowest modes and the vehicle's speed at its first sample are fitted
    too). Returns an ``Identification``."""
    if isinstance(free, Mapping):
        entries = [(k, None if b is None else (float(b[0]), float(b[1]))) for k, b in free.items()]
    elif isinstance(free, str):
        raise OptionError("free: a list of keys, e.g. ['masses.load']")
    else:
        entries = [(str(k), None) for k in free]
    noise_text = None if noise is None else ",".join(f"{k}={v}" for k, v in noise.items())
    unseen = None if validate is None else _columns(validate, "validate")
    result = _telescopic.identify(
        scene, _columns(data, "data"), entries, noise=noise_text, offsets=offsets, size=size,
        until=until, unseen=unseen, progress=_progress(progress), notes=progress is not False,
        start=start)
    return Identification(*result)
