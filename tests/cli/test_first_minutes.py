"""What a newcomer meets in the first ten minutes: the Python API takes a scene's text, speaks
Python in its errors, and the command line ends quietly under `| head`, hints at how to write
a negative --range, and says what one PNG picture shows."""
from __future__ import annotations

from pathlib import Path

import pytest
from helpers.clirun import run
from helpers.scenes import SHORT as CANNOT_ASSEMBLE_SOMEWHERE

import sheetkin
from sheetkin.kinematics.scene import SceneError

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
FOURBAR = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")


def test_compute_takes_the_scene_text():
    by_text = sheetkin.compute(FOURBAR)
    by_path = sheetkin.compute(WORKBOOKS / "fourbar.toml")
    assert by_text.equals(by_path) and len(by_text) == 13


def test_compute_of_a_missing_path_names_the_path_only(tmp_path):
    with pytest.raises(SceneError, match=r"^.*nofile\.toml: no such file$"):
        sheetkin.compute(str(tmp_path / "nofile.toml"))


def test_load_scene_of_a_text_names_the_function_that_reads_text():
    with pytest.raises(SceneError) as info:
        sheetkin.load_scene(FOURBAR)
    said = str(info.value)
    assert "sheetkin.parse_scene(text)" in said and "\n" not in said and "[crank]" not in said


def test_python_errors_speak_python(capsys):
    with pytest.raises(sheetkin.AssemblyError) as info:
        sheetkin.compute(CANNOT_ASSEMBLE_SOMEWHERE)
    assert "allow_gaps=True" in str(info.value) and "--allow-gaps" not in str(info.value)


def test_the_command_line_speaks_options(tmp_path, capsys):
    scene = tmp_path / "gap.toml"
    scene.write_text(CANNOT_ASSEMBLE_SOMEWHERE, encoding="utf-8")
    code, _, err = run(capsys, "compute", scene)
    assert code == 3 and "--allow-gaps" in err and "allow_gaps=True" not in err


def test_negative_range_start_says_how_to_write_it(capsys):
    code, _, err = run(capsys, "compute", WORKBOOKS / "fourbar.toml", "--range", "-90:90:1")
    assert code == 2 and "--range=-90:90:1" in err and err.count("\n") == 1
    code, out, _ = run(capsys, "compute", WORKBOOKS / "fourbar.toml", "--range=-90:90:30", "--format", "csv")
    assert code == 0 and len(out.splitlines()) == 1 + 6


def test_one_png_is_one_position(tmp_path, capsys):
    code, _, err = run(capsys, "animate", WORKBOOKS / "fourbar.toml", "-o", tmp_path / "first.png")
    assert code == 0 and "positions" not in err and "phi_1 = 0 deg" in err
    assert (tmp_path / "first.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_one_frame_gif_says_one_position(tmp_path, capsys):
    code, _, err = run(capsys, "animate", WORKBOOKS / "fourbar.toml", "-o", tmp_path / "x.gif", "--frames", "1")
    assert code == 0 and "x.gif: 1 position\n" in err


def test_examples_under_head_writes_every_scene(tmp_path):
    """`sheetkin examples . | head -n 2` (the teacher's first command) writes all the scenes: a
    reader that leaves after two lines must not stop the writing."""
    import os
    import subprocess
    import sys
    env = dict(os.environ, PYTHONPATH=str(WORKBOOKS.parent))
    for _ in range(3):
        out = tmp_path / f"run{_}"
        out.mkdir()
        p = subprocess.run(f"'{sys.executable}' -m sheetkin examples . | head -n 2", shell=True, cwd=out,
                           env=env, capture_output=True, text=True, timeout=60)
        assert len(p.stdout.splitlines()) == 2
        assert sorted(f.name for f in out.glob("*.toml")) == sorted(f.name for f in WORKBOOKS.glob("*.toml"))
