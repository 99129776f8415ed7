"""Plots as PNG (matplotlib): the force on the hand over a run (from a force log, a report beside its
force log, or a batch run's folder), and a batch's summary (a metric against each swept parameter).

    hapticut plot forces.csv                 # forces.png beside it
    hapticut plot batch-out/results.csv --metric max_displacement_m
    hapticut.plot_force_log("forces.csv", "forces.png")
"""

import argparse
import csv
import json
import math
import pathlib
import sys

import numpy as np

__all__ = ["plot_batch", "plot_force_log"]


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
    parser.add_argument("source", help="force log CSV, report JSON, run folder, or a batch's results.csv or folder")
    parser.add_argument("--out", help="the PNG to write (default: beside the source, .png)")
    parser.add_argument("--metric", default="max_force_N", help="a batch's column to plot (default max_force_N)")
    a = parser.parse_args(argv)
    try:
        if _is_results(a.source):
            png = plot_batch(a.source, a.out, a.metric)
        else:
            png = plot_force_log(a.source, a.out)
    except (OSError, ValueError) as e:
        print(f"hapticut plot: {e}", file=sys.stderr)
        return 1
    print(png)
    return 0
