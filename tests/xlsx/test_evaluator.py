"""sheetkin.xlsx.evaluator against LibreOffice, cell by cell; its messages; its vectorization.

Differential part: small workbooks of formula *cases* are written here with openpyxl. A row
case puts inputs a, b, c in B:F, G:K, L:P of its row and the same formula, copied with its
relative references shifted, in R:V (five cells, so one vectorized run); a single case has
one formula in R; a raw case is a sheet of its own (chains, cycles of runs, other sheets).
Every case book, every bundled workbook (workbooks/*.xlsx) and a 360-column shaper are
recalculated in ONE soffice call; every formula cell is then compared with ours: numbers to
1e-12 (relative, absolute below 1), errors as "an error" (LibreOffice's codes are not always
Excel's), text and booleans exactly.

Where LibreOffice 7.4 and Excel disagree and the evaluator follows Excel, the case says so
(`excel=`: those cells are compared with Excel's value, error codes exactly). A case the
evaluator gets wrong is marked `bug=` (strict xfail: fixing the evaluator turns it into a
failure that asks for the mark to go).
"""
from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import openpyxl
import pytest
from helpers.libreoffice import is_error, recalculate
from openpyxl.utils import get_column_letter
from openpyxl.workbook.defined_name import DefinedName

from sheetkin.xlsx.evaluator import EvaluationError, evaluate
from sheetkin.xlsx.functions import ERRORS, XlError

ROOT = Path(__file__).resolve().parents[2]
BUNDLED = sorted((ROOT / "workbooks").glob("*.xlsx"))

# columns of the inputs a, b, c and of the formulas (R:V); five cells each
COL = {"a": 2, "b": 7, "c": 12, "f": 18}
WIDTH = 5
FIRST_ROW = 6
PARAMS = [1, -2, 0, 0.5, 3]        # R2:V2, for row-absolute references {F}$2
ABS_PARAM = 2.5                    # $A$2
CASE_SHEET = "Cases"

T, F = True, False

# Evaluator bugs these cases show (strict xfail)



@dataclass
class Case:
    name: str
    formula: str | None = None       # template (see _render), None for a raw case
    a: list | None = None
    b: list | None = None
    c: list | None = None
    single: bool = False             # one formula cell (R) instead of five (R:V)
    raw: dict | None = None          # raw case: {"A1" or "Sheet!A1": value}
    excel: dict | None = None        # {column index: Excel's value} where LibreOffice differs
    bug: str | None = None           # the evaluator is wrong here: strict xfail with this reason
    split: bool = False              # a row case that refers to its own cells (a run of cells)
    book: str = ""                   # set by _register


BOOKS: dict[str, list[Case]] = {}


def _register(book: str, cases: list[Case]):
    for c in cases:
        c.book = book
    BOOKS[book] = cases


def row(name, formula, a=None, b=None, c=None, **kw) -> Case:
    return Case(name, formula, a, b, c, **kw)


def one(name, formula, a=None, b=None, c=None, **kw) -> Case:
    return Case(name, formula, a, b, c, single=True, **kw)


def raw(name, cells, **kw) -> Case:
    return Case(name, raw=cells, **kw)


_PLACEHOLDER = re.compile(r"\{([abcfABCF])([+-]\d+)?\}|\{r\}|\{rp\}|\{fp\}")


def _render(template: str, r: int, j: int) -> str:
    """The formula of column j of case row r: {a} {b} {c} {f} -> that column's input cell
    (same row), {a+1} one column further; {A} {B} {C} {F} -> the column letter alone;
    {r} -> the row, {rp} the previous row; {fp} -> the formula cell of the previous row,
    same column."""
    def sub(m):
        if m.group(0) == "{r}":
            return str(r)
        if m.group(0) == "{rp}":
            return str(r - 1)
        if m.group(0) == "{fp}":
            return f"{get_column_letter(COL['f'] + j)}{r - 1}"
        key, off = m.group(1), int(m.group(2) or 0)
        letter = get_column_letter(COL[key.lower()] + j + off)
        return letter if key.isupper() else f"{letter}{r}"
    return _PLACEHOLDER.sub(sub, template)


# --------------------------------------------------------------------------- the cases
_register("funcs", [
    row("sin", "=SIN({a})", [0, 1, -2.5, 1e6, "x"]),
    row("sin_coerced", "=SIN({a})", [None, T, "0.5", F, "#N/A"]),
    row("cos", "=COS({a})", [0, math.pi, -1, 100, None]),
    row("tan", "=TAN({a})", [0, 1, -1.2, "=PI()/2", "=PI()/4"]),
    row("asin", "=ASIN({a})", [0.5, -1, 1, 2, -1.0000001]),
    row("acos", "=ACOS({a})", [0.5, -1, 1, -2, 1.5]),
    row("atan", "=ATAN({a})", [0, 1, -1e300, 1e300, "1"]),
    row("atan2", "=ATAN2({a},{b})", [1, 0, -1, 0, -1], [0, 1, 0, -1, -1]),
    row("atan2_more", "=ATAN2({a},{b})", [1, -2, 1e-300, "x", 3], [2, 1e-300, 0, 1, "#NUM!"]),
    # LibreOffice: ATAN2(0,0) = 0 (and ATAN2(-0,0) = pi); Excel: #DIV/0! (the evaluator follows Excel)
    row("atan2_origin", "=ATAN2({a},{b})", [0, 0, 1, None, -0.0], [0, 1, 0, None, 0],
        excel={0: "#DIV/0!", 3: "#DIV/0!", 4: "#DIV/0!"}),
    one("atan2_origin_literal", "=ATAN2(0,0)", excel={0: "#DIV/0!"}),
    row("sqrt", "=SQRT({a})", [4, 2, 0, -1, "9"]),
    one("pi", "=PI()"),
    one("pi_expr", "=2*PI()-PI()/3"),
    row("radians", "=RADIANS({a})", [180, -30, 0, 1e308, "x"]),
    row("degrees", "=DEGREES({a})", [math.pi, -1, 0, 1e308, T]),
    row("abs", "=ABS({a})", [-3, 3, 0, "-2", None]),
    row("sign", "=SIGN({a})", [-3, 2.5, 0, "=-0", T]),
    row("power", "=POWER({a},{b})", [2, -2, 0, 0, 1.5], [10, 3, 2, -1, -2]),
    row("power_more", "=POWER({a},{b})", [2, -2, 10, 0.5, -2], [0.5, -2, 400, -2000, 0.5]),
    row("power_zero", "=POWER({a},{b})", [0, 0, 5, -5, 0], [3, 1, 0, 0, 0.5]),
    # a negative number to a fractional power: LibreOffice takes the odd root (-2), Excel #NUM!
    row("power_negative_root", "=POWER({a},{b})", [-8, -8, 8, -27, -1], ["=1/3", 3, "=1/3", "=1/3", 0.5],
        excel={0: "#NUM!", 3: "#NUM!"}),
    one("power_zero_zero", "=POWER(0,0)", excel={0: "#NUM!"}),
    row("caret", "={a}^{b}", [2, -2, 0, 0, 1.5], [10, 3, 2, -1, -2]),
    row("caret_zero", "={a}^{b}", [0, 0, 5, -5, 0], [3, 1, 0, 0, 0.5]),
    row("caret_negative_root", "={a}^{b}", [-8, -8, 8, -27, -1], ["=1/3", 3, "=1/3", "=1/3", 0.5],
        excel={0: "#NUM!", 3: "#NUM!"}),
    one("caret_zero_zero", "=0^0", excel={0: "#NUM!"}),
    row("trig_limit", "=SIN({a})", [134217727, 134217728, 1e9, 1e20, -1e20],
        excel={1: "#NUM!", 2: "#NUM!", 3: "#NUM!", 4: "#NUM!"}),
    row("trig_limit_cos_tan", "=COS({a})+TAN({a})", [134217727, 134217728, 1e9, 1e20, -1e20],
        excel={1: "#NUM!", 2: "#NUM!", 3: "#NUM!", 4: "#NUM!"}),
    row("exp", "=EXP({a})", [0, 1, -1000, 709, 710]),
    row("ln", "=LN({a})", [1, "=EXP(1)", 0, -1, 1e-300]),
    row("log10", "=LOG10({a})", [1000, 1e-5, 0, -1, "x"]),
    row("mod", "=MOD({a},{b})", [-7, 7, -7, 5, 5.5], [3, -3, -3, 0, 2]),
    row("mod_more", "=MOD({a},{b})", [0, -30.5, 390, 1e6, -0.5], [5, 360, 360, 7, 1]),
    row("mod_angle", "=MOD(DEGREES(ATAN2({a},{b})),360)", [1, -1, -1, 0, 1], [1, 1, -1, -1, -1e-9]),
    row("round", "=ROUND({a},{b})", [2.5, -2.5, 0.125, 1234.5678, -1234.5], [0, 0, 2, -2, -1]),
    row("round_more", "=ROUND({a},{b})", [1.45, 0.5, -0.5, 2.5, 123.456], [1, 0, 0, 0.7, 1.9]),
    row("round_exact_halves", "=ROUND({a},{b})", [0.375, -0.625, 2.675, 8.345, 1e15 + 0.5], [2, 2, 2, 2, 0]),
    row("round_decimal", "=ROUND({a},2)", [1.005, 0.285, 1.015, 4.005, 1.245]),
    one("round_many_digits", "=ROUND(2.5,400)"),
])

_register("crash_round_missing", [
    row("round_missing_argument", "=ROUND({a},)", [2.5, -0.5, 1.4, 0, 99.5]),
])

_CMP_A = [[1, "A", T, None, None], [None, "abc", "10", 2, F], [None, None, F, -1, "#N/A"]]
_CMP_B = [["a", "a", 1, 0, ""], ["a", "ABD", "9", 2, T], [F, -1, 0, None, 1]]
# LibreOffice has no boolean type (TRUE is 1): TRUE=1 and FALSE=0 are TRUE there. In Excel a
# boolean is greater than any number, so TRUE vs 1 and FALSE vs 0 are unequal, the boolean greater.
_CMP_EXCEL = {"=": F, "<>": T, "<": F, ">": T, "<=": F, ">=": T}
_register("ops", [
    one("neg_pow", "=-2^2"),
    one("pow_pow", "=2^3^2"),
    one("precedence", "=1+2*3^2"),
    one("parens", "=((1+2))*3^2"),
    one("sub_chain", "=10-4-3"),
    one("div_chain", "=100/10/5"),
    one("spaces", "= 1 + 2 * 3 "),
    one("literals", "=.5+1E3-2.5E-1+10E2+0E0+1.5E+3"),
    one("literals_scientific", "=12.5E-1+0.5E-15*1E15"),
    one("neg_neg", "=--TRUE", excel={0: 1.0}),          # LibreOffice: TRUE
    one("neg_text", '=-"2"'),
    one("pct_text", '="50"%'),
    one("pct_function", "=SUM(1,2)%"),
    one("neg_pct_pow", "=-50%^2"),
    one("concat_then_compare", "=1&2=12"),
    one("add_then_concat", "=1+2&3"),
    one("concat_literals", '="a"&1&TRUE', excel={0: "a1TRUE"}),     # LibreOffice: "a11"
    one("quotes", '="a""b"&1'),
    one("times_neg", "=2*-3^2"),
    one("pow_neg_exp", "=-2^-2"),
    one("error_literal", "=#N/A"),
    one("ref_error_literal", "=#REF!+1"),
    one("unknown_name", "=nosuchname+1"),
    one("less_than_text", '=1<"a"'),
    one("text_equal_case", '="A"="a"'),
    one("bool_greater", "=TRUE>1", excel={0: T}),        # LibreOffice: FALSE
    one("compare_float_sum", "=0.1+0.2=0.3", excel={0: T}),
    # Excel: FALSE (1.2-1.1 is 0.0999999999999999 to 15 digits); LibreOffice: TRUE
    one("compare_float_difference", "=0.1=(1.2-1.1)", excel={0: F}),
    row("neg_pow_ref", "=-{a}^2", [3, -3, 0, "2", T]),
    row("pct", "={a}%", [50, -3, "50", T, None]),
    row("neg_pct_ref", "=-{a}%^2", [50, -3, 0, 1e3, None]),
    row("pow_pct", "=2^{a}%", [100, 50, 0, -100, 200]),
    row("chain_ops", "={a}-{b}-{c}*2^{b}/4", [1, 2, 3, 4, 5], [0.5, 1, 2, -1, 3], [2, -1, 0, 7, 1]),
    row("concat", "={a}&{b}", ["x", 1.5, T, None, "=1/3"], [1, "y", F, None, 2],
        excel={2: "TRUEFALSE"}),                         # LibreOffice: "10"
    # Excel writes exponents with at least two digits, LibreOffice with three
    row("number_text", '={a}&""', [1234567.891, 1e14, 123456789012345678, -1.5, "=0.1+0.2"],
        excel={2: "1.23456789012346E+17"}),
    row("number_text_more", '={a}&"|"', [1e20, "=-0", 2.5e-3, 100, -123456.789], excel={0: "1E+20|"}),
    row("text_arith", "={a}+1", ["3", "1e3", "a", "-2.5", "1E-2"]),
    row("text_arith_spaces", "={a}*2", [" 3", "3 ", "4", " -1 ", "5"]),
    row("text_arith_python_only", "={a}*2", ["1_000", "inf", "nan", "Infinity", "12"],
        excel={0: "#VALUE!", 1: "#VALUE!", 2: "#VALUE!", 3: "#VALUE!"}),
    row("bool_arith", "={a}+{b}", [T, F, T, None, None], [1, T, None, None, "2"]),
    row("div", "={a}/{b}", [1, 1, 0, -1, "x"], [0, None, 0, 4, 1]),
    row("errors_first", "={a}+{b}", ["#DIV/0!", 1, "#N/A", "#NUM!", "x"], ["#N/A", "#REF!", 1, "#DIV/0!", "#VALUE!"]),
    *[row(f"compare{k}_{name}", f"={{a}}{op}{{b}}", a, b,
          excel={2: _CMP_EXCEL[op]} if k in (0, 2) else None)
      for op, name in (("=", "eq"), ("<>", "ne"), ("<", "lt"), (">", "gt"), ("<=", "le"), (">=", "ge"))
      for k, (a, b) in enumerate(zip(_CMP_A, _CMP_B, strict=False))],
    row("compare_formula_results", "=({a}*2)>({b}&\"\")", [1, 2, 3, 4, 5], [1, 2, 3, 4, 5]),
])

_register("aggs", [
    # LibreOffice counts booleans in ranges as numbers; Excel skips them (and the evaluator)
    row("sum_range", "=SUM($B{r}:$F{r})", [1, "2", T, None, 4], excel=dict.fromkeys(range(5), 5.0)),
    row("sum_window", "=SUM({a}:{a+1})", [1, "x", T, 3, None], [10, 0, 0, 0, 0], excel={1: 0.0, 2: 3.0}),
    row("sum_window_error", "=SUM({a}:{a+1})", [1, 2, "#DIV/0!", 4, 5], [6, 0, 0, 0, 0]),
    row("sum_cumulative", "=SUM($B{r}:{a})", [1, 2, 3, 4, 5], split=True),
    row("sum_shrinking", "=SUM({a}:$F{r})", [1, 2, 3, 4, 5], [100, 200, 300, 400, 500], split=True),
    row("sum_cells", "=SUM({a})", [1, "3", T, "a", None], excel={2: 0.0}),
    row("sum_cell_and_number", "=SUM({a},1)", [2, "3", T, None, -1], excel={2: 1.0}),
    row("sum_cell_numbers", "=SUM({a},{b})+SUM({a})", [2, -3, 0.5, None, 1e10], [1, 2, None, None, 3]),
    # typed booleans and numbers as text count (Excel); LibreOffice: #VALUE!
    one("sum_literals", '=SUM(TRUE,1,"3")', excel={0: 5.0}),
    one("sum_literal_text", '=SUM("a",1)'),
    row("sum_mixed_args", "=SUM($B{r}:$F{r},{a}*2,TRUE)", [1, 2, 3, 4, 5]),
    row("average_range", "=AVERAGE($B{r}:$F{r})", [1, "2", T, None, 4], excel=dict.fromkeys(range(5), 2.5)),
    row("average_window", "=AVERAGE({a}:{a+1})", ["x", "y", 1, None, None], [None, 0, 0, 0, 0]),
    one("average_literals", "=AVERAGE(TRUE,3)"),
    row("min_range", "=MIN($B{r}:$F{r})", [5, "1", F, None, 7], excel=dict.fromkeys(range(5), 5.0)),
    row("max_range", "=MAX($B{r}:$F{r})", [5, "1", F, None, 7]),
    row("minmax_window", "=MAX({a}:{a+1})+MIN({a}:{a+1})", ["x", None, T, -1, 3], [None, 0, 0, 0, 0],
        excel={1: 0.0, 2: -2.0}),
    row("min_window_error", "=MIN({a}:{a+1})", [1, "#N/A", 3, 4, 5], [6, 0, 0, 0, 0]),
    row("max_negative", "=MAX({a},{b},-100)", [-5, -1, -300, 2, -7], [-6, -2, -200, 1, None]),
    row("min_cells", "=MIN({a},{b})", ["x", T, 3, None, "2"], [5, 4, "y", None, 1], excel={1: 4.0}),
    one("min_literals", "=MIN(TRUE,5)"),
    one("max_literals", '=MAX("9",1)', excel={0: 9.0}),    # LibreOffice: #VALUE!
    row("count_range", "=COUNT($B{r}:$F{r})", [1, "2", T, None, "#DIV/0!"], excel=dict.fromkeys(range(5), 1.0)),
    row("count_window", "=COUNT({a}:{a+1})", [1, "2", 3, None, 5], [F, 0, 0, 0, 0], excel={4: 1.0}),
    one("count_literals", '=COUNT(1,"2",TRUE)'),
    row("count_cells", "=COUNT({a},{b})", [1, "2", T, None, "#N/A"], [2, 3, "x", None, 1], excel={2: 0.0}),
    one("count_error_argument", "=COUNT(1/0,2)"),
    row("sumproduct", "=SUMPRODUCT($B{r}:$F{r},$G{r}:$K{r})", [1, "2", T, None, 4], [2, 3, 4, 5, 0.5],
        excel=dict.fromkeys(range(5), 4.0)),
    row("sumproduct_window", "=SUMPRODUCT({a}:{a+1},{b}:{b+1})", [1, 2, 3, 4, 5], [6, 7, 8, 9, 10], [11, 0, 0, 0, 0]),
    row("sumproduct_booleans", "=SUMPRODUCT(--($B{r}:$F{r}))", [T, F, 2, None, T]),
    row("sumproduct_compare", "=SUMPRODUCT(--($B{r}:$F{r}>{b}))", [1, 2, 3, 4, 5], [0, 2, 3.5, 5, -1]),
    row("sumproduct_text", "=SUMPRODUCT(--($B{r}:$F{r}))", [1, "x", 2, None, 3]),
    row("sumproduct_error", "=SUMPRODUCT({a}:{a+1})", [1, "#DIV/0!", 3, 4, 5], [6, 0, 0, 0, 0]),
    row("sumproduct_product", "=SUMPRODUCT(($B{r}:$F{r})*{b})", [1, 2, 3, 4, 5], [1, 2, 0, -1, 0.5]),
    one("sumproduct_scalar", "=SUMPRODUCT(3)"),
    row("and_range", "=AND($B{r}:$F{r})", [T, "x", 1, None, T]),
    row("and_window", "=AND({a}:{a+1})", [T, F, "x", "y", None], [1, 0, 0, 0, 0]),
    row("or_window", "=OR({a}:{a+1})", [F, 0, "x", None, "#N/A"], [None, 0, 0, 0, 0]),
    row("and_compare", "=AND({a}>0,{b}>0)", [1, -1, 1, "x", None], [1, 1, -1, 2, 0]),
    row("or_cells", "=OR({a},{b})", [0, 1, 0, None, T], [0, 0, 1, None, "#N/A"]),
    row("or_cell_text", "=OR({a},{b})", ["x", "y", 1, None, T], [1, 0, "z", "x", None]),
    one("and_text_literal", '=AND(TRUE,"x")'),
    row("not", "=NOT({a})", [0, 1, "x", None, T]),
    row("if_branch", '=IF({a}>0,SQRT({a}),"neg")', [4, -1, 0, "x", None]),
    row("if_condition", '=IF({a},"y","n")', [1, 0, "x", None, T]),
    row("if_guard", "=IF({a}=0,0,1/{a})", [0, 2, 0, -4, None]),
    row("if_two_args", "=IF({a}>1,{a})", [2, 1, "x", None, 5]),
    row("if_missing_branch", "=IF({a},,1)", [1, 0, T, F, None]),
    row("if_error_condition", "=IF({a},1,2)", ["#DIV/0!", 1, "#N/A", 0, 2]),
    row("iferror", '=IFERROR({a}/{b},"bad")', [1, 1, "x", 0, "#N/A"], [2, 0, 1, 0, 1]),
    row("iferror_error_alternative", "=IFERROR(1/{a},1/{b})", [0, 1, 0, 2, "x"], [0, 0, 2, 0, 1]),
    row("isnumber", "=ISNUMBER({a})", [1, "x", T, None, "#N/A"], excel={2: F}),    # LibreOffice: TRUE
    row("iserror", "=ISERROR({a})", [1, "x", T, None, "#N/A"]),
    row("istext", "=ISTEXT({a})", [1, "x", T, None, "#N/A"]),
    # an error in one column stays in that column, through the rows below
    row("error_column", "=1/{a}", [1, 0, 2, 0, 4]),
    row("error_column_next", "={fp}*2+1"),
    row("error_column_caught", "=IFERROR({fp},-1)"),
    row("error_column_sum", "=SUM($R{rp}:$V{rp})+{fp}"),
    row("error_column_sum_running", "=SUM($R{rp}:{F}{rp})+{F}{rp}", split=True),
    # a formula whose value is an empty cell's is 0
    row("empty_reference", "=$Z$99"),
    row("empty_reference_used", '={fp}&"|"', excel=dict.fromkeys(range(5), "0|")),
    row("empty_reference_2", "=$Z$98*1"),
    row("empty_reference_2_used", "=ISNUMBER({fp})"),
    row("empty_reference_text", '=$Z$99&"|"'),
    one("empty_through_if", "=IF(TRUE,$Z$99)"),
    one("empty_through_iferror", "=IFERROR($Z$99,1)"),
    row("empty_compare", "={a}=$Z$99", [0, "", F, None, 1]),
    row("empty_order", '=AND($Z$99<1,$Z$99<"a",$Z$99=FALSE,$Z$99>-1)+{a}', [0, 1, 2, 3, 4]),
])

_register("crash_sumproduct_sizes", [
    one("sumproduct_sizes", "=SUMPRODUCT($B{r}:$F{r},$G{r}:$H{r})", [1, 2, 3, 4, 5], [1, 2, 0, 0, 0]),
])

_register("refs", [
    row("other_sheet", "='Кинематика'!{A}1*2", [0] * 5),
    row("other_sheet_spaces", "='My Data'!{A}1+{a}", [1, 2, 3, 4, 5]),
    row("other_sheet_apostrophe", "='O''Brien'!$B$1*{a}", [1, 2, 3, 4, 5]),
    row("other_sheet_plain", "=Data2!{A}1-{a}", [1, 2, 3, 4, 5]),
    row("other_sheet_range", "=SUM('My Data'!$B$1:$F$1)+SUM('Кинематика'!$B$1:$C$1)+SUM('Кинематика'!{A}1:{A+1}1)"),
    row("other_sheet_running", "=SUM('Кинематика'!$B1:{A}1)", split=True),
    row("other_sheet_sumproduct", "=SUMPRODUCT('My Data'!$B$1:$F$1,$B{r}:$F{r})", [1, 0, -1, 2, 0.5]),
    row("absolute", "=$A$2*{a}", [1, 2, 3, 4, 5]),
    row("row_absolute", "={a}*{F}$2", [1, 2, 3, 4, 5]),
    row("column_absolute", "=$B{r}*{a}+$G{r}", [1, 2, 3, 4, 5], [10, 0, 0, 0, 0]),
    row("mixed_all", "={a}*$R$2+{F}$2*$B{r}-$A2", [1, 2, 3, 4, 5]),
    row("relative_left", "={F-1}{r}+1", split=True),
    row("name_cell", "=Param*{a}", [1, 2, 3, 4, 5]),
    row("name_constant", "=Gravity*{a}", [1, 2, 3, 4, 5]),
    row("name_range", "=SUM(Span)+{a}", [1, 2, 3, 4, 5]),
    row("name_other_sheet", "=Kin+Gravity+{a}", [1, 2, 3, 4, 5]),
    row("name_sumproduct", "=SUMPRODUCT(Span,$B{r}:$F{r})", [1, 0, -1, 2, 0.5]),
    # a name for a range or a cell is a reference: text and booleans in it are skipped by the
    # aggregates (LibreOffice counts TRUE as 1)
    row("name_range_mixed", "=SUM(Mixed)+{a}", [1, 2, 3, 4, 5], excel={j: 6.0 + j for j in range(5)}),
    one("name_range_count", "=COUNT(Mixed)", excel={0: 2.0}),
    one("name_range_average", "=AVERAGE(Mixed)", excel={0: 2.5}),
    one("name_range_and", "=AND(Mixed)"),
    one("name_cell_text", "=SUM(Label)+COUNT(Label)+MAX(Label)"),
    one("name_lower_case", "=gravity*2"),
])

_register("raw", [
    # each formula uses the previous cell of its row: one run refers to itself -> cells
    raw("prefix_chain", {"A1": 1, **{f"{get_column_letter(c)}1": f"={get_column_letter(c - 1)}1*2+1"
                                     for c in range(2, 21)},
                         "A2": 1, **{f"{get_column_letter(c)}2":
                                     f"=SUM($A2:{get_column_letter(c - 1)}2)+{get_column_letter(c)}1"
                                     for c in range(2, 21)}}),
    raw("reverse_chain", {**{f"{get_column_letter(c)}1": f"={get_column_letter(c + 1)}1*1.5+1"
                             for c in range(1, 20)}, "T1": 2}),
    # runs B1:F1 -> B2:F2 -> A1:E1 form a cycle of runs, not of cells
    raw("row_cycle", {"A1": 1, **{f"{get_column_letter(c)}1": f"={get_column_letter(c)}2+1" for c in range(2, 7)},
                      **{f"{get_column_letter(c)}2": f"={get_column_letter(c - 1)}1*2" for c in range(2, 7)}}),
    # the same across two sheets
    raw("sheet_cycle", {"A1": 1, **{f"{get_column_letter(c)}1": f"='Y cycle'!{get_column_letter(c)}1+1"
                                    for c in range(2, 8)},
                        **{f"Y cycle!{get_column_letter(c)}1": f"=sheet_cycle!{get_column_letter(c - 1)}1*2"
                           for c in range(2, 8)}}),
    raw("irregular", {"A1": 3, "B1": 4, "C1": "=A1+1", "D1": "=A1*2", "E1": "=SUM(A1:B1)", "F1": "=B1-1",
                      "G1": "=C1+D1", "H1": "=H2*2", "H2": "=G1/2", "I1": "=B1+1", "J1": "=C1+1"}),
    raw("forward_rows", {**{f"{get_column_letter(c)}1": f"={get_column_letter(c)}3*10" for c in range(1, 6)},
                         **{f"{get_column_letter(c)}2": c for c in range(1, 6)},
                         **{f"{get_column_letter(c)}3": f"={get_column_letter(c)}2^2" for c in range(1, 6)}}),
    raw("wide", {**{f"{get_column_letter(c)}1": c * 10 for c in range(1, 41)},
                 **{f"{get_column_letter(c)}2": f"=SIN(RADIANS({get_column_letter(c)}1))*$A$1+"
                                                f"{get_column_letter(c - 1)}1" for c in range(2, 41)}}),
])


# the features real files use (tests/xlsx/test_real_files.py tries them in both XML shapes):
# here as five-cell runs, so the vectorized path computes them per cell
_register("features", [
    row("true_false_functions", "=IF({a}>0,TRUE(),FALSE())", [1, -1, 0, "2", 3]),
    row("int", "=INT({a})", [-2.5, 2.5, 0, "3.7", 1e15 + 0.5]),
    row("trunc", "=TRUNC({a},{b})", [-2.567, 2.567, 1234.5, -0.5, 7], [2, 1, -2, None, "1"]),
    row("floor", "=FLOOR({a},{b})", [-2.5, -2.5, 2.5, 5, 0.3], [2, -2, -2, 0, 0.1]),
    row("ceiling", "=CEILING({a},{b})", [-2.5, -2.5, 2.5, 5, 7.1], [2, -2, -2, 0, 0.5]),
    row("atan_function", "=ATAN({a})*{b}", [1, -1, 0, 1e10, "0.5"], [4, 4, 1, 2, 1]),
    row("index_varying", "=INDEX($B{r}:$F{r},{b})", [10, 20, 30, 40, 50], [1, 5, 3, 2.9, 7]),
    row("index_2d", "=INDEX($B$6:$F$8,{b},{c})", [1, 2, 3, 4, 5], [1, 2, 3, 4, 2], [5, 4, 3, 1, 2]),
    row("choose_varying", "=CHOOSE({b},{a},{c},-1)", [1, 2, 3, 4, 5], [1, 2, 3, 2.7, 4], [9, 8, 7, 6, 5]),
    row("sumsq_window", "=SUMSQ({a}:{a+1})+SUMSQ({b})", [1, -2, 3, 0.5, 4], [1, 2, 3, 4, 5]),
    row("product_window", "=PRODUCT($B{r}:{a})", [2, -1, 3, 0.5, 4], split=True),
    row("abs_of_range", "=SUMPRODUCT(ABS($B{r}:$F{r}))+{b}", [1, -2, 3, -4, 5], [0, 1, 2, 3, 4]),
    row("whole_columns", "=SUM({A}:{A})-SUM($B:$B)+COUNT({A+1}:{A+1})", [1, 2, 3, 4, 5]),
    row("whole_rows", "=SUM({rp}:{rp})+SUM($2:$2)", [1, 2, 3, 4, 5]),
    row("local_name", "=LocalK*{a}+GlobalOnly", [1, 2, 3, 4, 5]),
    row("name_of_formula_cell", "=FormulaCell+{a}", [1, 2, 3, 4, 5]),
])


def _bug_marks(case: Case):
    if case.bug:
        return [pytest.mark.xfail(strict=True, reason=case.bug)]
    return []


ALL_CASES = [c for cases in BOOKS.values() for c in cases]
assert len({c.name for c in ALL_CASES}) == len(ALL_CASES), "case names must be unique"


# --------------------------------------------------------------------------- writing the books
def _input(ws, r, c, value):
    if value is not None:
        ws.cell(r, c, value)


def build_book(name: str, cases: list[Case]) -> tuple[openpyxl.Workbook, dict[str, list[tuple[str, int, int]]]]:
    """The workbook of `cases`, and for each case the formula cells (sheet, row, col) it owns."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = CASE_SHEET
    ws["A1"], ws["A2"], ws["A3"], ws["A4"] = "params", ABS_PARAM, "txt", True
    for j, p in enumerate(PARAMS):
        ws.cell(2, COL["f"] + j, p)
    owned: dict[str, list[tuple[str, int, int]]] = {}
    r = FIRST_ROW
    for case in cases:
        cells = []
        if case.raw is not None:
            for key, value in case.raw.items():
                sheet, coord = key.rsplit("!", 1) if "!" in key else (case.name, key)
                wsr = wb[sheet] if sheet in wb.sheetnames else wb.create_sheet(sheet)
                wsr[coord] = value
                if isinstance(value, str) and value.startswith("="):
                    cell = wsr[coord]
                    cells.append((sheet, cell.row, cell.column))
            owned[case.name] = cells
            continue
        ws.cell(r, 1, case.name)
        for key in ("a", "b", "c"):
            values = getattr(case, key) or []
            for j, v in enumerate(values):
                _input(ws, r, COL[key] + j, v)
                if isinstance(v, str) and v.startswith("="):
                    cells.append((CASE_SHEET, r, COL[key] + j))
        for j in range(1 if case.single else WIDTH):
            ws.cell(r, COL["f"] + j, _render(case.formula, r, j))
            cells.append((CASE_SHEET, r, COL["f"] + j))
        owned[case.name] = cells
        r += 1
    if name == "refs":
        kin, data, obrien, data2 = (wb.create_sheet(n) for n in ("Кинематика", "My Data", "O'Brien", "Data2"))
        for j in range(WIDTH):
            kin.cell(1, 2 + j, j + 1)
            data.cell(1, 2 + j, 10 * (j + 1))
            data2.cell(1, 2 + j, -j - 0.5)
        kin["B2"], data["B2"], obrien["B1"] = 10, 7, 3
        for j, v in enumerate([1, "x", True, None, 4]):
            if v is not None:
                data.cell(3, 2 + j, v)
        data["B4"] = "3"
    if name == "features":
        # LocalK: scoped to the case sheet, shadowing the workbook's LocalK; FormulaCell
        # names a formula cell written after the cells that use it
        ws["A300"], ws["B300"], ws["C300"] = 3, 7, "=A300*B300"
        for n, target in (("LocalK", f"{CASE_SHEET}!$B$300"), ("GlobalOnly", f"{CASE_SHEET}!$A$300"),
                          ("FormulaCell", f"{CASE_SHEET}!$C$300")):
            wb.defined_names[n] = DefinedName(n, attr_text=target)
        ws.defined_names["LocalK"] = DefinedName("LocalK", attr_text=f"{CASE_SHEET}!$A$300")
        owned["name_of_formula_cell"].append((CASE_SHEET, 300, 3))
    if name == "refs":
        for n, target in (("Param", "'My Data'!$B$2"), ("Gravity", "9.81"),
                          ("Span", "'My Data'!$B$1:$F$1"), ("Kin", "'Кинематика'!$B$2"),
                          ("Mixed", "'My Data'!$B$3:$F$3"), ("Label", "'My Data'!$B$4")):
            wb.defined_names[n] = DefinedName(n, attr_text=target)
    return wb, owned


# --------------------------------------------------------------------------- comparison
def _is_our_error(v) -> bool:
    return isinstance(v, str) and v in ERRORS


def agrees(ours, theirs, exact_errors=False) -> bool:
    """ours (Book.value) against a spreadsheet's value (openpyxl data_only)."""
    if is_error(theirs) or _is_our_error(ours):
        if exact_errors:
            return ours == theirs
        return is_error(theirs) and _is_our_error(ours)
    if theirs is None or theirs == "":
        return ours is None or ours == ""        # a formula giving "" reads back as empty
    if isinstance(theirs, bool) or isinstance(ours, bool):
        return type(ours) is bool and type(theirs) is bool and ours == theirs
    if isinstance(theirs, (int, float)):
        if not isinstance(ours, float) or not math.isfinite(ours):
            return False
        return abs(ours - theirs) <= 1e-12 * max(1.0, abs(theirs))
    return ours == theirs


def _lo_values(path: Path) -> dict[tuple[str, int, int], object]:
    wb = openpyxl.load_workbook(path, data_only=True)
    try:
        return {(ws.title, c.row, c.column): c.value
                for ws in wb.worksheets for row_ in ws.iter_rows() for c in row_ if c.value is not None}
    finally:
        wb.close()


def _where(sheet, r, c):
    return f"{sheet}!{get_column_letter(c)}{r}"


def _mismatches(book, lo: dict, cells, excel: dict | None = None) -> list[str]:
    bad = []
    for sheet, r, c in cells:
        ours = book.value(sheet, r, c)
        j = c - COL["f"]
        if excel and sheet == CASE_SHEET and j in excel:
            expected, exact, who = excel[j], True, "Excel"
        else:
            expected, exact, who = lo.get((sheet, r, c)), False, "LibreOffice"
        if not agrees(ours, expected, exact):
            bad.append(f"{_where(sheet, r, c)}: ours {ours!r}, {who} {expected!r}")
    return bad


# --------------------------------------------------------------------------- one soffice call
@dataclass
class Checked:
    source: Path
    lo: dict
    book: object = None           # our Book, or None when evaluate raised
    error: Exception | None = None
    owned: dict | None = None
    lo_path: Path | None = None   # the file LibreOffice saved


@pytest.fixture(scope="module")
def checked(soffice, tmp_path_factory) -> dict[str, Checked]:
    """Every case book, every bundled workbook and the 360-column shaper, recalculated by
    LibreOffice in one call and evaluated by us."""
    src = tmp_path_factory.mktemp("eval_in")
    out = tmp_path_factory.mktemp("eval_out")
    paths, owned = {}, {}
    for name, cases in BOOKS.items():
        wb, owned[name] = build_book(name, cases)
        paths[name] = src / f"cases_{name}.xlsx"
        wb.save(paths[name])
    for p in BUNDLED:
        paths[p.stem] = src / p.name
        shutil.copy(p, paths[p.stem])
    paths["shaper360"] = src / "shaper360.xlsx"
    subprocess.run([sys.executable, "-m", "sheetkin", "workbook", str(ROOT / "workbooks" / "shaper.toml"),
                    "--positions", "360", "--step-deg", "-1", "-o", str(paths["shaper360"])],
                   check=True, capture_output=True, cwd=ROOT)
    outputs = recalculate(list(paths.values()), out)
    result = {}
    for name, p in paths.items():
        ch = Checked(p, _lo_values(outputs[p.resolve()]), owned=owned.get(name), lo_path=outputs[p.resolve()])
        try:
            ch.book = evaluate(p)
        except Exception as e:        # reported by the tests of this book
            ch.error = e
        result[name] = ch
    return result


def _book_of(checked, name) -> Checked:
    ch = checked[name]
    if ch.error is not None:
        pytest.fail(f"evaluate({ch.source.name}) raised {type(ch.error).__name__}: {ch.error}")
    return ch


@pytest.mark.parametrize("case", [pytest.param(c, id=f"{c.book}-{c.name}", marks=_bug_marks(c))
                                  for c in ALL_CASES])
def test_case_agrees_with_libreoffice(checked, case: Case):
    ch = _book_of(checked, case.book)
    cells = ch.owned[case.name]
    assert cells, "the case has no formula cell"
    bad = _mismatches(ch.book, ch.lo, cells, case.excel)
    assert not bad, f"{case.name}: " + "; ".join(bad)


@pytest.mark.parametrize("name", [n for n in BOOKS if not n.startswith("crash_")])
def test_case_books_are_fully_compared_and_vectorized(checked, name):
    """Every formula cell of a case book belongs to a case (so it is compared), and the
    five-cell rows became one run each (the vectorized path ran)."""
    ch = _book_of(checked, name)
    formula_cells = {(s, r, c) for s, sh in ch.book.sheets.items() for (r, c) in sh.formulas}
    owned = {cell for cells in ch.owned.values() for cell in cells}
    assert formula_cells == owned
    assert ch.book.cells == len(formula_cells)
    rows = [c for c in BOOKS[name] if c.raw is None and not c.single]
    if rows:
        singles = ch.book.cells - WIDTH * len(rows)
        split = sum(c.split for c in rows)
        # one run per row case (all five cells; a self-referring one: five), one per other cell
        assert ch.book.runs <= len(rows) + singles + (WIDTH - 1) * split, (ch.book.runs, ch.book.cells)


@pytest.mark.parametrize("stem", [p.stem for p in BUNDLED])
def test_bundled_workbook_agrees_with_libreoffice(checked, stem):
    ch = _book_of(checked, stem)
    cells = [(s, r, c) for s, sh in ch.book.sheets.items() for (r, c) in sh.formulas]
    assert len(cells) > 100
    bad = _mismatches(ch.book, ch.lo, cells)
    assert not bad, f"{len(bad)} of {len(cells)} cells differ: " + "; ".join(bad[:20])


def test_shaper_360_columns_is_vectorized_and_agrees(checked):
    ch = _book_of(checked, "shaper360")
    book = ch.book
    cells = [(s, r, c) for s, sh in book.sheets.items() for (r, c) in sh.formulas]
    assert book.cells == len(cells) > 360 * 50
    assert book.runs < book.cells / 50, (book.runs, book.cells)
    bad = _mismatches(book, ch.lo, cells)
    assert not bad, f"{len(bad)} of {len(cells)} cells differ: " + "; ".join(bad[:20])


# --------------------------------------------------------------------------- messages
def _save(tmp_path, name, cells: dict, sheet="Calc") -> Path:
    wb = openpyxl.Workbook()
    wb.active.title = sheet
    for key, value in cells.items():
        s, coord = key.rsplit("!", 1) if "!" in key else (sheet, key)
        ws = wb[s] if s in wb.sheetnames else wb.create_sheet(s)
        ws[coord] = value
    path = tmp_path / name
    wb.save(path)
    return path


def test_unsupported_function_strict_names_file_sheet_cells_and_function(tmp_path):
    path = _save(tmp_path, "lookup.xlsx", {
        "A1": 1, "B1": 2, "A2": 3, "B2": 4,
        "C3": "=XLOOKUP(1,A1:A2,B1:B2)",
        "Other sheet!D5": "=FOO(1)", "Other sheet!E5": "=FOO(1)", "Other sheet!F5": "=FOO(1)",
        "D1": "=A1+B1",
    })
    with pytest.raises(EvaluationError) as exc:
        evaluate(path, strict=True)
    msg = str(exc.value)
    assert "lookup.xlsx" in msg
    assert "Calc!C3" in msg and "XLOOKUP" in msg
    assert "FOO" in msg and "Other sheet!D5" in msg    # the run of FOO cells (D5:F5) or its cells


def test_unsupported_function_lenient_gives_name_error_and_lists_problems(tmp_path):
    path = _save(tmp_path, "lenient.xlsx", {
        "A1": 1, "B1": 2, "A2": 3, "B2": 4,
        "C3": "=XLOOKUP(1,A1:A2,B1:B2)", "C4": "=C3+1",
        "D5": "=FOO(A1)", "E5": "=FOO(B1)", "F5": "=FOO(C1)",
        "D1": "=A1+B1",
    })
    book = evaluate(path, strict=False)
    assert book.value("Calc", 3, 3) == "#NAME?"
    assert book.value("Calc", 4, 3) == "#NAME?"            # propagates
    assert [book.value("Calc", 5, c) for c in (4, 5, 6)] == ["#NAME?"] * 3
    assert book.value("Calc", 1, 4) == 3.0                  # the rest is computed
    problems = " ".join(book.problems)
    assert "Calc!C3" in problems and "XLOOKUP" in problems
    assert "FOO" in problems and "D5" in problems
    assert len(book.problems) == 2


def test_circular_reference_names_both_cells(tmp_path):
    path = _save(tmp_path, "circle.xlsx", {"A1": "=B1+1", "B1": "=A1+1", "C1": 5, "D1": "=C1*2"})
    with pytest.raises(EvaluationError) as exc:
        evaluate(path, strict=True)
    lenient = evaluate(path, strict=False)       # the cells' problem: #VALUE! and a note
    assert [lenient.value("Calc", 1, c) for c in (1, 2, 4)] == ["#VALUE!", "#VALUE!", 10.0]
    assert len(lenient.notes) == 1
    for msg in (str(exc.value), lenient.notes[0]):
        assert "circular" in msg.lower()
        cells = msg.replace(str(path), "")
        assert "Calc!A1" in cells and "Calc!B1" in cells
        assert "D1" not in cells and "C1" not in cells
    assert str(path) in str(exc.value)


def test_self_reference_names_the_cell(tmp_path):
    path = _save(tmp_path, "self.xlsx", {"A1": 1, "B2": "=B2+A1", "C2": "=A1*2"})
    with pytest.raises(EvaluationError) as exc:
        evaluate(path)
    msg = str(exc.value)
    assert str(path) in msg and "circular" in msg.lower()
    cells = msg.replace(str(path), "")
    assert "Calc!B2" in cells and "C2" not in cells and "A1" not in cells


def test_cycle_inside_a_run_of_cells_names_the_cells(tmp_path):
    """B1:F1 is one run (=C1+1 shifted) whose last cell closes a loop through G1."""
    cells = {f"{get_column_letter(c)}1": f"={get_column_letter(c + 1)}1+1" for c in range(2, 7)}
    cells["G1"] = "=B1*2"
    cells["A1"] = "=A2+1"          # outside the loop
    path = _save(tmp_path, "loop.xlsx", cells, sheet="Лист 1")
    with pytest.raises(EvaluationError) as exc:
        evaluate(path)
    msg = str(exc.value)
    assert str(path) in msg
    cells = msg.replace(str(path), "")
    for coord in ("B1", "C1", "D1", "E1", "F1", "G1"):
        assert f"Лист 1!{coord}" in cells, msg
    assert "A1" not in cells and "A2" not in cells


def test_chains_are_not_circular(tmp_path):
    """Prefix and reverse chains inside one row evaluate (no false circular reference)."""
    cells = {"A1": 1, **{f"{get_column_letter(c)}1": f"={get_column_letter(c - 1)}1+1" for c in range(2, 30)}}
    cells.update({f"{get_column_letter(c)}2": f"={get_column_letter(c + 1)}2*2" for c in range(1, 29)})
    cells["AC2"] = 1
    book = evaluate(_save(tmp_path, "chains.xlsx", cells))
    assert [book.value("Calc", 1, c) for c in range(1, 30)] == [float(c) for c in range(1, 30)]
    assert [book.value("Calc", 2, c) for c in range(1, 30)] == [2.0 ** (29 - c) for c in range(1, 30)]


# --------------------------------------------------------------------------- reading the XML
# xlsxread reads a sheet part in the usual shape with one regex (the fast path) and anything
# else through ElementTree; both must give the same cells, and openpyxl must agree.
MAIN_NS = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
SST = (f'<sst xmlns="{MAIN_NS}" count="2" uniqueCount="2"><si><t>shared &amp; text</t></si>'
       '<si><r><t>rich </t></r><r><rPr><b/></rPr><t>text</t></r></si></sst>').encode()
CELLS_XML = """
<row r="1" spans="1:9"><c r="A1" t="inlineStr"><is><t>a &lt; b &amp; &quot;c&quot; &#1044;&#x416; &gt;</t></is></c>
<c r="B1" s="0"><v>2.5</v></c><c r="C1" t="b"><v>1</v></c><c r="D1" t="e"><v>#DIV/0!</v></c>
<c r="E1" t="s"><v>0</v></c><c r="F1" t="str"><f>"x"&amp;A1</f><v>xa &lt; b</v></c><c r="G1" s="0"/>
<c r="H1"><v/></c><c r="I1" t="s"><v>1</v></c></row>
<row r="2"><c r="B2"><f t="shared" ref="B2:E2" si="0">B1*2+$B$1</f><v>7.5</v></c>
<c r="C2"><f t="shared" si="0"/><v>3</v></c><c r="D2"><f t="shared" si="0"/></c>
<c r="E2"><f t="shared" si="0"/><v>1</v></c></row>
<row r="3"><c r="A3"><f t="shared" ref="A3:A5" si="1">B1&lt;3</f><v>1</v></c></row>
<row r="4"><c r="A4" t="b"><f t="shared" si="1"/><v>0</v></c></row>
<row r="5"><c r="A5" t="b"><f t="shared" si="1"/><v>0</v></c></row>
<row r="6"><c r="A6"><f>IF(B1&lt;&gt;2,"&lt;&gt;","&amp;")</f></c><c r="B6"><f>IF(B1&#60;3,1,0)</f><v>1</v></c>
<c r="C6" t="e"><f>1/0</f><v>#DIV/0!</v></c><c r="D6"><f></f><v>4</v></c>
<c r="E6"><f aca="false">B1+1</f><v>3.5</v></c></row>
<row r="7"><c r="A7" t="inlineStr"><is><t xml:space="preserve">  two spaces </t></is></c>
<c r="B7" t="inlineStr"><is><t></t></is></c></row>
<row r="8"><c r="A8" t="n" s="0"><v>3</v></c><c r="B8" s="0" t="n" cm="1"><v>-1.5E-3</v></c></row>
<row r="9"/><row r="10"></row><row r="11"><c r="AB11"><v>11</v></c></row>"""


def _sheet_xml(cells: str = CELLS_XML, *, prefix: str = "", pretty: bool = False) -> bytes:
    p = f"{prefix}:" if prefix else ""
    body = cells if pretty else "".join(line.strip() for line in cells.splitlines())
    if prefix:
        body = re.sub(r"<(/?)(row|c|f|v|is|t)\b", rf"<\1{p}\2", body)
    ns = f'xmlns{":" + prefix if prefix else ""}="{MAIN_NS}"'
    return (f'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<{p}worksheet {ns}>'
            f'<{p}sheetData>{body}</{p}sheetData></{p}worksheet>').encode()


def _crafted(tmp_path, name: str, sheet: bytes) -> Path:
    """A workbook whose first sheet is the given XML, with shared strings (SST)."""
    import zipfile
    base = tmp_path / "base.xlsx"
    if not base.exists():
        wb = openpyxl.Workbook()
        wb.active.title = "Calc"
        wb.save(base)
    rel = (b'<Relationship Id="rId99" Type="http://schemas.openxmlformats.org/officeDocument/2006/'
           b'relationships/sharedStrings" Target="sharedStrings.xml"/></Relationships>')
    ct = (b'<Override PartName="/xl/sharedStrings.xml" ContentType="application/vnd.openxmlformats-'
          b'officedocument.spreadsheetml.sharedStrings+xml"/></Types>')
    path = tmp_path / name
    with zipfile.ZipFile(base) as zin, zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zout:
        for info in zin.infolist():
            data = zin.read(info.filename)
            if info.filename == "xl/worksheets/sheet1.xml":
                data = sheet
            elif info.filename == "xl/_rels/workbook.xml.rels":
                data = data.replace(b"</Relationships>", rel)
            elif info.filename == "[Content_Types].xml":
                data = data.replace(b"</Types>", ct)
            zout.writestr(info.filename, data)
        zout.writestr("xl/sharedStrings.xml", SST)
    return path


def _read_both(path, monkeypatch, **kw):
    """read_book through the normal path (recording whether the fast path read each sheet)
    and through ElementTree alone."""
    from sheetkin.xlsx import cells as xlsxread
    fast_read, used = xlsxread._read_fast, []

    def spy(*a, **k):
        sh = fast_read(*a, **k)
        used.append(sh is not None)
        return sh
    monkeypatch.setattr(xlsxread, "_read_fast", spy)
    normal = xlsxread.read_book(path, **kw)
    monkeypatch.setattr(xlsxread, "_read_fast", lambda *a, **k: None)
    tree = xlsxread.read_book(path, **kw)
    monkeypatch.setattr(xlsxread, "_read_fast", fast_read)
    return normal, tree, used


def _same_cells(a, b):
    assert a.order == b.order
    for name in a.order:
        x, y = a.sheets[name], b.sheets[name]
        assert (x.max_row, x.max_col, x.state) == (y.max_row, y.max_col, y.state), name
        for kind in ("consts", "formulas", "cached"):
            dx, dy = getattr(x, kind), getattr(y, kind)
            assert list(dx.items()) == list(dy.items()), (name, kind)
            assert [type(v) for v in dx.values()] == [type(v) for v in dy.values()], (name, kind)


def _agrees_with_openpyxl(path, book, sheet="Calc"):
    sh = book.sheets[sheet]
    wb, cached = openpyxl.load_workbook(path), openpyxl.load_workbook(path, data_only=True)
    seen = set()
    for row_ in wb[sheet].iter_rows():
        for c in row_:
            key = (c.row, c.column)
            if c.value is None or c.value == "=":      # openpyxl: <f></f> is "="; ours: no formula
                continue
            seen.add(key)
            if c.data_type == "f":
                assert sh.formulas[key] == c.value[1:], key
                v = cached[sheet].cell(*key).value
                assert sh.cached.get(key) == (float(v) if type(v) is int else v), key
            else:
                v = c.value
                assert sh.consts[key] == (float(v) if type(v) is int else v), key
                # a saved error (openpyxl's data_type "e", a str) is an XlError: not a text
                want = float if type(v) is int else XlError if c.data_type == "e" else type(v)
                assert type(sh.consts[key]) is want, key
    assert (set(sh.formulas) | set(sh.consts)) - {(6, 4)} == seen


def test_reading_every_kind_of_cell(tmp_path, monkeypatch):
    """Inline, shared and formula strings with references (&lt; &amp; &#1044;), numbers,
    booleans, errors, empty and self-closing cells, shared formulas along a row and down a
    column, an <f> without text, t before s: the fast path reads them as ElementTree and
    openpyxl do."""
    path = _crafted(tmp_path, "kinds.xlsx", _sheet_xml())
    normal, tree, used = _read_both(path, monkeypatch)
    assert used[0] is True                        # Calc went through the fast path
    _same_cells(normal, tree)
    _agrees_with_openpyxl(path, normal)
    sh = normal.sheets["Calc"]
    assert sh.consts[(1, 1)] == 'a < b & "c" ДЖ >'
    assert sh.consts[(1, 5)] == "shared & text" and sh.consts[(1, 9)] == "rich text"
    assert sh.consts[(1, 3)] is True and sh.consts[(1, 4)] == "#DIV/0!"
    assert sh.formulas[(1, 6)] == '"x"&A1' and sh.cached[(1, 6)] == "xa < b"
    assert [sh.formulas[(2, c)] for c in range(2, 6)] == ["B1*2+$B$1", "C1*2+$B$1", "D1*2+$B$1", "E1*2+$B$1"]
    assert (2, 4) not in sh.cached
    assert [sh.formulas[(r, 1)] for r in (3, 4, 5)] == ["B1<3", "B2<3", "B3<3"]
    assert sh.cached[(4, 1)] is False
    assert sh.formulas[(6, 1)] == 'IF(B1<>2,"<>","&")' and sh.formulas[(6, 2)] == "IF(B1<3,1,0)"
    assert (6, 4) not in sh.formulas and sh.consts[(6, 4)] == 4.0     # <f></f>: its value
    assert sh.consts[(7, 1)] == "  two spaces " and sh.consts[(7, 2)] == ""
    assert sh.consts[(8, 2)] == -1.5e-3 and (sh.max_row, sh.max_col) == (11, 28)
    book = evaluate(path, strict=False)
    assert book.value("Calc", 6, 1) == "<>" and book.value("Calc", 6, 2) == 1.0
    assert book.value("Calc", 2, 2) == 7.5 and book.value("Calc", 4, 1) is False


FORMULA_TEXTS = [b'IF(E1,0,"&#1085;&#1077; &#1089;&#1086;")', b'IF(F1,0,"&#1085;&#1077; &#1089;&#1086;")',
                 b'A1&amp;"&amp;#1085;"', b'"&#38;amp;"&amp;B2', b'IF(A1&gt;3,"&quot;&#34;","")', b'"',
                 b'""&lt;&#x416;&#x41;', b"SUM(A1:B2)", b"", b'"&#1085;', b'&#1085;"x"&#1085;', b"&#128512;&apos;"]


@pytest.mark.parametrize("bad", [b"&nbsp;", b'"&#0;"', b"A1 & B1", b'"]]>"', b"&#xD800;", b"&#12345678;", b"&#X41;"])
def test_formula_texts_unescape_as_expat_does(bad):
    """_decoded (the fast path's unescaping, memoized per piece between quotes) gives what
    expat gives for each text, with the same pieces repeated and references that spell
    "&", '"' and further references; a text expat refuses is _NotSimple (the tree path decides)."""
    from xml.etree import ElementTree

    from sheetkin.xlsx import cells as xlsxread
    items = FORMULA_TEXTS * 3
    want = [ElementTree.fromstring(b"<t>" + i + b"</t>").text or "" for i in items]
    assert xlsxread._decoded(items) == (want, "\0".join(want).encode("utf-8"))
    assert want[2] == 'A1&"&#1085;"' and want[3] == '"&amp;"&B2' and want[4] == 'IF(A1>3,"""","")'
    with pytest.raises(ElementTree.ParseError):
        ElementTree.fromstring(b"<t>" + bad + b"</t>")
    with pytest.raises(xlsxread._NotSimple):
        xlsxread._decoded([*items, bad])


_TEXT_BITS = [b'"', b"&amp;", b"&lt;", b"&gt;", b"&quot;", b"&apos;", b"&#1085;", b"&#x416;", b"&#34;", b"&#38;",
              b"&#60;", b"amp;", b"#1085;", b"A1", b"IF(", b",", b" ", "\u0416".encode(), b"&nbsp;", b"&", b"]]>",
              b"&#0;", b"&#xD800;"]


def test_formula_texts_unescape_as_expat_does_fuzzed():
    """_decoded against expat on texts assembled from references, quotes and text, alone
    and next to each other (a reference that spells '"' or "&" in the code or in a string,
    an &amp; before "#1085;", a stray "&"): expat's texts, or _NotSimple where expat
    refuses one (the fast path's code and literal passes, and its fallback, issue 32)."""
    from xml.etree import ElementTree

    from hypothesis import given, settings
    from hypothesis import strategies as st

    from sheetkin.xlsx import cells as xlsxread

    item = st.lists(st.sampled_from(_TEXT_BITS), max_size=8).map(b"".join)

    @settings(max_examples=400, derandomize=True, database=None, deadline=None)
    @given(st.lists(item, min_size=1, max_size=6), st.integers(1, 3))
    def check(items, repeat):
        items = items * repeat
        try:
            want = [ElementTree.fromstring(b"<t>" + i + b"</t>").text or "" for i in items]
        except ElementTree.ParseError:
            with pytest.raises(xlsxread._NotSimple):
                xlsxread._decoded(items)
            return
        # the texts, and the UTF-8 bytes the sheet-name scan reads
        assert xlsxread._decoded(items) == (want, "\0".join(want).encode("utf-8"))

    check()


@pytest.mark.parametrize("variant", ["pretty", "prefixed", "crlf", "t_after_other", "stray_ampersand",
                                     "control_character", "escape_character"])
def test_unusual_xml_falls_back_to_the_element_tree(tmp_path, monkeypatch, variant):
    """Indented XML stays on the fast path; prefixed names (x:c), a carriage return in text,
    t after another attribute go to ElementTree with the same cells; XML that is not
    well-formed is refused as before."""
    sheet = {
        "pretty": _sheet_xml(pretty=True),
        "prefixed": _sheet_xml(prefix="x"),
        "crlf": _sheet_xml().replace(b"two spaces", b"two\r\nlines"),
        "t_after_other": _sheet_xml().replace(b'<c r="C1" t="b">', b'<c r="C1" cm="1" t="b">'),
        "stray_ampersand": _sheet_xml().replace(b"&amp; &quot;", b"&nbsp; &quot;"),
        # XML 1.0 allows no other control character: not read as text by either path
        "control_character": _sheet_xml().replace(b"two spaces", b"two\x01spaces"),
        "escape_character": _sheet_xml().replace(b"two spaces", b"two\x1bspaces"),
    }[variant]
    path = _crafted(tmp_path, f"{variant}.xlsx", sheet)
    if variant in ("control_character", "escape_character"):
        from sheetkin.xlsx import cells as xlsxread
        from sheetkin.xlsx.package import UnusableWorkbook
        with pytest.raises(UnusableWorkbook, match="not well-formed XML"):
            xlsxread.read_book(path)                # the fast path declines, the tree refuses
        with pytest.raises(UnusableWorkbook, match="not well-formed XML"):
            xlsxread.read_book(path, needed_for=0, saved=False)
        return
    if variant == "stray_ampersand":
        from sheetkin.xlsx.package import UnusableWorkbook
        with pytest.raises(UnusableWorkbook, match="not well-formed XML"):
            _read_both(path, monkeypatch)
        return
    normal, tree, used = _read_both(path, monkeypatch)
    assert used[0] is (variant == "pretty")
    _same_cells(normal, tree)
    _agrees_with_openpyxl(path, normal)
    if variant == "crlf":
        assert normal.sheets["Calc"].consts[(7, 1)] == "  two\nlines "


def test_a_cell_past_the_limits_is_refused_by_both_paths(tmp_path, monkeypatch):
    from sheetkin.xlsx import cells as xlsxread
    from sheetkin.xlsx.package import Limits, UnusableWorkbook
    path = _crafted(tmp_path, "wide.xlsx", _sheet_xml())
    messages = []
    for fast in (True, False):
        if not fast:
            monkeypatch.setattr(xlsxread, "_read_fast", lambda *a, **k: None)
        with pytest.raises(UnusableWorkbook) as info:
            xlsxread.read_book(path, Limits(max_cols=20))
        messages.append(str(info.value))
    assert messages[0] == messages[1] and "has a cell at AB11" in messages[0]


@pytest.mark.parametrize("stem", [p.stem for p in BUNDLED])
def test_bundled_workbooks_are_read_on_the_fast_path(stem, monkeypatch):
    """The workbooks sheetkin writes take the fast path (every sheet), with the same cells."""
    normal, tree, used = _read_both(ROOT / "workbooks" / f"{stem}.xlsx", monkeypatch)
    assert used and all(used)
    _same_cells(normal, tree)


def test_libreoffice_saved_workbooks_read_alike(checked, monkeypatch):
    """The files LibreOffice saved in the differential run (its own XML: every formula with
    attributes, cached values of every type) read the same on both paths."""
    for name, ch in checked.items():
        normal, tree, used = _read_both(ch.lo_path, monkeypatch)
        assert any(used), name
        _same_cells(normal, tree)


def test_shared_formulas_along_a_row_equal_openpyxl(tmp_path, monkeypatch):
    """Excel fills a row with one shared formula: the cells after the first are rendered
    from the first one's template once it matched the shifter (_shift_formula) on the
    first such cell (whole-column ranges included)."""
    masters = {1: "SUM($A1:B1)+A$1*'My Sheet'!C1-Data!$D$2+IF(E1&lt;&gt;\"F1\",G1,0)",
               2: "SUM(B:B)+C2",                    # a whole column shifts too
               3: "ROUND(B1,2)+LOG10(C1)+ZZ1"}
    rows = []
    for r, text in masters.items():
        cells = [f'<c r="B{r}"><f t="shared" ref="B{r}:AF{r}" si="{r}">{text}</f></c>']
        cells += [f'<c r="{get_column_letter(c)}{r}"><f t="shared" si="{r}"/></c>' for c in range(3, 33)]
        rows.append(f'<row r="{r}">{"".join(cells)}</row>')
    rows.append('<row r="4"><c r="C4"><f t="shared" si="1"/></c></row>')    # down a row: Translator
    path = _crafted(tmp_path, "shared.xlsx", _sheet_xml("".join(rows)))
    from sheetkin.xlsx import cells as xlsxread
    translate, calls = xlsxread._shift_formula, []
    monkeypatch.setattr(xlsxread, "_shift_formula", lambda *a: calls.append(a) or translate(*a))
    normal, tree, used = _read_both(path, monkeypatch)
    assert used[0] is True
    # per path: one check each for rows 1, 2 and 3, and row 4's cell
    assert len(calls) == 2 * (1 + 1 + 1 + 1)
    _same_cells(normal, tree)
    _agrees_with_openpyxl(path, normal)
    f = normal.sheets["Calc"].formulas
    assert f[(1, 32)] == "SUM($A1:AF1)+AE$1*'My Sheet'!AG1-Data!$D$2+IF(AI1<>\"F1\",AK1,0)"
    assert f[(2, 32)] == "SUM(AF:AF)+AG2" and f[(3, 3)] == "ROUND(C1,2)+LOG10(D1)+AAA1"
    assert f[(4, 3)] == "SUM($A4:C4)+B$1*'My Sheet'!D4-Data!$D$2+IF(F4<>\"F1\",H4,0)"


def test_date_cells_and_malformed_values(tmp_path, monkeypatch, capsys):
    """A t="d" cell (an ISO 8601 date, strict OOXML) reads as its text on both paths; a
    number cell whose value is not a number is one clear line (exit 2), never a traceback."""
    from sheetkin.cli.commands import main
    dated = _crafted(tmp_path, "dated.xlsx", _sheet_xml(
        '<row r="1"><c r="A1" t="d"><v>2026-11-23T00:00:00</v></c><c r="B1"><v>2</v></c></row>'))
    normal, tree, used = _read_both(dated, monkeypatch)
    _same_cells(normal, tree)
    assert normal.sheets["Calc"].consts[(1, 1)] == "2026-11-23T00:00:00" and used == [True]
    bad = _crafted(tmp_path, "bad.xlsx", _sheet_xml('<row r="1"><c r="A1"><v>12abc</v></c></row>'))
    assert main(["evaluate", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert "cell A1 has the value '12abc'" in err and "\n" not in err


def test_column_letters_and_tokenizer_are_openpyxls():
    # sheetkin.xlsx.coords spares `evaluate` the import of openpyxl (issue 24): the same rules
    import openpyxl.formula.tokenizer as real
    from openpyxl.utils import column_index_from_string, get_column_letter

    from sheetkin.xlsx import coords
    for c in (1, 25, 26, 27, 52, 53, 701, 702, 703, 16384, 18277, 18278):
        assert coords.get_column_letter(c) == get_column_letter(c)
        assert coords.column_index_from_string(get_column_letter(c).lower()) == c == column_index_from_string(
            get_column_letter(c))
    for bad in (0, 18279, -1):
        with pytest.raises(ValueError):
            coords.get_column_letter(bad)
    for bad in ("", "AAAA", "A1", "Ä"):
        with pytest.raises(ValueError):
            coords.column_index_from_string(bad)
    text = '=IF(A1<>"x",SUM($B$2:C3)*-1.5E-3%,{1,2;3,4})&"н/д"'
    ours = [(t.value, t.type, t.subtype) for t in coords.Tokenizer(text).items]
    assert ours == [(t.value, t.type, t.subtype) for t in real.Tokenizer(text).items]


@pytest.mark.parametrize("op", ["=", "<>", "<", ">", "<=", ">="])
def test_numbers_against_text_fast_path_is_the_general_one(op):
    # issue 24: E34:Q34="" in every check status; numbers rank below text, never equal
    import numpy as np

    from sheetkin.xlsx.values import NUM, TEXT, Val, compare
    num = np.array([[[0.0, -1.5, 3e300, 2.0]]])
    pure = Val(num, None, None, NUM)
    general = Val(num, np.zeros(num.shape, np.int8))              # the same numbers, not marked pure
    for text in ("", "abc", "0"):
        t = Val(np.zeros((1, 1, 1)), np.full((1, 1, 1), TEXT, np.int8), np.array([[[text]]], dtype=object))
        for a, b, ga, gb in ((pure, t, general, t), (t, pure, t, general)):
            fast, slow = compare(op, a, b), compare(op, ga, gb)
            assert fast.shape == slow.shape
            assert np.array_equal(fast.num, slow.num) and np.array_equal(fast.tag, slow.tag), (op, text)


def test_aggregates_fast_paths_are_the_general_ones():
    """SUM, MIN, MAX, SUMPRODUCT, AND, OR and unary minus over values of numbers only (or
    booleans only) take fast paths that skip the tags (issue 32): the same numbers, tags and
    errors as the general path gives the same cells unmarked, for random shapes (one value
    per cell of a run or one block for all), signs, zeros, overflow to #NUM! and booleans."""
    import itertools

    import numpy as np
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from sheetkin.xlsx.context import Context
    from sheetkin.xlsx.parse import Ref
    from sheetkin.xlsx.runs import Run
    from sheetkin.xlsx.values import AGGREGATES, BOOL, NUM, Val, arith, constant

    def unmarked(v: Val) -> Val:                # the same cells, through the general path
        return Val(v.num.copy(), v.tag.copy(), None, -1)

    def same(fast: Val, slow: Val) -> bool:
        return (fast.shape == slow.shape and np.array_equal(fast.tag, slow.tag)
                and np.array_equal(np.signbit(fast.num), np.signbit(slow.num))
                and np.array_equal(fast.num, slow.num, equal_nan=True))

    numbers = st.sampled_from([0.0, -0.0, 1.0, -2.5, 3e-300, 1e308, -1e308, 7.0, 0.1])

    @st.composite
    def arguments(draw):
        k, r, c = draw(st.sampled_from([1, 3])), draw(st.integers(1, 3)), draw(st.integers(1, 4))
        out = []
        for _ in range(draw(st.integers(1, 3))):
            kk = draw(st.sampled_from([1, k]))
            kind = draw(st.sampled_from([NUM, NUM, BOOL]))
            xs = draw(st.lists(numbers if kind == NUM else st.sampled_from([0.0, 1.0]),
                               min_size=kk * r * c, max_size=kk * r * c))
            out.append(Val(np.array(xs).reshape(kk, r, c), None, None, kind))
        return out, draw(st.lists(st.booleans(), min_size=len(out), max_size=len(out)))

    @settings(max_examples=300, derandomize=True, database=None, deadline=None)
    @given(arguments(), st.sampled_from(["SUM", "MIN", "MAX", "SUMPRODUCT", "AND", "OR"]))
    def check(args_ranges, name):
        args, ranges = args_ranges
        with np.errstate(all="ignore"):
            fast = AGGREGATES[name](args, ranges)
            slow = AGGREGATES[name]([unmarked(v) for v in args], ranges)
        assert same(fast, slow), (name, [a.num.tolist() for a in args], ranges)

    check()
    # zeros of both signs in ranges long enough for numpy's vectorized loops (a fresh-eyes
    # review found MIN(0, 0, -0, 1) -0.0 in the fast path, 0.0 in the general one and LibreOffice)
    rng = np.random.default_rng(32)
    for size, k, other in itertools.product((4, 5, 8, 16, 17, 33, 64, 100), (1, 3), (1.0, -1.0)):
        for _ in range(4):
            xs = rng.choice([0.0, -0.0, other], size=(k, 1, size))      # zeros decide MIN (MAX) often
            for name in ("MIN", "MAX", "SUM", "SUMPRODUCT"):
                for args in ([Val(xs, None, None, NUM)], [Val(xs[:1], None, None, NUM), Val(xs, None, None, NUM)]):
                    fast = AGGREGATES[name](args, [True] * len(args))
                    slow = AGGREGATES[name]([unmarked(v) for v in args], [True] * len(args))
                    assert same(fast, slow), (name, size, k, xs.tolist())
    # numbers in another memory layout (a transposed or strided view): numpy's pairwise sums
    # follow the layout, so the fast paths sum a contiguous copy, as the general path does
    for k, size in ((3, 2000), (1, 301), (3, 64)):
        xs = rng.normal(size=(k, 2, size)) * 10.0 ** rng.integers(-8, 8, size=(k, 2, size))
        for view in (np.asfortranarray(xs), xs[:, :, ::2], np.asfortranarray(xs)[:, :1, :]):
            for name in ("SUM", "SUMPRODUCT", "MIN", "MAX"):
                fast = AGGREGATES[name]([Val(view, None, None, NUM)], [True])
                slow = AGGREGATES[name]([unmarked(Val(view, None, None, NUM))], [True])
                assert same(fast, slow), (name, k, size, view.strides)
    # unary minus (and --) of a stored range of numbers, of booleans: as 0 - x through arith
    for xs, kind in (([0.0, -0.0, 2.5, -1e308, 1e308], NUM), ([0.0, 1.0, 1.0, 0.0, 1.0], BOOL)):
        num, tag = np.zeros((2, 6)), np.zeros((2, 6), np.int8)
        num[1, 1:] = xs
        tag[1, 1:] = kind
        ctx = Context({"S": num}, {"S": tag}, {"S": np.empty((2, 6), dtype=object)}, {None: {}})
        ctx.implicit = False                    # the range as it is, not intersected
        run = Run("S", 1, np.array([1]), "x")
        ref = ("ref", Ref("S", 1, 1, 1, 5, True, True, True, True))
        read = ctx.eval(ref, run)
        assert read.pure == kind
        once = arith("-", constant(0.0), unmarked(read))
        for tree, slow in ((("neg", ref), once), (("neg", ("neg", ref)), arith("-", constant(0.0), unmarked(once)))):
            fast = ctx.eval(tree, run)
            assert fast.pure == NUM and same(fast, slow), (tree, fast.num, slow.num)


def test_cell_regex_possessive_parts_match_as_backtracking_ones():
    """The fast reader's cell regex has every optional part possessive (issue 32), or atomic
    where CPython matches possessive groups wrongly (3.11.0-3.11.4, gh-106052: a fresh-eyes
    review found a broken row read on Debian 12's 3.11.2): on cells in any shape (attributes
    in any order and case, whitespace, empty and self-closed elements, rows alone, junk),
    either splits a piece exactly as the same regex with ordinary, backtracking optional
    parts does, here and in any other Python 3.11 on this machine."""
    import pickle
    import re

    from hypothesis import given, settings
    from hypothesis import strategies as st

    from sheetkin.xlsx import cells
    possessive, atomic = cells._cells_pattern(True), cells._cells_pattern(False)
    assert cells._CELLS.pattern == (possessive if sys.version_info >= (3, 11, 5) else atomic)
    plain = possessive.replace(b")?+", b")?")
    assert plain == atomic.replace(b"(?>(?:", b"(?:").replace(b")?)", b")?") != possessive
    backtracking, atomic_re = re.compile(plain), re.compile(atomic)
    broken = b'<row r="1" x<c r="A1" t="n"><v>1</v></c><c r="B1"><v>2</v></c></row>'
    parts = cells._CELLS.split(broken)
    assert parts == backtracking.split(broken) and any(parts[::cells._GROUPS + 1])    # not all read

    ws = st.sampled_from([b"", b" ", b"\n", b"\t ", b"  "])
    attr = st.sampled_from([b' s="3"', b' t="s"', b' t="str"', b' t="inlineStr"', b' cm="1"', b' t="e"',
                            b' s="x"', b' xmlns="u"', b' T="n"', b' s="1"'])
    inner = st.sampled_from([b"", b"<f>A1+1</f>", b"<f/>", b'<f t="shared" si="0"/>', b'<f t="array" ref="A1:B2">1</f>',
                             b"<v>1.5</v>", b"<v/>", b"<f>B1</f><v>2</v>", b'<is><t xml:space="preserve"> a</t></is>',
                             b"<is><t>x</t></is>", b"<v>1</v><f>A1</f>", b"<f >A1&amp;B1</f><v >0</v>", b"<x/>"])

    @st.composite
    def cell(draw):
        if draw(st.integers(0, 9)) == 0:
            return draw(st.sampled_from([b"<row>", b"</row>", b'<row r="2" spans="1:3">', b"<row/>", b"junk", b"<c/>"]))
        ref = draw(st.sampled_from([b"A1", b"XFD9", b"b2", b"AB12", b"A", b"1"]))
        attrs = b"".join(draw(st.lists(attr, max_size=3)))
        body = draw(inner)
        return (draw(ws) + b'<c r="' + ref + b'"' + attrs + draw(ws)
                + (b"/>" if not body and draw(st.booleans()) else b">" + body + b"</c>") + draw(ws))

    seen: list[bytes] = []

    @settings(max_examples=600, derandomize=True, database=None, deadline=None)
    @given(st.lists(cell(), max_size=8))
    def check(pieces):
        data = b"".join(pieces)
        seen.append(data)
        assert cells._CELLS.split(data) == backtracking.split(data), data
        assert atomic_re.split(data) == backtracking.split(data), data

    check()
    # the same pieces through another Python 3.11 on this machine (Debian 12's is 3.11.2):
    # the pattern is plain `re`, the interpreter's own engine decides
    script = ("import re,sys,pickle; p,a,r,ds=pickle.load(sys.stdin.buffer); "
              "c=re.compile(p if sys.version_info>=(3,11,5) else a); b=re.compile(r); "
              "print(sum(c.split(d)!=b.split(d) for d in ds))")
    for python in {shutil.which("python3.11"), "/usr/bin/python3.11"} - {None, sys.executable}:
        if python and Path(python).exists():
            given_in = pickle.dumps((possessive, atomic, plain, [broken, *seen]))
            out = subprocess.run([python, "-c", script], input=given_in, capture_output=True, timeout=120, check=True)
            assert out.stdout.strip() == b"0", (python, out.stdout, out.stderr[-300:])


def test_control_characters_found_by_the_smallest_byte_first():
    """_has_control (the fast reader's check for characters XML forbids) looks at a piece's
    smallest byte first and at its bytes one by one only when one lies below the space: it
    answers as the byte-by-byte check does, for every byte below 32 (tab and line feed are
    allowed, a carriage return is not), anywhere in a piece, and for none."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from sheetkin.xlsx import cells

    def reference(piece: bytes) -> bool:
        return any(b in cells._CONTROLS for b in piece)

    for b in range(33):
        for piece in (bytes([b]), b"<c>" + bytes([b]) + b"</c>", bytes([b]) * 3 + b"x"):
            assert cells._has_control(piece) == reference(piece) == (b < 32 and b not in (9, 10)), (b, piece)
    assert not cells._has_control(b"")

    @settings(max_examples=300, derandomize=True, database=None, deadline=None)
    @given(st.binary(max_size=64), st.sampled_from([b"", b"\t", b"\n", b"\r", b"\x00", b"\x1f", b" "]))
    def check(data, extra):
        piece = data + extra + data
        assert cells._has_control(piece) == reference(piece)

    check()
