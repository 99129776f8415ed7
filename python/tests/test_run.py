"""hapticut.run: the same report and force log as `hapticut run` for the same run, and clear errors."""

import json
import subprocess

import numpy as np
import pytest

import hapticut
from conftest import ticks_while

# Wall-clock measurements, and who made the report: the only fields two runs of one experiment may differ in.
TIMING = {"provenance", "wall_time_s", "steps_per_wall_s", "step_us", "physics_rate_hz", "physics_realtime_factor",
          "physics_step_us", "physics_time_lost_s", "physics_lag_at_end_s",
          "cut_event_us", "physics_sync_us"}


def cli_run(cli, tmp_path, *args):
    report, log = tmp_path / "report.json", tmp_path / "forces.csv"
    subprocess.run([cli, "run", *args, "--report", str(report), "--force-log", str(log)], check=True,
                   capture_output=True)
    return json.loads(report.read_text()), hapticut._step_log_array(log.read_text())


@pytest.mark.parametrize("case", ["liver scene", "heart cut"])
def test_a_run_from_python_is_the_command_lines(case, tmp_path, assets, cli):
    if case == "liver scene":
        scene = str(assets / "scenes" / "liver.toml")
        expected, expected_log = cli_run(cli, tmp_path, "--scene", scene)
        result = hapticut.run(scene)
    else:
        trajectory = str(assets / "trajectories" / "cut-front.csv")
        expected, expected_log = cli_run(cli, tmp_path, "--trajectory", trajectory, "--tool", "scalpel")
        result = hapticut.run(trajectory=trajectory, tool="scalpel")
    report = result.report
    assert list(report) == list(expected), "the same fields in the same order"
    for key in expected:
        if key not in TIMING:
            assert report[key] == expected[key], key
    assert report["cuts"] == 1 and report["invariants_ok"]
    assert result.force_log.dtype == expected_log.dtype
    for column in expected_log.dtype.names:
        np.testing.assert_array_equal(result.force_log[column], expected_log[column], err_msg=column)
    assert len(result.force_log) == report["steps"] == 2801


def test_steps_and_overrides_are_taken(assets):
    trajectory = assets / "trajectories" / "press-front.csv"
    result = hapticut.run(trajectory=trajectory, steps=300, integrator="implicit", triangles=3000)
    assert result.report["steps"] == 300 and len(result.force_log) == 300
    assert result.report["integrator"] == "implicit"
    assert abs(result.report["faces"] - 3000) <= 60
    assert result.force_log["t"][-1] == pytest.approx(0.299)


def test_bad_runs_are_clear_errors(tmp_path, assets):
    with pytest.raises(ValueError, match="nothing to replay"):
        hapticut.run()
    with pytest.raises(ValueError, match="steps must be at least 1"):
        hapticut.run(trajectory=assets / "trajectories" / "press-front.csv", steps=0)
    bad = tmp_path / "bad.csv"
    bad.write_text("t,x,y,z,button\n0,0,0,0,0\n0.1,0,zero,0,0\n")
    with pytest.raises(hapticut.HapticutError) as caught:
        hapticut.run(trajectory=bad)
    assert caught.value.file == str(bad) and caught.value.line == 3
    with pytest.raises(hapticut.HapticutError, match="lancet"):
        hapticut.run(trajectory=assets / "trajectories" / "press-front.csv", tool="lancet")


def test_other_threads_run_while_a_run_goes_on(assets):
    # The 1,619 heart loads in milliseconds; 100,000 steps take the better part of a second.
    press = assets / "trajectories" / "press-front.csv"
    assert ticks_while(lambda: hapticut.run(trajectory=press, steps=100_000)) > 2_000_000  # about 0.2 s of turns


def test_settings_are_scene_keys_set_over_the_scenes(assets):
    press = assets / "trajectories" / "press-front.csv"
    soft = hapticut.run(trajectory=press)
    stiff = hapticut.run(trajectory=press, settings={"material.positioning_stiffness_N_per_m3": 1.76e7,
                                                     "device.stiffness_N_per_m": 200})
    assert stiff.report["coupling_stiffness_N_per_m"] == 200
    assert stiff.report["max_displacement_m"] < 0.6 * soft.report["max_displacement_m"], "anchored twice as stiffly"
    liver = hapticut.run(assets / "scenes" / "liver.toml", steps=10, settings={"simulation.integrator": "rk4"})
    assert liver.report["integrator_requested"] == "rk4" and liver.report["model"].endswith("liver.obj")

    with pytest.raises(hapticut.HapticutError) as caught:
        hapticut.run(trajectory=press, settings={"material.mass_kg": 1.0, "material.mass": 1.0})
    assert caught.value.file == "<settings>" and caught.value.line == 2
    assert "allowed here: bulk_modulus_Pa, mass_kg" in caught.value.message
    with pytest.raises(ValueError, match="not a scene key"):
        hapticut.run(trajectory=press, settings={"material mass": 1.0})
    with pytest.raises(ValueError, match="must be finite"):
        hapticut.run(trajectory=press, settings={"material.mass_kg": float("inf")})
    sim = hapticut.Simulation(settings={"simulation.integrator": "implicit", "material.mass_kg": 0.5})
    assert sim.integrator == "implicit"
