"""hapticut.Simulation: a scene's haptic loop driven from Python gives the forces the command line's
replay of the same path gives, bit for bit, cut and all; bad arguments are clear errors."""

import json
import subprocess

import numpy as np
import pytest

import hapticut


def replay_motion(trajectory, time_s):
    """What a replayed trajectory gives the loop at `time_s`: its segment's velocity and the button of
    the segment's nearer end (the replay device's own rule)."""
    t = trajectory["t"][0] + time_s
    if t <= trajectory["t"][0] or t >= trajectory["t"][-1]:
        return np.zeros(3), trajectory["button"][0 if t <= trajectory["t"][0] else -1]
    c = 0
    while c + 1 < len(trajectory) and trajectory["t"][c + 1] < t:
        c += 1
    a, b = trajectory[c], trajectory[c + 1]
    velocity = (np.array([b["x"], b["y"], b["z"]]) - np.array([a["x"], a["y"], a["z"]])) / (b["t"] - a["t"])
    return velocity, a["button"] if (t - a["t"]) / (b["t"] - a["t"]) < 0.5 else b["button"]


def test_stepping_from_python_feels_what_the_replay_felt(tmp_path, assets, cli):
    path = assets / "trajectories" / "cut-front.csv"
    log_file, report_file = tmp_path / "forces.csv", tmp_path / "report.json"
    subprocess.run([cli, "run", "--trajectory", str(path), "--tool", "scalpel", "--force-log", str(log_file),
                    "--report", str(report_file)], check=True, capture_output=True)
    trajectory = np.genfromtxt(path, delimiter=",", names=True)
    log = np.genfromtxt(log_file, delimiter=",", names=True)
    report = json.loads(report_file.read_text())

    sim = hapticut.Simulation(tool="scalpel")
    assert (sim.model, sim.tool, sim.rate_hz) == ("heart", "scalpel", 1000.0)
    forces = []
    for row in log:
        velocity, button = replay_motion(trajectory, row["t"])
        forces.append(sim.step((row["device_x"], row["device_y"], row["device_z"]), button=bool(button),
                               velocity=velocity))
    np.testing.assert_array_equal(np.array(forces), np.stack([log["fx"], log["fy"], log["fz"]], axis=1))
    assert sim.steps == len(log) and sim.time_s == pytest.approx(len(log) / 1000)
    assert sim.integrator == report["integrator"]
    cut = sim.cut_stats
    assert sim.cut_model == cut
    assert cut["cuts"] == report["cuts"] == 1
    for key in ("cut_points", "faces_added", "walls_closed", "wounds_crossed", "cut_length_m"):
        assert cut[key] == report[key], key
    assert len(sim.faces) == report["faces"]
    sim.export(tmp_path / "cut.obj")
    exported = hapticut.info(tmp_path / "cut.obj")
    assert exported["faces"] == report["faces"] and exported["closed"], "the wound is walled in the export"


def test_a_press_is_felt_and_the_proxy_stays_on_the_surface():
    sim = hapticut.Simulation(model="heart", triangles=1619)
    free = sim.step((0, -0.01, 0.2))
    assert not sim.contact and np.all(free == 0)
    for i in range(601):  # from 9 cm in front to 1 cm behind the centre in 0.6 s, deep into the organ
        device_z = 0.09 - 0.1 * i / 600
        force = sim.step((0, -0.01, device_z))
    assert sim.contact
    assert 0.5 < np.linalg.norm(force) <= 3.3 + 1e-9, "pressed hard, clamped at the device's 3.3 N"
    assert force[2] > 0, "the organ pushes the hand back out of its front"
    assert sim.proxy[2] > device_z + 0.02, "the proxy stays on the (pressed) front while the device goes deep"


def test_bad_arguments_are_clear_errors(tmp_path):
    sim = hapticut.Simulation()
    with pytest.raises(ValueError, match="position must be 3 numbers"):
        sim.step((0, 0))
    with pytest.raises(ValueError, match="position must be finite"):
        sim.step((0, float("nan"), 0))
    with pytest.raises(ValueError, match="'fast' is none of auto, euler"):
        hapticut.Simulation(integrator="fast")
    with pytest.raises(hapticut.HapticutError, match="lancet"):
        hapticut.Simulation(tool="lancet")
    scene = tmp_path / "bad.toml"
    scene.write_text("[device]\nbackend = \"joystick\"\n")
    with pytest.raises(hapticut.HapticutError) as caught:
        hapticut.Simulation(str(scene))
    assert caught.value.file == str(scene) and caught.value.line == 2
    with pytest.raises(hapticut.HapticutError, match="missing"):
        sim.export(tmp_path / "missing" / "organ.obj")


def test_positions_view_the_librarys_array_and_follow_every_step():
    sim = hapticut.Simulation(tool="scalpel")
    view = sim.positions
    rest = hapticut.load_mesh("heart").positions
    assert view.shape == rest.shape and view.dtype == np.float64
    assert not view.flags.writeable and not view.flags.owndata, "a read-only view, not a copy"
    np.testing.assert_array_equal(view, rest)
    with pytest.raises(ValueError, match="read-only"):
        view[0, 0] = 1.0
    for i in range(300):  # the blade pressed 1 cm into the front, button up: it dents, nothing cuts
        sim.step((0, -0.01, 0.09 - 0.08 * i / 299))
    assert np.shares_memory(view, sim.positions)
    np.testing.assert_array_equal(view, sim.positions)
    assert np.linalg.norm(view - rest, axis=1).max() > 0.003, "the view taken at the start shows the dent"

    for i in range(400):  # then the button down and a stroke across: the cut adds nodes
        sim.step((-0.02 + 0.04 * i / 399, -0.01, 0.02), button=True)
    assert sim.cut_stats["vertices_added"] > 0
    now = sim.positions
    assert len(now) == len(rest) + sim.cut_stats["vertices_added"]
    np.testing.assert_array_equal(view, now[: len(view)])
    del sim
    assert np.isfinite(view).all() and np.isfinite(now).all(), "the views keep the simulation alive"
