"""Fuzzing the formula parser and the evaluator (issue 11, item 7): only our values or our
one-line notes and errors ever come out.

Formulas are assembled by hypothesis from random tokens, numbers (huge, tiny, malformed),
references (inside, far outside and past Excel's grid, other and missing sheets, #REF!),
defined names (good, in a circle, malformed, unknown), functions (every supported one and
unknown ones, with any number of arguments), operators and nesting (up to and past
MAX_NESTING), and also as plain random text. They go three ways:

- parse_formula: a tree or a ParseError, nothing else;
- evaluate_sheets (the evaluator without a file): small sheets of random formulas, each
  also copied along a row so runs form; every formula cell holds a finite number, text, a
  boolean or an Excel error, every note is one line naming its cell and none is an
  "internal error" (the evaluator's safety net must never be what caught it); strict
  evaluation returns the same book or raises one EvaluationError line;
- a few through real .xlsx files and `sheetkin evaluate`: exit 0 or 2, never a traceback.

derandomize=True: the same examples every run (CI reproducible); deadline generous (a
hang, not a slow machine, is what it is there for). The counts of a run are in README
("Reliability").
"""
from __future__ import annotations

import json
import math
import os
from datetime import timedelta
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from openpyxl.utils import get_column_letter
from openpyxl.workbook.defined_name import DefinedName

from sheetkin.cli.commands import main
from sheetkin.xlsx.cells import Sheet
from sheetkin.xlsx.evaluator import EvaluationError, evaluate, evaluate_sheets
from sheetkin.xlsx.functions import ERRORS
from sheetkin.xlsx.parse import MAX_NESTING, ParseError, parse_formula
from sheetkin.xlsx.table import SUPPORTED

FUZZ = settings(max_examples=300, derandomize=True, database=None, deadline=timedelta(seconds=20),
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
FILES = settings(max_examples=25, derandomize=True, database=None, deadline=timedelta(seconds=30),
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

NAMES = {"good": "Calc!$A$1*2", "rng": "Calc!$A$1:$C$3", "loop_a": "loop_b", "loop_b": "loop_a",
         "self_x": "self_x+1", "broken": "1+)", "calls": "SIN(1,2)", "far": "Calc!$XFD$1048576"}

numbers = st.one_of(
    st.integers(-10**6, 10**6).map(str),
    st.floats(allow_nan=False, allow_infinity=False, width=64).map(lambda x: repr(abs(x))),
    st.sampled_from(["0", "1e308", "1e309", "1e999", "2.5E-3", "1E+2", "9.99e-324", ".5", "1.", "00012",
                     "1e", "1e+", "123456789012345678901234567890"]),
)
cells = st.builds(lambda col, row, a, b: f"{a}{col}{b}{row}",
                  st.sampled_from(["A", "B", "C", "D", "Z", "AA", "XFD", "XFE", "ZZZ"]),
                  st.sampled_from([1, 2, 3, 4, 5, 100, 1048576, 1048577, 0]),
                  st.sampled_from(["", "$"]), st.sampled_from(["", "$"]))
references = st.one_of(
    cells,
    st.builds(lambda a, b: f"{a}:{b}", cells, cells),
    st.builds(lambda s, a: f"{s}!{a}", st.sampled_from(["Data", "Calc", "'No such'", "Nope", "'Da''ta'"]), cells),
    st.sampled_from(["Data!#REF!", "#REF!", "A:A", "2:2", "Data!B:C", "$A$1:$XFD$1048576", "A1:A1:B2"]),
)
texts = st.text(st.sampled_from('ab "x1,()'), max_size=6).map(lambda t: '"' + t.replace('"', '""') + '"')
atoms = st.one_of(numbers, references, texts,
                  st.sampled_from(["TRUE", "FALSE", "#DIV/0!", "#N/A", "#VALUE!", "#NAME?", "#NUM!", "#NULL!"]),
                  st.sampled_from(list(NAMES) + ["undefined_name", "x"]))
functions = st.sampled_from(sorted(SUPPORTED) + ["FOO", "XLOOKUP", "_xlfn.XLOOKUP", "SUM.", "sin", "If"])
binary = st.sampled_from(["+", "-", "*", "/", "^", "&", "=", "<>", "<", ">", "<=", ">="])


def _extend(inner):
    return st.one_of(
        st.builds(lambda a, op, b: f"{a}{op}{b}", inner, binary, inner),
        st.builds(lambda f, args: f"{f}({','.join(args)})", functions, st.lists(inner, max_size=4)),
        st.builds(lambda a: f"({a})", inner),
        st.builds(lambda op, a: f"{op}{a}", st.sampled_from(["-", "+", "--"]), inner),
        st.builds(lambda a: f"{a}%", inner),
    )


expressions = st.recursive(atoms, _extend, max_leaves=12)
# deep nests around the limit, long chains, and plain garbage
nested = st.builds(lambda n, f, a: f"{f}(" * n + a + ")" * n,
                   st.integers(MAX_NESTING - 3, MAX_NESTING + 3), st.sampled_from(["", "SIN", "ABS", "SUM"]), atoms)
chains = st.builds(lambda n, op, a: op.join([a] * n),
                   st.one_of(st.integers(2, 40), st.sampled_from([700, 4100])), binary, atoms)
garbage = st.lists(st.sampled_from(list("AB12$:!,;()[]{}\"'+-*/^&=<>%#? ~.eE") + ["SUM(", "IF(", "Data!"]),
                   max_size=40).map("".join)
formulas = st.one_of(expressions, expressions, expressions, nested, chains, garbage).map(lambda f: "=" + f)


# what a run tried (README, "Reliability"): SHEETKIN_FUZZ_COUNTS=FILE writes them as JSON
COUNTS = {"formulas tried": 0, "refused cleanly (an error and a note, or a ParseError)": 0,
          "evaluated without a note": 0, "crashes": 0}


@pytest.fixture(scope="module", autouse=True)
def _write_counts():
    yield
    if os.environ.get("SHEETKIN_FUZZ_COUNTS"):
        Path(os.environ["SHEETKIN_FUZZ_COUNTS"]).write_text(json.dumps(COUNTS, indent=1) + "\n")


def _count(n: int, refused: int) -> None:
    COUNTS["formulas tried"] += n
    COUNTS["refused cleanly (an error and a note, or a ParseError)"] += refused
    COUNTS["evaluated without a note"] += n - refused


def _refused(book, n: int, cols=(5, 6, 7)) -> int:
    """Formulas (rows) of the book that have a note."""
    noted = {note.split(":", 1)[0] for note in book.notes}
    return sum(any(f"Calc!{get_column_letter(c)}{5 + i}" in noted for c in cols) for i in range(n))


def _sheets(row_formulas: list[str]):
    """Calc: A1:C3 numbers, text and a boolean; the formulas in rows 5..., each also copied
    to the next two cells of its row (a run of three); Data: A1, C5."""
    calc = Sheet("Calc", "visible")
    for (r, c), v in {(1, 1): 2.0, (1, 2): -1.5, (1, 3): 0.0, (2, 1): "text", (2, 2): True,
                      (2, 3): "#DIV/0!", (3, 1): 1e300, (3, 2): 7.0, (3, 3): "3"}.items():
        calc.consts[(r, c)] = v
    for i, f in enumerate(row_formulas):
        for c in (5, 6, 7):
            calc.formulas[(5 + i, c)] = f[1:]
    calc.max_row, calc.max_col = 5 + len(row_formulas), 7
    data = Sheet("Data", "visible", consts={(1, 1): 3.0, (5, 3): 4.0}, max_row=5, max_col=3)
    return {"Calc": calc, "Data": data}


def _check_book(book, n: int):
    for i in range(n):
        for c in (5, 6, 7):
            v = book.value("Calc", 5 + i, c)
            assert v is not None
            if isinstance(v, float):
                assert math.isfinite(v), (i, c, v)
            elif isinstance(v, str):
                pass                                   # text, or an error text (below)
            else:
                assert isinstance(v, bool), (i, c, type(v))
            if book.tag["Calc"][5 + i, c] >= 10:
                assert v in ERRORS
    for note in book.notes:
        assert "\n" not in note and "\r" not in note and len(note) < 1000
        assert note.split(":", 1)[0].split("!")[0] in ("Calc", "Data"), note
        assert "internal error" not in note, note


@FUZZ
@given(formulas)
def test_parse_formula_gives_a_tree_or_a_parse_error(formula):
    try:
        tree = parse_formula(formula, 5, 5, {n.upper(): None for n in NAMES})
    except ParseError as e:
        assert str(e) and "\n" not in str(e)
        _count(1, 1)
        return
    _count(1, 0)
    assert isinstance(tree, tuple) and tree[0] in ("const", "ref", "name", "neg", "pct", "bin", "fn", "missing")


@FUZZ
@given(st.lists(formulas, min_size=1, max_size=4))
def test_evaluating_random_formulas_gives_values_or_notes(row_formulas):
    sheets = _sheets(row_formulas)
    book = evaluate_sheets("fuzz.xlsx", sheets, ["Calc", "Data"], dict(NAMES), strict=False)
    _check_book(book, len(row_formulas))
    _count(len(row_formulas), _refused(book, len(row_formulas)))
    try:
        strict = evaluate_sheets("fuzz.xlsx", _sheets(row_formulas), ["Calc", "Data"], dict(NAMES), strict=True)
    except EvaluationError as e:
        assert str(e).startswith("fuzz.xlsx: ") and "\n" not in str(e)
        assert book.notes, "strict refused a book whose lenient evaluation has no note"
        return
    assert not book.notes
    for i in range(len(row_formulas)):
        for c in (5, 6, 7):
            a, b = book.value("Calc", 5 + i, c), strict.value("Calc", 5 + i, c)
            assert a == b or (isinstance(a, float) and np.isnan(a) and np.isnan(b))


@FILES
@given(st.lists(formulas, min_size=1, max_size=3))
def test_random_formulas_in_xlsx_files_through_sheetkin_evaluate(tmp_path_factory, capsys, row_formulas):
    path = tmp_path_factory.mktemp("fuzz") / "fuzz.xlsx"
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    ws["A1"], ws["B1"], ws["A2"] = 2, -1.5, "text"
    for i, f in enumerate(row_formulas):
        for c in (5, 6):
            ws.cell(5 + i, c).value = f
    wb.create_sheet("Data")["C5"] = 4
    for n, text in NAMES.items():
        wb.defined_names[n] = DefinedName(n, attr_text=text)
    wb.save(path)
    book = evaluate(path, strict=False)
    _count(len(row_formulas), _refused(book, len(row_formulas), (5, 6)))
    for i in range(len(row_formulas)):
        for c in (5, 6):
            v = book.value("Calc", 5 + i, c)
            assert v is not None and (not isinstance(v, float) or math.isfinite(v))
    assert not any("internal error" in n for n in book.notes)
    code = main(["evaluate", str(path), "--format", "csv"])
    out = capsys.readouterr()
    assert code in (0, 2) and "Traceback" not in out.err
    if code == 2:
        assert out.err.count("\n") == 1 and out.err.startswith(f"sheetkin: error: {path}: ")
    else:
        assert not book.notes


@pytest.mark.parametrize("formula", [
    "=1e999", "=-1e999+1", "=1e308*10", "=10^400", "=SUM(1e308,1e308)", "=\"a\"&1e999",
    "=SIN(1e300)", "=1/0", "=0^0", "=MOD(1,0)", "=ATAN2(0,0)", "=SQRT(-1)", "=LN(0)",
])
def test_numbers_that_overflow_are_num_errors_never_inf(formula):
    book = evaluate_sheets("n.xlsx", _sheets([formula]), ["Calc", "Data"], {}, strict=False)
    v = book.value("Calc", 5, 5)
    assert v in ERRORS, v
    _count(1, 0)
