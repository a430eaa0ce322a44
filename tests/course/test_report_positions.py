"""Reports name positions as the sheet does: its row i and the crank angle phi_1."""
from __future__ import annotations

import json
from pathlib import Path

import openpyxl

from sheetkin.course.report import json_report, text_report
from sheetkin.course.report_html import html_page
from sheetkin.course.validator import validate

WB = Path(__file__).resolve().parents[2] / "workbooks"


def _flip(src: Path, dst: Path, name: str, cols) -> Path:
    wb = openpyxl.load_workbook(src)
    ws = wb.worksheets[0]
    r = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == name)
    for k in cols:
        c = ws.cell(r, 5 + k)
        c.value = "=-(" + c.value[1:] + ")"
    wb.save(dst)
    return dst


def test_shaper_positions_are_named_by_i_and_phi(tmp_path):
    """The shaper turns clockwise from 248.2617 deg in -30 deg steps: the 4th and 5th
    columns are i = 3, 4 at phi_1 = 158.2617, 128.2617."""
    rep = validate(_flip(WB / "shaper.xlsx", tmp_path / "s.xlsx", "omega_3", [3, 4]))
    cause = next(r for r in rep.causes)
    assert cause.name == "omega_3" and cause.wrong_cells == [4, 5]
    assert [round(p, 4) for _, p in rep.position_names[3:5]] == [158.2617, 128.2617]
    text = text_report(rep)
    assert "wrong from i = 3 (phi_1 = 158.262 deg)" in text and "wrong at i = 3-4;" in text
    row = next(r for r in json.loads(json_report([rep]))["reports"][0]["rows"] if r["name"] == "omega_3")
    assert row["wrong_i"] == [3, 4] and row["first_wrong_i"] == 3
    assert abs(row["first_wrong_phi_1"] - 158.2617) < 1e-9
    page = html_page([rep])
    assert "wrong from i = 3 (phi_1 = 158.262 deg)" in page and "<svg" in page
