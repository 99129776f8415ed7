"""hapticut plot: PNGs are written, show what they claim (the contact shading, the cut marks, a panel per
swept parameter, an assessment's target and cut), and a file that is not a force log or a batch's results
is a clear error."""

import subprocess

import numpy as np
import pytest

import hapticut

CONTACT = (0xF3, 0xD9, 0xB1)  # the shading of the steps in contact
CUT = (0x94, 0x67, 0xBD)  # the marks of the steps that cut


def pixels(png):
    from matplotlib import image

    rgb = image.imread(png)[..., :3]
    return np.round(rgb * 255).astype(int)


def share_of(rgb, colour):
    return np.mean(np.all(np.abs(rgb - np.array(colour)) <= 2, axis=-1))


def not_blank(rgb):
    return np.mean(np.any(rgb < 250, axis=-1)) > 0.02 and len(np.unique(rgb.reshape(-1, 3), axis=0)) > 20


def test_a_scalpel_runs_plot_shades_its_contact_and_marks_its_cut(tmp_path, assets, cli):
    log = tmp_path / "cut.csv"
    subprocess.run([cli, "run", "--trajectory", str(assets / "trajectories" / "cut-front.csv"), "--tool", "scalpel",
                    "--force-log", str(log)], check=True, capture_output=True)
    done = subprocess.run([cli, "plot", str(log)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    png = tmp_path / "cut.png"
    assert done.stdout.strip() == str(png)
    rgb = pixels(png)
    assert rgb.shape[0] > 500 and rgb.shape[1] > 800 and not_blank(rgb)
    assert share_of(rgb, CONTACT) > 0.05, "the steps in contact are shaded"
    assert share_of(rgb, CUT) > 0.0005, "the steps that cut are marked"


def test_a_press_that_cuts_nothing_has_no_cut_marks(tmp_path, assets):
    run = hapticut.run(trajectory=assets / "trajectories" / "press-front.csv", steps=1500)
    log = tmp_path / "press.csv"
    names = run.force_log.dtype.names
    np.savetxt(log, np.array(run.force_log.tolist()), delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    png = hapticut.plot_force_log(log, tmp_path / "press.png")
    rgb = pixels(png)
    assert not_blank(rgb) and share_of(rgb, CONTACT) > 0.05
    assert share_of(rgb, CUT) == 0


def test_a_batchs_summary_has_a_panel_a_swept_parameter(tmp_path, assets):
    spec = tmp_path / "sweep.toml"
    spec.write_text(f'[batch]\ntrajectory = "{assets / "trajectories" / "press-front.csv"}"\nsteps = 1200\n[sweep]\n'
                    '"device.stiffness_N_per_m" = [200, 400, 800]\n"simulation.integrator" = ["rk4", "implicit"]\n')
    result = hapticut.batch(spec, workers=1, out=tmp_path / "out", progress=False)
    one = hapticut.plot_batch(tmp_path / "out", tmp_path / "force.png")
    two = hapticut.plot_batch(result.results, tmp_path / "depth.png", metric="max_displacement_m")
    for png in (one, two):
        rgb = pixels(png)
        assert not_blank(rgb)
        assert rgb.shape[1] > 2 * rgb.shape[0] * 0.9, "two panels side by side"
    with pytest.raises(ValueError, match="no column 'depth'; numeric ones: .*max_force_N"):
        hapticut.plot_batch(result.results, tmp_path / "x.png", metric="depth")


def test_what_is_not_a_force_log_is_a_clear_error(tmp_path, cli):
    other = tmp_path / "table.csv"
    other.write_text("a,b\n1,2\n")
    done = subprocess.run([cli, "plot", str(other)], capture_output=True, text=True)
    assert done.returncode == 1
    assert "table.csv: not a force log (expected a header with t, fx" in done.stderr
    done = subprocess.run([cli, "plot", str(tmp_path / "missing.json")], capture_output=True, text=True)
    assert done.returncode == 1 and "no force log" in done.stderr


TARGET = (0xF0, 0xC0, 0x00)  # the dashed target line
CUT_LINE = (0x10, 0x60, 0xD0)  # the cut, and a lump's circle


def test_assess_draws_the_organ_with_the_target_and_the_cut(tmp_path, assets, cli):
    png = tmp_path / "incision.png"
    done = subprocess.run([cli, "assess", "--scene", str(assets / "scenes" / "incision-front.toml"), "--session",
                           str(assets / "sessions" / "incision-front.csv"), "--png", str(png)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "incision.json").is_file(), "the report goes beside the picture"
    rgb = pixels(png)
    assert not_blank(rgb)
    assert share_of(rgb, CUT_LINE) > 0.0001, "the cut is drawn"
    assert share_of(rgb, TARGET) > 0.0001, "the target is drawn"
    tissue = np.mean((rgb[..., 0] > 120) & (rgb[..., 0] > rgb[..., 1] + 40))
    assert tissue > 0.1, "the organ is drawn"
    again = hapticut.plot_assessment(tmp_path / "incision.json", tmp_path / "again.png")
    assert not_blank(pixels(again))

