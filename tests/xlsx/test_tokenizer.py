"""sheetkin's formula tokenizer (parse._Tokenizer: openpyxl's, with runs of operand
characters consumed at once, and a formula of words, strings, spaces, operators,
parentheses and commas read one regex match a piece, issue 32 item 5) gives openpyxl's
tokens, or openpyxl's error, for every formula: the bundled workbooks' formulas, hand-picked corners and
hypothesis's fragments of every character class the tokenizer dispatches on."""
from __future__ import annotations

from pathlib import Path

import openpyxl
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from openpyxl.formula.tokenizer import Tokenizer

from sheetkin.xlsx.functions import ERRORS
from sheetkin.xlsx.parse import _Tokenizer

ROOT = Path(__file__).resolve().parents[2]


class _Openpyxl(Tokenizer):
    """openpyxl's own loop and methods, with sheetkin's error literals (the one difference
    sheetkin means to have)."""
    ERROR_CODES = tuple(ERRORS)


def tokens(cls, text: str):
    try:
        return [(t.value, t.type, t.subtype) for t in cls(text).items]
    except Exception as e:      # noqa: BLE001 - the error is part of what is compared
        return (type(e).__name__, str(e))


def _bundled_formulas() -> list[str]:
    """Each row's formulas of columns A..F (the position columns repeat them shifted)."""
    out: set[str] = set()
    for path in sorted((ROOT / "workbooks").glob("*.xlsx")):
        for ws in openpyxl.load_workbook(path, read_only=True).worksheets:
            for row in ws.iter_rows(max_col=6, values_only=True):
                out.update(v for v in row if isinstance(v, str) and v.startswith("="))
    return sorted(out)


CORNERS = [
    "=1.5E+3", "=1E-3*2", "=2.5e+10%", "=1E+", "=A1E+1", "=12.5E-1", "='Sheet 1'!A1", "=Sheet1!#REF!",
    "='Sh''s'!#REF!+1", "=A1:'x'", "={1,2;3,4}", "=[1]Sheet!A1", "=Table1[[#Headers],[Col]]", '="a""b"&"c"',
    "=  A1 + 2 ", "=A1\n+1", "=#N/A", "=#SPILL!", "=SUM(A1:A3 B2:B4)", "=1%", "=-+-1", "=A1 :B2",
    '="open', "='open", "=[open", "=#BAD", "=(1", "=1)", "=)", "={1,2)", "=SUM((A1,B1))", "=A1,B1",
    "=IF(A1<>\"\",A1>=2,A1<=3)", "=x!A1:y!B2", "=Лист1!A1*2", '=IF(E5>0,"да","нет")', "=A1'b'",
    "=A1\"b\"", "=A#N/A", "=A1!#REF!", "plain text", "", "=", "=a[b]c", "=1e5e+5", "=E+1", "=9E-",
    # words float() reads as numbers, and the logical words in both cases
    "=inf+1", "=NaN*2", "=-Infinity", "=infinity(1)", "=TRUE+FALSE", "=true", "=$A$1", "=_x1", "=1_000",
    "=inf\t+1", "=nan\u00a0", "=\u0661\u0662+1",
]


@pytest.mark.parametrize("text", CORNERS)
def test_corners_tokenize_as_openpyxl(text):
    assert tokens(_Tokenizer, text) == tokens(_Openpyxl, text)


def test_every_bundled_formula_tokenizes_as_openpyxl():
    formulas = _bundled_formulas()
    assert len(formulas) > 1000
    differ = [f for f in formulas if tokens(_Tokenizer, f) != tokens(_Openpyxl, f)]
    assert not differ, differ[:3]


FRAGMENTS = st.sampled_from(list("\"'[]#  \n+-*/^&=><%{}();,:!.$AEeZz019_ЖёΣ")
                            + ["E+", "E-", "1.5E", "A1", "$B$2", "SUM(", "IF(", "#N/A", "#REF!", "#DIV/0!",
                               "'S h'!", "Sheet1!", '""', "''", "<=", "<>", ">="])


@settings(max_examples=1500, derandomize=True, database=None, deadline=None)
@given(st.lists(FRAGMENTS, max_size=30).map(lambda parts: "=" + "".join(parts)))
def test_random_formulas_tokenize_as_openpyxl(text):
    assert tokens(_Tokenizer, text) == tokens(_Openpyxl, text)
