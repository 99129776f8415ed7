"""The Python API's costs: what a Simulation.step call adds to the loop's own step, and how a batch of
short runs scales from one Dask worker to two. Prints a JSON report (and writes it with --json).

    PYTHONPATH=build/python python3 bench/python_bench.py [--runs 100] [--json python-bench.json]

Each figure is compared only with the others of the same run, on the same machine.
"""

import argparse
import json
import os
import pathlib
import platform
import shutil
import sys
import tempfile
import time

import numpy as np

import hapticut

ASSETS = pathlib.Path(__file__).resolve().parents[1] / "assets"
PRESS = ASSETS / "trajectories" / "press-front.csv"


def step_overhead(repeats=5):
    """The press replayed by the loop in C++ (its report's step_us mean) and stepped from Python along the
    same device positions and velocities (wall time per call): the best of `repeats` of each."""
    native, scripted = [], []
    for _ in range(repeats):
        run = hapticut.run(trajectory=PRESS)
        native.append(run.report["step_us"]["mean"])
        log = run.force_log
        positions = np.stack([log["device_x"], log["device_y"], log["device_z"]], axis=1)
        velocities = np.gradient(positions, log["t"], axis=0)
        sim = hapticut.Simulation()
        started = time.perf_counter()
        for p, v in zip(positions, velocities):
            sim.step(p, False, v)
        scripted.append(1e6 * (time.perf_counter() - started) / len(positions))
    return {"steps": len(positions), "cpp_step_us": min(native), "python_step_us": min(scripted),
            "python_overhead_us": min(scripted) - min(native)}


def batch_scaling(runs, folder, repeats=3):
    """`runs` presses of the 1,619 heart swept over two keys, on a local cluster of 1 and of 2 workers,
    each from a clean results folder, the two taking turns `repeats` times; the best wall time of each,
    which includes starting and stopping the cluster."""
    side = int(np.ceil(np.sqrt(runs)))
    stiffness = [float(v) for v in np.geomspace(2.2e6, 3.52e7, side)]
    coupling = [float(v) for v in np.linspace(150, 900, int(np.ceil(runs / side)))]
    spec = folder / "scaling.toml"
    spec.write_text(f'[batch]\nmodel = "heart"\ntrajectory = "{PRESS}"\n[sweep]\n'
                    f'"material.positioning_stiffness_N_per_m3" = {stiffness}\n'
                    f'"device.stiffness_N_per_m" = {coupling}\n')
    total = len(stiffness) * len(coupling)
    seconds = {1: [], 2: []}
    for _ in range(repeats):
        for workers in (1, 2):
            out = folder / f"out-{workers}"
            shutil.rmtree(out, ignore_errors=True)
            started = time.perf_counter()
            result = hapticut.batch(spec, workers=workers, out=out, progress=False)
            seconds[workers].append(time.perf_counter() - started)
            assert result.failed == 0 and result.ran == total, result
            print(f"python_bench: {total} runs on {workers} worker(s): {seconds[workers][-1]:.2f} s", file=sys.stderr)
    best = {w: min(s) for w, s in seconds.items()}
    return {"runs": total, "seconds_1_worker": best[1], "seconds_2_workers": best[2], "ratio_2_to_1": best[2] / best[1],
            "all_seconds": {f"{w}_workers": s for w, s in seconds.items()}}


def main():
    # Called under this guard, as a script that starts processes should be.
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=100, help="runs in the batch (default 100)")
    parser.add_argument("--json", help="also write the report here")
    a = parser.parse_args()
    report = {"hapticut": hapticut.__version__, "cpu": platform.processor() or platform.machine(),
              "cores": os.cpu_count()}
    report["step"] = step_overhead()
    print(f"python_bench: step {report['step']}", file=sys.stderr)
    with tempfile.TemporaryDirectory() as folder:
        report["batch"] = batch_scaling(a.runs, pathlib.Path(folder))
    text = json.dumps(report, indent=1)
    print(text)
    if a.json:
        pathlib.Path(a.json).write_text(text + "\n")


if __name__ == "__main__":
    main()
