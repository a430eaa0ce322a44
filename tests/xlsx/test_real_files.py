"""Spreadsheet features that real files use, computed as Excel computes them.

Every feature is tried in the two shapes the evaluator meets: a hand-written LibreOffice
flat ODF file (.fods) that LibreOffice converts to .xlsx (its own XML), and a package in
Excel's own XML shape (the writers: tests/helpers/realfiles.py; the books: tests/helpers/realbooks.py). Each
file's cells are checked against Excel's values worked out by hand (`Book.expected`), and every formula cell
against LibreOffice's recalculation (errors compared as "an error"). All the conversions
and recalculations of the module run in ONE soffice call (the `lo` fixture).
"""
from __future__ import annotations

import math
from pathlib import Path

import openpyxl
import pytest
from helpers import realfiles as rf
from helpers.libreoffice import is_error, recalculate
from helpers.realbooks import (
    BUILDERS,
    FUNCTIONS,
    ROOT,
    Book,
    differential_book,
    fourbar_with_name,
    generated_formulas,
    row_numbers,
)
from helpers.realfiles import cell
from hypothesis import example, given, settings
from hypothesis import strategies as st
from openpyxl.utils import get_column_letter

from sheetkin.course.validator import validate
from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.functions import ERRORS


# ------------------------------------------------------------------ one soffice call
@pytest.fixture(scope="module")
def lo(soffice, tmp_path_factory):
    """Every book written, then converted (.fods) or recalculated (.xlsx) by LibreOffice
    in one soffice call; also the fourbar regression workbook."""
    src = tmp_path_factory.mktemp("real_in")
    out = tmp_path_factory.mktemp("real_out")
    books = {b.name: b for b in (build(src) for build in BUILDERS)}
    diff_path, diff_cells = differential_book(src)
    fourbar = fourbar_with_name(src / "fourbar_dfi.xlsx")
    paths = [b.source for b in books.values()] + [diff_path, fourbar]
    outputs = recalculate(paths, out)
    for b in books.values():
        b.lo = outputs[b.source.resolve()]
    return {"books": books, "differential": (diff_path, outputs[diff_path.resolve()], diff_cells),
            "fourbar": (fourbar, outputs[fourbar.resolve()])}


def _lo_values(path: Path) -> dict:
    wb = openpyxl.load_workbook(path, data_only=True)
    try:
        return {(ws.title, c.row, c.column): c.value for ws in wb.worksheets for row in ws.iter_rows()
                for c in row if c.value is not None}
    finally:
        wb.close()


def _formula_cells(path: Path) -> list[tuple[str, int, int]]:
    wb = openpyxl.load_workbook(path)
    try:
        return [(ws.title, c.row, c.column) for ws in wb.worksheets for row in ws.iter_rows() for c in row
                if c.data_type == "f" or (isinstance(c.value, str) and c.value.startswith("="))
                or type(c.value).__name__ == "ArrayFormula"]
    finally:
        wb.close()


def agrees(ours, theirs) -> bool:
    """Ours against a spreadsheet's value: errors as "an error", numbers to 1e-12."""
    if is_error(theirs) or theirs == "#ERR" or (isinstance(ours, str) and ours in ERRORS):
        return (isinstance(ours, str) and ours in ERRORS) and (is_error(theirs) or theirs == "#ERR")
    if theirs is None or theirs == "":
        return ours is None or ours == ""
    if isinstance(theirs, bool) or isinstance(ours, bool):
        return type(ours) is bool and type(theirs) is bool and ours == theirs
    if isinstance(theirs, (int, float)):
        return isinstance(ours, float) and math.isfinite(ours) and abs(ours - theirs) <= 1e-12 * max(1.0, abs(theirs))
    return ours == theirs


def split_run(key: str) -> tuple[str, int, int]:
    sheet, ref = key.split("!")
    letters = ref.rstrip("0123456789")
    return sheet, int(ref[len(letters):]), openpyxl.utils.column_index_from_string(letters)


def _evaluated(b: Book):
    """Our evaluation of the file the feature is checked on: LibreOffice's .xlsx for a
    .fods book, the file written here for Excel's shape."""
    return evaluate(b.lo if b.shape == "lo" else b.source)


# ------------------------------------------------------------------ the tests
BOOK_NAMES = ["lo_names", "xl_names", "lo_arrays", "xl_arrays", "xl_shared", "lo_functions", "xl_functions",
              "lo_whole", "xl_whole", "lo_styled", "xl_styled"]


@pytest.mark.parametrize("key", BOOK_NAMES)
def test_feature_values_are_excels(lo, key):
    """Each book's cells against Excel's values worked out by hand."""
    b = lo["books"][key]
    book = _evaluated(b)
    bad = [f"{k}: ours {book.value(*split_run(k))!r}, Excel {v!r}" for k, v in b.expected.items()
           if not agrees(book.value(*split_run(k)), v)]
    assert not bad, "; ".join(bad)


@pytest.mark.parametrize("key", BOOK_NAMES)
def test_every_formula_cell_agrees_with_libreoffice(lo, key):
    """Every formula cell of the file (and every cell of an array range) against
    LibreOffice's own recalculation of the same file."""
    b = lo["books"][key]
    book = _evaluated(b)
    theirs = _lo_values(b.lo)
    cells = set(_formula_cells(b.lo))
    for s, sh in book.sheets.items():
        for (r, c), (r2, c2) in sh.arrays.items():
            cells |= {(s, i, j) for i in range(r, r2 + 1) for j in range(c, c2 + 1)}
    assert len(cells) >= 2
    skip = LO_DIFFERS.get(key, set())
    bad = [f"{s}!{get_column_letter(c)}{r}: ours {book.value(s, r, c)!r}, LibreOffice {theirs.get((s, r, c))!r}"
           for s, r, c in sorted(cells) if f"{s}!{get_column_letter(c)}{r}" not in skip
           and not agrees(book.value(s, r, c), theirs.get((s, r, c)))]
    assert not bad, f"{len(bad)} of {len(cells)}: " + "; ".join(bad[:20])


# Where LibreOffice 7.4 is not Excel (the cells are checked against Excel's values above)
LO_DIFFERS: dict[str, set] = {
    # LibreOffice 7.4 knows neither E1# (ANCHORARRAY) nor @ (SINGLE)
    "xl_arrays": {"Calc!F6", "Calc!F7", "Calc!G6"},
    # LibreOffice computes its own FLOOR(-7.3; 2; 1) and CEILING(-7.3; 2; 1) (an error: x and
    # s of different signs) but writes them as FLOOR.MATH and CEILING.MATH, which Excel
    # computes as -6 and -8 (FUNCTIONS)
    "lo_functions": {f"Calc!F{5 + i}" for i, (_, odf, _) in enumerate(FUNCTIONS)
                     if odf in ("FLOOR(-7.3;2;1)", "CEILING(-7.3;2;1)")},
}


def test_generated_formulas_agree_with_libreoffice(lo):
    """The differential test over the features: random formulas with names (global,
    local, of formula cells), the functions, whole columns and rows, arrays."""
    path, lo_path, cells = lo["differential"]
    book = evaluate(path)
    theirs = _lo_values(lo_path)
    formulas = generated_formulas()
    bad = [f"G{r} ={formulas[r - 1]}: ours {book.value(s, r, c)!r}, LibreOffice {theirs.get((s, r, c))!r}"
           for s, r, c in cells if not agrees(book.value(s, r, c), theirs.get((s, r, c)))]
    assert len(cells) == 240
    assert not bad, f"{len(bad)} of {len(cells)} differ: " + "; ".join(bad[:15])


@pytest.mark.parametrize("saved_by", ["openpyxl", "libreoffice"])
def test_fourbar_with_a_name_of_a_formula_cell_grades_correct(lo, saved_by):
    """Regression: a name (dfi) of a formula cell is computed before the row that uses it,
    so the student's correct workbook is graded correct in every row."""
    src, lo_path = lo["fourbar"]
    report = validate(src if saved_by == "openpyxl" else lo_path)
    assert report.error is None, report.error
    wrong = [r.name for r in report.rows if r.status != "correct"]
    assert len(report.rows) > 50 and not wrong, wrong


def test_opendocument_spreadsheet_is_converted(lo, tmp_path, soffice):
    """An .ods (and a .fods) is read through LibreOffice: the same values as LibreOffice's
    own .xlsx of it, the original file untouched, nothing left next to it."""
    b = lo["books"]["lo_functions"]
    folder = tmp_path / "class"
    folder.mkdir()
    ods = rf.ods(folder / "student.ods", b.source)
    before = (ods.read_bytes(), ods.stat().st_mtime_ns)
    ours, ref = evaluate(ods), evaluate(b.lo)
    assert (ods.read_bytes(), ods.stat().st_mtime_ns) == before
    assert sorted(p.name for p in folder.iterdir()) == ["student.ods"]
    assert ours.path == str(ods)
    from sheetkin.cli.commands import main
    assert main(["evaluate", str(ods), "--format", "csv"]) == 0
    for key, v in b.expected.items():
        assert agrees(ours.value(*split_run(key)), v), key
        assert agrees(ours.value(*split_run(key)), ref.value(*split_run(key))), key


def test_validate_accepts_an_ods_submission(lo, tmp_path):
    """The fourbar workbook saved as .ods (LibreOffice's default on Save) is validated."""
    from sheetkin.xlsx.libreoffice import _convert
    src, _ = lo["fourbar"]
    ods = _convert([src], tmp_path, "ods", "ods", 120)[src.resolve()]
    report = validate(ods)
    assert report.error is None, report.error
    assert report.rows and all(r.status == "correct" for r in report.rows)


def test_ods_without_libreoffice_is_refused_with_the_command(tmp_path, monkeypatch, capsys):
    from sheetkin.cli.commands import main
    from sheetkin.xlsx import libreoffice
    src = rf.fods(tmp_path / "a.fods", [rf.table("Calc", [[rf.num(1)]])])
    ods = rf.ods(tmp_path / "a.ods", src)
    monkeypatch.setattr(libreoffice, "soffice_path", lambda: None)
    for p in (ods, src):
        assert main(["evaluate", str(p)]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and str(p) in err, err
        assert "soffice --headless --convert-to xlsx" in err and "Traceback" not in err
    report = validate(ods)
    assert report.error and "soffice --headless --convert-to xlsx" in report.error


def test_book_value_gives_any_cell(lo):
    """evaluate(path).value(sheet, row, col) on a workbook sheetkin did not write: typed
    numbers, computed numbers, text, booleans, errors, empty cells, outside the sheet."""
    book = evaluate(lo["books"]["lo_arrays"].lo)
    assert book.value("Calc", 1, 1) == 2.0                  # typed
    assert book.value("Calc", 1, 5) == 4.0                  # an array formula's element
    assert book.value("Calc", 3, 3) == "x"                  # text
    assert book.value("Calc", 3, 1) == "#DIV/0!"            # an error
    assert book.value("Calc", 1, 4) is None                 # empty, inside the used range
    assert book.value("Calc", 500, 500) is None             # outside it
    assert book.value("Calc", 0, 1) is None and book.value("Calc", 1, -1) is None
    assert book.value("calc", 1, 1) == 2.0                  # sheet names are case-insensitive
    assert evaluate(lo["books"]["xl_functions"].source).value("Calc", 5 + 32, 6) is True
    with pytest.raises(KeyError, match="sheets: Calc"):
        book.value("Nope", 1, 1)


def test_styled_emptiness_is_not_the_used_range(lo):
    for key in ("lo_styled", "xl_styled"):
        b = lo["books"][key]
        book = _evaluated(b)
        sh = book.sheets["Calc"]
        assert (sh.max_row, sh.max_col) == (2, 3), key
        assert book.num["Calc"].size < 100, key             # stores of the used range, not of the styling


def test_spilled_cells_are_computed_not_typed(lo):
    """The cells of an array's range hold the anchor's computed values, not the (stale)
    values saved in the file, and are not read as typed numbers."""
    b = lo["books"]["xl_arrays"]
    book = evaluate(b.source)
    sh = book.sheets["Calc"]
    assert (7, 3) not in sh.consts and sh.cached[(7, 3)] == 99
    assert book.value("Calc", 7, 3) == 1.0 and book.value("Calc", 7, 4) == 2.0


@pytest.mark.parametrize("key", [k for k in BOOK_NAMES if k.startswith("xl_")])
def test_both_readers_read_excels_shape_alike(lo, key, monkeypatch):
    """The element-tree reader (any well-formed sheet) reads shared formulas whose master
    comes after its children, array ranges and styled emptiness as the fast reader does."""
    from sheetkin.xlsx import cells as xlsxread
    src = lo["books"][key].source
    fast = xlsxread.read_book(src)
    monkeypatch.setattr(xlsxread, "_read_fast", lambda *a: None)
    tree = xlsxread.read_book(src)
    for name, sh in fast.sheets.items():
        other = tree.sheets[name]
        for attr in ("consts", "formulas", "cached", "arrays", "names", "max_row", "max_col"):
            assert getattr(sh, attr) == getattr(other, attr), (name, attr)


def test_readme_value_example_holds():
    """docs/evaluator.md's `book.value(...)` lines give what their comments say."""
    import ast
    import re
    text = (ROOT / "docs" / "evaluator.md").read_text("utf-8")
    block = text[text.index("Any cell's value, from Python"):]
    block = block[block.index("```python"):block.index("```\n", 10)]
    book = evaluate(ROOT / "workbooks" / "fourbar.xlsx")
    lines = [m for m in re.finditer(r"^book\.value\((.*)\)\s+# .*?: (.+?)(?:;.*)?$", block, re.M)]
    assert len(lines) >= 5
    for m in lines:
        args = ast.literal_eval(f"({m.group(1)})")
        assert book.value(*args) == ast.literal_eval(m.group(2)), m.group(0)
    assert repr(book.order) in block


def test_fourbar_row_as_one_array_formula_grades_correct(tmp_path):
    """A student who fills row Fi with ONE array formula over E32:Q32 (its other cells hold
    no formula in the file) is graded correct, and the row counts as formulas, not typed."""
    from openpyxl.worksheet.formula import ArrayFormula
    wb = openpyxl.load_workbook(ROOT / "workbooks" / "fourbar.xlsx")
    ws = wb.worksheets[0]
    row = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "Fi")
    last = max(c for c in range(5, ws.max_column + 1) if ws.cell(row, c).value is not None)
    span = f"E{row}:{get_column_letter(last)}{row}"
    for c in range(5, last + 1):
        ws.cell(row, c).value = None
    at = row_numbers(ws)
    ws[f"E{row}"] = ArrayFormula(span, f"=RADIANS($D${at['Fi0']})+E{at['i']}:{get_column_letter(last)}{at['i']}"
                                       f"*$D${at['Delta_Fi_rad']}")
    wb.save(tmp_path / "array_row.xlsx")
    report = validate(tmp_path / "array_row.xlsx")
    assert report.error is None, report.error
    assert all(r.status == "correct" for r in report.rows), [r.name for r in report.rows if r.status != "correct"]
    fi = next(r for r in report.rows if r.name == "Fi")
    assert fi.source == "formula"


def test_an_array_range_past_the_limits_is_refused(tmp_path):
    """An array formula's range holds computed cells: past the row limit it is one line,
    not a store of a million rows."""
    from sheetkin.xlsx.cells import read_book
    from sheetkin.xlsx.package import UnusableWorkbook
    xml = rf.sheet_xml([cell("A1", 1), cell("B1", 0, "A1*2", ' t="array" ref="B1:B1048576"')])
    path = rf.xlsx(tmp_path / "big_array.xlsx", [("Calc", xml)])
    with pytest.raises(UnusableWorkbook) as info:
        read_book(path)
    msg = str(info.value)
    assert msg.startswith(str(path)) and "B1:B1048576" in msg and "at most 100000 rows" in msg


def test_a_class_of_ods_files_is_converted_in_one_run(lo, tmp_path, monkeypatch, capsys):
    """`sheetkin validate FOLDER` converts all the folder's .ods and .fods files in one
    LibreOffice run (not one per file), and reads each from its converted copy."""
    from sheetkin.cli.commands import main
    from sheetkin.xlsx import convert as xlsxconvert
    from sheetkin.xlsx import libreoffice
    folder = tmp_path / "class"
    folder.mkdir()
    b = lo["books"]["lo_functions"]
    for i in range(3):
        rf.ods(folder / f"s{i}.ods", b.source)
    (folder / "s3.fods").write_bytes(b.source.read_bytes())
    runs = []
    convert = libreoffice._convert
    monkeypatch.setattr(libreoffice, "_convert",
                        lambda paths, *a, **k: runs.append(len(paths)) or convert(paths, *a, **k))
    monkeypatch.setattr(xlsxconvert, "_CONVERTED", {})
    assert main(["validate", str(folder), "--progress", "always", "--lang", "en"]) == 2  # no scene: one line each
    assert runs == [4]
    out, err = capsys.readouterr()
    assert "4 OpenDocument spreadsheets: converting them" in err
    assert all(f"s{i}." in out for i in range(4)) and "no embedded scene" in out
    for p in folder.iterdir():
        assert agrees(evaluate(p).value("Calc", 5, 6), math.pi / 4)
    assert runs == [4]                                   # read from the converted copies


@settings(max_examples=300, deadline=None)
@example("ZZZ9+A1", 0, -1)                  # past XFD: a name, left alone
@example("A1:B2+$C$3+D:E+2:3", -1, -1)
@example("Q1!a1+b2+c:d", 1, 1)              # references in lower case come back in capitals
@given(st.lists(st.one_of(
           st.builds(lambda ca, c, ra, r: f"{ca}{get_column_letter(c)}{ra}{r}", st.sampled_from(["", "$"]),
                     st.integers(1, 16384), st.sampled_from(["", "$"]), st.integers(1, 1048576)),
           st.builds(lambda a, b: f"{get_column_letter(a)}:{get_column_letter(b)}", st.integers(1, 16384),
                     st.integers(1, 16384)),
           st.sampled_from(['"A1"', "SUM(", ")", "+", ",", "dfi", "'My Sheet'!", "Data!", "LOG10(", "1.5", "ZZZ9"]),
           st.text(max_size=3)), max_size=8).map("".join),
       st.integers(-20, 20), st.integers(-20, 20))
def test_shifting_a_shared_formula_there_and_back_is_the_identity(text, dr, dc):
    """_shift_formula never raises; moved by (dr, dc) and back it is the text it was (its
    references in capitals), unless a reference left the sheet on the way (then it says
    #REF!)."""
    from sheetkin.xlsx.cells import _shift_formula
    there = _shift_formula(text, dr, dc)
    assert isinstance(there, str)
    back = _shift_formula(there, -dr, -dc)
    if "#REF!" not in there:
        assert back.upper() == text.upper()


@pytest.mark.parametrize("text", ["Q1!a1", "'Data A1'!b2+c3", "SUM(a1:b2)*$c$3", "a:c+2:3"])
def test_references_in_lower_case_shift_as_openpyxl_translates(text):
    """A shared formula's text with references in lower case (a hand-edited file; Excel's
    formulas read q1 as Q1) shifts as openpyxl's Translator moves it: Q1!a1 down a row is
    Q1!A2, where the shifter once moved the unquoted sheet name Q1 as if it were the cell
    (found by a fresh-eyes review of issue 32's change)."""
    from openpyxl.formula.translate import Translator

    from sheetkin.xlsx.cells import _shift_formula
    for dr, dc in ((1, 0), (0, 1), (2, 3)):
        want = Translator("=" + text, origin="E5").translate_formula(f"{get_column_letter(5 + dc)}{5 + dr}")
        assert "=" + _shift_formula(text, dr, dc) == want
    # where openpyxl's Translator itself errs (it drops Q1! before a name, leaves a1 in a
    # 3-D-looking range): a sheet's name stays, its references move
    assert _shift_formula("Q1!abc+A1", 1, 0) == "Q1!abc+A2"
    assert _shift_formula("Data!a1:Data!b2", 1, 0) == "Data!A2:Data!B3"
