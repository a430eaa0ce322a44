"""Cells "not computed here": a formula that calls a function the evaluator does not know (an
add-in, a function newer than the table), and every formula that reads such a cell, through
any chain of cells or defined names. Their values are not sheetkin's: the cell holds #NAME?
(what Excel shows for a function it does not know), and `Book.not_computed` names each such
cell and the functions behind it, so that a caller (the validator) uses the value the
spreadsheet saved there, or says it cannot judge the cell, and never takes a computed value
that silently depends on an unknown one (=IFERROR(FOO(A1), 0) is not 0 here: it is not
computed).

Marked in evaluation order (runs after the runs they read), so one pass over the runs
suffices; a run is checked cell by cell only when its blocks touch a marked cell.
"""
from __future__ import annotations

import numpy as np

from .functions import NAME
from .runs import Run, span, target_block


class Uncomputed:
    """The marks of one workbook: per sheet a mask of the value stores' shape, and per
    marked cell the unknown functions behind it."""

    def __init__(self, dims: dict):
        self.dims = dims
        self.mask: dict[str, np.ndarray] = {}
        self.why: dict[str, dict[tuple[int, int], frozenset[str]]] = {}

    def _mark(self, sheet: str, cells: list[tuple[int, int]], functions: frozenset[str], tag: dict) -> None:
        mask = self.mask.setdefault(sheet, np.zeros(self.dims[sheet], bool))
        why = self.why.setdefault(sheet, {})
        for r, c in cells:
            mask[r, c] = True
            why[(r, c)] = why.get((r, c), frozenset()) | functions
            tag[sheet][r, c] = NAME

    def _cells(self, run: Run) -> list[tuple[int, int]]:
        if run.array is not None:
            r2, c2 = run.array
            c0 = int(run.cols[0])
            return [(r, c) for r in range(run.row, r2 + 1) for c in range(c0, c2 + 1)]
        return [(run.row, int(c)) for c in run.cols]

    def unknown(self, run: Run, functions: frozenset[str], tag: dict) -> None:
        """A run that calls unknown functions: its cells are not computed."""
        self._mark(run.sheet, self._cells(run), functions, tag)

    def reads(self, run: Run, refs: list, tag: dict) -> None:
        """After a run is evaluated: its cells that read a marked cell are marked too."""
        if not self.mask:
            return
        touched = [ref for ref in refs if (ref.sheet or run.sheet) in self.mask and self._touches(run, ref)]
        if not touched:
            return
        hit: dict[int, frozenset[str]] = {}
        for ref in touched:
            sheet = ref.sheet or run.sheet
            r1, r2, c1, c2 = target_block(run, ref)
            for i in range(len(run.cols)):
                block = self.mask[sheet][max(r1, 0):r2 + 1, max(int(c1[i]), 0):int(c2[i]) + 1]
                if block.any():
                    rows, cols = np.nonzero(block)
                    found = frozenset().union(*(self.why[sheet][(int(a) + max(r1, 0), int(b) + max(int(c1[i]), 0))]
                                               for a, b in zip(rows[:16], cols[:16], strict=True)))
                    hit[i] = hit.get(i, frozenset()) | found
        for i, functions in hit.items():
            cells = self._cells(run) if run.array is not None else [(run.row, int(run.cols[i]))]
            self._mark(run.sheet, cells, functions, tag)

    def _touches(self, run: Run, ref) -> bool:
        r1, r2, c1, c2 = span(run, ref)
        return bool(self.mask[ref.sheet or run.sheet][max(r1, 0):r2 + 1, max(c1, 0):c2 + 1].any())

    def by_sheet(self) -> dict[str, dict[tuple[int, int], tuple[str, ...]]]:
        """{sheet: {(row, column): the unknown functions behind the cell, sorted}}."""
        return {s: {rc: tuple(sorted(f)) for rc, f in sorted(cells.items())} for s, cells in self.why.items() if cells}
