"""Spreadsheet features that real files use, computed as Excel computes them.

Every feature is tried in the two shapes the evaluator meets: a hand-written LibreOffice
flat ODF file (.fods) that LibreOffice converts to .xlsx (its own XML), and a package in
Excel's own XML shape written here (tests/realfiles.py). Each file's cells are checked
against Excel's values worked out by hand in the test (`EXPECTED`), and every formula cell
against LibreOffice's recalculation (errors compared as "an error"). All the conversions
and recalculations of the module run in ONE soffice call (the `lo` fixture).
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from pathlib import Path

import openpyxl
import pytest
from openpyxl.utils import get_column_letter

import realfiles as rf
from libreoffice import is_error, recalculate
from realfiles import cell
from sheetkin.evaluator import ERRORS, evaluate
from sheetkin.validator import validate

ROOT = Path(__file__).resolve().parent.parent
NA = "#N/A"


@dataclass
class Book:
    """A test workbook: where it is written, and Excel's value of some of its cells."""
    name: str
    shape: str                                   # "lo" (.fods via LibreOffice) or "excel"
    expected: dict = field(default_factory=dict)  # "Sheet!A1" -> Excel's value ("#ERR" for any error)
    source: Path | None = None                   # the file written here
    lo: Path | None = None                       # LibreOffice's conversion or recalculation


# ------------------------------------------------------------------ the books
def names_lo(d: Path) -> Book:
    """Names as dependencies (a formula cell, a name of a name, a range of formula cells,
    a target written after its users), a sheet-scoped name shadowing the workbook's."""
    calc = [
        [rf.num(2), rf.formula("[.A1]*3"), rf.formula("dfi+1"), rf.formula("twice+1"),
         rf.formula("SUM(rng)"), rf.formula("late+1"), rf.formula("k*10"), rf.formula("onlycalc+1")],
        [rf.num(5), rf.formula("[.B1]+1"), *[rf.formula(f"[.{c}4]*dfi") for c in "CDEFG"]],
        [rf.empty(), rf.formula("[.B2]+1")],
        [rf.empty(2), *[rf.num(x) for x in (1, 2, 3, 4, 5)]],
        [rf.empty(), rf.formula("[.A1]*5")],
    ]
    other = [[rf.num(100), rf.formula("k*10"), rf.formula("ISERROR(onlycalc)")]]
    path = rf.fods(d / "lo_names.fods",
                   [rf.table("Calc", calc, [rf.named("k", "$Calc.$A$2"), rf.named("onlycalc", "$Calc.$A$1")]),
                    rf.table("Other", other)],
                   [rf.named("dfi", "$Calc.$B$1"), rf.named_expression("twice", "dfi*2"),
                    rf.named("rng", "$Calc.$B$1:.$B$3"), rf.named("late", "$Calc.$B$5"),
                    rf.named("k", "$Other.$A$1")])
    return Book("lo_names", "lo", NAMES_EXPECTED, path)


NAMES_EXPECTED = {"Calc!B1": 6.0, "Calc!C1": 7.0, "Calc!D1": 13.0, "Calc!E1": 21.0, "Calc!F1": 11.0,
                  "Calc!G1": 50.0, "Calc!H1": 3.0, "Other!B1": 1000.0, "Other!C1": True,
                  **{f"Calc!{c}2": 6.0 * x for c, x in zip("CDEFG", (1, 2, 3, 4, 5))}}


def names_excel(d: Path) -> Book:
    cells = [cell("A1", 2), cell("B1", 0, "A1*3"), cell("C1", 0, "dfi+1"), cell("D1", 0, "twice+1"),
             cell("E1", 0, "SUM(rng)"), cell("F1", 0, "late+1"), cell("G1", 0, "k*10"), cell("H1", 0, "onlycalc+1"),
             cell("A2", 5), cell("B2", 0, "B1+1"), cell("B3", 0, "B2+1"), cell("B5", 0, "A1*5"),
             # a row of one shared formula using the name (the cached values are stale)
             cell("C2", 0, "C4*dfi", ' t="shared" ref="C2:G2" si="0"'),
             *[cell(f"{c}2", 0, "", ' t="shared" si="0"') for c in "DEFG"],
             *[cell(f"{c}4", x) for c, x in zip("CDEFG", (1, 2, 3, 4, 5))]]
    other = [cell("A1", 100), cell("B1", 0, "k*10"), cell("C1", False, "ISERROR(onlycalc)")]
    path = rf.xlsx(d / "xl_names.xlsx", [("Calc", rf.sheet_xml(cells)), ("Other", rf.sheet_xml(other))],
                   [("dfi", "Calc!$B$1", None), ("twice", "dfi*2", None), ("rng", "Calc!$B$1:$B$3", None),
                    ("late", "Calc!$B$5", None), ("k", "Other!$A$1", None), ("k", "Calc!$A$2", 0),
                    ("onlycalc", "Calc!$A$1", 0)])
    return Book("xl_names", "excel", NAMES_EXPECTED, path)


def arrays_lo(d: Path) -> Book:
    """Array formulas: one cell over a range (top-left element), a row, a block, a row
    repeated down, a range larger than the result (#N/A), an aggregate of ABS of a range."""
    calc = [
        [rf.num(2), rf.num(-6), rf.num(7), rf.empty(),
         rf.formula("[.A1:.C1]*2", (1, 3)), rf.empty(2), rf.formula("SUM(ABS([.A1:.C1]))", (1, 1))],
        [rf.num(1), rf.num(3), rf.empty(2), rf.formula("[.A1:.B2]+10", (2, 2)), rf.empty(2),
         rf.formula("[.A1:.C1]*1", (2, 3))],
        [rf.formula("1/0"), rf.num(3), rf.formula('IFERROR([.A3:.B3];"x")', (1, 1)),
         rf.formula('IFERROR([.B3:.C3];"x")', (1, 1)), rf.empty(6), rf.formula("[.A1:.B1]", (1, 3))],
        [rf.formula("[.E1]+[.F1]+[.G1]"), rf.formula("SUM([.E2:.F3])")],
    ]
    path = rf.fods(d / "lo_arrays.fods", [rf.table("Calc", calc)])
    return Book("lo_arrays", "lo", {**ARRAYS_LO_EXPECTED, "Calc!K3": 2.0, "Calc!L3": -6.0, "Calc!M3": "#ERR"},
                path)


ARRAYS_LO_EXPECTED = {
    "Calc!E1": 4.0, "Calc!F1": -12.0, "Calc!G1": 14.0, "Calc!H1": 15.0,
    "Calc!E2": 12.0, "Calc!F2": 4.0, "Calc!E3": 11.0, "Calc!F3": 13.0,
    "Calc!H2": 2.0, "Calc!I2": -6.0, "Calc!J2": 7.0, "Calc!H3": 2.0, "Calc!I3": -6.0, "Calc!J3": 7.0,
    "Calc!C3": "x", "Calc!D3": 3.0, "Calc!A4": 6.0, "Calc!B4": 40.0,
}


def arrays_excel(d: Path) -> Book:
    cells = [
        cell("A1", 2), cell("B1", -6), cell("C1", 7),
        cell("E1", 0, "A1:C1*2", ' t="array" ref="E1:G1"'), cell("F1", 99), cell("G1", 99),
        cell("H1", 0, "SUM(ABS(A1:C1))", ' t="array" ref="H1"'),
        cell("A2", 1), cell("B2", 3),
        cell("E2", 0, "A1:B2+10", ' t="array" ref="E2:F3"'), cell("F2", 0), cell("E3", 0), cell("F3", 0),
        cell("H2", 0, "A1:C1*1", ' t="array" ref="H2:J3"'),
        *[cell(f"{c}{r}", 0) for c in "HIJ" for r in (2, 3) if (c, r) != ("H", 2)],
        cell("A3", "#DIV/0!", "1/0"), cell("B3", 3),
        cell("C3", "x", 'IFERROR(A3:B3,"x")', ' t="array" ref="C3"'),
        cell("D3", 3, 'IFERROR(B3:C3,"x")', ' t="array" ref="D3:D3"'),
        cell("K1", 0, "A1:B1", ' t="array" ref="K1:M1"'), cell("L1", 0), cell("M1", NA),
        cell("A4", 0, "E1+F1+G1"), cell("B4", 0, "SUM(E2:F3)"),
        # Excel 365: dynamic arrays spill; the spilled cells hold stale values (99) in the file
        cell("A6", -1), cell("A7", 0.5), cell("A8", -2.25),
        cell("C6", 99, "ABS(A6:A8)*2", ' t="array" ref="C6:C8"', ' cm="1"'), cell("C7", 99), cell("C8", 99),
        cell("D7", 0, "C7+1"),                      # a formula reading a spilled cell
        cell("E6", 99, 'IF(A6:A8<0,"neg",A6:A8)', ' t="array" ref="E6:E8"', ' cm="1"'),
        cell("E7", 99), cell("E8", 99),
        # E1# (a spill's range) and @ (implicit intersection), as Excel 365 writes them
        cell("F6", 0, "SUM(_xlfn.ANCHORARRAY(C6))"), cell("F7", 0, "_xlfn.SINGLE(A6:A8)*2"),
        cell("G6", 0, "_xlfn.SINGLE(A6:A8)"), cell("F9", 0, "_xlfn.SINGLE(A6:A8)"),
        cell("F10", 0, "SUM(_xlfn.ANCHORARRAY(A6))"), cell("G8", 0, "_xlfn.SINGLE(A8:C8)"),
    ]
    path = rf.xlsx(d / "xl_arrays.xlsx", [("Calc", rf.sheet_xml(cells))], dynamic=True)
    expected = dict(ARRAYS_LO_EXPECTED)
    expected.update({"Calc!K1": 2.0, "Calc!L1": -6.0, "Calc!M1": "#ERR",
                     "Calc!C6": 2.0, "Calc!C7": 1.0, "Calc!C8": 4.5, "Calc!D7": 2.0,
                     "Calc!E6": "neg", "Calc!E7": 0.5, "Calc!E8": "neg",
                     "Calc!F6": 7.5, "Calc!F7": 1.0, "Calc!G6": -1.0, "Calc!F9": "#ERR", "Calc!F10": "#ERR",
                     "Calc!G8": "#ERR"})
    return Book("xl_arrays", "excel", expected, path)


def shared_excel(d: Path) -> Book:
    """Shared formulas whose master is not the block's top-left cell (Excel writes
    ref="Y142:AR153" with the master elsewhere): every child is the master's formula moved
    by its offset from the master; one moved off the sheet is #REF!."""
    cells = [cell(f"{get_column_letter(c)}{r}", 10 * r + c) for r in range(1, 6) for c in (1, 2)]
    # master D3 = B3*10+$A$1 in the block C2:F5 (neither its first row nor its first column)
    block = [(r, c) for r in range(2, 6) for c in range(3, 7)]
    for r, c in block:
        ref = f"{get_column_letter(c)}{r}"
        if (r, c) == (3, 4):
            cells.append(cell(ref, 0, "B3*10+$A$1", ' t="shared" ref="C2:F5" si="0"'))
        else:
            cells.append(cell(ref, 0, "", ' t="shared" si="0"'))
    # a block whose children lie up and left of the master: G1, H1 reach row 0 (#REF!)
    cells.append(cell("H2", 0, "G1+1", ' t="shared" ref="G1:H2" si="1"'))
    cells += [cell("G1", 0, "", ' t="shared" si="1"'), cell("H1", 0, "", ' t="shared" si="1"'),
              cell("G2", 0, "", ' t="shared" si="1"')]
    path = rf.xlsx(d / "xl_shared.xlsx", [("Calc", rf.sheet_xml(cells))])
    value = {(r, c): 10.0 * r + c for r in range(1, 6) for c in (1, 2)}
    for c in range(3, 7):                 # each cell is the one two columns left, *10 + A1
        for r in range(2, 6):
            value[(r, c)] = value[(r, c - 2)] * 10 + 11
    expected = {f"Calc!{get_column_letter(c)}{r}": value[(r, c)] for r, c in block}
    expected.update({"Calc!G1": "#ERR", "Calc!H1": "#ERR", "Calc!H2": "#ERR", "Calc!G2": 1.0})
    return Book("xl_shared", "excel", expected, path)


FUNCTIONS = [  # (Excel formula, ODF formula, Excel's value); A1:A3 = 3, -4, 12; B1:D1 = 1, 2, 3
    ("ATAN(1)", "ATAN(1)", math.pi / 4),
    ("INDEX(B1:D1,3)", "INDEX([.B1:.D1];3)", 3.0),
    ("INDEX(A1:A3,2)", "INDEX([.A1:.A3];2)", -4.0),
    ("INDEX(A1:D3,3,1)", "INDEX([.A1:.D3];3;1)", 12.0),
    ("INDEX(A1:D3,1,4)", "INDEX([.A1:.D3];1;4)", 3.0),
    ("SUM(INDEX(A1:D1,0,2))", "SUM(INDEX([.A1:.D1];0;2))", 1.0),
    ("INDEX(B1:D1,5)", "INDEX([.B1:.D1];5)", "#ERR"),
    ("CHOOSE(2,A1,A2,A3)", "CHOOSE(2;[.A1];[.A2];[.A3])", -4.0),
    ("CHOOSE(3.9,A1,A2,A3)", "CHOOSE(3.9;[.A1];[.A2];[.A3])", 12.0),
    ("CHOOSE(4,A1,A2,A3)", "CHOOSE(4;[.A1];[.A2];[.A3])", "#ERR"),
    ("INT(-2.5)", "INT(-2.5)", -3.0),
    ("INT(A1/2)", "INT([.A1]/2)", 1.0),
    ("TRUNC(-2.567,2)", "TRUNC(-2.567;2)", -2.56),
    ("TRUNC(-2.567)", "TRUNC(-2.567)", -2.0),
    ("TRUNC(1234.5,-2)", "TRUNC(1234.5;-2)", 1200.0),
    ("FLOOR(-2.5,2)", "COM.MICROSOFT.FLOOR(-2.5;2)", -4.0),
    ("FLOOR(-2.5,-2)", "COM.MICROSOFT.FLOOR(-2.5;-2)", -2.0),
    ("FLOOR(2.5,-2)", "COM.MICROSOFT.FLOOR(2.5;-2)", "#ERR"),
    ("FLOOR(5,0)", "COM.MICROSOFT.FLOOR(5;0)", "#ERR"),
    ("FLOOR(0.3,0.1)", "COM.MICROSOFT.FLOOR(0.3;0.1)", 0.3),
    ("FLOOR(A3,5)", "COM.MICROSOFT.FLOOR([.A3];5)", 10.0),
    ("CEILING(-2.5,2)", "COM.MICROSOFT.CEILING(-2.5;2)", -2.0),
    ("CEILING(-2.5,-2)", "COM.MICROSOFT.CEILING(-2.5;-2)", -4.0),
    ("CEILING(2.5,-2)", "COM.MICROSOFT.CEILING(2.5;-2)", "#ERR"),
    ("CEILING(2.5,0)", "COM.MICROSOFT.CEILING(2.5;0)", 0.0),
    ("CEILING(A3,5)", "COM.MICROSOFT.CEILING([.A3];5)", 15.0),
    ("SUMSQ(A1:A3)", "SUMSQ([.A1:.A3])", 169.0),
    ("SUMSQ(A1,2,A2:A3)", "SUMSQ([.A1];2;[.A2:.A3])", 173.0),
    ("PRODUCT(A1:A3)", "PRODUCT([.A1:.A3])", -144.0),
    ("PRODUCT(A1:A3,0.5)", "PRODUCT([.A1:.A3];0.5)", -72.0),
    ("PRODUCT(E20:E22)", "PRODUCT([.E20:.E22])", 0.0),
    ("SUM(ABS(A1:A3))", None, 19.0),            # an array formula (written as one below)
    ("TRUE()", "TRUE()", True),
    ("FALSE()", "FALSE()", False),
    ("TRUE()+1", "TRUE()+1", 2.0),
    ("AND(TRUE(),A1>0)", "AND(TRUE();[.A1]>0)", True),
    ("IF(FALSE(),1,2)", "IF(FALSE();1;2)", 2.0),
    ("NOT(TRUE)", "NOT(TRUE())", False),
    # LibreOffice writes its own FLOOR(x; s[; mode]) and CEILING to .xlsx as FLOOR.MATH and
    # CEILING.MATH (the sign of s ignored; mode: a negative x toward / away from zero)
    ("_xlfn.FLOOR.MATH(7.3,2)", "FLOOR(7.3;2)", 6.0),
    ("_xlfn.FLOOR.MATH(-7.3,-2)", "FLOOR(-7.3;-2)", -8.0),
    ("_xlfn.FLOOR.MATH(-7.3,2,1)", "FLOOR(-7.3;2;1)", -6.0),
    ("_xlfn.CEILING.MATH(7.3,2)", "CEILING(7.3;2)", 8.0),
    ("_xlfn.CEILING.MATH(-7.3,-2)", "CEILING(-7.3;-2)", -6.0),
    ("_xlfn.CEILING.MATH(-7.3,2,1)", "CEILING(-7.3;2;1)", -8.0),
    ("_xlfn.FLOOR.MATH(A3)", "", 12.0),
    ("_xlfn.FLOOR.PRECISE(-7.3,2)", "", -8.0),
    ("_xlfn.CEILING.PRECISE(-7.3,-2)", "", -6.0),
    ("ISO.CEILING(-7.3,2)", "", -6.0),
]


def functions_lo(d: Path) -> Book:
    rows = [[rf.num(3), rf.num(1), rf.num(2), rf.num(3)], [rf.num(-4)], [rf.num(12)], [rf.empty()]]
    expected = {}
    for i, (_, odf, value) in enumerate(FUNCTIONS):
        r = 5 + i
        if odf is None:
            rows.append([rf.empty(5), rf.formula("SUM(ABS([.A1:.A3]))", (1, 1))])
        elif odf == "":                            # Excel's shape only
            rows.append([rf.empty()])
            continue
        else:
            rows.append([rf.empty(5), rf.formula(odf)])
        expected[f"Calc!F{r}"] = value
    path = rf.fods(d / "lo_functions.fods", [rf.table("Calc", rows)])
    return Book("lo_functions", "lo", expected, path)


def functions_excel(d: Path) -> Book:
    cells = [cell("A1", 3), cell("B1", 1), cell("C1", 2), cell("D1", 3), cell("A2", -4), cell("A3", 12)]
    expected = {}
    for i, (f, _, value) in enumerate(FUNCTIONS):
        r = 5 + i
        array = ' t="array" ref="F{0}"'.format(r) if "ABS(A1:A3)" in f else ""
        cells.append(cell(f"F{r}", 0, f, array))
        expected[f"Calc!F{r}"] = value
    path = rf.xlsx(d / "xl_functions.xlsx", [("Calc", rf.sheet_xml(cells))])
    return Book("xl_functions", "excel", expected, path)


WHOLE = [  # (Excel formula, ODF formula, value): A1:A3 = 1, 2, "t"; B1:B3 = 10, 20, 30; C2 = 5
    ("SUM(A:A)", "SUM([.A:.A])", 3.0),
    ("SUM($A:$C)", "SUM([.$A:.$C])", 68.0),
    ("SUM(2:2)", "SUM([.2:.2])", 27.0),
    ("COUNT(B:B)", "COUNT([.B:.B])", 3.0),
    ("MAX(Data!A:A)", "MAX([$Data.A:.A])", 40.0),
    ("SUMPRODUCT(A:A,B:B)", "SUMPRODUCT([.A:.A];[.B:.B])", 50.0),
    ("SUM(A:B)-SUM(A1:B3)", "SUM([.A:.B])-SUM([.A1:.B3])", 0.0),
]


def whole_lo(d: Path) -> Book:
    rows = [[rf.num(1), rf.num(10)], [rf.num(2), rf.num(20), rf.num(5)], [rf.text("t"), rf.num(30)]]
    expected = {}
    for i, (_, odf, value) in enumerate(WHOLE):
        rows.append([rf.empty(4), rf.formula(odf)])
        expected[f"Calc!E{4 + i}"] = value
    data = [[rf.num(40)], [rf.num(-1)]]
    path = rf.fods(d / "lo_whole.fods", [rf.table("Calc", rows), rf.table("Data", data)])
    return Book("lo_whole", "lo", expected, path)


def whole_excel(d: Path) -> Book:
    cells = [cell("A1", 1), cell("B1", 10), cell("A2", 2), cell("B2", 20), cell("C2", 5), cell("A3", "t"),
             cell("B3", 30)]
    expected = {}
    for i, (f, _, value) in enumerate(WHOLE):
        cells.append(cell(f"E{4 + i}", 0, f))
        expected[f"Calc!E{4 + i}"] = value
    # a row of one formula with relative whole columns: SUM(A:A), SUM(B:B), SUM(C:C)
    cells.append(cell("G1", 0, "SUM(A:A)", ' t="shared" ref="G1:I1" si="0"'))
    cells += [cell("H1", 0, "", ' t="shared" si="0"'), cell("I1", 0, "", ' t="shared" si="0"')]
    expected.update({"Calc!G1": 3.0, "Calc!H1": 60.0, "Calc!I1": 5.0})
    path = rf.xlsx(d / "xl_whole.xlsx", [("Calc", rf.sheet_xml(cells)),
                                         ("Data", rf.sheet_xml([cell("A1", 40), cell("A2", -1)]))])
    return Book("xl_whole", "excel", expected, path)


def styled_lo(d: Path) -> Book:
    """Whole columns and every row down to 1,048,576 styled (a sheet formatted by
    selecting columns): the file is accepted; the used range is what holds something."""
    rows = [[rf.num(1), rf.num(2), rf.formula("[.A1]+[.B1]")], [rf.formula("SUM([.B:.B])+[.C1]")]]
    path = rf.fods(d / "lo_styled.fods", [rf.table("Calc", rows, styled=True)])
    return Book("lo_styled", "lo", {"Calc!C1": 3.0, "Calc!A2": 5.0}, path)


def styled_excel(d: Path) -> Book:
    cols = '<cols><col min="1" max="16384" width="9" style="1" customWidth="1"/></cols>'
    cells = [cell("A1", 1), cell("B1", 2), cell("C1", 3, "A1+B1"), cell("A2", 4, "SUM(B:B)+C1"),
             '<c r="XFD2" s="1"/>', '<c r="A1048576" s="1"/>', '<c r="D5" s="1"><v></v></c>']
    rows = {r: ' s="1" customFormat="1"' for r in (5, 6, 7, 1048575, 1048576)}
    xml = rf.sheet_xml(cells, dimension="A1:XFD1048576", cols=cols, rows=rows)
    path = rf.xlsx(d / "xl_styled.xlsx", [("Calc", xml)])
    return Book("xl_styled", "excel", {"Calc!C1": 3.0, "Calc!A2": 5.0}, path)


BUILDERS = [names_lo, names_excel, arrays_lo, arrays_excel, shared_excel, functions_lo, functions_excel,
            whole_lo, whole_excel, styled_lo, styled_excel]


# ------------------------------------------------------------------ the differential book
def generated_formulas(seed: int = 11, count: int = 240) -> list[str]:
    """Random formulas over the differential book's inputs (Calc!A1:E5, Data!A1:A5),
    using the features: names (global, local, names of formula cells), the functions,
    whole columns and rows. Arguments are cells, names or small expressions."""
    rnd = random.Random(seed)
    cells = [f"{c}{r}" for c in "ABCDE" for r in range(1, 6)]

    def x():
        pick = rnd.random()
        if pick < 0.45:
            return rnd.choice(cells)
        if pick < 0.65:
            return rnd.choice(["gk", "lk", "gf", "gg", "gk*lk", "gf-1"])
        if pick < 0.8:
            return repr(rnd.choice([-3.5, -2, -0.25, 0, 0.5, 1, 2.75, 7]))
        return f"({rnd.choice(cells)}{rnd.choice('+-*')}{rnd.choice(cells)})"

    def rng():
        return rnd.choice(["A1:A5", "B1:E1", "A1:E5", "C2:D4", "A:A", "2:2", "$B:$C", "grng", "Data!A:A", "Data!A1:A5"])

    makers = [
        lambda: f"INT({x()})", lambda: f"TRUNC({x()},{rnd.choice([0, 1, 2, -1])})", lambda: f"TRUNC({x()})",
        lambda: f"ATAN({x()})", lambda: f"ABS({x()})",
        lambda: f"FLOOR({x()},{rnd.choice(['0.5', '2', '-2', '1', '0.1', x()])})",
        lambda: f"CEILING({x()},{rnd.choice(['0.5', '2', '-2', '1', '0.1', x()])})",
        lambda: f"INDEX({rnd.choice(['A1:E1', 'B1:B5', 'A1:E5', 'grng'])},{rnd.randint(1, 5)},{rnd.randint(1, 5)})",
        lambda: f"INDEX({rnd.choice(['A1:E1', 'B1:B5'])},{rnd.randint(0, 6)})",
        lambda: f"CHOOSE({rnd.choice(['1', '2', '3', '2.5', x()])},{x()},{x()},{x()})",
        lambda: f"SUMSQ({rng()})", lambda: f"PRODUCT({rng()})", lambda: f"SUM({rng()})",
        lambda: f"COUNT({rng()})", lambda: f"MAX({rng()})", lambda: f"SUMSQ({x()},{rng()})",
        lambda: f"IF({x()}>{x()},TRUE(),FALSE())", lambda: f"AND(TRUE(),{x()}<{x()})",
        lambda: f"{x()}*gf+lk", lambda: f"SUM(ABS({rnd.choice(['A1:A5', 'B2:D2'])}))",
        lambda: f"_xlfn.FLOOR.MATH({x()},{rnd.choice(['0.5', '2', '-2', x()])},{rnd.choice([0, 1])})",
        lambda: f"_xlfn.CEILING.MATH({x()},{rnd.choice(['0.5', '2', '-2', x()])},{rnd.choice([0, 1])})",
    ]
    return [rnd.choice(makers)() for _ in range(count)]


def differential_book(d: Path) -> tuple[Path, list[tuple[str, int, int]]]:
    """The generated formulas in Calc!G1..; inputs, names (gk, gg workbook-wide; lk local
    to Calc and shadowing a workbook lk; gf naming a formula cell; grng a range holding a
    formula cell). Formulas with ABS of a range are array formulas, as Excel needs them."""
    from openpyxl.worksheet.formula import ArrayFormula
    from openpyxl.workbook.defined_name import DefinedName
    rnd = random.Random(5)
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    for r in range(1, 6):
        for c in range(1, 6):
            ws.cell(r, c, rnd.choice([-7.5, -3, -1, -0.5, 0, 0.25, 1, 2, 3.5, 10, 12.125]))
    ws["E5"] = "=A1*2+B2"                   # a formula cell inside grng, and named by gf
    ws["C3"] = "text"               # (no booleans in ranges: LibreOffice counts them, Excel does not)
    data = wb.create_sheet("Data")
    for r, v in enumerate([4, -2, 9, 0.5, 1], 1):
        data.cell(r, 1, v)
    for name, target in (("gk", "Calc!$A$1"), ("gg", "Data!$A$3"), ("gf", "Calc!$E$5"),
                         ("grng", "Calc!$A$5:$E$5"), ("lk", "Data!$A$1")):
        wb.defined_names[name] = DefinedName(name, attr_text=target)
    ws.defined_names["lk"] = DefinedName("lk", attr_text="Calc!$B$2")      # shadows the global lk
    cells = []
    for i, f in enumerate(generated_formulas()):
        r = 1 + i
        ref = f"G{r}"
        ws[ref] = ArrayFormula(ref, "=" + f) if "ABS(" in f and ":" in f else "=" + f
        cells.append(("Calc", r, 7))
    path = d / "xl_differential.xlsx"
    wb.save(path)
    return path, cells


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


def _split(key: str) -> tuple[str, int, int]:
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
    bad = [f"{k}: ours {book.value(*_split(k))!r}, Excel {v!r}" for k, v in b.expected.items()
           if not agrees(book.value(*_split(k)), v)]
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


def fourbar_with_name(path: Path) -> Path:
    """workbooks/fourbar.xlsx as a student wrote it: row Fi is =RADIANS($D$18)+E28*dfi with
    dfi a defined name of Delta_Fi_rad (D22, itself a formula)."""
    wb = openpyxl.load_workbook(ROOT / "workbooks" / "fourbar.xlsx")
    ws = wb.worksheets[0]
    row = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "Fi")
    assert ws.cell(22, 1).value == "Delta_Fi_rad" and str(ws["D22"].value).startswith("=")
    from openpyxl.workbook.defined_name import DefinedName
    wb.defined_names["dfi"] = DefinedName("dfi", attr_text=f"'{ws.title}'!$D$22")
    for c in range(5, ws.max_column + 1):
        if ws.cell(row, c).value is not None:
            ws.cell(row, c, f"=RADIANS($D$18)+{get_column_letter(c)}28*dfi")
    wb.save(path)
    return path


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
    from sheetkin.cli import main
    assert main(["evaluate", str(ods), "--format", "csv"]) == 0
    for key, v in b.expected.items():
        assert agrees(ours.value(*_split(key)), v), key
        assert agrees(ours.value(*_split(key)), ref.value(*_split(key))), key


def test_validate_accepts_an_ods_submission(lo, tmp_path):
    """The fourbar workbook saved as .ods (LibreOffice's default on Save) is validated."""
    from sheetkin.libreoffice import _convert
    src, _ = lo["fourbar"]
    ods = _convert([src], tmp_path, "ods", "ods", 120)[src.resolve()]
    report = validate(ods)
    assert report.error is None, report.error
    assert report.rows and all(r.status == "correct" for r in report.rows)


def test_ods_without_libreoffice_is_refused_with_the_command(tmp_path, monkeypatch, capsys):
    from sheetkin import libreoffice
    from sheetkin.cli import main
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
    from sheetkin import xlsxread
    src = lo["books"][key].source
    fast = xlsxread.read_book(src)
    monkeypatch.setattr(xlsxread, "_read_fast", lambda *a: None)
    tree = xlsxread.read_book(src)
    for name, sh in fast.sheets.items():
        other = tree.sheets[name]
        for attr in ("consts", "formulas", "cached", "arrays", "names", "max_row", "max_col"):
            assert getattr(sh, attr) == getattr(other, attr), (name, attr)


def test_readme_value_example_holds():
    """The README's `book.value(...)` lines give what their comments say."""
    import ast
    import re
    text = (ROOT / "README.md").read_text("utf-8")
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
    """A student who fills row Fi with ONE array formula over E30:Q30 (its other cells hold
    no formula in the file) is graded correct, and the row counts as formulas, not typed."""
    from openpyxl.worksheet.formula import ArrayFormula
    wb = openpyxl.load_workbook(ROOT / "workbooks" / "fourbar.xlsx")
    ws = wb.worksheets[0]
    row = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "Fi")
    last = max(c for c in range(5, ws.max_column + 1) if ws.cell(row, c).value is not None)
    span = f"E{row}:{get_column_letter(last)}{row}"
    for c in range(5, last + 1):
        ws.cell(row, c).value = None
    ws[f"E{row}"] = ArrayFormula(span, f"=RADIANS($D$18)+E28:{get_column_letter(last)}28*$D$22")
    wb.save(tmp_path / "array_row.xlsx")
    report = validate(tmp_path / "array_row.xlsx")
    assert report.error is None, report.error
    assert all(r.status == "correct" for r in report.rows), [r.name for r in report.rows if r.status != "correct"]
    fi = next(r for r in report.rows if r.name == "Fi")
    assert fi.source == "formula"


def test_an_array_range_past_the_limits_is_refused(tmp_path):
    """An array formula's range holds computed cells: past the row limit it is one line,
    not a store of a million rows."""
    from sheetkin.xlsxread import read_book
    from sheetkin.xlsxsafe import UnusableWorkbook
    xml = rf.sheet_xml([cell("A1", 1), cell("B1", 0, "A1*2", ' t="array" ref="B1:B1048576"')])
    path = rf.xlsx(tmp_path / "big_array.xlsx", [("Calc", xml)])
    with pytest.raises(UnusableWorkbook) as info:
        read_book(path)
    msg = str(info.value)
    assert msg.startswith(str(path)) and "B1:B1048576" in msg and "at most 100000 rows" in msg
