"""Array constants ({1,2;3,4}: "," between the values of a row, ";" between rows) are read and
computed as the range of those values would be (issue 32's gap left by the function table).
The expected values are the arithmetic of the constants, as Excel defines each function."""
from __future__ import annotations

import openpyxl
import pytest

from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.parse import ParseError, parse_formula

CASES = {
    "=SUM({1,2;3,4})": 10.0,
    "=MDETERM({1,2;3,4})": float(1 * 4 - 2 * 3),
    "=INDEX({1,2;3,4},2,1)": 3.0,
    "=VLOOKUP(2,{1,\"a\";2,\"b\"},2,FALSE)": "b",
    "=SUMPRODUCT({1,-2,3},{1,1,1})*2": float((1 - 2 + 3) * 2),
    "=COUNTA({1,TRUE,\"x\"})": 3.0,
    "=MAX({-1.5;-2})": -1.5,
    "=ROWS({1,2;3,4;5,6})*10+COLUMNS({1,2;3,4;5,6})": 32.0,
    "=ISERROR(INDEX({1,#N/A},1,2))": True,
}


def test_array_constants_compute_as_their_ranges(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    for i, f in enumerate(CASES, start=1):
        ws.cell(i, 1, f)
    path = tmp_path / "arrays.xlsx"
    wb.save(path)
    book = evaluate(path, strict=False)
    assert not book.problems
    for i, (f, want) in enumerate(CASES.items(), start=1):
        got = book.value(book.order[0], i, 1)
        if isinstance(want, float):
            assert got == pytest.approx(want, rel=1e-12), f
        else:
            assert got == want, f


@pytest.mark.parametrize("text", ["={1,A1}", "={1,2;3}", "={1,2", "={SUM(1)}"])
def test_what_excel_refuses_in_an_array_constant_does_not_parse(text):
    with pytest.raises(ParseError):
        parse_formula(text, 1, 1, {})
