"""Hapticut from Python: load and check organ models, and drive a scene's haptic loop step by step.

    import hapticut
    liver = hapticut.load_mesh("assets/models/liver.obj")
    liver.positions        # (N, 3) float64, metres, a read-only view of the library's array
    hapticut.info("assets/models/kidney.obj")["min_angle_deg"]

    sim = hapticut.Simulation("assets/scenes/liver.toml", tool="scalpel")
    force = sim.step((-0.04, 0.0, 0.06), button=True)   # one 1 ms step, the force on the hand (N)
    sim.positions          # (N, 3) the nodes now, a read-only view that follows every step

    hapticut.batch("sweep.toml", workers=2)   # every combination of a sweep, on a local Dask cluster

Every function raises hapticut.HapticutError, with the file and line, for input it cannot use.
"""

import io
import json
import math
import os
import re

import numpy as np

from . import _hapticut
from .errors import HapticutError

__version__ = _hapticut.__version__
Model = _hapticut.Model

_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}

__all__ = ["BatchResult", "HapticutError", "Model", "RunResult", "Simulation", "assess", "batch", "info", "load_mesh",
           "plot_assessment", "plot_batch", "plot_force_log", "run", "__version__"]


def _scale(units, scale):
    if units not in _UNITS:
        raise ValueError(f"units must be one of {', '.join(_UNITS)}, not {units!r}")
    return _UNITS[units] * float(scale)


def load_mesh(model, triangles=1619, parts=None, units="m", scale=1.0):
    """Load a model: "heart" (the procedural heart of `triangles` triangles) or a file (.txt in the
    thesis format, .obj, .ply, .stl, .gltf, .glb, .fbx, .dae, ...).

    parts: only these named parts (hapticut.info lists them). units: "mm", "cm" or "m", what the
    file's coordinates are in; scale multiplies them after that. Returns a hapticut.Model.
    """
    return _hapticut._load(str(model), int(triangles), list(parts or []), _scale(units, scale))


def info(model, triangles=1619, parts=None, units="m", scale=1.0):
    """The validation report of a model as a dict, the same as `hapticut info --json` prints."""
    return json.loads(_hapticut._info_json(str(model), int(triangles), list(parts or []), _scale(units, scale)))


def assess(scene, session):
    """A session of the scene's exercise replayed and scored, as a dict: the report `hapticut assess
    --report` writes (score, parts with their thresholds, every metric, the figure's data). The same
    session gives the same report. Errors name the file and line."""
    return json.loads(_hapticut._assess(str(scene), str(session)))


class RunResult:
    """A finished run: `report`, the dict `hapticut run --report` writes, and `force_log`, a NumPy
    structured array with the columns of `hapticut run --force-log` (t, device_x, ..., fx, fy, fz,
    contact, face, cut), one row a step."""

    def __init__(self, report, force_log):
        self.report = report
        self.force_log = force_log

    def __repr__(self):
        r = self.report
        return (f"<hapticut.RunResult {r['model']}: {r['steps']} steps, max force {r['max_force_N']:.3g} N, "
                f"{r['cuts']} cut(s)>")


_KEY = re.compile(r"[A-Za-z0-9_]+(\.[A-Za-z0-9_]+)*")


def _toml_value(key, value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float, np.integer, np.floating)):
        if not math.isfinite(value):
            raise ValueError(f"settings[{key!r}] must be finite, not {value!r}")
        return repr(int(value)) if isinstance(value, (int, np.integer)) else repr(float(value))
    if isinstance(value, (str, os.PathLike)):
        return json.dumps(str(value))  # a JSON string is a TOML basic string
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(key, v) for v in value) + "]"
    raise ValueError(f"settings[{key!r}]: {type(value).__name__} is not a scene value (number, bool, text, list)")


def _settings_toml(settings):
    """Scene keys as a scene file spells them ("material.positioning_stiffness_N_per_m3",
    "device.stiffness_N_per_m", "simulation.integrator") to TOML lines set over the scene's."""
    lines = []
    for key, value in (settings or {}).items():
        if not isinstance(key, str) or not _KEY.fullmatch(key):
            raise ValueError(f"settings: {key!r} is not a scene key such as 'material.mass_kg'")
        lines.append(f"{key} = {_toml_value(key, value)}")
    return "\n".join(lines) + ("\n" if lines else "")


class Simulation(_hapticut.Simulation):
    __doc__ = _hapticut.Simulation.__doc__

    def __init__(self, scene=None, model=None, triangles=None, tool="probe", integrator=None, rate_hz=None,
                 settings=None):
        """The scene (a scene file; None, the built-in heart with the probe and the scalpel), with model,
        triangles, integrator and rate_hz over its own, and `settings`, scene keys as a scene file spells
        them ({"material.mass_kg": 1.5}), over those; `tool` in the hand."""
        super().__init__("" if scene is None else str(scene), None if model is None else str(model), triangles,
                         tool, integrator, rate_hz, _settings_toml(settings))

    @property
    def cut_model(self):
        """The cut model's statistics (the same dict as cut_stats): cuts, cut points, vertices and faces
        added, openings, walls closed, the cut's length."""
        return self.cut_stats


def run(scene=None, model=None, triangles=None, trajectory=None, tool=None, steps=None, integrator=None,
        rate_hz=None, settings=None):
    """A headless run in simulated time, as `hapticut run` makes it: the scene (a scene file; None, the
    built-in heart with the probe and the scalpel) with `trajectory` replayed by the first hand, or the
    scene's own replays. model, triangles, tool, integrator and rate_hz override the scene's, and
    `settings`, scene keys as a scene file spells them ({"material.positioning_stiffness_N_per_m3":
    4.4e6, "device.stiffness_N_per_m": 200}), are set over its keys first; steps defaults to the
    trajectory's length. The interpreter's lock is released while it runs.
    """
    report, log = _hapticut._run(
        "" if scene is None else str(scene), _settings_toml(settings), None if model is None else str(model), triangles,
        None if trajectory is None else str(trajectory), tool, steps, integrator, rate_hz)
    return RunResult(json.loads(report), _step_log_array(log))


def _step_log_array(text):
    """A step log's CSV as a structured array: counts and flags (contact, face, cut) as integers, the
    rest as float64."""
    names = text.split("\n", 1)[0].split(",")
    integer = ("contact", "face", "cut", "button")
    dtype = [(n, np.int64 if n.rstrip("2") in integer else np.float64) for n in names]
    return np.atleast_1d(np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, dtype=dtype, ndmin=1))


from .batching import BatchResult, batch  # noqa: E402  (it uses run's C++ half, loaded above)
from .plotting import plot_assessment, plot_batch, plot_force_log  # noqa: E402  (matplotlib is imported when a plot is made)
