"""Ranges whose end is a reference-returning function (`=SUM(A1:INDEX(A1:A10,3))`,
`OFFSET(...):INDEX(...)`), and an array constant as a whole single-cell formula (`={1,2}`:
Excel shows its first element), issue 32. Excel's semantics: the range operator spans both
references (the smallest block holding both), evaluated after the cells it may read; in a
cell that is not an array formula, a range result is intersected with the cell's row or
column and an array result shows its top-left element. Checked against LibreOffice's
recalculation, and against the arithmetic of the cells where it is plain."""
from __future__ import annotations

import math

import openpyxl
import pytest
from helpers.libreoffice import read_values, recalculate

from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.parse import parse_formula

A = [3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0, 29.0, 31.0]      # A1:A10
B = [2.0, 4.0, 8.0, 16.0, 32.0]                                    # B1:B5

# cell -> (formula, the value from the cells' arithmetic, or None where only LibreOffice says)
FORMULAS = {
    "C1": ("=SUM(A1:INDEX(A1:A10,3))", sum(A[:3])),
    "C2": ("=SUM(INDEX(A1:A10,2):A5)", sum(A[1:5])),
    "C3": ("=SUM(A2:OFFSET(A2,3,0))", sum(A[1:5])),
    "C4": ("=SUM(OFFSET(A1,1,0):INDEX(A1:A10,4))", sum(A[1:4])),
    "C5": ("={1,2}", 1.0),                                   # an array constant: its first element
    "C6": ("=INDEX(B1:B5,0)", "#VALUE!"),                   # a column, row 6 outside B1:B5
    "D2": ("=INDEX(B1:B5,0)", B[1]),                          # the same column, intersected at row 2
    "C7": ("=ROWS(A1:INDEX(A1:A10,4))", 4.0),
    "C8": ("=A3:INDEX(A1:A10,5)", "#VALUE!"),               # A3:A5 from row 8: no intersection
    "D4": ("=A3:INDEX(A1:A10,5)", A[3]),                      # ... from row 4: A4
    "C9": ("={1,2;3,4}*2", 2.0),
    "C10": ("=SUM(A1:INDEX(B1:B5,2))", A[0] + A[1] + B[0] + B[1]),   # the block A1:B2
    "C11": ("=A1:INDEX(A1:A10,1)", A[0]),
    "C12": ("=SUM(A1:INDEX(A1:A10,20))", "#REF!"),
    "C13": ("=SUM(E1:INDEX(E1:E5,3))", 2 * sum(A[:3])),      # E1:E5 are formulas: computed first
    "C14": ("=INDEX(A1:INDEX(A1:A10,6),5)", A[4]),
    "C15": ("=SUM(A1:INDEX(A1:A10,MATCH(11,A1:A10,0)))", sum(A[:4])),
    "C16": ('=COUNTA(A1:INDIRECT("A"&3))', 3.0),
    "C17": ("={\"x\",2}", "x"),
    "D17": ("=SUM({1,2})", 3.0),
    # IF and CHOOSE whose chosen argument is a reference (Excel's "IF returns a reference")
    "C18": ("=SUM(IF(B1>3,A3,A2):A6)", sum(A[1:6])),
    "C19": ("=SUM(A1:CHOOSE(2,A2,A4,A6))", sum(A[:4])),
    "C20": ("=SUM(CHOOSE(3,A2,A4,A6):A8)", sum(A[5:8])),
    "C21": ("=SUM(A1:CHOOSE(5,A2,A4))", "#VALUE!"),          # no 5th choice
    "C22": ("=SUM(IF(B1>1,A2:A3,A4):A6)", sum(A[1:6])),
}
RUN = {f"{c}12": "=SUM($A$1:INDEX($A$1:$A$10,COLUMN()-5))" for c in "FGHIJ"}    # a run: 1, 2 ... 5 cells
RUN_IF = {f"{c}13": "=SUM($A$1:CHOOSE(COLUMN()-5,$A$1,$A$2,$A$3,$A$4,$A$5))" for c in "FGHIJ"}   # each cell its own
# ranges that end in IF: Excel computes them; LibreOffice reads `A1:IF(` from a .xlsx as #NAME?
# and Gnumeric gives #REF! (measured 2026-11-29), so these follow Excel and are not compared
EXCEL_ONLY = {
    "K1": ("=SUM(A1:IF(TRUE,A3,A5))", sum(A[:3])),
    "K2": ("=SUM(A1:IF(B1>3,A3,A5))", sum(A[:5])),
    "K3": ("=ROWS(A2:IF(B2=4,A9))", 8.0),
    "K4": ("=SUM(A1:IF(FALSE,A3))", "#VALUE!"),             # no argument chosen
    "K5": ('=SUM(A1:IF("x",A3,A5))', "#VALUE!"),            # a text test
    "K6": ("=SUM(A1:IF(1/0,A3,A5))", "#DIV/0!"),             # the test's own error
    "K7": ("=SUM(A1:IF(TRUE,A3,A5),B1)", sum(A[:3]) + B[0]),
}


def _book(path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "S"
    for i, v in enumerate(A, start=1):
        ws.cell(i, 1, v)
    for i, v in enumerate(B, start=1):
        ws.cell(i, 2, v)
    for i in range(1, 6):
        ws.cell(i, 5, f"=A{i}*2")
    for cell, (f, _) in FORMULAS.items():
        ws[cell] = f
    for cell, f in {**RUN, **RUN_IF}.items():
        ws[cell] = f
    for cell, (f, _) in EXCEL_ONLY.items():
        ws[cell] = f
    wb.save(path)
    return path


def _agree(mine, theirs) -> bool:
    if isinstance(theirs, str) and theirs.startswith("#"):
        return isinstance(mine, str) and mine.startswith("#")
    if isinstance(theirs, (int, float)) and not isinstance(theirs, bool):
        return isinstance(mine, float) and math.isclose(mine, theirs, rel_tol=1e-12)
    return mine == theirs


def test_range_ends_and_array_constants_compute_as_excel(tmp_path):
    book = evaluate(_book(tmp_path / "ends.xlsx"), strict=False)
    assert not book.problems and not book.uncomputed()
    for cell, (f, want) in {**FORMULAS, **EXCEL_ONLY}.items():
        got = book.value("S", int(cell[1:]), ord(cell[0]) - 64)
        if isinstance(want, float):
            assert got == pytest.approx(want, rel=1e-12), (cell, f, got)
        else:
            assert got == want, (cell, f, got)
    assert [book.value("S", 12, c) for c in range(6, 11)] == pytest.approx([sum(A[:n]) for n in range(1, 6)])
    assert [book.value("S", 13, c) for c in range(6, 11)] == pytest.approx([sum(A[:n]) for n in range(1, 6)])


def test_range_ends_and_array_constants_agree_with_libreoffice(tmp_path, soffice):
    src = _book(tmp_path / "ends_lo.xlsx")
    lo = read_values(recalculate([src], tmp_path / "lo")[src.resolve()], "S")
    ours = evaluate(src, strict=False)
    cells = [*FORMULAS, *RUN, *RUN_IF]
    wrong = [(cell, ours.value("S", int(cell[1:]), ord(cell[0]) - 64), lo.get(cell)) for cell in cells
             if not _agree(ours.value("S", int(cell[1:]), ord(cell[0]) - 64), lo.get(cell))]
    assert not wrong


@pytest.mark.parametrize("text", ["=A1:INDEX(A1:A3,2)", "=INDEX(A1:A3,2):A5", "=OFFSET(A1,1,0):INDEX(A1:A3,2)",
                                  "=Data!A1:INDEX(Data!A1:A3,2)"])
def test_a_range_ending_in_a_reference_function_parses_to_the_range_operator(text):
    tree = parse_formula(text, 1, 1, {})
    assert tree[0] == "fn" and tree[1] == ":" and len(tree[2]) == 2


@pytest.mark.parametrize("text", ["=A1:SUM(A1:A3)", "=A1:ABS(A3)"])
def test_a_range_ending_in_another_function_stays_not_computed(tmp_path, text):
    """Only INDEX, OFFSET, INDIRECT, IF and CHOOSE return references here: A1:SUM(...) is an
    unknown function for the evaluator (not computed here), never a wrong value."""
    tree = parse_formula(text, 1, 1, {})
    assert tree[1] != ":"
    wb = openpyxl.Workbook()
    wb.active["A1"], wb.active["B1"] = 1, text
    wb.save(tmp_path / "other.xlsx")
    book = evaluate(tmp_path / "other.xlsx", strict=False)
    assert book.value(book.order[0], 1, 2) == "#NAME?" and book.problems
