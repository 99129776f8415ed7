"""Plots as PNG (matplotlib): the force on the hand over a run (from a force log, a report beside its
force log, or a batch run's folder), a batch's summary (a metric against each swept parameter), and an
exercise's assessment (the organ with the target and the cut, or the marks and the lumps, and the force).

    hapticut plot forces.csv                 # forces.png beside it
    hapticut plot batch-out/results.csv --metric max_displacement_m
    hapticut plot assessment.json            # hapticut assess --report writes one
    hapticut.plot_force_log("forces.csv", "forces.png")
"""

import argparse
import csv
import json
import math
import pathlib
import sys

import numpy as np

__all__ = ["plot_assessment", "plot_batch", "plot_force_log"]


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")  # files only: no display needed, none opened
    import matplotlib.pyplot as plt

    return plt


def _force_log_of(source):
    """The force log a source names: the CSV itself, or the force_log.csv beside a report or in a run's folder."""
    source = pathlib.Path(source)
    if source.is_dir():
        source = source / "force_log.csv"
    elif source.suffix == ".json":
        source = source.parent / "force_log.csv"
    if not source.is_file():
        raise FileNotFoundError(f"{source}: no force log (hapticut run --force-log FILE writes one; a batch run's "
                                f"folder has force_log.csv)")
    return source


def _spans(mask, t):
    """(start, end) times of the runs of True in mask."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(t[a], t[min(b, len(t) - 1)]) for a, b in zip(edges[::2], edges[1::2])]


def plot_force_log(source, png=None, title=None):
    """Force on the hand against time (|F| and x, y, z) above the device's position, with the steps in
    contact shaded and the steps that cut marked. Returns the PNG's path (default: the log's, .png)."""
    log_file = _force_log_of(source)
    log = np.genfromtxt(log_file, delimiter=",", names=True)
    if log.size == 0 or "fx" not in (log.dtype.names or ()):
        raise ValueError(f"{log_file}: not a force log (expected a header with t, fx, fy, fz, contact, cut)")
    log = np.atleast_1d(log)
    png = pathlib.Path(png) if png else log_file.with_suffix(".png")
    t = log["t"]
    force = np.stack([log["fx"], log["fy"], log["fz"]], axis=1)
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(9, 6), height_ratios=[3, 2])
    for axis in (top, bottom):
        for a, b in _spans(log["contact"] > 0, t):
            axis.axvspan(a, b, color="#f3d9b1", lw=0, zorder=0)
    top.plot(t, np.linalg.norm(force, axis=1), color="black", lw=1.6, label="|F|")
    for k, (name, colour) in enumerate(zip("xyz", ("#d62728", "#2ca02c", "#1f77b4"))):
        top.plot(t, force[:, k], color=colour, lw=0.9, label=f"F{name}")
    low, high = top.get_ylim()
    top.set_ylim(low, high + 0.35 * (high - low))  # room above the curves for the legend and the cut marks
    cuts = t[log["cut"] > 0] if "cut" in log.dtype.names else []
    if len(cuts):
        top.plot(cuts, np.full(len(cuts), 0.86), "|", color="#9467bd", ms=10, mew=1.5,
                 transform=top.get_xaxis_transform(), label=f"cut ({len(cuts)} steps)")
    top.set_ylabel("force on the hand (N)")
    top.legend(loc="upper left", ncol=5, fontsize=8, frameon=False)
    for k, (name, colour) in enumerate(zip("xyz", ("#d62728", "#2ca02c", "#1f77b4"))):
        bottom.plot(t, 1000 * log[f"device_{name}"], color=colour, lw=0.9, label=f"device {name}")
    bottom.set_ylabel("device (mm)")
    bottom.set_xlabel("time (s); shaded: in contact")
    bottom.legend(loc="upper left", ncol=3, fontsize=8, frameon=False)
    top.set_title(title or f"{log_file.resolve().parent.name}/{log_file.name}: peak {np.abs(force).max(initial=0):.3g} N, "
                  f"{int((log['contact'] > 0).sum())} of {len(t)} steps in contact")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def _swept(results, rows):
    """The swept parameters' names: from a run's params.json beside results.csv, else the columns
    between `session` and the report's first (`model`)."""
    for row in rows:
        params = pathlib.Path(results).parent / "runs" / row["id"] / "params.json"
        if params.is_file():
            return list(json.loads(params.read_text())["params"])
    columns = list(rows[0]) if rows else []
    if "session" in columns and "model" in columns:
        return columns[columns.index("session") + 1:columns.index("model")]
    return []


def _number(text):
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def plot_batch(results, png=None, metric="max_force_N"):
    """One panel a swept parameter: `metric` of every run that completed against the parameter's value,
    with the mean at each value joined. Returns the PNG's path (default: results.csv's, .png)."""
    results = pathlib.Path(results)
    if results.is_dir():
        results = results / "results.csv"
    with open(results, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{results}: no runs")
    if metric not in rows[0]:
        numeric = [k for k in rows[0] if _number(rows[0][k]) is not None and k not in ("run",)]
        raise ValueError(f"{results}: no column {metric!r}; numeric ones: {', '.join(numeric)}")
    params = _swept(results, rows)
    ok = [r for r in rows if r["status"] == "ok" and _number(r[metric]) is not None]
    failed = len(rows) - len(ok)
    if not params:
        params = ["run"]
    png = pathlib.Path(png) if png else results.with_suffix(".png")
    plt = _pyplot()
    fig, axes = plt.subplots(1, len(params), figsize=(4.2 * len(params), 3.8), squeeze=False)
    for axis, param in zip(axes[0], params):
        xs = [_number(r[param]) for r in ok]
        if any(x is None for x in xs):  # text values (an integrator's name): one place each, in order
            labels = list(dict.fromkeys(r[param] for r in ok))
            xs = [labels.index(r[param]) for r in ok]
            axis.set_xticks(range(len(labels)), labels)
        ys = [_number(r[metric]) for r in ok]
        axis.scatter(xs, ys, s=18, color="#1f77b4", alpha=0.7)
        values = sorted(set(xs))
        axis.plot(values, [np.mean([y for x, y in zip(xs, ys) if x == v]) for v in values], color="black", lw=1.2)
        positive = [x for x in xs if x > 0]
        if len(positive) == len(xs) and positive and max(positive) / min(positive) >= 10:
            axis.set_xscale("log")
        axis.set_xlabel(param)
        axis.set_ylabel(metric)
        axis.grid(alpha=0.3)
    fig.suptitle(f"{results.parent.name}: {metric} over {len(ok)} runs" + (f" ({failed} failed, left out)"
                                                                             if failed else ""))
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def _view_of(positions, faces, focus):
    """An orthographic view of the organ looking at `focus` (points on its surface) along the mean normal
    of the surface round them: (horizontal, vertical, toward the viewer) unit vectors."""
    corners = positions[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])  # twice the area
    centres = corners.mean(axis=1)
    near = np.linalg.norm(centres - focus.mean(axis=0), axis=1) < max(0.015, np.ptp(focus, axis=0).max() / 2)
    toward = normals[near].sum(axis=0) if near.any() else np.array([0.0, 0.0, 1.0])
    toward /= np.linalg.norm(toward)
    up = np.array([0.0, 1.0, 0.0]) - toward[1] * toward  # the scene's y, as upright as the view allows
    if np.linalg.norm(up) < 1e-6:
        up = np.array([0.0, 0.0, 1.0]) - toward[2] * toward
    up /= np.linalg.norm(up)
    return np.cross(up, toward), up, toward


def plot_assessment(report, png=None):
    """An exercise's assessment (the JSON `hapticut assess --report` writes): the organ's rest surface seen
    from in front of the task, with the target (dashed) and the cut (red), or the lumps (dotted circles of
    the radius a mark must be within) and the marks, beside the force over time. Returns the PNG's path."""
    from . import Simulation  # the scene's organ, as the assessment saw it at rest

    report = pathlib.Path(report)
    r = json.loads(report.read_text())
    if "exercise" not in r or "figure" not in r:
        raise ValueError(f"{report}: not an assessment (hapticut assess --report writes one)")
    png = pathlib.Path(png) if png else report.with_suffix(".png")
    sim = Simulation(r["scene"])
    positions, faces = np.asarray(sim.positions, dtype=float), np.asarray(sim.faces, dtype=np.int64)
    figure, exercise = r["figure"], r["exercise"]
    incision = exercise["kind"] == "incision"
    if incision:
        target = np.asarray(figure["target_m"], dtype=float)
        cuts = [np.asarray(c, dtype=float).reshape(-1, 3) for c in figure["cuts_m"]]
        focus = np.vstack([target] + [c for c in cuts if len(c)])
    else:
        lumps = [(np.asarray(l["surface_m"]), l["found"]) for l in figure["lumps"]]
        marks = [(np.asarray(m["at_m"]), m["lump"] >= 0) for m in figure["marks"]]
        focus = np.vstack([p for p, _ in lumps] + [p for p, _ in marks])
    across, up, toward = _view_of(positions, faces, focus)
    flat = lambda p: np.stack([p @ across, p @ up], axis=-1) * 1e3  # noqa: E731  (mm on the view's plane)

    plt = _pyplot()
    from matplotlib.collections import PolyCollection
    from matplotlib.patches import Circle

    fig, (organ, forces) = plt.subplots(1, 2, figsize=(13, 7), gridspec_kw={"width_ratios": [1.15, 1]})
    corners = positions[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    facing = (normals @ toward) > 0
    shade = np.clip(np.where(lengths > 0, (normals @ toward) / np.maximum(lengths, 1e-30), 0), 0, 1)
    order = np.argsort(corners.mean(axis=1) @ toward)  # far faces first: near ones are drawn over them
    order = order[facing[order]]
    tissue = np.array([0.80, 0.45, 0.42])
    organ.add_collection(PolyCollection(flat(corners[order]), facecolors=tissue * (0.35 + 0.65 * shade[order, None]),
                                        edgecolors=(0, 0, 0, 0.08), linewidths=0.2))
    if incision:
        line = flat(target)
        organ.plot(line[:, 0], line[:, 1], "--", color="#f0c000", lw=2.4, label="target", zorder=4)
        corridor = exercise["corridor_mm"]
        for i, cut in enumerate(cuts):
            if len(cut):
                c = flat(cut)
                organ.plot(c[:, 0], c[:, 1], "-", color="#1060d0", lw=2.2, label="cut" if i == 0 else None)
        what = (f"deviation {r['deviation_rms_mm']:.2f} mm RMS, coverage {r['coverage_pct']:.0f}% "
                f"(corridor ±{corridor:g} mm), {r['strokes']} stroke{'s' if r['strokes'] != 1 else ''}")
    else:
        radius = exercise["radius_mm"]
        for i, (p, found) in enumerate(lumps):
            x, y = flat(p)
            organ.add_patch(Circle((x, y), radius, fill=False, ls=":", lw=2, color="#1060d0",
                                   label=f"hidden lump (±{radius:g} mm)" if i == 0 else None))
        for i, (p, right) in enumerate(marks):
            x, y = flat(p)
            organ.plot(x, y, "x", ms=11, mew=3, color="#10a040" if right else "#d02020",
                       label=("marks" if i == 0 else None))
        error = r["localisation_error_mm"]
        what = (f"{r['found']} of {exercise['lumps']} found, {r['marks']} mark{'s' if r['marks'] != 1 else ''}"
                + (f", error {error:.1f} mm" if error is not None else ""))
    lo, hi = flat(focus).min(axis=0) - 15, flat(focus).max(axis=0) + 15
    side = max(hi - lo) / 2
    middle = (lo + hi) / 2
    organ.set_xlim(middle[0] - side, middle[0] + side)
    organ.set_ylim(middle[1] - side, middle[1] + side)
    organ.set_aspect("equal")
    organ.set_xlabel("mm across the view")
    organ.set_ylabel("mm up the view")
    organ.legend(loc="upper right")
    organ.set_title(what, fontsize=10)

    t, f = np.asarray(figure["force_t_s"]), np.asarray(figure["force_N"])
    forces.plot(t, f, color="black", lw=1, label="|F| on the hand")
    forces.axhline(exercise["max_force_N"], ls="--", color="#d02020", label=f"exercise's maximum {exercise['max_force_N']:g} N")
    forces.set_xlabel("time (s)")
    forces.set_ylabel("force (N)")
    forces.set_ylim(0, max(1.1 * f.max(initial=0), 1.2 * exercise["max_force_N"]))
    forces.legend(loc="upper right")
    parts = "\n".join(f"{p['metric']:<22} {p['value']:9.2f}  against {p['threshold']:7.2f}  "
                      f"{p['points']:5.1f} of {p['weight']:g}" for p in r["parts"])
    fig.suptitle(f"{exercise['kind']}: score {r['score']:.0f} of 100 ({pathlib.Path(r['session']).name})")
    fig.tight_layout(rect=(0, 0.15, 1, 0.96))
    fig.text(0.5, 0.02, parts, ha="center", va="bottom", fontsize=9, family="monospace")
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


def _is_assessment(path):
    path = pathlib.Path(path)
    if path.suffix != ".json" or not path.is_file():
        return False
    try:
        return "exercise" in json.loads(path.read_text())
    except (ValueError, OSError):
        return False


def _is_results(path):
    path = pathlib.Path(path)
    if path.is_dir():
        return (path / "results.csv").is_file()
    if path.suffix != ".csv" or not path.is_file():
        return False
    with open(path) as f:
        return f.readline().startswith("run,id,status")


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="hapticut plot",
        description="Plot a run's forces (a force log, a report with its force_log.csv beside it, or a batch run's "
                    "folder) or a batch's results (results.csv or its folder: a metric against each swept "
                    "parameter) as PNG.")
    parser.add_argument("source", help="force log CSV, report JSON, run folder, a batch's results.csv or folder, or "
                                       "an assessment's JSON")
    parser.add_argument("--out", help="the PNG to write (default: beside the source, .png)")
    parser.add_argument("--metric", default="max_force_N", help="a batch's column to plot (default max_force_N)")
    a = parser.parse_args(argv)
    try:
        if _is_results(a.source):
            png = plot_batch(a.source, a.out, a.metric)
        elif _is_assessment(a.source):
            png = plot_assessment(a.source, a.out)
        else:
            png = plot_force_log(a.source, a.out)
    except (OSError, ValueError) as e:
        print(f"hapticut plot: {e}", file=sys.stderr)
        return 1
    print(png)
    return 0
