"""The compiled part of telescopic (PyO3). Use the functions of ``telescopic`` itself; these
return the plain data they wrap."""

from os import PathLike
from typing import Any, Callable, Mapping

import numpy as np

__version__: str

class TelescopicError(Exception):
    """An error of telescopic; the message is complete on its own."""

class SceneError(TelescopicError):
    """A scene that cannot be read or breaks a rule."""

    errors: list[tuple[str, str]]
    """The broken rules as (field, rule), e.g. ("contact.clearance", "must be ... >= 0")."""

class OptionError(TelescopicError):
    """A bad argument (an unknown method, a negative tolerance, ...), named in the message."""

    option: str
    """The argument's name as the library spells it."""

class SolverError(TelescopicError):
    """A numerical failure; the message gives the likely cause."""

    time: float
    """When the integration failed (s)."""
    method: str
    """The method that failed."""

class Scene:
    """A validated scene: sections, masses, contacts, telescopic positions, drive, time span."""

    @staticmethod
    def load(path: str | PathLike[str], set: Mapping[str, Any] | None = None) -> Scene:
        """Reads a scene file with overrides (the keys of ``--set``), e.g.
        ``Scene.load("scenes/case-study.toml", set={"contact.clearance": 0.005})``."""
    @staticmethod
    def from_toml(text: str, set: Mapping[str, Any] | None = None) -> Scene:
        """A scene from TOML text, with overrides."""
    def with_set(self, set: Mapping[str, Any]) -> Scene:
        """A new scene: this one with more overrides, validated like ``--set``."""
    def to_toml(self) -> str:
        """The scene as TOML, overrides applied."""
    @property
    def name(self) -> str:
        """Short name."""
    @property
    def description(self) -> str:
        """One line on what the scene is."""
    @property
    def time(self) -> tuple[float, float, float]:
        """``(start, end, sample)`` (s)."""
    @property
    def overrides(self) -> list[str]:
        """The overrides applied, as ``KEY=VALUE``."""
    @property
    def path(self) -> PathLike[str]:
        """The file it was read from (``<string>`` for text)."""

def simulate(
    scene: Scene,
    method: str = "auto",
    rtol: float | None = None,
    atol: float | None = None,
    dt: float | None = None,
    accuracy: float | None = None,
    controller: str | None = None,
    stations: list[tuple[int, float]] | None = None,
    model: str = "auto",
    progress: Callable[[float], None] | None = None,
    modes_as_given: bool = False,
    error_estimate: bool = True,
    moment_tolerance: float | None = None,
    statistics_tolerance: float | None = None,
    reuse: bool = True,
) -> tuple[list[str], np.ndarray, dict[str, Any]]:
    """Columns, samples (t first) and the run summary (with its error budget) of a simulation."""

class Movie:
    """A finished animated view: its page and what a GIF needs."""

    @property
    def html(self) -> str: ...
    @property
    def frame_count(self) -> int: ...
    def save(self, path: str) -> int: ...

def animate(
    scene: Scene,
    options: dict[str, Any],
    controller: str | None = None,
    compare: Scene | None = None,
    fps: float | None = None,
    scale: float | None = None,
    size: tuple[int, int] | None = None,
    speed: float | None = None,
    progress: Callable[[float], None] | None = None,
) -> Movie: ...
def animate_modes_of(
    scene: Scene, at: float | None = None, count: int | None = None, model: str = "auto",
) -> Movie: ...
def modes(
    scene: Scene, at: float | None = None, count: int | None = None, points: int = 51,
    model: str = "auto",
) -> dict[str, Any]:
    """Frequencies, damping, kinds and sampled shapes."""

def linearize(
    scene: Scene,
    positions: list[tuple[str, float]] | None = None,
    at_time: float | None = None,
    contacts: str = "closed",
    grid: tuple[str, tuple[float, float, int]] | None = None,
    disturbance: bool = False,
    discrete: float | None = None,
    model: str = "auto",
) -> dict[str, Any]:
    """Names, operating point and the matrices of each point."""

def design(
    scene: Scene,
    controller: str | None = None,
    force_limit: float | None = None,
    sensors: list[str] | None = None,
    rate_hz: float | None = None,
    law: str | None = None,
    shaper_timing: str | None = None,
    tip_scale: float | None = None,
    vehicle_scale: float | None = None,
    estimator: str | None = None,
    process_noise_floor: float | None = None,
    added_damping: float | None = None,
    model: str = "auto",
    progress: Callable[[float], None] | None = None,
) -> str:
    """The controller file's JSON."""

def check_controller(text: str) -> str:
    """The controller JSON, checked."""

def sweep(
    spec: str | PathLike[str] | Mapping[str, Any], out: str | PathLike[str], jobs: int | None = None,
    progress: Callable[[float], None] | None = None,
) -> tuple[str, list[str]]:
    """The result's column line and rows."""

def equations(scene: Scene, format: str = "latex") -> str:
    """The derived equations: text, latex, rust or json."""

def read_input(path: str) -> str:
    """The text of an input file, at most 16 MiB."""

def identify(
    scene: Scene,
    record: tuple[list[str], list[list[float]]],
    free: list[tuple[str, tuple[float, float] | None]],
    noise: str | None = None,
    offsets: str = "fitted",
    size: str | None = None,
    until: float | None = None,
    unseen: tuple[list[str], list[list[float]]] | None = None,
    progress: Callable[[float], None] | None = None,
    notes: bool = True,
    start: str = "rest",
) -> tuple[
    list[dict[str, Any]],
    list[dict[str, Any]],
    tuple[list[str], list[list[float]]],
    list[dict[str, Any]] | None,
    str,
    dict[str, Any],
]:
    """Scene values fitted to a record: (values, sensors, residuals, validation, fitted
    scene TOML, summary)."""

def plan(
    scene: Scene,
    distance: float,
    v_max: float = 2.5,
    a_max: float = 0.7,
    j_max: float = 2.0,
    tolerance: float = 0.005,
    robust: list[tuple[str, float, float]] | None = None,
    settle: float = 10.0,
    optimize: bool = True,
    checks: int | None = None,
    force_limit: float | None = None,
    feedback: float | None = None,
    options: dict[str, Any] | None = None,
    progress: Callable[[float], None] | None = None,
) -> tuple[list[dict[str, Any]], str, dict[str, Any]]: ...
