"""Where a student's table is (issue 21, item 2): the layout is found, not assumed.

Students insert a scratch sheet before the main one (LibreOffice's Insert Sheet puts it
there), drag the charts tab first, rename tabs, insert a notes column after C, insert or
delete rows, and leave notes, dragged formulas and scratch cells around the table. So:

* the graded sheet is the one whose cells name the most rows of the issued table (the
  reference's row names), wherever its tab is and whatever its name; ties go to the sheet
  with the issued sheet's name, then to the first;
* the name column is the column of that sheet holding the most row names; the header row is
  the row where that column says "имя" / "name"; the unit, description and value columns
  are found by their headers in that row, the positions by their numbers 0..N-1 in it (N: the
  issued positions, from the embedded scene; numbered by i, as row i is); a header a student edited falls back to the
  issued offsets (unit, description, value right of the name; then the positions), and a
  position whose number is gone to row `i`'s value (0..N-1);
* rows are found by their names (the validator), so inserted and deleted rows do no harm;
* every other cell of the sheet (right of the table, in an inserted column, below the last
  named row) is outside the table: it is evaluated (a student's formula may read it) but
  never graded, and the report mentions it in one line.

The validator then grades a *view* of the sheet in the issued layout (names in A, value in
D, positions from E), built by moving columns, so the rest of the grading is unchanged.
"""
from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import cast

import numpy as np
from openpyxl.utils import column_index_from_string, get_column_letter

from sheetkin.messages import message
from sheetkin.sheet.workbook import FIRST_COL, HEADERS
from sheetkin.xlsx.cells import Sheet
from sheetkin.xlsx.evaluator import EMPTY, Book

VALUE_COL = 4                        # column D of the issued layout
SHOWN = 5                            # cells outside the table named in the one line


@dataclass
class Layout:
    sheet: str                       # the graded sheet's name
    columns: dict[int, int]          # issued column (1 name, 2 unit, 3 desc, 4 value, 5.. positions) -> student's
    positions: int
    header_row: int | None = None
    outside: list[str] = field(default_factory=list)     # cells outside the table (A1 style)
    notes: list[str] = field(default_factory=list)

    @property
    def moved(self) -> bool:
        return any(k != v for k, v in self.columns.items())

    def cell(self, r: int, c: int) -> str:
        """The student's cell of issued column c in row r: 'F40'."""
        return f"{get_column_letter(self.columns.get(c, c))}{r}"

    def outside_line(self) -> str:
        if not self.outside:
            return ""
        n = len(self.outside)
        shown = ", ".join(self.outside[:SHOWN]) + (", ..." if n > SHOWN else "")
        return message("cell_outside_issued_table", n=n, cells=shown)


def _text(v) -> str:
    return " ".join(str(v).split()).casefold() if isinstance(v, str) else ""


def _name_counts(sh: Sheet, names: set[str]) -> dict[int, int]:
    """Per column, how many distinct row names of the issued table it holds."""
    seen: dict[int, set] = {}
    for (_, c), v in sh.consts.items():
        if isinstance(v, str) and v in names:
            seen.setdefault(c, set()).add(v)
    return {c: len(s) for c, s in seen.items()}


def graded_sheet(sheets: dict[str, Sheet], order: list[str], names: set[str], issued_name: str,
                 skip: set[str]) -> tuple[str, int]:
    """(sheet, its name column): the sheet naming the most rows of the issued table."""
    best = None
    for k, n in enumerate(order):
        if n in skip:
            continue
        counts = _name_counts(sheets[n], names)
        if not counts:
            continue
        col, hits = max(counts.items(), key=lambda kv: (kv[1], -kv[0]))
        key = (hits, n == issued_name, len(sheets[n].formulas), -k)
        if best is None or key > best[0]:
            best = (key, n, col)
    if best is None:
        return "", 0
    return best[1], best[2]


def find_layout(sheets: dict[str, Sheet], order: list[str], names: set[str], issued_name: str,
                positions: int, i_values: list[float], skip: set[str]) -> Layout | None:
    """The graded sheet and its columns (module docstring); None when no sheet names a row.
    names: the issued table's row names; i_values: row i's issued values (0..N-1)."""
    sheet, name_col = graded_sheet(sheets, order, names, issued_name, skip)
    if not sheet:
        return None
    sh = sheets[sheet]
    header = _header_row(sh, name_col)
    cols = {1: name_col}
    row_texts = {c: _text(v) for (r, c), v in sh.consts.items() if r == header} if header else {}
    for std, key in ((2, "unit"), (3, "desc"), (4, "value")):
        found = [c for c, t in sorted(row_texts.items()) if c > name_col and t in _headers(key)]
        cols[std] = found[0] if found else cols[std - 1] + 1
    i_row = next((r for (r, c), v in sh.consts.items() if c == name_col and v == "i"), None)
    nums = _numbers_in_row(sh, header, cols[VALUE_COL])     # a number in the header row -> its column
    i_cols = _numbers_in_row(sh, i_row, cols[VALUE_COL])    # a value of row i -> its column
    last = cols[VALUE_COL]
    for k in range(positions):
        c = nums.get(float(k))          # the header numbers positions by i, from 0 (as row i does)
        if c is None and k < len(i_values):
            c = i_cols.get(float(i_values[k]))
        if c is None or c <= last:
            c = last + 1
        cols[FIRST_COL + k] = last = c
    layout = Layout(sheet, cols, positions, header)
    layout.outside = _outside(sh, set(cols.values()), name_col)
    _note_where(layout, order)
    return layout


def _numbers_in_row(sh: Sheet, row: int | None, after: int) -> dict[float, int]:
    """The numbers of a row (none if row is None or 0) right of column `after`: each the
    column where it first stands."""
    out: dict[float, int] = {}
    if row:
        for (r, c), v in sh.consts.items():
            if r == row and c > after and isinstance(v, (int, float)) and not isinstance(v, bool):
                out.setdefault(float(v), c)
    return out


def _note_where(layout: Layout, order: list[str]) -> None:
    """The layout's notes: a graded sheet that is not the first tab, columns that moved."""
    sheet, cols = layout.sheet, layout.columns
    if sheet != order[0]:
        layout.notes.append(message("graded_sheet_found_row", sheet=sheet, k=order.index(sheet) + 1, n=len(order)))
    if layout.moved:
        layout.notes.append(message("columns_found_their_headers", list=", ".join(
            f"{what} {get_column_letter(cols[c])}" for c, what in ((1, "names"), (4, "values"),
                                                                   (FIRST_COL, "first position")) if cols[c] != c)))


def _headers(key: str) -> set[str]:
    """The column's header texts in every language, casefolded."""
    # the name, unit, desc and value headers are plain texts (texts.SHEET): no tuple among them
    return {cast(str, h).casefold() for h in HEADERS[key]}


def _header_row(sh: Sheet, name_col: int) -> int | None:
    heads = _headers("name")
    rows = [r for (r, c), v in sh.consts.items() if c == name_col and _text(v) in heads]
    return min(rows) if rows else None


def _outside(sh: Sheet, used_cols: set[int], name_col: int) -> list[str]:
    """Cells holding something outside the table: in a column that is not the table's, or
    below its last named row."""
    named = [r for (r, c), v in sh.consts.items() if c == name_col and isinstance(v, str) and v.strip()]
    last = max(named, default=0)
    cells = sorted({rc for rc in list(sh.consts) + list(sh.formulas)
                    if rc[1] not in used_cols or rc[0] > last})
    return [f"{get_column_letter(c)}{r}" for r, c in cells]


_CELL = re.compile(r"(?<![A-Za-z0-9_.])\$?([A-Za-z]{1,3})\$?(\d+)(?![A-Za-z0-9_(])")
_WHOLE = re.compile(r"(?<![A-Za-z0-9_.$])\$?([A-Za-z]{1,3}|\d+):\$?([A-Za-z]{1,3}|\d+)(?![A-Za-z0-9_($])")


def _reach(texts) -> tuple[float, float]:
    """(last row, last column) any formula or defined name may read: the largest cell
    address in their texts; infinite where one uses a whole row or column (A:A, 2:2)."""
    rows = cols = 0.0
    for t in texts:
        if not isinstance(t, str):
            continue
        for a, b in _WHOLE.findall(t):
            if a.isdigit() != b.isdigit() or (a.isdigit() and b.isdigit()):
                return np.inf, np.inf                  # whole rows (2:2) or columns (A:A)
            if not a.isdigit():
                return np.inf, np.inf
        for letters, digits in _CELL.findall(t):
            try:
                cols = max(cols, column_index_from_string(letters.upper()))
            except ValueError:
                continue
            rows = max(rows, int(digits))
    return rows, cols


def without_unread(sheets: dict[str, Sheet], names: dict, layout: Layout, skip: set[str]) -> dict[str, Sheet]:
    """The sheets to evaluate: a cell outside the issued table (the graded sheet) or on
    another sheet (a scratch sheet) that lies beyond every cell a formula or a defined name
    refers to is left out: no formula can read it, and a "1" typed far away (row 99,999,
    column 3,999) then costs no time or memory (it is still named as outside the table)."""
    texts = [f for sh in sheets.values() for f in sh.formulas.values()]
    texts += [str(v) for k, v in names.items() if not str(k).startswith("_xlnm.")]
    # (print titles and areas, _xlnm.*, are read by no formula)
    texts += [str(v) for sh in sheets.values() for k, v in sh.names.items() if not str(k).startswith("_xlnm.")]
    rows, cols = _reach(texts)
    if rows == np.inf:
        return sheets
    table = set(layout.columns.values())
    out = {}
    for n, sh in sheets.items():
        if n in skip:
            out[n] = sh
            continue
        keep: Callable[[int, int], bool]
        if n == layout.sheet:
            last = max((r for (r, c), v in sh.consts.items() if c == layout.columns[1] and isinstance(v, str)),
                       default=0)

            def keep_table(r: int, c: int, table: set[int] = table, last: int = last) -> bool:
                return (c in table and r <= last) or (r <= rows and c <= cols)
            keep = keep_table
        else:
            def keep_reach(r: int, c: int) -> bool:
                return r <= rows and c <= cols
            keep = keep_reach
        dropped = [rc for rc in list(sh.consts) + list(sh.formulas) if not keep(*rc)]
        if not dropped:
            out[n] = sh
            continue
        consts = {rc: v for rc, v in sh.consts.items() if keep(*rc)}
        formulas = {rc: v for rc, v in sh.formulas.items() if keep(*rc)}
        cells = list(consts) + list(formulas) + [rc for rc in sh.arrays.values()]
        out[n] = Sheet(sh.name, sh.state, consts=consts, formulas=formulas,
                       cached={rc: v for rc, v in sh.cached.items() if keep(*rc)},
                       max_row=max((r for r, _ in cells), default=0), max_col=max((c for _, c in cells), default=0),
                       arrays=sh.arrays, names=sh.names, dangling=sh.dangling)
    return out


def standard_view(book: Book, layout: Layout, view: Sheet | None = None) -> tuple[Book, Sheet]:
    """The graded sheet in the issued layout (layout.columns moved to 1..4, 5..): a Book
    holding it under its own name (the other sheets as they are) and its Sheet (consts,
    formulas, cached values and array ranges of the table's cells only). view: that Sheet
    as made already for a book with the same sheets (a replay of it, sheetkin.xlsx.replay:
    its values change, not its cells), taken as it is."""
    src = book.sheets[layout.sheet]
    width = max(layout.columns) + 1
    back = {s: t for t, s in layout.columns.items()}
    n, t, x = book.num[layout.sheet], book.tag[layout.sheet], book.txt[layout.sheet]
    num, tag = np.zeros((n.shape[0], width)), np.full((n.shape[0], width), EMPTY, np.int8)
    txt = np.full((n.shape[0], width), None, dtype=object)
    for std, c in layout.columns.items():
        if c < n.shape[1]:
            num[:, std], tag[:, std], txt[:, std] = n[:, c], t[:, c], x[:, c]

    def moved(d: dict) -> dict:
        return {(r, back[c]): v for (r, c), v in d.items() if c in back}
    if view is None:
        arrays = {}
        for (r0, c0), (r2, c2) in src.arrays.items():
            for c in range(c0, c2 + 1):            # each column of an array range, in its new place
                if c in back:
                    arrays[(r0, back[c])] = (r2, back[c])
        view = Sheet(src.name, src.state, consts=moved(src.consts), formulas=moved(src.formulas),
                     cached=moved(src.cached), max_row=src.max_row, max_col=width - 1, arrays=arrays,
                     names=src.names)
    sheets = {**book.sheets, layout.sheet: view}
    # the cells not computed here (a function the evaluator lacks), in their new places too
    not_computed = {**book.not_computed}
    if layout.sheet in not_computed:
        not_computed[layout.sheet] = {(r, back[c]): fs for (r, c), fs in not_computed[layout.sheet].items()
                                      if c in back}
    out = Book(book.path, sheets, book.order, {**book.num, layout.sheet: num}, {**book.tag, layout.sheet: tag},
               {**book.txt, layout.sheet: txt}, book.problems, book.runs, book.cells, book.schedule, not_computed)
    return out, view
