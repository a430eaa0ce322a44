"""Cells "not computed here" (issue 32, item 4): a function the evaluator does not know leaves
the cells that call it, and every cell that reads them through cells or names, marked, named
with the function, and #NAME?; the rest of the book is computed."""
from __future__ import annotations

import openpyxl
from openpyxl.workbook.defined_name import DefinedName

from sheetkin.xlsx.evaluator import evaluate


def test_an_unknown_function_marks_the_cells_that_depend_on_it(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "S"
    ws["A1"] = 2
    ws["B1"] = "=FOO(A1)"                 # unknown
    ws["C1"] = "=IFERROR(B1,0)"           # would be a silent 0
    ws["D1"] = "=A1*3"                    # independent
    ws["E1"] = "=SUM(A1:C1)"              # a range over it
    ws["F1"] = "=bar+1"                   # through a name calling an add-in
    other = wb.create_sheet("T")
    other["A1"] = "=S!C1*2"               # another sheet
    for c in "BCDE":
        ws[f"{c}2"] = f"={c}1+0"          # a run of cells filled right, one of them independent
    wb.defined_names["bar"] = DefinedName("bar", attr_text="ADDIN.X(S!$A$1)")
    path = tmp_path / "unknown.xlsx"
    wb.save(path)
    book = evaluate(path, strict=False)
    assert book.not_computed == {
        "S": {(1, 2): ("FOO",), (1, 3): ("FOO",), (1, 5): ("FOO",), (1, 6): ("ADDIN.X",),
              (2, 2): ("FOO",), (2, 3): ("FOO",), (2, 5): ("FOO",)},
        "T": {(1, 1): ("FOO",)}}
    assert book.computed("S", 1, 4) and book.computed("S", 2, 4) and not book.computed("S", 1, 3)
    assert book.value("S", 1, 4) == 6.0 and book.value("S", 2, 4) == 6.0
    assert book.value("S", 1, 3) == "#NAME?"          # never the silent 0 of IFERROR
    assert "T!A1: FOO" in book.uncomputed()
