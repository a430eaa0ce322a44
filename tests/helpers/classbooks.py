"""A class made in the tests: variants of the four-bar, exercise and key books, and
students' books filled in from the key (honest, or with a mistake, or copied)."""
from __future__ import annotations

import re
from pathlib import Path

import openpyxl

import sheetkin
from helpers.scenes import FOURBAR
from sheetkin.sheet.workbook import IDENTITY_CELLS, write_workbook

# five variants of the spec's four-bar: the crank's length differs (the teacher's variants
# would differ in more; one given value is enough to make every computed row differ)
VARIANT_L1 = {"v1": 0.14, "v2": 0.15, "v3": 0.13, "v4": 0.16, "v5": 0.12}


def variant_text(l1: float) -> str:
    text, n = re.subn(r"(?m)^length   = 0\.14$", f"length   = {l1:g}", FOURBAR)
    assert n == 1
    return text


def issue_variants(folder: Path) -> dict[str, tuple[Path, Path]]:
    """{variant: (exercise book, answer key)} written in `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for v, l1 in VARIANT_L1.items():
        text = variant_text(l1)
        scene = sheetkin.parse_scene(text, f"{v}.toml")
        ex, key = folder / f"{v}-exercise.xlsx", folder / f"{v}-key.xlsx"
        write_workbook(scene, ex, exercise=True, scene_text=text)
        write_workbook(scene, key, scene_text=text)
        out[v] = (ex, key)
    return out


def rows_of(ws) -> dict[str, int]:
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if isinstance(ws.cell(r, 1).value, str)}


def fill(exercise: Path, key: Path, dst: Path, *, student: str = "", group: str = "", change=None) -> Path:
    """The student's book: the exercise with the key's formulas typed into its empty
    computed cells (what an honest student writes: the lecture's formulas), their name and
    group in their own cells when the book has them, then change(ws, rows) (a mistake)."""
    wb = openpyxl.load_workbook(exercise)
    ws = wb.worksheets[0]
    kws = openpyxl.load_workbook(key).worksheets[0]
    for row in kws.iter_rows(min_row=5):
        for c in row:
            if c.column >= 4 and c.value is not None and ws.cell(c.row, c.column).value is None:
                ws.cell(c.row, c.column).value = c.value
    rows = rows_of(ws)
    for name, text in (("student", student), ("group", group)):
        if text:                                # the student's own cells: D1, D2 (rows 1-2)
            cell = ws.cell(*IDENTITY_CELLS[name])
            cell.value, cell.data_type = text, "s"
    if change is not None:
        change(ws, rows)
    wb.save(dst)
    return dst


def flip_sign(name: str):
    """A sign error in every column of row `name`."""
    def change(ws, rows):
        for k in range(13):
            c = ws.cell(rows[name], 5 + k)
            c.value = "=-(" + c.value[1:] + ")"
    return change


def type_numbers(name: str, values: list[float], digits: int = 2):
    """Numbers typed over the formulas of row `name`, rounded to `digits` decimals."""
    def change(ws, rows):
        for k, v in enumerate(values):
            ws.cell(rows[name], 5 + k).value = round(v, digits)
    return change


def set_input(name: str, value: float):
    def change(ws, rows):
        ws.cell(rows[name], 4).value = value
    return change


def both(*changes):
    def change(ws, rows):
        for ch in changes:
            ch(ws, rows)
    return change


def row_values(book: Path, name: str) -> list[float]:
    """Row `name`'s values at the 13 positions, by sheetkin's evaluator."""
    from sheetkin.xlsx.evaluator import evaluate
    b = evaluate(book)
    sheet = b.order[0]
    ws = b.sheets[sheet]
    r = next(r for (r, c), v in ws.consts.items() if c == 1 and v == name)
    return [b.value(sheet, r, 5 + k) for k in range(13)]
