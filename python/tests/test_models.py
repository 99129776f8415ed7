"""hapticut.load_mesh and hapticut.info: the same models and reports as the command line, NumPy views
without copies, and the library's errors as exceptions that name the file and the line."""

import gc
import json
import subprocess

import numpy as np
import pytest

import hapticut
from conftest import ticks_while


def write(path, text):
    path.write_text(text)
    return path


TETRAHEDRON = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def test_a_model_file_loads_as_written(tmp_path):
    m = hapticut.load_mesh(write(tmp_path / "t.obj", TETRAHEDRON))
    np.testing.assert_array_equal(m.positions, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    np.testing.assert_array_equal(m.faces, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert m.positions.dtype == np.float64 and m.faces.dtype == np.uint32
    assert m.part_names == [] and list(m.face_parts) == [0, 0, 0, 0]
    assert m.tool_threshold_N is None
    # Millimetres, as segmentation tools write them.
    np.testing.assert_allclose(hapticut.load_mesh(tmp_path / "t.obj", units="mm").positions[1], [1e-3, 0, 0])
    with pytest.raises(ValueError, match="units must be one of"):
        hapticut.load_mesh(tmp_path / "t.obj", units="inch")


def test_a_model_says_what_is_unusual_about_it_in_metres_and_comes_outward(tmp_path):
    # The tetrahedron in millimetres, inside out, one face dropped: turned outward is not possible for an
    # open piece, so it stays as it came and says it is open; closed, it is turned and says so.
    inside_out = "".join(f"f {a} {c} {b}\n" for a, b, c in [(1, 3, 2), (1, 2, 4), (1, 4, 3), (2, 3, 4)])
    points = "v 0 0 0\nv 50 0 0\nv 0 50 0\nv 0 0 50\n"
    closed = hapticut.load_mesh(write(tmp_path / "in.obj", points + inside_out), units="mm")
    assert any("came inside out (4 faces" in w for w in closed.warnings), closed.warnings
    np.testing.assert_array_equal(closed.faces, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    opened = hapticut.load_mesh(write(tmp_path / "open.obj", points + inside_out.split("\n", 1)[1]), units="mm")
    assert any("open surface, 3 boundary edges" in w for w in opened.warnings), opened.warnings
    assert not any("inside out" in w for w in opened.warnings)


def test_a_file_in_no_spatial_order_is_renumbered_and_says_where_each_vertex_was(tmp_path):
    heart = hapticut.load_mesh("heart", triangles=5000)
    order = np.random.default_rng(5).permutation(len(heart.positions))  # file vertex k is heart vertex order[k]
    where = np.argsort(order)
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in heart.positions[order]]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in where[heart.faces]]
    shuffled = write(tmp_path / "shuffled.obj", "\n".join(lines) + "\n")
    m = hapticut.load_mesh(shuffled)
    file_positions = heart.positions[order]
    assert m.file_vertices.dtype == np.uint32
    assert sorted(m.file_vertices) == list(range(len(order)))
    np.testing.assert_array_equal(m.positions, file_positions[m.file_vertices])
    # The same triangles, named by the file's numbers.
    file_faces = {tuple(np.roll(f, -int(np.argmin(f)))) for f in where[heart.faces]}
    assert {tuple(np.roll(f, -int(np.argmin(f)))) for f in m.file_vertices[m.faces]} == file_faces
    assert not np.array_equal(m.file_vertices, np.arange(len(order))), "the shuffled file was renumbered"
    # A file in a spatial order (the heart's own) keeps its numbers, in the simulation too.
    ordered = write(tmp_path / "ordered.obj", TETRAHEDRON)
    np.testing.assert_array_equal(hapticut.load_mesh(ordered).file_vertices, [0, 1, 2, 3])
    sim = hapticut.Simulation(model=str(shuffled))
    np.testing.assert_array_equal(sim.file_vertices, m.file_vertices)


def test_positions_view_the_models_own_array_read_only():
    heart = hapticut.load_mesh("heart", triangles=5000)
    a, b = heart.positions, heart.positions
    assert np.shares_memory(a, b), "two looks at one array, not two copies"
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0] = 1.0
    expected = a.copy()
    del heart, b
    gc.collect()
    np.testing.assert_array_equal(a, expected)  # the view keeps its model alive
    assert abs(len(hapticut.load_mesh("heart", triangles=5000).faces) - 5000) <= 100


def test_the_shipped_liver_has_two_parts_and_one_can_be_chosen(assets):
    liver = hapticut.load_mesh(assets / "models" / "liver.obj")
    assert liver.part_names == ["liver", "gallbladder"]
    counts = np.bincount(liver.face_parts, minlength=2)
    assert counts.sum() == len(liver.faces) and counts.min() > 100
    alone = hapticut.load_mesh(assets / "models" / "liver.obj", parts=["gallbladder"])
    assert len(alone.faces) == counts[1]
    assert hapticut.load_mesh(assets / "tools" / "scalpel.txt").tool_threshold_N == 2.0


@pytest.mark.parametrize("model", ["heart", "models/kidney.obj", "tools/probe.txt"])
def test_info_is_the_command_lines_report(model, assets, cli):
    path = model if model == "heart" else str(assets / model)
    printed = json.loads(subprocess.run([cli, "info", path, "--json"], check=True, capture_output=True, text=True).stdout)
    assert hapticut.info(path) == printed


def test_errors_name_the_file_and_the_line(tmp_path, assets):
    bad = write(tmp_path / "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n")
    with pytest.raises(hapticut.HapticutError) as caught:
        hapticut.load_mesh(bad)
    assert caught.value.file == str(bad) and caught.value.line == 3
    assert "vertex index 3 is out of range" in caught.value.message
    assert str(caught.value).startswith(f"{bad}:3: ")

    with pytest.raises(hapticut.HapticutError, match="no such file"):
        hapticut.info(tmp_path / "missing.stl")
    with pytest.raises(hapticut.HapticutError, match="the model's parts are 'liver' and 'gallbladder'"):
        hapticut.load_mesh(assets / "models" / "liver.obj", parts=["spleen"])


def test_other_threads_run_while_a_large_model_loads():
    assert ticks_while(lambda: hapticut.load_mesh("heart", triangles=400_000)) > 2_000_000  # about 0.2 s of turns
