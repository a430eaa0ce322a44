"""Evaluating an expression tree (parse.py) for all the cells of a run at once:
Context reads references from the workbook's value stores (views of a row where it can;
ranges past the used range padded or clipped, PAD_CELLS), follows defined names (a name
scoped to the sheet shadows the workbook's, lookup_name), walks chains of operators in a loop,
and calls the operators and functions of values.py. The functions that need the tree
itself (IF, IFERROR, INDEX, CHOOSE, ANCHORARRAY, SINGLE, TRUNC, FLOOR.MATH ...) are entries
of values.LAZY, each with its hook; the hooks that read the workbook (INDEX, ANCHORARRAY,
SINGLE) call back into the context's methods of those names.

Separate from evaluator.py, which reads the workbook, orders its runs, makes one Context
for the workbook and writes the results into the stores; this module never imports it.
"""
from __future__ import annotations

import math
from typing import Any, cast

import numpy as np

from . import functions as fx
from .cells import MAX_COL, MAX_ROW
from .parse import CHOOSERS, ParseError, Ref, parse_formula, tree_nodes
from .runs import EvaluationError, Run, span, target_block
from .table import FUNCTIONS, SCALAR_CONTEXT
from .values import (
    BOOL,
    EMPTY,
    NUM,
    TEXT,
    VALUE,
    Val,
    arith,
    array_constant,
    compare,
    concat,
    constant,
    error_value,
    first_error_of,
    pure_result,
    result_shape,
    to_bool,
    to_number,
    with_error,
)


def lookup_name(scopes: dict, sheet: str, name: str):
    """A name's tree as a formula on `sheet` sees it: a name scoped to that sheet shadows the
    workbook's name (Excel); None if neither exists."""
    local = scopes.get(sheet)
    if local and name in local:
        return local[name]
    return scopes[None].get(name)


def _binary_op(op: str, a: Val, b: Val) -> Val:
    try:
        result_shape(a, b)
    except ValueError:                      # ranges of different sizes (=A1:B2+A1:C3): #VALUE!
        return error_value("#VALUE!", max(a.shape[0], b.shape[0]))
    if op in ("+", "-", "*", "/", "^"):
        return arith(op, a, b)
    if op == "&":
        return concat(a, b)
    return compare(op, a, b)


REFERENCE_FUNCTIONS = frozenset({"ANCHORARRAY", "OFFSET", "INDIRECT", ":"})   # their value is a reference
# a reference these make where one value is wanted is intersected with the formula's cell
_INTERSECTED = frozenset({"INDEX", "OFFSET", "INDIRECT", ":"})
PAD_CELLS = 1 << 16      # a range up to this many cells keeps its shape past the used range


def _rows_cols(r1: int, r2: int, c1: int, c2: int, nr: int, nc: int) -> tuple[np.ndarray, np.ndarray]:
    """The rows and columns of a block that reaches past a store of nr x nc: all of them
    when the block is small (PAD_CELLS: its shape is kept, the cells outside read as
    empty), else clipped to the store (=SUM($A$1:$XFD$1048576) reads the used range)."""
    if (r2 - r1 + 1) * (c2 - c1 + 1) > PAD_CELLS:
        r2, c2 = min(r2, nr - 1), min(c2, nc - 1)
    return np.arange(r1, r2 + 1), np.arange(c1, c2 + 1)




class ReadsLater(Exception):
    """A reference made while a formula runs (OFFSET, INDIRECT) reads a cell that is not
    computed yet: the formula's cell is "not computed here" (the function named)."""


def absolute(ref: Ref, run: Run) -> Ref:
    """A reference as the run's first cell sees it: absolute rows and columns, its sheet named."""
    c0 = int(run.cols[0])
    r1 = ref.r1 if ref.r1_abs else run.row + ref.r1
    r2 = ref.r2 if ref.r2_abs else run.row + ref.r2
    c1 = ref.c1 if ref.c1_abs else c0 + ref.c1
    c2 = ref.c2 if ref.c2_abs else c0 + ref.c2
    return Ref(ref.sheet or run.sheet, min(r1, r2), min(c1, c2), max(r1, r2), max(c1, c2), True, True, True, True)


def intersect(v: Val, ref: Ref, run: Run) -> Val:
    """Implicit intersection of the range `ref` (its value v, shape (k0, R, C)) with each cell
    of the run: the cell in the formula's row (a column range) or column (a row range);
    #VALUE! where the formula's row or column misses the range."""
    k0, R, C = v.shape
    k = len(run.cols)
    # the range's own extent decides (v may be clipped to the used range: =Z1:Z1048576 in G5
    # is Z5, empty, though v holds no row 5)
    r1, r2, c1, c2 = target_block(run, ref)
    rows, cols = r2 - r1 + 1, np.broadcast_to(c2 - c1 + 1, (k,))
    i = np.full(k, run.row - r1) if rows > 1 else np.zeros(k, np.int64)
    j = np.where(cols > 1, run.cols - c1, 0)
    bad = (i < 0) | (i >= rows) | (j < 0) | (j >= cols)
    stored = ~bad & (i < R) & (j < C)
    i, j = np.where(stored, i, 0), np.where(stored, j, 0)
    cells = np.arange(k) if k0 == k else np.zeros(k, np.int64)
    if R == 0 or C == 0:                    # nothing of the range is in the store: all empty
        out = Val(np.zeros((k, 1, 1)), np.full((k, 1, 1), EMPTY, np.int8), None)
    else:
        pick = (cells, i, j)
        out = Val(np.where(stored, v.num[pick], 0.0).reshape(k, 1, 1),
                  np.where(stored, v.tag[pick], EMPTY).reshape(k, 1, 1).astype(np.int8),
                  None if v.txt is None else np.asarray(v.txt)[pick].reshape(k, 1, 1))
    return with_error(out, np.where(bad, VALUE, 0).astype(np.int8).reshape(k, 1, 1))


class Context:
    def __init__(self, num, tag, txt, scopes):
        self.num, self.tag, self.txt, self.scopes = num, tag, txt, scopes
        self.open_names: set = set()          # the names being evaluated (a cycle: #REF!)
        self.arrays: dict = {}                # sheet -> its array formulas (Sheet.arrays)
        # Excel's implicit intersection: in a formula that is not an array formula, a range
        # where one value is expected (=RADIANS(phi) with phi = $E$31:$Q$31, =E1:I1*2) is
        # the cell in the formula's column (a row range) or row (a column range); off
        # inside the arguments of functions that take ranges (SUM, SUMPRODUCT, INDEX ...),
        # which Excel evaluates as arrays. Set per run by formula().
        self.implicit = False
        # formula cells not computed yet (per sheet): a reference made while a formula runs
        # (OFFSET, INDIRECT) that reads one is "not computed here" (ReadsLater)
        self.pending: dict[str, np.ndarray] = {}

    def formula(self, tree, run: Run) -> Val:
        """A run's formula evaluated, with implicit intersection unless it is an array formula.
        In a cell that is not an array formula, an array made of constants alone (={1,2},
        ={1,2;3,4}*2) shows its first element, as in Excel; any other array there stays as it
        is (#VALUE! in the cell: a reference's values were intersected before)."""
        self.implicit = run.array is None
        try:
            v = self.eval(tree, run)
        finally:
            self.implicit = False
        if run.array is None and v.shape[1:] != (1, 1) and not any(
                node[0] in ("ref", "name") or (node[0] == "fn" and node[1] in _INTERSECTED | REFERENCE_FUNCTIONS)
                for node in tree_nodes(tree)):
            return Val(v.num[:, :1, :1], v.tag[:, :1, :1], None if v.txt is None else v.txt[:, :1, :1])
        return v

    def name(self, name: str, run: Run):
        """The tree a name stands for in a formula of run's sheet, or None."""
        return lookup_name(self.scopes, run.sheet, name)

    def ref(self, ref: Ref, run: Run) -> Val:
        sheet = ref.sheet or run.sheet
        if sheet not in self.num:
            return error_value("#REF!", len(run.cols))
        if (ref.r1, ref.c1, ref.r1_abs, ref.c1_abs) == (ref.r2, ref.c2, ref.r2_abs, ref.c2_abs) and run.contiguous:
            return self._row_stretch(sheet, ref, run)
        if len(run.cols) == 1 or (ref.c1_abs and ref.c2_abs):
            return self._one_block(sheet, ref, run)
        return self._block_per_cell(sheet, ref, run)

    def _stored(self, sheet: str, rows, cols, shape) -> Val:
        """The stores' cells at [rows, cols] (views where they can be), reshaped; pure when
        they hold only numbers or only booleans."""
        tag = self.tag[sheet][rows, cols].reshape(shape)
        num = self.num[sheet][rows, cols].reshape(shape)
        if not tag.any():
            return Val(num, tag, None, NUM)
        if (tag == BOOL).all():
            return Val(num, tag, None, BOOL)
        txt = self.txt[sheet][rows, cols].reshape(shape) if (tag == TEXT).any() else None
        return Val(num, tag, txt)

    def _row_stretch(self, sheet: str, ref: Ref, run: Run) -> Val:
        """One cell per cell of the run, adjacent: views of one stretch of a row."""
        r = ref.r1 if ref.r1_abs else run.row + ref.r1
        k = len(run.cols)
        c = ref.c1 if ref.c1_abs else int(run.cols[0]) + ref.c1
        if r < 1 or c < 1:
            return error_value("#REF!", k)
        n = 1 if ref.c1_abs else k
        if r >= self.tag[sheet].shape[0] or c + n > self.tag[sheet].shape[1]:
            return self._gather(sheet, np.array([r]), (c + np.arange(n))[:, None])   # past the used range
        return self._stored(sheet, r, slice(c, c + n), (n, 1, 1))

    def _one_block(self, sheet: str, ref: Ref, run: Run) -> Val:
        """One block for all the cells (a single cell's range, or absolute columns): a view."""
        r1, r2, c1, c2 = span(run, ref)
        if r1 < 1 or c1 < 1:
            return error_value("#REF!", len(run.cols))
        nr, nc = self.tag[sheet].shape
        if r2 >= nr or c2 >= nc:                   # past the used range
            rows, cols = _rows_cols(r1, r2, c1, c2, nr, nc)
            return self._gather(sheet, rows, cols[None, :])
        return self._stored(sheet, slice(r1, r2 + 1), slice(c1, c2 + 1), (1, r2 - r1 + 1, c2 - c1 + 1))

    def _block_per_cell(self, sheet: str, ref: Ref, run: Run) -> Val:
        """A block per cell of the run (relative columns), gathered."""
        r1, r2, c1, c2 = target_block(run, ref)
        if r1 < 1 or int(c1.min()) < 1:
            return error_value("#REF!", len(run.cols))
        absolute = ref.c1_abs and ref.c2_abs
        width = int(c2[0] - c1[0]) + 1
        nr, nc = self.tag[sheet].shape
        if r2 >= nr or int(c1.max()) + width > nc:     # past the used range
            rows, offsets = _rows_cols(r1, r2, 0, width - 1, nr, max(0, nc - int(c1.min())))
            cols = (c1[:1] if absolute else c1)[:, None] + offsets[None, :]
            return self._gather(sheet, rows, cols)
        cols = (c1[:1] if absolute else c1)[:, None] + np.arange(width)[None, :]   # (k, C)
        rows = np.arange(r1, r2 + 1)
        at = (rows[:, None, None], cols[None, :, :])
        num = self.num[sheet][at].transpose(1, 0, 2)
        tag = self.tag[sheet][at].transpose(1, 0, 2)
        txt = self.txt[sheet][at].transpose(1, 0, 2) if (tag == TEXT).any() else None
        return Val(num, tag, txt)

    def _gather(self, sheet: str, rows: np.ndarray, cols: np.ndarray) -> Val:
        """Cells rows x cols[i] for each cell i of a run, shape (k, R, C); cells past the
        store (the used range) read as empty."""
        nr, nc = self.tag[sheet].shape
        inside = (rows < nr)[None, :, None] & (cols < nc)[:, None, :]
        idx = (np.where(rows < nr, rows, 0)[None, :, None], np.where(cols < nc, cols, 0)[:, None, :])
        tag = np.where(inside, self.tag[sheet][idx], EMPTY).astype(np.int8)
        num = np.where(inside, self.num[sheet][idx], 0.0)
        # numpy's stubs refuse None as where's fill (numpy takes it: an object array of text)
        txt = cast(np.ndarray, np.where(inside, self.txt[sheet][idx], None)) if (tag == TEXT).any() else None
        return Val(num, tag, txt, NUM if not tag.any() else -1)

    def eval(self, node, run: Run) -> Val:
        kind = node[0]
        if kind == "const":
            return constant(node[1])
        if kind == "ref":
            v = self.ref(node[1], run)
            return intersect(v, node[1], run) if self.implicit and v.shape[1:] != (1, 1) else v
        if kind == "name":
            tree = self.name(node[1], run)
            if tree is None:
                return error_value("#NAME?")
            if node[1] in self.open_names:          # a name that refers back to itself
                return error_value("#REF!")
            self.open_names.add(node[1])
            try:
                return self.eval(tree, run)
            finally:
                self.open_names.discard(node[1])
        if kind == "neg":
            x = self.eval(node[1], run)
            if x.pure != -1:                # numbers or booleans: 0 - x, finite, as arith makes it
                return pure_result(0.0 - x.num)
            return arith("-", constant(0.0), x)
        if kind == "pct":
            return arith("/", self.eval(node[1], run), constant(100.0))
        if kind == "bin":
            # a chain =A1+A2+...+A4000 leans left: walk its spine in a loop, not recursively
            spine = []
            while node[0] == "bin":
                spine.append(node)
                node = node[2]
            a = self.eval(node, run)
            for node in reversed(spine):
                a = _binary_op(node[1], a, self.eval(node[3], run))
            return a
        if kind == "missing":
            return constant(0.0)
        if kind == "array":
            return array_constant(node[1])
        if kind == "fn":
            return self.call(node[1], node[2], run)
        raise EvaluationError(f"cannot evaluate {node!r}")

    def call(self, name: str, args, run: Run) -> Val:
        if self.implicit and name not in SCALAR_CONTEXT:
            self.implicit = False             # its arguments are ranges or arrays (Excel)
            try:
                v = self._call(name, args, run)
            finally:
                self.implicit = True
            if v.shape[1:] != (1, 1) and name in _INTERSECTED:
                # a reference made where one value is wanted (=INDEX(B1:B5,0) in D2: B2):
                # intersected with the formula's cell, as a typed range is
                ref = self.reference(("fn", name, args), run)
                if ref is not None and v.shape[1:] == (ref.r2 - ref.r1 + 1, ref.c2 - ref.c1 + 1):
                    return intersect(v, ref, run)
            return v
        return self._call(name, args, run)

    def _call(self, name: str, args, run: Run) -> Val:
        f = FUNCTIONS.get(name)
        if f is None:
            return error_value("#NAME?", len(run.cols))
        if f.lazy:
            return f.kernel(self, args, run)
        if not f.ranges:
            return f.kernel(*(self.eval(a, run) for a in args))
        vals = [self.eval(a, run) for a in args]
        # a reference, even to one cell or through a defined name, is read like a range:
        # text and booleans skipped
        ranges = [a[0] == "ref" or (a[0] == "name" and (self.name(a[1], run) or ("",))[0] == "ref")
                  or (a[0] == "fn" and a[1] in REFERENCE_FUNCTIONS) for a in args]
        return f.kernel(vals, ranges)

    def spill(self, args, run: Run) -> Val:
        """Excel 365's E1# (written _xlfn.ANCHORARRAY(E1)): the range an array formula at E1
        fills; #REF! where E1 holds no array formula."""
        if len(args) != 1 or args[0][0] != "ref" or args[0][1].is_range:
            return error_value("#REF!", len(run.cols))
        ref = args[0][1]
        sheet = ref.sheet or run.sheet
        r = ref.r1 if ref.r1_abs else run.row + ref.r1
        cols = [ref.c1] if ref.c1_abs else [c + ref.c1 for c in run.cols.tolist()]
        ends = [self.arrays.get(sheet, {}).get((r, c)) for c in cols]
        if any(e is None for e in ends) or len({(e[0] - r, e[1] - c) for e, c in zip(ends, cols, strict=False)}) != 1:
            return error_value("#REF!", len(run.cols))
        (r2, c2), c = ends[0], cols[0]
        block = Ref(sheet, r, c if ref.c1_abs else c - int(run.cols[0]), r2,
                    c2 if ref.c1_abs else c2 - int(run.cols[0]), True, ref.c1_abs, True, ref.c1_abs)
        return self.ref(block, run)

    def single(self, args, run: Run) -> Val:
        """Excel 365's @ (written _xlfn.SINGLE(...)), implicit intersection: of a range, the
        cell in the formula's row (a column range) or column (a row range); of an array, its
        first element; #VALUE! where the formula's row or column misses the range."""
        if len(args) != 1:
            return error_value("#VALUE!", len(run.cols))
        v = self.eval(args[0], run)
        _, R, C = v.shape
        if (R, C) == (1, 1):
            return v
        if args[0][0] != "ref":
            return Val(v.num[:, :1, :1], v.tag[:, :1, :1], None if v.txt is None else v.txt[:, :1, :1])
        return intersect(v, args[0][1], run)

    def reference(self, node, run: Run) -> Ref | None:
        """The block a reference-valued tree stands for in the run's first cell, absolute (sheet
        set): a reference, a name of one, OFFSET(...), INDIRECT(...), INDEX(reference, ...);
        None where it makes no reference (#REF!)."""
        kind = node[0]
        if kind == "ref":
            return absolute(node[1], run)
        if kind == "name":
            tree = self.name(node[1], run)
            return self.reference(tree, run) if tree is not None and node[1] not in self.open_names else None
        if kind != "fn":
            return None
        name, args = node[1], node[2]
        if name == "OFFSET":
            return self._offset(args, run)
        if name == "INDIRECT":
            return self._indirect(args, run)
        if name == "INDEX":
            return self._index_reference(args, run)
        if name == ":":
            return self._span(args, run)
        if name in CHOOSERS:
            chosen, _ = self._choice(name, args, run)
            return None if chosen is None else self.reference(chosen, run)
        return None

    def _choice(self, name: str, args, run: Run) -> tuple[Any, str | None]:
        """The argument that IF(test, a, [b]) or CHOOSE(k, a, b, ...) picks in the run's first
        cell, where a range ends at it (A1:IF(B1>0,A5,A9), A1:CHOOSE(2,A3,A5): Excel uses the
        picked reference); else (None, the error Excel gives: #VALUE! for no such argument, a
        text test or index, the test's or index's own error)."""
        first = self._first_value(args[0], run)
        if name == "IF":
            test, err = to_bool(first)
            k = 1 if bool(test.reshape(-1)[0]) else 2
        else:
            n, err = to_number(first)
            k = int(n.reshape(-1)[0]) if not err.any() and math.isfinite(n.reshape(-1)[0]) else 0
        if err.any():
            return None, str(fx.ERROR_TEXT[int(err.reshape(-1)[0])])
        if not 1 <= k < len(args) or args[k][0] == "missing":
            return None, "#VALUE!"
        return args[k], None

    def _span(self, args, run: Run) -> Ref | None:
        """start:end, either a reference-returning function (A1:INDEX(A1:A9,3)): the smallest
        block that holds both, on their sheet (None, #REF!, for two sheets or no reference)."""
        a, b = self.reference(args[0], run), self.reference(args[1], run)
        if a is None or b is None or a.sheet != b.sheet:
            return None
        return Ref(a.sheet, min(a.r1, b.r1), min(a.c1, b.c1), max(a.r2, b.r2), max(a.c2, b.c2),
                   True, True, True, True)

    def range_value(self, args, run: Run) -> Val:
        """The values of start:end (see _span), read after the cells it may read, as OFFSET's;
        an end at IF or CHOOSE that picks no argument is that error (#VALUE!), as in Excel."""
        ends = []
        for end in args:            # an IF or CHOOSE end replaced by what it picks, its test run once
            if end[0] == "fn" and end[1] in CHOOSERS:
                end, code = self._choice(end[1], end[2], run)
                if code is not None:
                    return error_value(code, len(run.cols))
            ends.append(end)
        return self.read_reference(self.reference(("fn", ":", ends), run), run, "the range A1:INDEX(...)")

    def _first_value(self, node, run: Run) -> Val:
        """A tree's value in the run's first cell (where a reference is made, as OFFSET's)."""
        v = self.eval(node, run)
        return Val(v.num[:1, :1, :1], v.tag[:1, :1, :1], None if v.txt is None else v.txt[:1, :1, :1])

    def _number(self, node, run: Run, default: float | None = None) -> float | None:
        """An argument's value in the run's first cell as a number; None for an error or text."""
        if node is None or node[0] == "missing":
            return default
        n, err = to_number(self._first_value(node, run))
        return None if err.any() else float(n.reshape(-1)[0])

    def _offset(self, args, run: Run) -> Ref | None:
        base = self.reference(args[0], run)
        if base is None:
            return None
        rows, cols = self._number(args[1], run), self._number(args[2], run)
        h = self._number(args[3] if len(args) > 3 else None, run, float(base.r2 - base.r1 + 1))
        w = self._number(args[4] if len(args) > 4 else None, run, float(base.c2 - base.c1 + 1))
        if None in (rows, cols, h, w) or int(cast(float, h)) == 0 or int(cast(float, w)) == 0:
            return None
        r1, c1 = base.r1 + int(cast(float, rows)), base.c1 + int(cast(float, cols))
        hh, ww = int(cast(float, h)), int(cast(float, w))
        r2, c2 = r1 + hh - 1 if hh > 0 else r1, c1 + ww - 1 if ww > 0 else c1
        r1, r2 = (r1, r2) if hh > 0 else (r1 + hh + 1, r1)
        c1, c2 = (c1, c2) if ww > 0 else (c1 + ww + 1, c1)
        if r1 < 1 or c1 < 1 or r2 > MAX_ROW or c2 > MAX_COL:
            return None
        return Ref(base.sheet, r1, c1, r2, c2, True, True, True, True)

    def _indirect(self, args, run: Run) -> Ref | None:
        v = self.eval(args[0], run)
        if v.tag.reshape(-1)[0] != TEXT or v.txt is None:
            return None
        a1 = len(args) < 2 or args[1][0] == "missing" or self._number(args[1], run) != 0
        text = str(v.txt.reshape(-1)[0]).strip()
        if not a1 or not text:
            return None                          # R1C1 text: not computed here (#REF!)
        try:
            tree = parse_formula("=" + text, run.row, int(run.cols[0]), {})
        except ParseError:
            return None
        if tree[0] == "name":
            target = self.name(tree[1], run)
            return self.reference(target, run) if target is not None else None
        return absolute(tree[1], run) if tree[0] == "ref" else None

    def _index_reference(self, args, run: Run) -> Ref | None:
        base = self.reference(args[0], run)
        if base is None:
            return None
        r = self._number(args[1] if len(args) > 1 else None, run, 0.0)
        c = self._number(args[2] if len(args) > 2 else None, run, None)
        if r is None:
            return None
        ri, ci, bad = fx.index_positions(base.r2 - base.r1 + 1, base.c2 - base.c1 + 1, np.array([r]),
                                         None if c is None else np.array([c]))
        if bad[0]:
            return None
        r1, r2 = (base.r1, base.r2) if ri[0] < 0 else (base.r1 + int(ri[0]),) * 2
        c1, c2 = (base.c1, base.c2) if ci[0] < 0 else (base.c1 + int(ci[0]),) * 2
        return Ref(base.sheet, r1, c1, r2, c2, True, True, True, True)

    def read_reference(self, ref: Ref | None, run: Run, function: str) -> Val:
        """The values of a reference made while the formula runs; #REF! for none. A cell in
        it still to be computed (ordered after this one) raises ReadsLater."""
        if ref is None:
            return error_value("#REF!", len(run.cols))
        pending = self.pending.get(cast(str, ref.sheet))
        if pending is not None and pending[ref.r1:ref.r2 + 1, ref.c1:ref.c2 + 1].any():
            raise ReadsLater(function)
        v = self.ref(ref, run)
        return intersect(v, ref, run) if self.implicit and v.shape[1:] != (1, 1) else v

    def index(self, args, run: Run) -> Val:
        """INDEX(array, row, [column]): one element per cell of the run, or a whole row or
        column where an index is 0."""
        arr = self.eval(args[0], run)
        k0, R, C = arr.shape
        r, er = (to_number(self.eval(args[1], run)) if len(args) > 1
                 else (np.zeros((1, 1, 1)), np.zeros((1, 1, 1), np.int8)))
        c, ec = (to_number(self.eval(args[2], run)) if len(args) > 2 and args[2][0] != "missing"
                 else (None, np.zeros((1, 1, 1), np.int8)))
        ri, ci, bad = fx.index_positions(R, C, r, c)
        err = first_error_of(er, ec, bad)
        k = max(k0, err.shape[0])
        ri, ci, err = (np.broadcast_to(x, (k, 1, 1)).reshape(k) for x in (ri, ci, err))
        if (ri >= 0).all() and (ci >= 0).all():
            cells = np.arange(k) if k0 == k else np.zeros(k, np.int64)
            pick = (cells, ri, ci)
            v = Val(arr.num[pick].reshape(k, 1, 1), arr.tag[pick].reshape(k, 1, 1).astype(np.int8),
                    None if arr.txt is None else np.asarray(arr.txt)[pick].reshape(k, 1, 1))
            return with_error(v, err.reshape(k, 1, 1))
        if k == 1:                               # a whole row or column of the array
            rs = slice(None) if ri[0] < 0 else slice(ri[0], ri[0] + 1)
            cs = slice(None) if ci[0] < 0 else slice(ci[0], ci[0] + 1)
            v = Val(arr.num[:, rs, cs], arr.tag[:, rs, cs], None if arr.txt is None else arr.txt[:, rs, cs])
            return with_error(v, err.reshape(1, 1, 1))
        return error_value("#VALUE!", k)
