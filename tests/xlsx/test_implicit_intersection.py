"""Implicit intersection (issue 21, item 2): a row or column range where one value is
expected, in a formula that is not an array formula, is the cell in the formula's column
or row, as LibreOffice and Excel compute it; ranges stay whole inside SUM, SUMPRODUCT,
INDEX and in array formulas. The values are checked against LibreOffice's recalculation."""
from __future__ import annotations

import math

import openpyxl
from helpers.libreoffice import read_values, recalculate
from openpyxl.workbook.defined_name import DefinedName
from openpyxl.worksheet.formula import ArrayFormula

from sheetkin.xlsx.evaluator import evaluate

FORMULAS = {          # row -> formula typed in E..I of that row
    2: "=RADIANS(phi)",               # a named row range (the phi = $E$31:$Q$31)
    3: "=E1:I1*2",                    # a relative row range in an operator
    4: "=SIN($E$1:$I$1)+1",           # an absolute row range in a scalar function
    5: "=SUM($E$1:$I$1)-phi",         # whole in SUM, intersected outside it
    6: "=RADIANS(colr)",              # a named column range B6:B8 from row 6: B6
    7: "=SUMPRODUCT(--($E$1:$I$1>40))",   # an array argument stays whole
    8: "=INDEX(phi,1,2)+colr",        # INDEX takes the range whole; colr from row 8: B8
    9: "=colr",                       # a column range B6:B8 from row 9: outside it, #VALUE!
}


def book(path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "S"
    for c in range(5, 10):
        ws.cell(1, c, (c - 5) * 30)
        for r, f in FORMULAS.items():
            ws.cell(r, c, f)
    for r in range(6, 9):
        ws.cell(r, 2, r * 10.0)
    ws["K1"] = ArrayFormula("K1", "=SUM(E1:I1*2)")       # an array formula: no intersection
    wb.defined_names["phi"] = DefinedName("phi", attr_text="S!$E$1:$I$1")
    wb.defined_names["colr"] = DefinedName("colr", attr_text="S!$B$6:$B$8")
    wb.save(path)
    return path


def test_implicit_intersection_as_libreoffice(tmp_path, soffice):
    src = book(tmp_path / "ii.xlsx")
    lo = read_values(recalculate([src], tmp_path / "lo")[src.resolve()], "S")
    ours = evaluate(src, strict=False)
    checked = 0
    for r in [*FORMULAS, 1]:
        for c in "EFGHIK" if r == 1 else "EFGHI":
            cell = f"{c}{r}"
            mine = ours.value("S", r, ord(c) - 64)
            theirs = lo.get(cell)
            if isinstance(theirs, str) and theirs.startswith("#"):
                assert isinstance(mine, str) and mine.startswith("#"), (cell, mine, theirs)
            elif theirs is not None:
                assert math.isclose(mine, theirs, rel_tol=1e-12, abs_tol=1e-12), (cell, mine, theirs)
            checked += 1
    assert checked >= 40
    assert math.isclose(ours.value("S", 2, 6), math.radians(30))       # F2 = RADIANS(F1)
    assert ours.value("S", 9, 5) == "#VALUE!"


def test_a_whole_column_past_the_used_range_intersects_as_excel(tmp_path):
    """=Z1:Z1048576 in G5 is Z5 (Excel's implicit intersection), though the store holds only
    the used range: found by the formula fuzzer (an internal error before)."""
    import openpyxl
    from openpyxl.utils import column_index_from_string

    from sheetkin.xlsx.evaluator import evaluate
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    ws["A1"], ws["Z5"], ws["Z2"] = 2.0, 7, 1
    cells = {"G5": ("=Z1:Z1048576", 7.0), "G2": ("=Z1:Z1048576*2", 2.0), "H9": ("=Z1:Z3", "#VALUE!"),
             "I5": ("=$Z$1:$Z$1048576+1", 8.0), "J3": ("=A1:Z1", 0.0), "K4": ("=AA1:AA1048576", 0.0)}
    for cell, (f, _) in cells.items():
        ws[cell] = f
    wb.save(tmp_path / "z.xlsx")
    book = evaluate(tmp_path / "z.xlsx", strict=True)
    got = {c: book.value("Calc", int(c[1:]), column_index_from_string(c[0])) for c in cells}
    assert got == {c: want for c, (_, want) in cells.items()}
