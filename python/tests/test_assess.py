"""hapticut.assess: a session of a scene's exercise scored from Python, the same report as the command
line's, and a scene without an exercise a clear error."""

import json
import subprocess

import pytest

import hapticut


def test_assess_from_python_gives_the_command_lines_report(tmp_path, assets, cli):
    scene, session = assets / "scenes" / "palpation-lump.toml", assets / "sessions" / "palpation-lump.csv"
    report = hapticut.assess(scene, session)
    assert report["found"] == 1 and report["score"] > 70
    assert [p["metric"] for p in report["parts"]][0] == "found"
    subprocess.run([cli, "assess", "--scene", str(scene), "--session", str(session), "--report",
                    str(tmp_path / "r.json")], check=True, capture_output=True)
    written = json.loads((tmp_path / "r.json").read_text())
    del written["provenance"], report["provenance"]
    assert written == report
    with pytest.raises(hapticut.HapticutError, match="heart.toml.*no \\[exercise\\]"):
        hapticut.assess(assets / "scenes" / "heart.toml", session)
