"""Issue 22: the given data are given, the exercise guides. The kinematics sheet is
protected without a password: the given data locked, the student's cells (name, group,
the computed rows, the derived values of an exercise) unlocked; the student's name and
group in D1, D2 (the lecture's rows 1-2); an instruction block and a legend; the check
cells blank until the rows they read are filled; one numbering of positions (i)."""
from __future__ import annotations

import re
import subprocess
import zipfile
from pathlib import Path

import openpyxl
import pytest

import sheetkin
from sheetkin.sheet.checks import STATUS
from sheetkin.sheet.texts import GUIDE
from sheetkin.sheet.workbook import FIRST_COL, IDENTITY_CELLS, build_workbook, sheet_rows

WB = Path(__file__).resolve().parents[2] / "workbooks"


@pytest.fixture(scope="module")
def exercise():
    scene = sheetkin.load_scene(WB / "shaper.toml")
    ws = build_workbook(scene, exercise=True).worksheets[0]
    rows = {r.name: r for r in sheet_rows(scene).rows}
    where = {ws.cell(r, 1).value: r for r in range(5, ws.max_row + 1)}
    return scene, ws, rows, where


def test_given_data_locked_the_students_cells_open(exercise):
    scene, ws, rows, where = exercise
    assert ws.protection.sheet and not ws.protection.password          # no password: a slip, not a lock
    n = scene.crank.positions
    for name, row in rows.items():
        if row.kind == "input":
            assert ws.cell(where[name], 4).protection.locked, name
        elif row.kind == "derived":
            assert not ws.cell(where[name], 4).protection.locked, name
        elif row.kind in ("calc", "accepted") and name not in ("i", "phi_1"):
            assert not any(ws.cell(where[name], FIRST_COL + k).protection.locked for k in range(n)), name
        elif row.kind in ("check", "fdcheck", "guard", "index"):
            assert all(ws.cell(where[name], FIRST_COL + k).protection.locked for k in range(n)), name
    for r, c in IDENTITY_CELLS.values():
        assert not ws.cell(r, c).protection.locked and ws.cell(r, c).number_format == "@"
    section = next(ws.cell(r, 1).value for r in range(5, ws.max_row) if ws.cell(r + 1, 1).value == "L1")
    assert section == "Исходные данные (не изменять)"


def test_name_and_group_in_rows_1_2_and_the_guide(exercise):
    _, ws, _, where = exercise
    assert (ws["A1"].value, ws["A2"].value) == ("студент", "группа") and ws["D1"].value is None
    assert "student" not in where and "group" not in where            # no longer input rows
    lines = [ws.cell(r, 1).value for r in range(5, 5 + len(GUIDE["ru"]))]
    assert lines == list(GUIDE["ru"])
    assert any("D1" in x and "D2" in x for x in lines) and any("не изменяйте" in x for x in lines)
    assert any(x.strip().startswith("0 (зелёный)") for x in lines) and any("н/д" in x for x in lines)


def test_check_cells_blank_until_filled_and_one_numbering(exercise):
    """A check row's cells get a white-on-white rule first, while its status says "не
    заполнено"; the headers of row 4 are the row i's numbers, from 0."""
    scene, ws, rows, where = exercise
    checks = [n for n, r in rows.items() if r.kind in ("check", "fdcheck")]
    for rng in ws.conditional_formatting:
        ref = str(rng.sqref)
        m = re.fullmatch(r"E(\d+):[A-Z]+\1", ref)
        if m and ws.cell(int(m.group(1)), 1).value in checks:
            first = rng.rules[0]
            assert first.formula[0].endswith(f'="{STATUS["ru"]["unfilled"]}"') and first.stopIfTrue
            assert first.dxf.font.color.rgb.endswith("FFFFFF")
    n = scene.crank.positions
    assert [ws.cell(4, FIRST_COL + k).value for k in range(n)] == [ws.cell(where["i"], FIRST_COL + k).value
                                                                    for k in range(n)] == list(range(n))


def test_libreoffice_keeps_the_protection(soffice, tmp_path):
    """LibreOffice opens the sheet protected, D1 (the student's name) unprotected and L1
    (a given length) protected: its own ODS says so."""
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    book = tmp_path / "ex.xlsx"
    build_workbook(scene, exercise=True).save(book)
    subprocess.run([soffice, "--headless", "--convert-to", "ods", "--outdir", str(tmp_path), str(book)],
                   check=True, capture_output=True, timeout=300)
    xml = zipfile.ZipFile(tmp_path / "ex.ods").read("content.xml").decode("utf-8")
    assert re.search(r'<table:table table:name="Кинематика"[^>]*table:protected="true"', xml)
    styles = dict(re.findall(r'<style:style style:name="([^"]+)" style:family="table-cell"[^>]*>(.*?)</style:style>',
                             xml, flags=re.S))

    def protect(row: int, col: int) -> str:
        """The cell-protect of LibreOffice's style of the cell (row, col), both 1-based."""
        rows = re.findall(r"<table:table-row[^>]*?>(.*?)</table:table-row>", xml.split("Кинематика", 1)[1],
                          flags=re.S)
        k = 0
        for chunk in re.findall(r"<table:table-cell([^>]*?)(?:/>|>.*?</table:table-cell>)", rows[row - 1],
                                flags=re.S):
            span = int((re.search(r'number-columns-repeated="(\d+)"', chunk) or [0, 1])[1])
            if k < col <= k + span:
                name = (re.search(r'table:style-name="([^"]+)"', chunk) or [0, "Default"])[1]
                m = re.search(r'style:cell-protect="([^"]+)"', styles.get(name, ""))
                return m.group(1) if m else "protected"
            k += span
        return "protected"
    assert protect(1, 4) == "none"
    ws = openpyxl.load_workbook(book).worksheets[0]
    l1 = next(r for r in range(5, ws.max_row) if ws.cell(r, 1).value == "L1")
    assert protect(l1, 4) != "none"
