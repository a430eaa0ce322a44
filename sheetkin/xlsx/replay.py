"""A workbook evaluated again with some typed values changed, its parsed formulas shared.

evaluate_sheets parses each run of formulas once and orders the runs (Book.schedule); a
replay reuses that plan: the value stores are copied, the changed cells written, and the runs
evaluated again in the same order. No formula is tokenized or parsed again, and no run is
grouped or scheduled again, so a replay costs the arithmetic alone. (The validator's
behavioural check, sheetkin/course/behaviour.py: the student's formulas on other given data.)

Only typed cells (no formula) may be changed: a formula cell is computed again by its run.
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .evaluator import Book, name_scopes, run_all, store_value
from .package import Limits
from .runs import Run
from .uncomputed import Uncomputed


class Replay:
    """The plan of an evaluated book (its runs in order, its names), to evaluate it again
    with other values in some typed cells."""

    def __init__(self, book: Book, names: dict, limits: Limits = Limits(),
                 skip: dict[str, set[int]] | None = None, only: dict[str, set[int]] | None = None,
                 keep: Callable[[Run], bool] | None = None):
        """skip: rows (by sheet) whose formulas are not evaluated again (their values stay the
        first evaluation's): rows nothing the caller reads depends on. only: the rows (by
        sheet) whose formulas alone are evaluated again, every other formula's value kept
        (the validator's check rows judged with the rows they check held). keep: of those
        runs, the ones evaluated again (the others keep their values too)."""
        self.book = book
        skip = skip or {}
        self.schedule = [run for run in book.schedule if run.row not in skip.get(run.sheet, ())
                         and (only is None or run.row in only.get(run.sheet, ()))
                         and (keep is None or keep(run))]
        sheets = book.sheets
        bound = (max([sh.max_row for sh in sheets.values()] + [1]), max([sh.max_col for sh in sheets.values()] + [1]))
        self.scopes = name_scopes(names, sheets, bound, {})
        self.name_refs = {**self.scopes[None], **{n: t for sc in self.scopes.values() for n, t in sc.items()}}
        self.dims = {n: list(a.shape) for n, a in book.num.items()}     # as evaluate_sheets made them

    def run(self, changes: dict[str, dict[tuple[int, int], object]]) -> Book:
        """The book evaluated again with the typed cells `changes` (sheet -> {(r, c): value})."""
        from .context import Context
        b = self.book
        for sheet, where in changes.items():
            for (r, c) in where:
                if b.sheets[sheet].computed(r, c):
                    raise ValueError(f"{sheet}!R{r}C{c} holds a formula: only typed cells are replayed")
        num = {n: a.copy() for n, a in b.num.items()}
        tag = {n: a.copy() for n, a in b.tag.items()}
        txt = {n: a.copy() for n, a in b.txt.items()}
        for sheet, cells in changes.items():
            for (r, c), v in cells.items():
                store_value(num[sheet], tag[sheet], txt[sheet], r, c, v)
        ctx = Context(num, tag, txt, self.scopes)
        ctx.arrays = {n: sh.arrays for n, sh in b.sheets.items()}
        problems: list[str] = []
        with np.errstate(all="ignore"):
            marks = Uncomputed(self.dims)
            evaluated = run_all(b.path, self.schedule, ctx, self.dims, self.name_refs, False, problems, marks)
        return Book(b.path, b.sheets, b.order, num, tag, txt, problems, b.runs, evaluated, b.schedule,
                    marks.by_sheet())
