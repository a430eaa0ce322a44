"""Runs: the formula cells of a row that hold one formula with its relative references
shifted, which the evaluator parses once and evaluates for all their cells at once (see
evaluator.py). Here: Run; grouping a sheet's formula cells into runs (group_runs, by
rendering the first formula as a template for the next columns); splitting a run into
single cells (split_run); the cells a reference of a run touches (target_block, span); and
EvaluationError, the error of a workbook that cannot be evaluated as a whole.

Separate from evaluator.py so that the checks of hostile input (limits.py) and the
evaluation of a tree (context.py) use runs without importing evaluator.py, which
imports them both.
"""
from __future__ import annotations

from dataclasses import dataclass
from operator import itemgetter

import numpy as np

from .caches import Cache
from .cells import MAX_COL, Sheet, Template
from .coords import get_column_letter
from .errors import SpreadsheetError
from .parse import Ref


class EvaluationError(SpreadsheetError):
    """A workbook that cannot be evaluated as a whole (circular reference, unsupported
    function with strict=True); str() names the file and the cells."""


@dataclass
class Run:
    """Formula cells host_r, cols[...] of one sheet sharing one formula (shifted)."""
    sheet: str
    row: int
    cols: np.ndarray
    formula: str                      # the first cell's formula (without "=")
    tree: object = None
    error: str | None = None          # parse problem or unsupported function
    refs: list | None = None          # the references of tree (and of the names it uses)
    array: tuple | None = None        # an array formula's last cell (r2, c2); its anchor is the run
    unknown: frozenset = frozenset()  # functions it calls (itself or through names) that the table lacks
    dynamic: bool = False             # it makes references while it runs (OFFSET, INDIRECT)

    @property
    def contiguous(self) -> bool:
        """Adjacent cells (columns sorted, as runs are made)."""
        return int(self.cols[-1]) - int(self.cols[0]) == len(self.cols) - 1

    def cells(self) -> list[str]:
        return [f"{get_column_letter(c)}{self.row}" for c in self.cols]

    def where(self) -> str:
        a = f"{get_column_letter(int(self.cols[0]))}{self.row}"
        if len(self.cols) == 1:
            return f"{self.sheet}!{a}"
        return f"{self.sheet}!{a}:{get_column_letter(int(self.cols[-1]))}{self.row}"



TEMPLATES = Cache("run templates: (formula, column) -> Template", 100_000)


def group_runs(sheet: Sheet) -> list[Run]:
    """The sheet's formula cells as runs: in each row, the longest stretches of adjacent
    cells whose formulas are the first one's shifted (compared in growing batches of
    rendered text, so a regular row costs a few list comparisons)."""
    formulas = sheet.formulas
    if not formulas:
        return []
    keys = list(formulas)
    texts = list(formulas.values())
    rows = np.fromiter(map(itemgetter(0), keys), np.int64, len(keys))
    cols = np.fromiter(map(itemgetter(1), keys), np.int64, len(keys))
    code = rows * (MAX_COL + 1) + cols
    if len(code) > 1 and not (np.diff(code) > 0).all():      # not in row, column order
        order = np.argsort(code, kind="stable")
        rows, cols, texts = rows[order], cols[order], [texts[i] for i in order.tolist()]
    bounds = [0, *(np.flatnonzero(np.diff(rows)) + 1).tolist(), len(keys)]
    col_list = cols.tolist()
    runs: list[Run] = []
    name = sheet.name
    for a, b in zip(bounds[:-1], bounds[1:], strict=False):
        r = int(rows[a])
        i = a
        while i < b:
            tpl = TEMPLATES.get((texts[i], col_list[i]))
            if tpl is None:
                tpl = TEMPLATES.put((texts[i], col_list[i]), Template(texts[i], col_list[i]))
            j, window = i + 1, 4
            while j < b:
                m = min(b - j, window)
                if col_list[j + m - 1] - col_list[j - 1] != m:           # a gap in the row
                    m = next(k for k in range(m) if col_list[j + k] != col_list[j - 1] + k + 1)
                    if m == 0:
                        break
                expected = tpl.render_many(col_list[j], m)
                if expected == texts[j:j + m]:
                    j += m
                    if m < window:
                        break
                    window *= 4
                    continue
                j += next(k for k in range(m) if expected[k] != texts[j + k])
                break
            runs.append(Run(name, r, cols[i:j], texts[i]))
            i = j
    return runs


def split_run(run: Run) -> list[Run]:
    return [Run(run.sheet, run.row, np.array([c]), run.formula, run.tree, run.error, run.refs, run.array,
                run.unknown, run.dynamic) for c in run.cols]


def target_block(run: Run, ref: Ref):
    """Rows and columns (per cell of the run) a reference touches."""
    r1 = ref.r1 if ref.r1_abs else run.row + ref.r1
    r2 = ref.r2 if ref.r2_abs else run.row + ref.r2
    c1 = np.full(run.cols.shape, ref.c1) if ref.c1_abs else run.cols + ref.c1
    c2 = np.full(run.cols.shape, ref.c2) if ref.c2_abs else run.cols + ref.c2
    return min(r1, r2), max(r1, r2), np.minimum(c1, c2), np.maximum(c1, c2)


def span(run: Run, ref: Ref) -> tuple[int, int, int, int]:
    """The rows and columns a reference touches from all the cells of a run: first row,
    last row, first column, last column (the block _schedule and the stores consider)."""
    r1 = ref.r1 if ref.r1_abs else run.row + ref.r1
    r2 = ref.r2 if ref.r2_abs else run.row + ref.r2
    first, last = int(run.cols[0]), int(run.cols[-1])
    lo1, hi1 = (ref.c1, ref.c1) if ref.c1_abs else (first + ref.c1, last + ref.c1)
    lo2, hi2 = (ref.c2, ref.c2) if ref.c2_abs else (first + ref.c2, last + ref.c2)
    return min(r1, r2), max(r1, r2), min(lo1, lo2), max(hi1, hi2)
