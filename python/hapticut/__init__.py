"""Hapticut from Python: load and check organ models, and drive a scene's haptic loop step by step.

    import hapticut
    liver = hapticut.load_mesh("assets/models/liver.obj")
    liver.positions        # (N, 3) float64, metres, a read-only view of the library's array
    hapticut.info("assets/models/kidney.obj")["min_angle_deg"]

    sim = hapticut.Simulation("assets/scenes/liver.toml", tool="scalpel")
    force = sim.step((-0.04, 0.0, 0.06), button=True)   # one 1 ms step, the force on the hand (N)

Every function raises hapticut.HapticutError, with the file and line, for input it cannot use.
"""

import json

from . import _hapticut
from .errors import HapticutError

__version__ = _hapticut.__version__
Model = _hapticut.Model
Simulation = _hapticut.Simulation

_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}

__all__ = ["HapticutError", "Model", "Simulation", "info", "load_mesh", "__version__"]


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
