"""The cells sheetkin cannot compute, computed by LibreOffice when it is installed (issue 31
item 2: no penalty without evidence, and no pass without it either).

A formula that calls a function the evaluator's table lacks (an add-in, a function newer than
the table), and every formula that reads one, is "not computed here" (Book.not_computed,
sheetkin.xlsx.uncomputed): #NAME? in sheetkin's stores. When soffice is on the machine the
student's file is recalculated by it (one `--convert-to xlsx` run with a private profile that
recalculates every formula, sheetkin.xlsx.libreoffice) and those cells take LibreOffice's
values: the rows and check rows that read them are judged on them as on sheetkin's own. So do
the formulas that are #NAME? here while LibreOffice computes them (a formula sheetkin cannot
read, A1:IF(...), and what reads it). The cells stay not computed here (Book.computed is
False, or #NAME? in a nudged copy): the behavioural check does not judge them on the nudged
data (recalculating a nudged copy per variant would cost a soffice run each, ~3 s; only the
issued data are recalculated).

Without LibreOffice (or with --no-libreoffice) the cells stay #NAME? and what reads them is
"not judged: check by hand", out of the score's denominator (sheetkin.course.behaviour).
"""
from __future__ import annotations

from pathlib import Path

from sheetkin.xlsx.cells import read_book
from sheetkin.xlsx.evaluator import Book
from sheetkin.xlsx.functions import ERRORS, NAME, XlError
from sheetkin.xlsx.libreoffice import convert_to_xlsx, scratch_folder, soffice_path
from sheetkin.xlsx.values import constant

TIMEOUT = 120.0          # seconds one recalculation may take (a book is ~3 s)


def fill_uncomputed(book: Book, source: str | Path, enabled: bool = True) -> int:
    """The cells of `book` not computed here set to LibreOffice's recalculation of the file
    `source` (in place); returns how many took a value (0: nothing to do, LibreOffice absent
    or switched off, or it failed: then the cells stay #NAME?, not judged)."""
    # the cells not computed here, and the formulas that are #NAME? here (one sheetkin cannot
    # read, such as a range ending in a function other than INDEX, OFFSET or INDIRECT, A1:IF(...),
    # and every formula reading it)
    cells = {s: set(marked) for s, marked in book.not_computed.items()}
    for s, sh in book.sheets.items():
        if s in book.tag:
            tag = book.tag[s]
            cells.setdefault(s, set()).update(
                (r, c) for r, c in sh.formulas if r < tag.shape[0] and c < tag.shape[1] and tag[r, c] == NAME)
    cells = {s: at for s, at in cells.items() if at}
    if not enabled or not cells or soffice_path() is None or not Path(source).is_file():
        return 0
    try:
        with scratch_folder("sheetkin-recalc-") as folder:
            recalculated = read_book(convert_to_xlsx(Path(source), folder, TIMEOUT))
    except Exception:     # noqa: BLE001 - LibreOffice failing leaves the cells not judged, as without it
        return 0
    filled = 0
    for sheet, at in cells.items():
        saved = recalculated.sheets.get(sheet)
        if saved is None or sheet not in book.num:
            continue
        num, tag, txt = book.num[sheet], book.tag[sheet], book.txt[sheet]
        for r, c in sorted(at):
            if (r, c) not in saved.cached or r >= num.shape[0] or c >= num.shape[1]:
                continue
            value = saved.cached[(r, c)]
            if isinstance(value, str) and value in ERRORS:
                value = XlError(value)
            if value is None or value == "":
                continue                  # "" from a formula: left as sheetkin has it
            v = constant(value)
            num[r, c], tag[r, c] = v.num[0, 0, 0], v.tag[0, 0, 0]
            txt[r, c] = v.txt[0, 0, 0] if v.txt is not None else None
            filled += 1
    return filled
