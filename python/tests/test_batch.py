"""hapticut.batch on a real local Dask cluster: every combination run once and recorded with the numbers
the same run gives in this process, a second batch of the same spec does nothing, a failing run is
recorded while the rest complete, and a worker killed mid-batch loses no run."""

import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import hapticut

SWEEP = {
    "material.positioning_stiffness_N_per_m3": [4.4e6, 8.8e6, 1.76e7, 3.52e7],
    "device.stiffness_N_per_m": [200, 400, 800],
    "material.mass_kg": [0.25, 0.5],
}


def write_spec(folder, assets, sweep=SWEEP, steps=1500, name="sweep.toml"):
    lines = ["[batch]", 'model = "heart"', f'trajectory = "{assets / "trajectories" / "press-front.csv"}"',
             'tool = "probe"', f"steps = {steps}", "[sweep]"]
    lines += [f'"{key}" = {values}'.replace("'", '"') for key, values in sweep.items()]
    spec = folder / name
    spec.write_text("\n".join(lines) + "\n")
    return spec


def read_results(out):
    with open(out / "results.csv", newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def first_batch(tmp_path_factory, assets):
    folder = tmp_path_factory.mktemp("batch")
    spec = write_spec(folder, assets)
    result = hapticut.batch(spec, workers=2, out=folder / "out", progress=False)
    return spec, folder / "out", result


def test_every_combination_runs_once_with_the_numbers_it_gives_here(first_batch, assets):
    spec, out, result = first_batch
    assert (result.ran, result.skipped, result.failed) == (24, 0, 0)
    rows = read_results(out)
    assert len(rows) == 24 and [int(r["run"]) for r in rows] == list(range(24))
    combinations = {(float(r["material.positioning_stiffness_N_per_m3"]), float(r["device.stiffness_N_per_m"]),
                     float(r["material.mass_kg"])) for r in rows}
    assert len(combinations) == 24, "each combination once"
    assert len({r["max_force_N"] for r in rows}) > 12, "the parameters change what the hand feels"
    for r in rows:
        assert r["status"] == "ok" and r["error"] == ""
        folder = out / "runs" / r["id"]
        assert {p.name for p in folder.iterdir()} == {"params.json", "report.json", "force_log.csv"}
    assert not [p for p in (out / "runs").iterdir() if p.name.startswith(".")], "no partial run left behind"

    # The same runs in this process: the same numbers to the last bit, whichever worker ran them.
    for r in rows[::5]:
        settings = {"material.positioning_stiffness_N_per_m3": float(r["material.positioning_stiffness_N_per_m3"]),
                    "device.stiffness_N_per_m": int(r["device.stiffness_N_per_m"]),
                    "material.mass_kg": float(r["material.mass_kg"])}
        here = hapticut.run(model="heart", trajectory=assets / "trajectories" / "press-front.csv", tool="probe",
                            steps=1500, settings=settings)
        for key in ("max_force_N", "max_displacement_m", "contact_steps", "max_proxy_penetration_m", "max_strain"):
            assert float(r[key]) == float(here.report[key]), key
        log = np.genfromtxt(out / "runs" / r["id"] / "force_log.csv", delimiter=",", names=True)
        np.testing.assert_array_equal(log["fz"], here.force_log["fz"])


def test_each_run_solves_on_one_thread_unless_the_sweep_says_otherwise(tmp_path, assets):
    # The workers take a core each; a lone run's default pool (every core but two) in each would crowd them.
    # (On a machine of four cores or fewer that default is one thread too; the swept 2 must still win.)
    spec = write_spec(tmp_path, assets, sweep={"simulation.solver_threads": [2]}, steps=100)
    spec.write_text(spec.read_text().replace("[sweep]", 'integrator = "implicit"\n[sweep]'))
    one = write_spec(tmp_path, assets, sweep={"material.mass_kg": [0.3]}, steps=100, name="one.toml")
    one.write_text(one.read_text().replace("[sweep]", 'integrator = "implicit"\n[sweep]'))
    for path, threads in ((spec, 2), (one, 1)):
        out = tmp_path / f"out-{threads}"
        result = hapticut.batch(path, workers=1, out=out, progress=False)
        assert (result.ran, result.failed) == (1, 0)
        report = json.loads(next((out / "runs").iterdir()).joinpath("report.json").read_text())
        assert report["solver"]["threads"] == threads


def test_a_second_batch_of_the_same_spec_does_nothing(first_batch):
    spec, out, _ = first_batch
    before = {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()}
    results = (out / "results.csv").read_text()
    again = hapticut.batch(spec, workers=2, out=out, progress=False)
    assert (again.ran, again.skipped, again.failed) == (0, 24, 0)
    assert again.where == "no cluster (nothing to run)", "not even a cluster is started"
    assert {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()} == before
    assert (out / "results.csv").read_text() == results


def test_a_failing_run_is_recorded_and_the_others_complete(tmp_path, assets, cli):
    # A stiffness no explicit step can hold at 1 ms: that run alone is refused.
    spec = write_spec(tmp_path, assets, {"material.structural_stiffness_N": [50.0, 1e9, 100.0],
                                         "simulation.integrator": ["rk4"]}, steps=500)
    done = subprocess.run([cli, "batch", str(spec), "--workers", "2", "--out", str(tmp_path / "out")],
                          capture_output=True, text=True)
    assert done.returncode == 1, done.stderr
    assert "run 1 (material.structural_stiffness_N=1000000000.0, simulation.integrator=rk4) failed: rk4 would need" \
        in done.stderr
    assert "3 runs: 3 ran, 0 done before, 1 failed" in done.stderr
    rows = read_results(tmp_path / "out")
    assert [r["status"] for r in rows] == ["ok", "failed", "ok"]
    assert "rk4 would need" in rows[1]["error"] and rows[1]["max_force_N"] == ""
    assert (tmp_path / "out" / "runs" / rows[1]["id"] / "error.json").is_file()
    # Run again, the failed run is tried again (its cause may have been fixed), the others are not.
    again = hapticut.batch(spec, workers=1, out=tmp_path / "out", progress=False)
    assert (again.ran, again.skipped, again.failed) == (1, 2, 1)


def test_a_bad_spec_is_an_error_at_its_line_and_nothing_runs(tmp_path, cli):
    spec = tmp_path / "typo.toml"
    spec.write_text('[batch]\nmodel = "heart"\n[sweep]\n"material.stifness" = [1, 2]\n')
    done = subprocess.run([cli, "batch", str(spec), "--out", str(tmp_path / "out")], capture_output=True, text=True)
    assert done.returncode == 2
    assert f"{spec}:4: sweep \"material.stifness\" = 1: " in done.stderr
    assert not (tmp_path / "out").exists()
    with pytest.raises(hapticut.HapticutError) as caught:
        hapticut.batch(spec)
    assert caught.value.line == 4


def test_a_worker_killed_mid_batch_loses_no_run(tmp_path, assets):
    from dask.distributed import Client

    spec = write_spec(tmp_path, assets)
    out = tmp_path / "out"
    cluster = hapticut.batching._local_cluster(2)
    client = Client(cluster)
    try:
        pids = list(client.run(os.getpid).values())
        finished = {}
        batch = threading.Thread(target=lambda: finished.update(
            result=hapticut.batch(spec, client=client, out=out, progress=False)))
        batch.start()
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and len([p for p in (out / "runs").glob("[0-9a-f]*")]) < 4:
            time.sleep(0.01)
        assert len(list((out / "runs").glob("[0-9a-f]*"))) < 24, "killed mid-batch, not after it"
        os.kill(pids[0], signal.SIGKILL)
        batch.join(timeout=120)
        assert not batch.is_alive()
        result = finished["result"]
        assert (result.ran, result.failed) == (24, 0)
        assert pids[0] not in client.run(os.getpid).values(), "the killed worker is gone (its nanny started another)"
    finally:
        client.close()
        cluster.close()
    rows = read_results(out)
    assert len(rows) == 24 and all(r["status"] == "ok" for r in rows)
    assert all((out / "runs" / r["id"] / "report.json").is_file() for r in rows)


def test_a_script_that_calls_batch_at_its_top_level_runs_it_once(tmp_path, assets):
    # Without `if __name__ == "__main__":`, as scripts are written: the workers must not run it again.
    spec = write_spec(tmp_path, assets, {"device.stiffness_N_per_m": [200, 400]}, steps=300)
    script = tmp_path / "experiment.py"
    script.write_text(f"import hapticut\nresult = hapticut.batch({str(spec)!r}, workers=2, out={str(tmp_path / 'out')!r}, "
                      "progress=False)\nprint('batch', result.ran, result.failed)\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout == "batch 2 0\n", "the script ran once, in its own process"
