"""The cells sheetkin cannot compute, computed by LibreOffice when it is installed (issue 31
item 2: no penalty without evidence, and no pass without it either).

A formula that calls a function the evaluator's table lacks (an add-in, a function newer than
the table), and every formula that reads one, is "not computed here" (Book.not_computed,
sheetkin.xlsx.uncomputed): #NAME? in sheetkin's stores. When soffice is on the machine the
student's file is recalculated by it (one `--convert-to xlsx` run with a private profile that
recalculates every formula, sheetkin.xlsx.libreoffice) and those cells take LibreOffice's
values: the rows and check rows that read them are judged on them as on sheetkin's own. So do
the formulas that are #NAME? here while LibreOffice computes them (a formula sheetkin cannot
read, A1:IF(...), and what reads it). The nudged copies of the behavioural check (issue
31: the student's book on other given data, sheetkin.course.behaviour) get the same: a book
with such cells is written again once per nudged variant, its given data changed, and the
copies are recalculated by one more soffice run together (fill_copies); those cells of each
copy take LibreOffice's values and are judged on them as every other cell is.

Without LibreOffice (or with --no-libreoffice) the cells stay #NAME? and what reads them is
"not judged: check by hand", out of the score's denominator (sheetkin.course.behaviour).
"""
from __future__ import annotations

from pathlib import Path

from sheetkin.xlsx.cells import read_book
from sheetkin.xlsx.evaluator import Book
from sheetkin.xlsx.functions import ERRORS, NAME, XlError
from sheetkin.xlsx.libreoffice import convert_to_xlsx, recalculate, scratch_folder, soffice_path
from sheetkin.xlsx.values import constant

TIMEOUT = 120.0          # seconds one recalculation may take (a book is ~3 s)


def cells_to_fill(book: Book) -> dict[str, set[tuple[int, int]]]:
    """The cells not computed here, and the formulas that are #NAME? here (one sheetkin cannot
    read, such as a range ending in a function other than INDEX, OFFSET or INDIRECT, A1:IF(...),
    and every formula reading it), by sheet."""
    cells = {s: set(marked) for s, marked in book.not_computed.items()}
    for s, sh in book.sheets.items():
        if s in book.tag:
            tag = book.tag[s]
            cells.setdefault(s, set()).update(
                (r, c) for r, c in sh.formulas if r < tag.shape[0] and c < tag.shape[1] and tag[r, c] == NAME)
    return {s: at for s, at in cells.items() if at}


def fill_uncomputed(book: Book, source: str | Path, enabled: bool = True) -> int:
    """The cells of `book` not computed here set to LibreOffice's recalculation of the file
    `source` (in place); returns how many took a value (0: nothing to do, LibreOffice absent
    or switched off, or it failed: then the cells stay #NAME?, not judged)."""
    cells = cells_to_fill(book)
    if not enabled or not cells or soffice_path() is None or not Path(source).is_file():
        return 0
    try:
        with scratch_folder("sheetkin-recalc-") as folder:
            recalculated = read_book(convert_to_xlsx(Path(source), folder, TIMEOUT))
    except Exception:     # noqa: BLE001 - LibreOffice failing leaves the cells not judged, as without it
        return 0
    return _take(book, cells, recalculated)


def fill_copies(books: list[Book], source: str | Path, sheet: str, changes: list[dict[tuple[int, int], float]],
                enabled: bool = True) -> bool:
    """Each of `books` (the student's book evaluated again with the typed cells changes[k] of
    `sheet` changed: the behavioural check's nudged copies) with its cells not computed here
    set to LibreOffice's recalculation of a copy of the file `source` with the same cells
    changed (in place). One soffice run recalculates every copy. True when they were; False
    when there was nothing to do, LibreOffice is absent or switched off, the source is no
    .xlsx, or LibreOffice failed (the cells stay #NAME?: not judged on the nudged data)."""
    if not enabled or not any(any(b.not_computed.values()) or any((t == NAME).any() for t in b.tag.values())
                              for b in books):
        return False                     # most books: every cell computed here (no cell looked at)
    cells = [cells_to_fill(b) for b in books]
    if not any(cells) or soffice_path() is None or not Path(source).is_file() or Path(source).suffix.lower() != ".xlsx":
        return False
    try:
        with scratch_folder("sheetkin-nudged-") as folder:
            copies = []
            for k, changed in enumerate(changes):
                copies.append(folder / f"nudged{k + 1}.xlsx")
                _copy_with(Path(source), copies[-1], sheet, changed)
            out = recalculate(copies, folder / "recalculated", TIMEOUT * len(copies))
            recalculated = [read_book(out[p.resolve()]) for p in copies]
    except Exception:     # noqa: BLE001 - LibreOffice failing leaves the cells not judged, as without it
        return False
    for book, at, rec in zip(books, cells, recalculated, strict=True):
        _take(book, at, rec)
    return True


def _copy_with(source: Path, dest: Path, sheet: str, changed: dict[tuple[int, int], float]) -> None:
    """The workbook `source` written to `dest` with the typed cells `changed` of `sheet` (row,
    column: value) set; every formula as it was (LibreOffice computes them again)."""
    import openpyxl
    wb = openpyxl.load_workbook(source)
    try:
        ws = wb[sheet]
        for (r, c), v in changed.items():
            ws.cell(r, c).value = v
        wb.save(dest)
    finally:
        wb.close()


def _take(book: Book, cells: dict[str, set[tuple[int, int]]], recalculated) -> int:
    """The `cells` of `book` set to the values LibreOffice saved in `recalculated` (a read
    book); how many took a value."""
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
