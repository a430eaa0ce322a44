"""reaching(): which formula cells depend, through formulas, on given cells (sheetkin.xlsx.precedents):
on every sheet, through ranges, defined names (a row range read by implicit intersection),
whole columns, array formulas and positional functions; constants and typed numbers reach nothing."""
from __future__ import annotations

import openpyxl
from openpyxl.utils.cell import column_index_from_string, coordinate_from_string
from openpyxl.workbook.defined_name import DefinedName
from openpyxl.worksheet.formula import ArrayFormula

from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.precedents import reaching

# cell -> (formula, reaches the given cell S!D1?)
CELLS = {
    "E2": ("=D1*2", True),                  # direct
    "F2": ("=E2+1", True),                  # through a formula
    "G2": ("=P!A1", False),                 # a number typed on another sheet
    "H2": ("=P!B1", True),                  # another sheet's formula that reads D1
    "I2": ("=SUM(C1:D1)", True),            # a range holding the given cell
    "J2": ("=SUM(A5:B9)", False),           # a range of typed numbers only
    "G4": ("=RADIANS(phi)", True),          # a named row range: implicit intersection of E1:I1
    "L2": ("=PI()*180", False),             # constants and a function of none
    "M2": ("=0.1234", False),
    "N2": ("=COLUMN()-5", True),            # depends on its place: the position, not a paste
    "O2": ("=SUM(D:D)", True),              # a whole column
    "E3": ("=G2*D1*0", True),               # reads D1 (only to multiply it by 0: still reaches)
    "F3": ("=G2+L2", False),                # formulas over typed numbers only
    "G3": ("=alias", True),                 # a name of a name
}


def _book(path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "S"
    ws["D1"] = 0.5
    for c in range(5, 10):
        ws.cell(1, c, (c - 5) * 30.0)         # E1:I1, given too (the positions)
    for r in range(5, 10):
        ws.cell(r, 1, r * 1.5)
        ws.cell(r, 2, r * 2.5)
    for cell, (f, _) in CELLS.items():
        ws[cell] = f
    ws["H3"] = ArrayFormula("H3:I3", "=D1*E1:F1")          # an array formula fills its range
    ws["J3"] = "=INDEX({0.5236,0},1)"                     # cannot be read: cannot be traced
    ws["K3"] = '=INDIRECT("S!D1")'                        # names no cell: nothing to trace
    ws["L3"] = "=OFFSET(A5,0,0)"                          # unknown to sheetkin: traced through A5 (typed)
    ws["M3"] = "=NOSUCHFUNCTION(D1)"                      # unknown, traced through D1 (given)
    p = wb.create_sheet("P")
    p["A1"] = 3.25
    p["B1"] = "=S!D1+1"
    wb.defined_names["phi"] = DefinedName("phi", attr_text="S!$E$1:$I$1")
    wb.defined_names["given"] = DefinedName("given", attr_text="S!$D$1")
    wb.defined_names["alias"] = DefinedName("alias", attr_text="given*2")
    wb.save(path)


def test_reaching_follows_formulas_ranges_names_and_sheets(tmp_path):
    path = tmp_path / "b.xlsx"
    _book(path)
    book = evaluate(path, strict=False)
    sources = [(1, 4)] + [(1, c) for c in range(5, 10)]
    reach = reaching(book, {"S": sources})
    for cell, (f, expected) in CELLS.items():
        letters, row = coordinate_from_string(cell)
        assert bool(reach["S"][row, column_index_from_string(letters)]) is expected, (cell, f)
    assert reach["S"][3, 8] and reach["S"][3, 9]            # H3:I3, the array's range
    assert not reach["S"][3, 10] and not reach["S"][3, 11]   # J3, K3: their values cannot be traced
    assert not reach["S"][3, 12] and reach["S"][3, 13]       # L3 reads a typed number, M3 the given D1
    assert reach["P"][1, 2] and not reach["P"][1, 1]         # P!B1 reads D1; P!A1 is typed
    assert not reach["S"][5, 1]                              # a typed number is no source


def test_no_sources_nothing_reaches(tmp_path):
    path = tmp_path / "b.xlsx"
    _book(path)
    reach = reaching(evaluate(path, strict=False), {})
    computed = {"N2"}                                         # COLUMN(): its own place
    for cell in CELLS:
        letters, row = coordinate_from_string(cell)
        assert bool(reach["S"][row, column_index_from_string(letters)]) is (cell in computed), cell
