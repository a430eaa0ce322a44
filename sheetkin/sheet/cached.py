"""Workbooks saved with every formula's value: the cached values a spreadsheet shows before
it recalculates.

openpyxl writes a formula cell with an empty value (<v></v>). Whatever does not recalculate
then shows blanks: Excel's Protected View (a file that came by mail or from the web), file
previews, phones, pandas.read_excel and openpyxl's data_only. `CachedWorkbook.save` writes
the book with openpyxl, evaluates every formula with sheetkin's own engine (sheetkin.xlsx,
the evaluator that grades the students' books), and writes each value into its cell: a
number as <v>, text as t="str", a boolean as t="b", an error as t="e". An exercise book is
evaluated as it is, so its cached values are what its formulas give on the empty book (no
answers). The workbook still asks for a full recalculation on load (calcPr fullCalcOnLoad),
so Excel and LibreOffice show their own values once the file is trusted.
"""
from __future__ import annotations

import io
import re
import zipfile
from pathlib import Path
from xml.sax.saxutils import escape

from openpyxl import Workbook
from openpyxl.utils import get_column_letter

from sheetkin.xlsx.cells import Sheet
from sheetkin.xlsx.evaluator import Book, evaluate_sheets
from sheetkin.xlsx.functions import ERROR_TEXT, XlError
from sheetkin.xlsx.values import BOOL, EMPTY, NUM, TEXT

# a formula cell as openpyxl writes it (a formula's text holds no "<": it is escaped)
_FORMULA_CELL = re.compile(rb'<c r="([A-Z]+[0-9]+)"([^>]*)><f>([^<]*)</f><v\s*(?:/>|></v>)</c>')


class CachedWorkbook(Workbook):
    """An openpyxl Workbook whose save() writes every formula cell's value too (see the
    module's docstring). build_workbook and build_synthesis_workbook return one."""

    def save(self, filename) -> None:
        self.calculation.fullCalcOnLoad = True      # Excel recalculates on load all the same
        buf = io.BytesIO()
        Workbook.save(self, buf)
        data = with_cached_values(self, buf.getvalue())
        if hasattr(filename, "write"):
            filename.write(data)
        else:
            Path(filename).write_bytes(data)


def book_sheets(wb: Workbook) -> tuple[dict[str, Sheet], list[str]]:
    """The evaluator's sheets (constants and formulas) of an openpyxl workbook in memory."""
    sheets, order = {}, []
    for ws in wb.worksheets:
        sh = Sheet(ws.title, ws.sheet_state)
        # the cells that exist (ws.iter_rows would create every cell of the bounding box)
        for (r, c), cell in ws._cells.items():
            v = cell.value
            if v is None:
                continue
            if cell.data_type == "f":
                sh.formulas[(r, c)] = v[1:]
            else:
                sh.consts[(r, c)] = (float(v) if isinstance(v, int) and not isinstance(v, bool)
                                     else XlError(v) if cell.data_type == "e" else v)
            sh.max_row, sh.max_col = max(sh.max_row, r), max(sh.max_col, c)
        sheets[ws.title] = sh
        order.append(ws.title)
    return sheets, order


def evaluate_workbook(wb: Workbook) -> Book:
    """Every formula of `wb` evaluated by sheetkin's engine (strict: a formula it cannot
    evaluate is an EvaluationError naming the cell, never a silent blank)."""
    sheets, order = book_sheets(wb)
    return evaluate_sheets("<workbook being saved>", sheets, order, {}, strict=True)


def _cached_xml(book: Book, sheet: str) -> dict[bytes, tuple[bytes, bytes]]:
    """Cell reference -> (type attribute, <v> text) of every formula cell of `sheet`."""
    sh = book.sheets[sheet]
    num, tag, txt = book.num[sheet], book.tag[sheet], book.txt[sheet]
    out = {}
    for (r, c) in sh.formulas:
        ref = f"{get_column_letter(c)}{r}".encode()
        t = int(tag[r, c]) if r < tag.shape[0] and c < tag.shape[1] else EMPTY
        if t == NUM:
            out[ref] = (b"", repr(float(num[r, c])).encode())
        elif t == TEXT:
            out[ref] = (b' t="str"', escape(str(txt[r, c])).encode("utf-8"))
        elif t == BOOL:
            out[ref] = (b' t="b"', b"1" if num[r, c] else b"0")
        elif t == EMPTY:                     # a formula of an empty cell shows 0, as in Excel
            out[ref] = (b"", b"0")
        else:
            out[ref] = (b' t="e"', ERROR_TEXT[t].encode())
    return out


def with_cached_values(wb: Workbook, data: bytes) -> bytes:
    """The .xlsx `data` (as openpyxl saved `wb`) with every formula cell's value written in."""
    book = evaluate_workbook(wb)
    parts = {ws.path.lstrip("/"): ws.title for ws in wb.worksheets}
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            part = src.read(info.filename)
            if info.filename in parts:
                values = _cached_xml(book, parts[info.filename])

                def fill(m: re.Match, values=values) -> bytes:
                    t, v = values.get(m.group(1), (None, None))
                    if v is None:
                        return m.group(0)
                    return b'<c r="%s"%s%s><f>%s</f><v>%s</v></c>' % (m.group(1), m.group(2), t, m.group(3), v)
                part = _FORMULA_CELL.sub(fill, part)
            dst.writestr(info, part)
    return out.getvalue()
