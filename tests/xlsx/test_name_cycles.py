"""Defined names in a circle or a long chain cost linear time (issue 30, item 5): 30,000 names
in one circle, and a chain of 30,000, in a book of about 1 MB of XML. Before, a circle of 8,000
names took 32 s and 16,000 took 99 s (a note of the whole circle built once per name). The
results are asserted, not the time (printed with -s: about 3 s each on a busy 2-core VM)."""
from __future__ import annotations

import time

import openpyxl
import pytest
from openpyxl.workbook.defined_name import DefinedName

from sheetkin.xlsx.evaluator import evaluate

N = 30_000


def _book(path, target):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "S"
    ws["A1"] = 1
    for i in range(N):
        wb.defined_names[f"nm_{i}"] = DefinedName(f"nm_{i}", attr_text=target(i))
    ws["B1"] = "=nm_0+1"
    ws["B2"] = f"=nm_{N // 2}*2"
    ws["B3"] = "=A1+1"
    wb.save(path)
    return path


@pytest.mark.parametrize("shape", ["circle", "chain"])
def test_thirty_thousand_names(tmp_path, shape):
    if shape == "circle":
        path = _book(tmp_path / "circle.xlsx", lambda i: f"nm_{(i + 1) % N}")
    else:
        path = _book(tmp_path / "chain.xlsx", lambda i: f"nm_{i + 1}" if i + 1 < N else "S!$A$1")
    start = time.perf_counter()
    book = evaluate(path, strict=False)
    print(f"{shape} of {N} names: {time.perf_counter() - start:.2f} s")
    assert book.value("S", 3, 2) == 2.0                     # the rest of the book is computed
    if shape == "circle":                                    # names in a circle: #N/A, as LibreOffice
        assert book.value("S", 1, 2) == "#N/A" and book.value("S", 2, 2) == "#N/A"
        assert any("circle (NM_0 -> NM_1" in p and "more" in p for p in book.notes)
    else:                                                    # deeper than 200 levels: #VALUE!
        assert book.value("S", 1, 2) == "#VALUE!" and book.value("S", 2, 2) == "#VALUE!"
