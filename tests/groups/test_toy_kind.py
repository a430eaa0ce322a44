"""A sixth group kind is one module plus one registry line: tests/helpers/toykind.py, registered
at run time, is seen by compute, the workbook (recalculated by LibreOffice), the charts
sheet and the drawing, none of which names it. Its mechanism is RRP's on a fixed guide,
so an RRP twin of the scene is the oracle for compute."""
from __future__ import annotations

import math
import types

import numpy as np
import openpyxl
import pytest
from helpers import toykind
from helpers.libreoffice import recalculate

import sheetkin
from sheetkin.groups import KINDS, register, unregister
from sheetkin.kinematics import geometry
from sheetkin.sheet.charts import HELPER_COL
from sheetkin.sheet.workbook import build_workbook
from sheetkin.views import drawing

SCENE = """\
title = "A toy kind: coupler and slider on a line of the frame"
[frame]
O = [0.0, 0.0]
[crank]
pivot = "O"
joint = "A"
length = 0.1
positions = 13
omega = 10.0
epsilon = -3.0
[[group]]
type = "TOY"
links = [2, 3]
joints = ["A", "B"]
length = 0.35
line = [0.05, -0.04, {tilt}]
branch = 1
"""
TWIN = SCENE.replace('type = "TOY"', 'type = "RRP"').replace(
    "line = [0.05, -0.04, {tilt}]", "guide = {{ through = [0.05, -0.04], angle_deg = {tilt} }}")


@pytest.fixture(scope="module", autouse=True)
def toy():
    assert register(toykind) == "TOY"          # the one registry line
    yield toykind
    unregister("TOY")


def scene(tilt: float = 20.0, text: str = SCENE):
    return sheetkin.parse_scene(text.format(tilt=tilt), "toy.toml")


def test_register_checks_the_surface():
    with pytest.raises(ValueError, match=r"^half: not a group kind, it lacks .*parts.*protocol"):
        half = types.ModuleType("half")
        half.KIND = "HALF"
        register(half)
    with pytest.raises(ValueError, match="already"):
        copy = types.ModuleType("copy_of_toykind")
        copy.__dict__.update({m: getattr(toykind, m) for m in dir(toykind) if not m.startswith("__")})
        register(copy)
    assert "HALF" not in KINDS and list(KINDS)[-1] == "TOY"


def test_compute_sees_the_toy_as_its_rrp_twin():
    toy, twin = sheetkin.compute(scene()), sheetkin.compute(scene(text=TWIN))
    assert list(toy.columns) == list(twin.columns)
    numbers = toy.select_dtypes("number").columns
    assert len(numbers) > 20
    assert np.allclose(toy[numbers].to_numpy(float), twin[numbers].to_numpy(float), rtol=1e-12, atol=1e-12,
                       equal_nan=True)
    assert (toy.drop(columns=numbers) == twin.drop(columns=numbers)).all().all()
    u = (math.cos(math.radians(20.0)), math.sin(math.radians(20.0)))
    assert np.allclose(np.hypot(toy.x_B - toy.x_A, toy.y_B - toy.y_A), 0.35)       # the coupler's length
    assert np.allclose(-(toy.x_B - 0.05) * u[1] + (toy.y_B + 0.04) * u[0], 0, atol=1e-15)   # B on the line


def test_drawing_asks_the_toy_for_its_parts():
    sc = scene()
    st = geometry.structure(sc)
    (guide,), (block,) = st.guides, st.blocks
    assert (guide.link, guide.through, guide.angle_deg, guide.angle_input) == (0, (0.05, -0.04), 20.0, "tilt_g1")
    assert (block.link, block.at) == (3, "B") and st.members[2] == ("A", "B")
    svg = drawing.scene_svg(sc)
    assert svg.count("fill='#f6d58b'") == 1        # the block
    assert svg.count("stroke='#555555' stroke-width='1.2'") >= 1       # the hatched line


def _rows(ws) -> dict[str, int]:
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if isinstance(ws.cell(r, 1).value, str)}


def test_workbook_and_charts_sheet_follow_the_toys_inputs(soffice, tmp_path):
    """The book's tilt_g1 typed from 20 to 35 deg, position 4 chosen: after LibreOffice's
    recalculation every accepted row of B equals compute() of the scene with the line at
    35 deg, and the charts sheet draws the line at 35 deg with the block at B."""
    wb = build_workbook(scene(), scene_text=SCENE.format(tilt=20.0))
    ws, cs = wb.worksheets[0], wb.worksheets[1]
    rows = _rows(ws)
    ws.cell(rows["tilt_g1"], 4).value = 35.0
    cs["B1"] = 4
    wb.save(tmp_path / "toy.xlsx")
    out = recalculate([tmp_path / "toy.xlsx"], tmp_path / "out")
    book = openpyxl.load_workbook(out[(tmp_path / "toy.xlsx").resolve()], data_only=True)
    ws, cs = book.worksheets[0], book.worksheets[1]
    changed = scene(35.0)
    df = sheetkin.compute(changed)
    for name in ("x_B", "y_B", "vx_B", "vy_B", "ax_B", "ay_B", "s_B", "phi_2", "omega_2", "eps_2"):
        got = [ws.cell(rows[name], 5 + k).value for k in range(len(df))]
        assert np.allclose(np.array(got, dtype=float), df[name], rtol=1e-9, atol=1e-12), name
    scalars = {cs.cell(r, HELPER_COL + 4).value: cs.cell(r, HELPER_COL + 5).value for r in range(3, cs.max_row + 1)}
    # the book is Russian by default: the line of group 1 is "направляющая г1", the block "ползун 3 в B"
    assert scalars["направляющая г1: угол, град"] == pytest.approx(35.0, abs=1e-12)
    corners, label = [], None
    for r in range(3, cs.max_row + 1):
        label = cs.cell(r, HELPER_COL).value or (label if cs.cell(r, HELPER_COL + 1).value is not None else None)
        if label == "ползун 3 в B":
            corners.append((cs.cell(r, HELPER_COL + 1).value, cs.cell(r, HELPER_COL + 2).value))
    want = geometry.point_xy(changed, df.iloc[4:5], "B")[0]      # B1 is the sheet's i, from 0
    assert np.allclose(np.array(corners[:4], dtype=float).mean(axis=0), want, atol=1e-12)
