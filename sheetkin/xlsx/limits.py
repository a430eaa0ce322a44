"""The evaluator's defences against hostile input (a workbook from anyone): how deep
evaluating a formula recurses with the names it uses expanded (MAX_EVAL_DEPTH); defined
names that cannot be evaluated (unknown functions, circles of names, chains too deep: each
made a constant error with a note); and the refusals of a whole workbook, as one line
(UnusableWorkbook): a used range, a number of cells read or an amount of formula text past
the Limits. Runs whose relative ranges would read too many cells at once are evaluated in
pieces (CHUNK_READS).

Separate from evaluator.py so that these bounds are read, and changed, in one place;
evaluator.py calls them before and while it evaluates. The counts mirror how
context.py reads a reference.
"""
from __future__ import annotations

import dataclasses
from operator import itemgetter
from typing import cast

from sheetkin.messages import message

from .caches import Cache
from .cells import Sheet
from .context import PAD_CELLS
from .coords import get_column_letter
from .functions import XlError
from .package import Limits, UnusableWorkbook, shorten
from .parse import Note, Ref, functions_of, refs_of, tree_nodes
from .runs import Run, span
from .table import SUPPORTED, arity_problem

MAX_EVAL_DEPTH = 200     # levels of a formula with the names it uses expanded (~2 Python frames each)
CHUNK_READS = 1 << 22    # cells a piece of a run reads at once, per relative range (about 70 MB)


def _depth(tree, weights: dict | None = None) -> int:
    """How deep evaluating a tree recurses: levels of functions, parentheses and operators
    (a chain of + - ... leaning left counts once: Context.eval walks it in a loop), plus
    for each name the depth of the name's own formula (weights)."""
    best, stack = 0, [(tree, 1)]
    while stack:
        node, d = stack.pop()
        best = max(best, d)
        kind = node[0]
        if kind == "fn":
            stack.extend((a, d + 1) for a in node[2])
        elif kind in ("neg", "pct"):
            stack.append((node[1], d + 1))
        elif kind == "bin":
            stack.append((node[2], d))
            stack.append((node[3], d + 1))
        elif kind == "name" and weights:
            best = max(best, d + weights.get(node[1], 0))
    return best


_NAMES_USED = Cache("names a tree uses: id(tree) -> (tree, names)", 200_000)


def names_used(tree) -> tuple[str, ...]:
    """The defined names a tree uses, in order. Kept per tree (by identity, the tree held so
    that its id is not reused): parsed trees are shared by every book of a run (_PARSED),
    and this walk was asked 4-5 times per run per book (issue 24: 31k tree walks a book)."""
    hit = _NAMES_USED.get(id(tree))
    if hit is not None and hit[0] is tree:
        return hit[1]
    names = tuple(node[1] for node in tree_nodes(tree) if node[0] == "name")
    _NAMES_USED.put(id(tree), (tree, names))
    return names


def check_names(name_refs: dict) -> dict[str, Note]:
    """Defined names that cannot be evaluated, made constant errors (in place), with a note
    each: unknown functions (#NAME?), wrong numbers of arguments (#VALUE!), names that
    refer to each other in a circle or to themselves (#N/A, as LibreOffice gives), chains
    of names deeper than MAX_EVAL_DEPTH (#VALUE!). Iterative: a chain of 10,000 names is
    no recursion."""
    notes: dict[str, Note] = {}
    for n, tree in list(name_refs.items()):
        if tree[0] in ("name", "ref", "const"):       # no call to check
            continue
        bad = sorted(f for f in functions_of(tree) if f not in SUPPORTED)
        wrong = None if bad else arity_problem(tree)
        problem = message("unsupported_function", f=", ".join(bad)) if bad else wrong
        if problem:
            code = "#NAME?" if bad else "#VALUE!"
            notes[n] = Note(f"the name {n}: " + problem, code)
            name_refs[n] = ("const", code)
    uses = {n: ([t[1]] if t[1] in name_refs else []) if t[0] == "name" else
            [m for m in names_used(t) if m in name_refs] for n, t in name_refs.items()}
    state: dict[str, int] = {}          # 1 being visited, 2 done
    weight: dict[str, int] = {}
    for start in uses:
        if start in state:
            continue
        state[start] = 1
        path, stack = [start], [(start, iter(uses[start]))]
        while stack:
            n, it = stack[-1]
            m = next(it, None)
            if m is None:
                stack.pop()
                path.pop()
                state[n] = 2
                if n not in notes:
                    weight[n] = _depth(name_refs[n], weight)
                    if weight[n] > MAX_EVAL_DEPTH:
                        notes[n] = Note(f"the name {n}: names within names nested deeper than "
                                        f"{MAX_EVAL_DEPTH} levels", "#VALUE!")
                        name_refs[n], weight[n] = ("const", XlError("#VALUE!")), 1
                continue
            if state.get(m) == 1:                   # back to a name on the path: a circle
                circle = path[path.index(m):]
                # the note shows the circle's first names only, built once: a circle of
                # 30,000 names is one short text, not 30,000 long ones (issue 30)
                shown = circle[:6] + [m] if len(circle) <= 6 else circle[:6] + [f"... {len(circle) - 6} more", m]
                note = Note(f"the names refer to each other in a circle ({shorten(' -> '.join(shown), 200)}): #N/A",
                            "#N/A")
                for x in circle:
                    notes[x] = note
                    name_refs[x], weight[x] = ("const", XlError("#N/A")), 1
            elif m not in state:
                state[m] = 1
                path.append(m)
                stack.append((m, iter(uses[m])))
    return notes


def run_notes(run: Run, sheets: dict, name_refs: dict, name_notes: dict) -> list[str]:
    """Notes for a run that parsed: a sheet that does not exist (#REF!), a name that could
    not be evaluated, formulas nested too deep through names (the run becomes #VALUE!)."""
    out = []
    for ref in cast(list, run.refs):        # called for a run that parsed: refs is set
        if ref.sheet is not None and ref.sheet not in sheets:
            out.append(f"{run.where()}: refers to the sheet '{shorten(ref.sheet, 60)}', which does not exist: #REF!")
            break
    used = [n for n in names_used(run.tree) if n in name_refs] if run.tree is not None else []
    for n in dict.fromkeys(used):
        if n in name_notes:
            out.append(f"{run.where()}: {name_notes[n]}")
    if used and _depth(run.tree, _name_depths(name_refs)) > MAX_EVAL_DEPTH:
        run.error = Note(f"nesting deeper than {MAX_EVAL_DEPTH} levels with its names", "#VALUE!")
        out.append(f"{run.where()}: {run.error}")
    return out


_DEPTHS = Cache("depths of the names last asked about", 4)


def _name_depths(name_refs: dict) -> dict:
    """Each name's own depth (after check_names, no name is deeper than MAX_EVAL_DEPTH),
    kept for the last dict of names asked about."""
    if _DEPTHS.get("of") is not name_refs:
        _DEPTHS.clear()
        _DEPTHS.update(of=name_refs, depths={n: _depth(t) for n, t in name_refs.items()})
    return _DEPTHS["depths"]


def _used_range(sh: Sheet) -> tuple[int, int]:
    """(last row, last column) of the cells that hold something (styled empty cells do not count)."""
    rows = cols = 0
    for cells in (sh.consts, sh.formulas, getattr(sh, "dangling", {})):
        if cells:
            rows = max(rows, max(map(itemgetter(0), cells)))
            cols = max(cols, max(map(itemgetter(1), cells)))
    for r2, c2 in getattr(sh, "arrays", {}).values():     # an array formula's whole range
        rows, cols = max(rows, r2), max(cols, c2)
    return rows, cols


def store_dims(path: str, sheets: dict, limits: Limits) -> dict[str, list[int]]:
    """The value stores' shapes: each sheet's used range (cell A1 is [1, 1]). Refused
    (one line) when all sheets together span more than limits.max_used_cells."""
    dims, total = {}, 0
    for n, sh in sheets.items():
        rows, cols = _used_range(sh)
        dims[n] = [rows + 1, cols + 1]
        total += rows * cols
    if total > limits.max_used_cells:
        n = max(dims, key=lambda x: dims[x][0] * dims[x][1])
        rows, cols = dims[n][0] - 1, dims[n][1] - 1
        raise UnusableWorkbook(path, f"its sheets' used ranges span {total:,} cells (sheet '{shorten(n, 60)}' "
                               f"A1:{get_column_letter(cols)}{rows}, {rows * cols:,})",
                               f"expected at most {limits.max_used_cells:,} cells (rows x columns from A1 "
                               "to the last cell that holds something): clear stray cells far from the table")
    return dims


def _ref_reads(run: Run, ref: Ref, dims: dict, k: int) -> tuple[int, int]:
    """(cells read once for the run, cells read for each cell of the run) by one
    reference, as Context.ref reads it (small blocks whole, large ones clipped)."""
    d = dims.get(ref.sheet or run.sheet)
    if d is None:
        return 0, 0
    if not ref.is_range:
        return 0, 1
    r1, r2, c1, c2 = span(run, ref)
    clipped_rows = max(0, min(r2, d[0] - 1) - r1 + 1)
    if k == 1 or (ref.c1_abs and ref.c2_abs):          # one block for the run
        rows, cols = r2 - r1 + 1, c2 - c1 + 1
        if rows * cols > PAD_CELLS:
            rows, cols = clipped_rows, max(0, min(c2, d[1] - 1) - c1 + 1)
        return rows * cols, 0
    rows, width = r2 - r1 + 1, abs(ref.c2 - ref.c1) + 1  # a block per cell
    if rows * width > PAD_CELLS:
        rows, width = clipped_rows, min(width, max(0, d[1] - c1))
    return 0, rows * width


_READS = Cache("cells a run reads: (references, place, stores) -> counts", 200_000)


def dims_signature(dims: dict) -> tuple:
    """The stores' shapes as a key of _READS."""
    return tuple((n, d[0], d[1]) for n, d in dims.items())


def _run_reads(run: Run, dims: dict, name_refs: dict, dims_key: tuple | None = None) -> tuple[int, int]:
    """(cells read once, cells read per cell) by a run. Kept, for runs that use no names,
    per (its references' list, its place, the stores' shapes): the same in every book of a
    class (the list is the parse cache's, held in the entry so that its id stays its own)."""
    if dims_key is not None and run.refs is not None and (run.tree is None or not names_used(run.tree)):
        key = (id(run.refs), run.sheet, run.row, int(run.cols[0]), int(run.cols[-1]), len(run.cols), dims_key)
        hit = _READS.get(key)
        if hit is not None and hit[0] is run.refs:
            return hit[1]
        value = _count_reads(run, dims, name_refs)
        _READS.put(key, (run.refs, value))
        return value
    return _count_reads(run, dims, name_refs)


def _count_reads(run: Run, dims: dict, name_refs: dict) -> tuple[int, int]:
    k = len(run.cols)
    once = per_cell = 0
    refs = list(run.refs or [])
    if run.tree is not None:
        for n in names_used(run.tree):
            if n in name_refs:
                refs += refs_of(name_refs[n])
    for ref in refs:
        a, b = _ref_reads(run, ref, dims, k)
        once, per_cell = once + a, per_cell + b
    return once, per_cell


def check_reads(path: str, runs: list[Run], dims: dict, name_refs: dict, limits: Limits) -> None:
    """Refuse (one line) a workbook whose formulas read more than limits.max_reads cells
    in all (the evaluation's time is about proportional)."""
    total = 0
    dims_key = dims_signature(dims)
    for run in runs:
        if run.error:
            continue
        once, per_cell = _run_reads(run, dims, name_refs, dims_key)
        total += once + per_cell * len(run.cols)
        if total > limits.max_reads:
            raise UnusableWorkbook(path, f"its formulas read more than {limits.max_reads:,} cells in all "
                                   f"(at {run.where()}, among others)",
                                   message("at_most_limit", size=f"{limits.max_reads:,}"))


def check_formula_text(path: str, runs: list[Run], limits: Limits) -> None:
    """Refuse (one line) a workbook with more formula text to parse than
    limits.max_formula_chars (a run's formula counts once)."""
    total = sum(len(run.formula) for run in runs)
    if total > limits.max_formula_chars:
        raise UnusableWorkbook(path, f"its formulas hold {total:,} characters of text to read (each formula "
                               "once, a row of cells filled from a neighbour once)",
                               message("at_most_limit", size=f"{limits.max_formula_chars:,}"))


def run_pieces(run: Run, dims: dict, name_refs: dict, dims_key: tuple | None = None) -> list[Run]:
    """A run in pieces small enough that its relative ranges, read for every cell at once,
    stay below CHUNK_READS cells (a row of =SUM(A1:A100000) filled right is read 1000
    columns at a time, not 4000)."""
    k = len(run.cols)
    if k == 1 or run.error:
        return [run]
    per_cell = _run_reads(run, dims, name_refs, dims_key)[1]
    step = max(1, CHUNK_READS // max(per_cell, 1))
    if step >= k:
        return [run]
    return [dataclasses.replace(run, cols=run.cols[i:i + step]) for i in range(0, k, step)]
