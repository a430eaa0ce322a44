"""Which formula cells of an evaluated workbook depend, through formulas, on some given cells.

reaching(book, sources) follows the evaluator's own parsed formulas (Book.schedule: the runs
in the order they were evaluated, each after the cells it reads), so one pass settles every
cell: a formula cell reaches the sources when one of the cells its references touch is a
source or a formula cell that reaches them. References are followed on every sheet, through
ranges (a range reaches when any of its cells does: SUM(E5:Q5), a row range read by implicit
intersection), defined names (the references behind a name, through names of names) and whole
rows and columns (bounded as the evaluator bounds them). A formula whose value depends on its
own place (ROW, COLUMN, ROWS, COLUMNS: a position numbered =COLUMN()-5) counts as reaching:
the place is given like the position numbers. A formula sheetkin cannot read reaches nothing
(=INDEX({0.5236},1): its value cannot be traced, and a value saved with it is the
spreadsheet's word, not a computation to follow); one that calls a function sheetkin does
not have (INDIRECT, OFFSET, VLOOKUP ...) is traced through the references it names, so
=INDIRECT("Лист2!E42") reaches nothing and =OFFSET(Лист2!E42;0;0) only what E42 reaches. A
typed constant, an empty cell and a formula of constants reach nothing.

This is about where a value comes from, not whether it moves: a formula that reads a source
only to multiply it by 0 reaches it. sheetkin.course.validator grades with it: a computed
row's formula whose precedents end only in typed numbers (the key's values pasted on a
scratch sheet, then "=Лист2!E5") computes nothing.
"""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from .evaluator import Book
from .parse import functions_of
from .runs import target_block

# functions whose value is where the formula (or its reference) is: given, like the positions
POSITIONAL = frozenset({"ROW", "COLUMN", "ROWS", "COLUMNS"})


def reaching(book: Book, sources: dict[str, Iterable[tuple[int, int]]]) -> dict[str, np.ndarray]:
    """{sheet: boolean array over its cells (row r, column c from 1)}: the source cells and
    the formula cells that depend on one of them (module docstring)."""
    reach: dict[str, np.ndarray] = {n: np.zeros(tuple(a.shape[:2]), bool) for n, a in book.num.items()}
    for n, cells in sources.items():
        a = reach.get(n)
        if a is None:
            continue
        for r, c in cells:
            if 0 < r < a.shape[0] and 0 < c < a.shape[1]:
                a[r, c] = True
    folded = {n.casefold(): n for n in reach}
    for run in book.schedule:
        a = reach[run.sheet]
        cols = run.cols.astype(np.int64)
        if run.tree is None:                          # cannot be read, so cannot be traced
            hit = np.zeros(len(cols), bool)
        elif functions_of(run.tree) & POSITIONAL:
            hit = np.ones(len(cols), bool)
        else:
            hit = np.zeros(len(cols), bool)
            for ref in run.refs or ():
                target = ref.sheet or run.sheet
                arr = reach.get(target)
                if arr is None and target.casefold() in folded:
                    arr = reach[folded[target.casefold()]]
                if arr is not None:
                    hit |= _touches(arr, run, ref)
                if hit.all():
                    break
        h, w = a.shape[0], a.shape[1]
        inside = (cols > 0) & (cols < w)
        if 0 < run.row < h:
            a[run.row, cols[inside]] |= hit[inside]
        if run.array is not None and hit.any():          # an array formula fills its range
            r2, c2 = run.array
            a[run.row:r2 + 1, int(cols[0]):c2 + 1] = True
    return reach


def _touches(arr: np.ndarray, run, ref) -> np.ndarray:
    """Per cell of the run: whether the block its reference reads holds a reaching cell."""
    r1, r2, c1, c2 = target_block(run, ref)
    h, w = arr.shape[0], arr.shape[1]
    lo_r, hi_r = max(int(r1), 1), min(int(r2), h - 1)
    if lo_r > hi_r:
        return np.zeros(len(run.cols), bool)
    lo = np.clip(np.asarray(c1, np.int64), 1, w)
    hi = np.clip(np.asarray(c2, np.int64) + 1, 1, w)
    first, last = int(lo.min()), int(hi.max())
    if first >= last:
        return np.zeros(len(run.cols), bool)
    # only the columns the run's cells read: the work is bounded by what the evaluator read
    column_any = arr[lo_r:hi_r + 1, first:last].any(axis=0)
    counts = np.concatenate(([0], np.cumsum(column_any)))
    return (hi > lo) & (counts[hi - first] - counts[lo - first] > 0)
