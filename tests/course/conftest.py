"""Fixtures of the grading tests."""
from __future__ import annotations

from pathlib import Path

import pytest

import sheetkin
from sheetkin.sheet.workbook import write_workbook

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"


@pytest.fixture(scope="module")
def fourbar(tmp_path_factory) -> Path:
    """The bundled four-bar's workbook, written afresh (its scene embedded)."""
    d = tmp_path_factory.mktemp("fourbar")
    text = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    path = d / "fourbar.xlsx"
    write_workbook(sheetkin.parse_scene(text, "fourbar.toml"), path, scene_text=text)
    return path
