"""Notebook pictures: Scene._repr_svg_ and sheetkin.result(...)._repr_svg_ are valid SVG of
the mechanism; compute() still returns a plain DataFrame."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pandas as pd
import pytest

import sheetkin

WB = Path(__file__).resolve().parents[2] / "workbooks"
SVG = "{http://www.w3.org/2000/svg}"


def _parse(doc: str):
    root = ET.fromstring(doc)                 # well-formed XML, or this raises
    assert root.tag == f"{SVG}svg"
    return root


def test_scene_shows_as_svg():
    scene = sheetkin.load_scene(WB / "shaper.toml")
    root = _parse(scene._repr_svg_())
    texts = [t.text for t in root.iter(f"{SVG}text")]
    assert scene.title in texts and "phi_1 = 248.3 deg" in texts
    assert {"A", "B", "C", "D", "O"} <= set(texts)          # the joints are labelled
    assert len(list(root.iter(f"{SVG}polygon"))) >= 2       # the two blocks at least


def test_result_shows_as_svg_and_keeps_the_dataframe():
    res = sheetkin.result(WB / "fourbar.toml", at=[150.0])
    assert type(res.frame) is pd.DataFrame
    assert res.frame.loc[0, "omega_3"] == sheetkin.compute(WB / "fourbar.toml", at=[150.0]).loc[0, "omega_3"]
    root = _parse(res._repr_svg_())
    assert "position 1 of 1: phi_1 = 150 deg" in [t.text for t in root.iter(f"{SVG}text")]
    assert type(sheetkin.compute(WB / "fourbar.toml")) is pd.DataFrame     # the API is unchanged
    assert "2 positions" in repr(sheetkin.result(WB / "fourbar.toml", at=[0, 10]))


def test_ipython_formatter_picks_the_svg():
    pytest.importorskip("IPython")
    from IPython.core.formatters import DisplayFormatter
    data, _ = DisplayFormatter().format(sheetkin.load_scene(WB / "fourbar.toml"))
    assert "image/svg+xml" in data
    _parse(data["image/svg+xml"])
