"""The workbooks of the real-file tests (test_real_files.py): each feature written in
LibreOffice's flat ODF (lo_*.fods, which LibreOffice converts) and in Excel's own XML
(xl_*.xlsx), with Excel's values of its cells worked out by hand; the generated formulas of
the differential test; the fourbar workbook as a student who used a defined name wrote it.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from pathlib import Path

import openpyxl
from openpyxl.utils import get_column_letter

from helpers import realfiles as rf
from helpers.realfiles import cell

ROOT = Path(__file__).resolve().parents[2]
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
                  **{f"Calc!{c}2": 6.0 * x for c, x in zip("CDEFG", (1, 2, 3, 4, 5), strict=False)}}


def names_excel(d: Path) -> Book:
    cells = [cell("A1", 2), cell("B1", 0, "A1*3"), cell("C1", 0, "dfi+1"), cell("D1", 0, "twice+1"),
             cell("E1", 0, "SUM(rng)"), cell("F1", 0, "late+1"), cell("G1", 0, "k*10"), cell("H1", 0, "onlycalc+1"),
             cell("A2", 5), cell("B2", 0, "B1+1"), cell("B3", 0, "B2+1"), cell("B5", 0, "A1*5"),
             # a row of one shared formula using the name (the cached values are stale)
             cell("C2", 0, "C4*dfi", ' t="shared" ref="C2:G2" si="0"'),
             *[cell(f"{c}2", 0, "", ' t="shared" si="0"') for c in "DEFG"],
             *[cell(f"{c}4", x) for c, x in zip("CDEFG", (1, 2, 3, 4, 5), strict=False)]]
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
        array = f' t="array" ref="F{r}"' if "ABS(A1:A3)" in f else ""
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
    from openpyxl.workbook.defined_name import DefinedName
    from openpyxl.worksheet.formula import ArrayFormula
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


def row_numbers(ws) -> dict[str, int]:
    """Row of every name in column A of a generated sheet (the first of each name): tests
    find rows by name, so new input rows do not break them."""
    out: dict[str, int] = {}
    for r in range(1, ws.max_row + 1):
        v = ws.cell(r, 1).value
        if isinstance(v, str) and v not in out:
            out[v] = r
    return out


def fourbar_with_name(path: Path) -> Path:
    """workbooks/fourbar.xlsx as a student wrote it: row Fi is =RADIANS($D$<Fi0>)+E<i>*dfi
    with dfi a defined name of Delta_Fi_rad (itself a formula); rows found by name."""
    wb = openpyxl.load_workbook(ROOT / "workbooks" / "fourbar.xlsx")
    ws = wb.worksheets[0]
    at = row_numbers(ws)
    row, dfi = at["Fi"], at["Delta_Fi_rad"]
    assert str(ws[f"D{dfi}"].value).startswith("=")
    from openpyxl.workbook.defined_name import DefinedName
    wb.defined_names["dfi"] = DefinedName("dfi", attr_text=f"'{ws.title}'!$D${dfi}")
    for c in range(5, ws.max_column + 1):
        if ws.cell(row, c).value is not None:
            ws.cell(row, c, f"=RADIANS($D${at['Fi0']})+{get_column_letter(c)}{at['i']}*dfi")
    wb.save(path)
    return path
