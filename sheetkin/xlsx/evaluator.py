"""Headless evaluation of a workbook's formulas (numpy), without a spreadsheet program.

How: the cells are read by cells.py (through the input gate). Formula cells are
grouped into *runs*: consecutive cells of a row whose formulas are the same formula with
relative references shifted (recognised by rendering the run's first formula as a template
for the next columns, in growing batches, and comparing the text, so most cells are never
tokenized). Each run is tokenized once (openpyxl's formula tokenizer), parsed into an
expression tree whose relative references are column offsets, and evaluated for all its
cells at once as numpy arrays. Runs are evaluated in dependency order; a run that refers to
itself, or sits in a cycle of runs, is split into single cells (the irregular fallback); a
cycle of single cells is a circular reference, reported with its cells.

Speed: parsed formulas and run templates are kept for the rest of the process (a class's
workbooks share them); values known to be all numbers (or all booleans) without errors are
marked `pure` and take fast paths (no coercion, no error tags, references as views of the
value stores); any NaN or infinity sends an operation back to the general path, which
names the error.

Real files (see `sheetkin docs evaluator`, "What files the evaluator reads"): a defined name is a dependency of
the formulas that use it (the references behind it, through names of names, join the run's
references); a name scoped to a sheet shadows the workbook's; an array formula (CSE or a
dynamic-array spill) is a run of its own that fills its whole range (_write_array); whole
columns and rows end at the workbook's used range (_bound_whole).

Values follow Excel: numbers, text, booleans, empty cells and the errors #NULL! #DIV/0!
#VALUE! #REF! #NAME? #NUM! #N/A, which propagate per cell. Every value is an array of
shape (cells, rows, cols): (k, 1, 1) for one value per cell of a run, (k, R, C) for a range.

The modules, each importing only those before it: values.py (Val, coercions,
operators, functions, aggregates; kernels in functions.py), parse.py (formula text
to trees, Excel's limits for a formula), runs.py (Run, grouping cells into runs),
context.py (Context: a tree evaluated for a run), limits.py (hostile
input: depth, names, cells read, workbook-wide refusals), and this one: evaluate and
evaluate_sheets, defined names and array formulas, the order of runs (_schedule), Book and
the results as tables.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import compress
from operator import itemgetter
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np

from sheetkin.messages import message

from .caches import Cache
from .cells import MAX_COL, MAX_ROW, Sheet, read_book
from .context import Context, ReadsLater, lookup_name
from .coords import get_column_letter
from .functions import ERROR_TEXT, ERRORS, NA, VALUE, XlError
from .limits import (
    check_formula_text,
    check_names,
    check_reads,
    dims_signature,
    names_used,
    run_notes,
    run_pieces,
    store_dims,
)
from .package import Limits, UnusableWorkbook, shorten
from .parse import (
    Note,
    ParseError,
    Ref,
    functions_of,
    parse_formula,
    refs_of,
)
from .runs import EvaluationError, Run, group_runs, span, split_run
from .table import DYNAMIC, SUPPORTED, arity_problem
from .uncomputed import Uncomputed
from .values import BOOL, EMPTY, NUM, TEXT, Val, error_value

if TYPE_CHECKING:
    import pandas as pd  # only rows_frame builds a DataFrame: `sheetkin evaluate` loads no pandas


# --------------------------------------------------------------------------- the workbook evaluated
@dataclass
class Book:
    """A workbook's cells after evaluation."""
    path: str
    sheets: dict[str, Sheet]
    order: list[str]
    num: dict[str, np.ndarray]
    tag: dict[str, np.ndarray]
    txt: dict[str, np.ndarray]
    problems: list[str]               # unsupported functions, parse errors (cells set to #NAME?)
    runs: int = 0
    cells: int = 0
    # the runs in the order they were evaluated (parsed trees, references): what
    # sheetkin.xlsx.precedents traces through
    schedule: list = field(default_factory=list, repr=False)
    # cells "not computed here" (sheetkin.xlsx.uncomputed): {sheet: {(row, col): unknown functions}}
    not_computed: dict[str, dict[tuple[int, int], tuple[str, ...]]] = field(default_factory=dict)

    def computed(self, sheet: str, r: int, c: int) -> bool:
        """Whether sheetkin computed the cell's value: False for a formula that calls a
        function the evaluator does not know, or reads (through any chain of cells or names)
        a cell that does; its value is then #NAME? and not sheetkin's to judge."""
        return (int(r), int(c)) not in self.not_computed.get(sheet, {})

    def uncomputed(self) -> list[str]:
        """One line per cell not computed here: "Sheet!B3: FOO" (the unknown functions behind it)."""
        return [f"{s}!{get_column_letter(c)}{r}: {', '.join(fs)}"
                for s, cells in self.not_computed.items() for (r, c), fs in cells.items()]

    @property
    def notes(self) -> list[str]:
        """One line per cell problem ("Sheet!A1: what"): the problems, by another name."""
        return self.problems

    def value(self, sheet: str, r: int, c: int):
        """The value of any cell, row r and column c counted from 1 (B3 is r=3, c=2): a
        float for a number (typed or computed), a str for text, a bool, an error text such as
        '#DIV/0!', or None for an empty cell. A formula that refers to an empty cell holds 0,
        as in Excel. KeyError names the sheets when `sheet` is not one of them."""
        if sheet not in self.num:
            match = [n for n in self.num if n.casefold() == str(sheet).casefold()]
            if not match:
                raise KeyError(f"{self.path}: no sheet {sheet!r}; sheets: {', '.join(self.order)}")
            sheet = match[0]
        n, t = self.num[sheet], self.tag[sheet]
        r, c = int(r), int(c)
        if not (1 <= r < n.shape[0] and 1 <= c < n.shape[1]):
            return None
        tg = t[r, c]
        if tg == NUM:
            return float(n[r, c])
        if tg == BOOL:
            return bool(n[r, c])
        if tg == TEXT:
            return self.txt[sheet][r, c]
        if tg == EMPTY:
            return None
        return ERROR_TEXT[int(tg)]



# --------------------------------------------------------------------------- evaluation
def evaluate(path: str | Path, *, strict: bool = True, limits: Limits = Limits(),
             needed_for: str | int | None = None, saved: bool = True) -> Book:
    """Evaluate every formula of an .xlsx workbook (an .ods or .fods is converted by
    LibreOffice first, see cells.read_book); `Book.value(sheet, row, col)` then gives any
    cell. With strict, an unsupported function or an unparsable formula raises
    EvaluationError naming the cells; otherwise those cells become #NAME? and the problem is
    listed in Book.problems. needed_for: a sheet (its name, or 0 for the first) whose values
    alone are wanted: only it and the sheets it reads are read and computed (the others are
    listed, empty; their problems are not looked for), as `sheetkin evaluate` prints one.
    saved=False: Book.sheets need not hold the values the file saved for formula cells."""
    raw = read_book(path, limits, needed_for=needed_for, saved=saved)
    return evaluate_sheets(raw.path, raw.sheets, raw.order, raw.names, strict=strict, limits=limits)


def evaluate_sheets(path: str, sheets: dict[str, Sheet], order: list[str], names: dict, *,
                    strict: bool = True, limits: Limits = Limits()) -> Book:
    problems: list[str] = []
    runs: list[Run] = []
    for sh in sheets.values():
        runs.extend(_array_runs(sh, group_runs(sh)) if sh.arrays else group_runs(sh))
    check_formula_text(path, runs, limits)
    # whole columns and rows (A:A, 2:2) end at the workbook's used range
    bound = (max([sh.max_row for sh in sheets.values()] + [1]), max([sh.max_col for sh in sheets.values()] + [1]))
    name_notes: dict = {}                         # scope -> {NAME: Note} of names that cannot be evaluated
    scopes = name_scopes(names, sheets, bound, name_notes)
    name_refs = {**scopes[None], **{n: t for sc in scopes.values() for n, t in sc.items()}}
    names_key = frozenset(name_refs)
    # parse each run once (its first cell)
    unknown_in_names = _unknown_in_names(names, sheets)
    for run in runs:
        run.tree, run.error, run.refs, called = _parse_run(run.formula, run.row, int(run.cols[0]), name_refs,
                                                            names_key)
        run.unknown = _unknown_functions(run.tree, called, unknown_in_names)
        run.dynamic = bool(called & DYNAMIC)
        if run.error:
            problems.append(f"{run.where()}: {run.error}")
        else:
            if any(_is_whole(ref) for ref in run.refs):
                run.tree = _bound_whole(run.tree, bound)
                run.refs = refs_of(run.tree)
            problems.extend(run_notes(run, sheets, name_refs,
                                       {**name_notes.get(None, {}), **name_notes.get(run.sheet, {})}))
        if run.tree is not None and _has_names(run.tree):
            # a name is a dependency: what it refers to (through other names too) is
            # computed before the formula that uses it
            run.refs = run.refs + _name_deps(run.tree, run.sheet, scopes)
    for n, sh in sheets.items():
        for (r, c), what in sh.dangling.items():
            problems.append(f"{n}!{get_column_letter(c)}{r}: {what}: #N/A")
    if problems and strict:
        raise EvaluationError(f"{path}: " + "; ".join(problems[:10]) +
                              (f" (and {len(problems) - 10} more)" if len(problems) > 10 else ""))
    # value stores: the used range of each sheet (the cells that hold something); a
    # reference past it reads as empty cells, a range is clipped to it (Context.ref)
    dims = store_dims(path, sheets, limits)
    num = {n: np.zeros(d) for n, d in dims.items()}
    tag = {n: np.full(d, EMPTY, np.int8) for n, d in dims.items()}
    txt = {n: np.empty(d, dtype=object) for n, d in dims.items()}
    for n, sh in sheets.items():
        for (r, c), v in sh.consts.items():
            store_value(num[n], tag[n], txt[n], r, c, v)
        for (r, c) in getattr(sh, "dangling", {}):
            tag[n][r, c] = NA
    check_reads(path, runs, dims, name_refs, limits)      # before ordering: it scans the ranges too
    order_runs = _schedule(path, runs, dims, sheets, strict=strict, problems=problems)
    check_reads(path, order_runs, dims, name_refs, limits)  # runs split into cells read more
    ctx = Context(num, tag, txt, scopes)
    ctx.arrays = {n: sh.arrays for n, sh in sheets.items()}
    if any(run.dynamic for run in order_runs):
        ctx.pending = _formula_cells(order_runs, dims)
    marks = Uncomputed(dims)
    with np.errstate(all="ignore"):
        cells = run_all(path, order_runs, ctx, dims, name_refs, strict, problems, marks)
    return Book(path, sheets, order, num, tag, txt, problems, len(order_runs), cells, order_runs, marks.by_sheet())


def _unknown_in_names(names: dict, sheets: dict[str, Sheet]) -> dict[str, frozenset[str]]:
    """The unknown functions each defined name calls, itself (any scope; names are parsed
    again here because checking them replaces such a name by an error)."""
    out: dict[str, frozenset[str]] = {}
    for table in [names, *(sh.names for sh in sheets.values() if sh.names)]:
        for n, text in table.items():
            if "(" not in text:                    # no function call: nothing to parse
                continue
            try:
                tree = parse_formula("=" + text.removeprefix("="), 1, 1, {})
            except ParseError:
                continue
            bad = frozenset(f for f in functions_of(tree) if f not in SUPPORTED)
            if bad:
                out[n.upper()] = out.get(n.upper(), frozenset()) | bad
    return out


def _unknown_functions(tree, called: frozenset[str], unknown_in_names: dict[str, frozenset[str]]) -> frozenset[str]:
    """The functions a formula calls that the table lacks, itself or through the names it uses."""
    if tree is None:
        return frozenset()
    bad = called - SUPPORTED
    if unknown_in_names:
        for n in names_used(tree):
            bad |= unknown_in_names.get(n, frozenset())
    return bad


def _formula_cells(runs: list[Run], dims: dict) -> dict[str, np.ndarray]:
    """Per sheet, the cells that formulas compute (array formulas' whole ranges)."""
    owner = _owners(runs, dims)
    return {n: o >= 0 for n, o in owner.items()}


def run_all(path: str, order_runs: list[Run], ctx: Context, dims: dict, name_refs: dict, strict: bool,
             problems: list[str], marks: Uncomputed) -> int:
    """Every run evaluated in order, its values written into the context's stores (a run
    that cannot be evaluated: its error, and a note in `problems`); the cells not computed
    here marked as they go (`marks`); returns the cells."""
    cells, dims_key = 0, dims_signature(dims)
    for run in order_runs:
        cells += len(run.cols)
        for part in run_pieces(run, dims, name_refs, dims_key):
            try:
                _run_part(path, part, ctx, strict, problems)
            except ReadsLater as e:
                part.unknown = frozenset({str(e)})
            if ctx.pending:
                _done(ctx.pending, part)
            if part.unknown:
                marks.unknown(part, part.unknown, ctx.tag)
            elif part.refs:
                marks.reads(part, part.refs, ctx.tag)
    return cells


def _done(pending: dict[str, np.ndarray], run: Run) -> None:
    """The run's cells are computed now."""
    c0 = int(run.cols[0])
    if run.array is not None:
        pending[run.sheet][run.row:run.array[0] + 1, c0:run.array[1] + 1] = False
    else:
        pending[run.sheet][run.row, run.cols] = False


def _run_part(path: str, part: Run, ctx: Context, strict: bool, problems: list[str]) -> None:
    """One piece of a run evaluated and written into the stores (an array formula over its range)."""
    num, tag, txt = ctx.num, ctx.tag, ctx.txt
    k = len(part.cols)
    if part.error:
        code = getattr(part.error, "code", "#NAME?")
        if part.array is not None:          # the whole range holds the error
            _write_array(error_value(code), part, num, tag, txt)
            return
        v = error_value(code, k)
    else:
        try:
            if part.array is not None:
                _write_array(ctx.formula(part.tree, part), part, num, tag, txt)
                return
            v = _as_cells(ctx.formula(part.tree, part), k)
        except (EvaluationError, UnusableWorkbook, ReadsLater):
            raise
        except Exception as e:      # noqa: BLE001 - the cell's problem, not the process's
            note = (f"{part.where()}: internal error of the evaluator "
                    f"({type(e).__name__}: {shorten(e, 120)}): #VALUE!")
            if strict:
                raise EvaluationError(f"{path}: {note}") from e
            problems.append(note)
            v = error_value("#VALUE!", k)
    n = part.sheet
    where = ((part.row, slice(int(part.cols[0]), int(part.cols[0]) + k)) if part.contiguous
             else (part.row, part.cols))
    num[n][where] = v.num[:, 0, 0]
    tag[n][where] = v.tag[:, 0, 0]
    if v.txt is not None:
        txt[n][where] = v.txt[:, 0, 0]


# --------------------------------------------------------------------------- names, arrays, whole columns
def name_scopes(names: dict, sheets: dict[str, Sheet], bound, notes: dict | None = None) -> dict:
    """Parsed defined names by scope: None for the workbook's, a sheet's name for the names
    scoped to it (localSheetId). Names are case-insensitive. A name that cannot be read
    (#VALUE!, as LibreOffice), or cannot be evaluated (check_names: names in a circle,
    unknown functions...) is a constant error where it is used, and notes[scope][NAME] says why."""
    notes = {} if notes is None else notes

    def parsed(table, scope):
        out = {}
        for n, text in table.items():
            try:
                tree = parse_formula("=" + text.removeprefix("="), 1, 1, {})
            except ParseError as e:
                tree = ("const", XlError("#VALUE!"))
                notes.setdefault(scope, {})[n.upper()] = Note(
                    message("name_not_formula", n=shorten(n, 60)) + f"={shorten(text, 60)}: {e})", "#VALUE!")
            out[n.upper()] = _bound_whole(tree, bound)
        return out
    scopes: dict[str | None, dict] = {None: parsed(names, None)}
    notes.setdefault(None, {}).update(check_names(scopes[None]))
    for n, sh in sheets.items():
        scopes[n] = parsed(sh.names, n) if sh.names else {}
        if scopes[n]:
            # a sheet's names see the workbook's too: checked together, kept for the sheet
            seen = {**scopes[None], **scopes[n]}
            found = check_names(seen)
            for name in scopes[n]:
                scopes[n][name] = seen[name]
                if name in found:
                    notes.setdefault(n, {})[name] = found[name]
    return scopes



def _has_names(tree) -> bool:
    return bool(names_used(tree))             # kept per tree (limits.names_used)


def _names_in(tree, out: list):
    out.extend(names_used(tree))
    return out


def _name_deps(tree, sheet: str, scopes: dict) -> list[Ref]:
    """The references behind the names a formula uses, through names of names (each name
    followed once, so names that refer to each other end)."""
    refs, seen, todo = [], set(), _names_in(tree, [])
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        target = lookup_name(scopes, sheet, name)
        if target is not None:
            refs += refs_of(target)
            _names_in(target, todo)
    return refs


def _is_whole(ref: Ref) -> bool:
    return ((ref.r1_abs and ref.r2_abs and ref.r1 == 1 and ref.r2 == MAX_ROW)
            or (ref.c1_abs and ref.c2_abs and ref.c1 == 1 and ref.c2 == MAX_COL))


def _bound_whole(tree, bound: tuple[int, int]):
    """The tree with whole columns (rows 1 to 1,048,576) and whole rows (columns A to XFD)
    ending at the workbook's last used row (column): the same values, a store of the size
    the file holds. Rebuilt iteratively (children before parents): no recursion."""
    def fix(ref: Ref):
        r2, c2 = ref.r2, ref.c2
        if ref.r1_abs and ref.r2_abs and ref.r1 == 1 and ref.r2 == MAX_ROW:
            r2 = bound[0]
        if ref.c1_abs and ref.c2_abs and ref.c1 == 1 and ref.c2 == MAX_COL:
            c2 = bound[1]
        return ("ref", Ref(ref.sheet, ref.r1, ref.c1, r2, c2, ref.r1_abs, ref.c1_abs, ref.r2_abs, ref.c2_abs))

    def children(node):
        kind = node[0]
        return node[2] if kind == "fn" else [node[1]] if kind in ("neg", "pct") else [node[2], node[3]]
    done: list = []
    stack = [(tree, False)]
    while stack:
        node, built = stack.pop()
        kind = node[0]
        if kind not in ("fn", "neg", "pct", "bin"):
            done.append(fix(node[1]) if kind == "ref" and _is_whole(node[1]) else node)
            continue
        if not built:
            stack.append((node, True))
            stack.extend((c, False) for c in reversed(children(node)))
            continue
        n = len(children(node))
        args = done[len(done) - n:]
        del done[len(done) - n:]
        done.append(("fn", node[1], args) if kind == "fn" else (kind, args[0]) if kind in ("neg", "pct")
                    else ("bin", node[1], args[0], args[1]))
    return done[0]


def _array_runs(sheet: Sheet, runs: list[Run]) -> list[Run]:
    """The runs with each array formula's anchor on its own, marked with its range."""
    out = []
    for run in runs:
        if not any((run.row, int(c)) in sheet.arrays for c in run.cols):
            out.append(run)
            continue
        for c in run.cols.tolist():           # each its own text: parsed from its own cell
            out.append(Run(run.sheet, run.row, np.array([c]), sheet.formulas[(run.row, c)],
                           array=sheet.arrays.get((run.row, c))))
    return out


def _write_array(v: Val, run: Run, num, tag, txt) -> None:
    """An array formula's result into its range, as Excel fills it: element (i, j) in the
    cell i rows and j columns from the anchor; a single row or column (or value) repeats
    across the range; cells past the result's size are #N/A. A one-cell array formula holds
    the top-left element ({=IFERROR(A10:B10,"x")} in one cell)."""
    r0, c0 = run.row, int(run.cols[0])
    r2, c2 = cast(tuple, run.array)     # called only for an array formula: array is set
    h, w = r2 - r0 + 1, c2 - c0 + 1
    _, R, C = v.shape
    i = np.arange(h)[:, None] if R > 1 else np.zeros((h, 1), np.int64)
    j = np.arange(w)[None, :] if C > 1 else np.zeros((1, w), np.int64)
    ii, jj = np.broadcast_arrays(np.minimum(i, R - 1), np.minimum(j, C - 1))
    beyond = (np.broadcast_to(i, (h, w)) >= R) | (np.broadcast_to(j, (h, w)) >= C)
    t = np.where(beyond, NA, v.tag[0][ii, jj]).astype(np.int8)
    n = np.where(t == NUM, v.num[0][ii, jj], np.where(t == BOOL, v.num[0][ii, jj], 0.0))
    empty = t == EMPTY                       # an empty element of an array is 0
    t = np.where(empty, NUM, t).astype(np.int8)
    block = (run.sheet, slice(r0, r2 + 1), slice(c0, c2 + 1))
    num[block[0]][block[1:]] = n
    tag[block[0]][block[1:]] = t
    if v.txt is not None:
        words = np.where(t == TEXT, np.asarray(v.txt[0], dtype=object)[ii, jj], None)
        txt[block[0]][block[1:]] = words


def store_value(num, tag, txt, r, c, v):
    """A typed value (number, bool, text, an XlError) into a sheet's value stores at (r, c)."""
    if isinstance(v, bool):
        num[r, c], tag[r, c] = float(v), BOOL
    elif isinstance(v, (int, float)):
        num[r, c], tag[r, c] = float(v), NUM
    elif isinstance(v, XlError):               # an error; a str that spells one is text
        tag[r, c] = ERRORS.get(v, VALUE)
    elif isinstance(v, str):
        tag[r, c], txt[r, c] = TEXT, v


def _as_cells(v: Val, k: int) -> Val:
    """A cell holds one value: an array result that is not a single value is #VALUE!;
    a formula whose value is an empty cell holds 0 (=Z99 with Z99 empty is 0)."""
    if v.shape[1:] != (1, 1):
        return error_value("#VALUE!", k)
    if v.pure == -1 and (v.tag == EMPTY).any():
        v = Val(np.where(v.tag == EMPTY, 0.0, v.num), np.where(v.tag == EMPTY, NUM, v.tag).astype(np.int8), v.txt)
    if v.shape[0] != k:
        v = Val(np.broadcast_to(v.num, (k, 1, 1)), np.broadcast_to(v.tag, (k, 1, 1)),
                None if v.txt is None else np.broadcast_to(v.txt, (k, 1, 1)))
    return v


def _schedule(path, runs: list[Run], dims, sheets, *, strict: bool = True, problems: list | None = None) -> list[Run]:
    """Runs in dependency order; runs on a cycle (or referring to themselves) are split
    into single cells and ordered again; a cycle of single cells is circular: an
    EvaluationError with strict, else those cells get #VALUE! (as LibreOffice writes its
    Err:522) and a note naming them. A run whose references are made while it runs (OFFSET,
    INDIRECT) is split into cells, each evaluated after every run that does not depend on it."""
    runs = [r for run in runs for r in (split_run(run) if run.dynamic and len(run.cols) > 1 else [run])]
    while True:
        deps, split = _dependencies(runs, _owners(runs, dims))
        if split:
            runs = [r for i, run in enumerate(runs) for r in (split_run(run) if i in split else [run])]
            continue
        _dynamic_last(runs, deps)
        order, stuck = _topological(deps)
        if not stuck:
            return [runs[i] for i in order]
        multi = {i for i in stuck if len(runs[i].cols) > 1}
        if multi:
            runs = [r for i, run in enumerate(runs) for r in (split_run(run) if i in multi else [run])]
            continue
        _circular(path, runs, stuck, strict, problems)


def _owners(runs: list[Run], dims) -> dict[str, np.ndarray]:
    """Per sheet, the run that computes each cell (-1: none); an array formula owns its range."""
    owner = {n: np.full(d, -1, np.int32) for n, d in dims.items()}
    for i, run in enumerate(runs):
        c0 = int(run.cols[0])
        owner[run.sheet][run.row, slice(c0, c0 + len(run.cols)) if run.contiguous else run.cols] = i
    for i, run in enumerate(runs):
        if run.array is not None:
            block = owner[run.sheet][run.row:run.array[0] + 1, int(run.cols[0]):run.array[1] + 1]
            block[block == -1] = i
    return owner


def _dependencies(runs: list[Run], owner: dict[str, np.ndarray]) -> tuple[list[set[int]], set[int]]:
    """The runs each run reads, and the runs to split into cells first (a run that reads
    itself, or a range whose width changes from cell to cell)."""
    deps: list[set[int]] = []
    split = set()
    for i, run in enumerate(runs):
        d: set[int] = set()
        # a run without an error has its references (set by _parse_run)
        for ref in (cast(list, run.refs) if not run.error else ()):
            target = ref.sheet or run.sheet
            if target not in owner:
                continue
            r1, r2, c1, c2 = span(run, ref)
            if r1 < 1 or c1 < 1:
                continue
            ids = _owners_in(owner[target][r1:r2 + 1, c1:c2 + 1])
            if len(run.cols) > 1 and (i in ids or ref.c1_abs != ref.c2_abs):
                split.add(i)
            d |= ids
        deps.append(d)
    return deps, split


def _owners_in(block: np.ndarray) -> set[int]:
    """The runs that own cells of a block of the owner store (-1: none). A row of a run's
    range is mostly one owner repeated: the repeats are dropped in numpy before the set is
    made (the 360-column shaper's ranges: 600,000 set insertions, 4 % of `sheetkin
    evaluate`, issue 32)."""
    flat = block.ravel()
    if flat.size > 8:
        if flat.size > 4096:
            return set(np.unique(flat[flat >= 0]).tolist())
        flat = flat[np.concatenate(([True], flat[1:] != flat[:-1]))]
    ids = set(flat.tolist())
    ids.discard(-1)
    return ids


def _dynamic_last(runs: list[Run], deps: list[set[int]]) -> None:
    """A run with references made while it runs (OFFSET, INDIRECT) reads cells nobody can
    name before: it is ordered after every run that does not itself depend on such a run
    (what it reads is then computed; a cell it reads that is still to be computed makes it
    "not computed here", see Context.read_reference)."""
    dynamic = [i for i, run in enumerate(runs) if run.dynamic]
    if not dynamic:
        return
    users: list[list[int]] = [[] for _ in runs]
    for i, d in enumerate(deps):
        for j in d:
            users[j].append(i)
    downstream, todo = set(dynamic), list(dynamic)
    while todo:
        for u in users[todo.pop()]:
            if u not in downstream:
                downstream.add(u)
                todo.append(u)
    before = {i for i in range(len(runs)) if i not in downstream}
    for i in dynamic:
        deps[i] |= before


def _topological(deps: list[set[int]]) -> tuple[list[int], list[int]]:
    """The runs in an order where each comes after those it reads, and the runs left on a
    cycle (or reading themselves)."""
    order, indeg = [], [len(d - {i}) for i, d in enumerate(deps)]
    users: list[list[int]] = [[] for _ in deps]
    for i, d in enumerate(deps):
        for j in d - {i}:
            users[j].append(i)
    ready = [i for i, n in enumerate(indeg) if n == 0]
    self_loops = [i for i, d in enumerate(deps) if i in d]
    while ready:
        i = ready.pop()
        order.append(i)
        for u in users[i]:
            indeg[u] -= 1
            if indeg[u] == 0:
                ready.append(u)
    return order, [i for i in range(len(deps)) if indeg[i] > 0] + self_loops


def _circular(path, runs: list[Run], stuck: list[int], strict: bool, problems: list | None) -> None:
    """Single cells on a cycle: an EvaluationError with strict, else #VALUE! and a note."""
    cells = sorted({runs[i].where() for i in stuck})
    what = (message("circular_more", cells=", ".join(cells[:12]), n=len(cells) - 12) if len(cells) > 12
            else message("circular") + ", ".join(cells[:12]))
    if strict or problems is None:
        raise EvaluationError(f"{path}: {what}")
    problems.append(f"{cells[0]}: {what}: #VALUE!")
    note = Note(what, "#VALUE!")
    for i in set(stuck):
        runs[i].error = note                # no inputs now: ordered first in the next pass
        runs[i].dynamic = False


_PARSED = Cache("parsed formulas: (text, cell, names) -> (tree, error, references)", 100_000)


def _parse_run(formula: str, row: int, col: int, names: dict, names_key) -> tuple:
    """(tree, error, references, the functions it calls) of a run's first formula; kept for
    the rest of the process (a class's workbooks share their formulas), keyed by the text,
    the cell and the names."""
    key = (formula, row, col, names_key)
    hit = _PARSED.get(key)
    if hit is not None:
        return hit
    tree, error, called = None, None, frozenset[str]()
    try:
        tree = parse_formula("=" + formula, row, col, names)
        called = frozenset(functions_of(tree))
        bad = sorted(f for f in called if f not in SUPPORTED)
        if bad:
            error = Note(message("unsupported_functions" if len(bad) > 1 else "unsupported_function", f=", ".join(bad)))
        elif (wrong := arity_problem(tree)) is not None:
            error = Note(wrong, "#VALUE!")
    except ParseError as e:
        error = Note(message("cannot_read_formula", f="=" + shorten(formula, 80)) + str(e), e.code)
    hit = (tree, error, refs_of(tree) if tree is not None else [], called)
    _PARSED.put(key, hit)
    return hit


# --------------------------------------------------------------------------- formulas over given values
def parse_rows(sheet: Sheet, rows: set[int]) -> list[Run]:
    """The formula cells of some rows of a sheet (no defined names) as parsed runs, for
    evaluate_runs: sheetkin.course.localjudge evaluates a generated sheet's formulas over a
    student's numbers. A run whose ranges change width from cell to cell is split into cells
    (as _schedule does); a formula that cannot be read is left out."""
    sub = Sheet(sheet.name, sheet.state, formulas={k: f for k, f in sheet.formulas.items() if k[0] in rows})
    out = []
    for run in group_runs(sub):
        run.tree, run.error, run.refs, _ = _parse_run(run.formula, run.row, int(run.cols[0]), {}, frozenset())
        if run.error:
            continue
        varies = len(run.cols) > 1 and any(ref.c1_abs != ref.c2_abs for ref in run.refs)
        out.extend(split_run(run) if varies else [run])
    return out


def evaluate_runs(runs: list[Run], num: dict, tag: dict, txt: dict) -> list[tuple[Run, np.ndarray, np.ndarray]]:
    """(run, numbers, tags) of each run's formula evaluated over the given value stores
    (sheet -> arrays, as Book holds them), nothing written back: every run reads the
    stores as they are, whatever order the runs come in. An internal error of the
    evaluator is the cell's #VALUE!, as in evaluate_sheets without strict."""
    ctx = Context(num, tag, txt, {None: {}})
    out = []
    with np.errstate(all="ignore"):
        for run in runs:
            k = len(run.cols)
            try:
                v = _as_cells(ctx.formula(run.tree, run), k)
            except Exception:      # noqa: BLE001 - the cell's problem, not the caller's
                v = error_value("#VALUE!", k)
            out.append((run, v.num[:, 0, 0], v.tag[:, 0, 0]))
    return out


# --------------------------------------------------------------------------- results as tables
def rows_table(book: Book, sheet: str | None = None, first_col: int = 5) -> tuple[list[str], list[list], int]:
    """One sheet as (row names, rows of values, positions): rows named by column A, columns =
    positions (column E on), every row `positions` long. Rows without a name in column A are
    left out; values are floats, text, booleans, None (empty) or error texts such as '#NUM!'."""
    sheet = sheet or book.order[0]
    sh = book.sheets[sheet]
    # the table's rows start at 5: cells above (a workbook's summary counts) do not widen it
    last, filled = first_col, set[int]()
    for cells in (sh.formulas, sh.consts):
        # C-level iterators over the cells' keys, not a Python loop: the 360-column
        # shaper's 42,146 formulas, twice, were 2 % of `sheetkin evaluate` (issue 32)
        rows, cols = list(map(itemgetter(0), cells)), list(map(itemgetter(1), cells))
        last = max(last, max(compress(cols, map((4).__lt__, rows)), default=first_col))
        filled.update(compress(rows, map(first_col.__le__, cols)))
    num, tag = book.num[sheet], book.tag[sheet]
    stop = min(last + 1, num.shape[1])             # columns past the stores are empty
    names, data = [], []
    for r in range(1, sh.max_row + 1):
        label = book.value(sheet, r, 1)
        if not isinstance(label, str) or not label or r <= 4 or r not in filled:
            continue
        names.append(label)
        if r < num.shape[0]:
            values = num[r, first_col:stop].tolist()    # numbers as Book.value gives them
            tags = tag[r, first_col:stop]
            if tags.any():                  # the other cells (text, empty, errors...) one by one
                for j in np.flatnonzero(tags).tolist():
                    values[j] = book.value(sheet, r, first_col + j)
        else:
            values = [None] * max(stop - first_col, 0)
        data.append(values + [None] * (last + 1 - max(stop, first_col)))
    return names, data, last - first_col + 1


def rows_csv(book: Book, sheet: str | None = None, first_col: int = 5) -> str:
    """rows_table as CSV text, byte for byte what pandas' `rows_frame(...).to_csv(lineterminator="\\n")`
    writes (the csv module's minimal quoting, numbers as repr, empty cells empty), without pandas."""
    import csv
    import io
    names, data, width = rows_table(book, sheet, first_col)
    numeric = [set(map(type, row)) == {float} for row in data]
    # the same numbers recur (a length in every column, angles that repeat): each distinct
    # number's repr made once (the shaper: 22,078 distinct of 41,736; repr is most of the
    # CSV's cost). 0.0 and -0.0 are one key, so zeros are left to _Reprs.__missing__.
    distinct = set().union(*compress(data, numeric))
    fields = _Reprs(zip(distinct, map(repr, distinct), strict=True))
    fields.pop(0.0, None)
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["name", *range(1, width + 1)])
    for name, row, only_numbers in zip(names, data, numeric, strict=True):
        if only_numbers:
            # numbers only (most rows): the writer's field for each is its repr, joined
            # here in one pass (the shaper's 360 columns: 0.078 -> 0.061 s, issue 32)
            w.writerow([name])
            out.seek(out.tell() - 1)                # the name's field without its "\n"
            out.write("," + ",".join(map(fields.__getitem__, row)) + "\n")
        else:
            w.writerow([name, *("" if v is None else v for v in row)])
    return out.getvalue()


class _Reprs(dict):
    """number -> its repr; a number not held (a zero: 0.0 and -0.0 are one key) made as it comes."""

    def __missing__(self, x: float) -> str:
        return repr(x)


def rows_frame(book: Book, sheet: str | None = None, first_col: int = 5) -> pd.DataFrame:
    """One sheet as a table (pandas): rows named by column A, columns = positions (column E
    on). Rows without a name in column A are left out; values are floats, text, booleans or
    error texts such as '#NUM!'."""
    import pandas as pd
    names, data, width = rows_table(book, sheet, first_col)
    df = pd.DataFrame(data, index=names, columns=list(range(1, width + 1)), dtype=object)
    df.index.name = "name"
    return df


def evaluate_frame(path: str | Path, sheet: str | None = None) -> pd.DataFrame:
    """A workbook's named rows (column A) against its positions (column E onwards), every
    formula evaluated headlessly: the Python face of `sheetkin evaluate`."""
    return rows_frame(evaluate(path), sheet)
