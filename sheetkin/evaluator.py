"""Headless evaluation of a workbook's formulas (numpy), without a spreadsheet program.

How: the cells are read by xlsxread (through the input gate). Formula cells are
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

Real files (see README, "What files the evaluator reads"): a defined name is a dependency of
the formulas that use it (the references behind it, through names of names, join the run's
references); a name scoped to a sheet shadows the workbook's; an array formula (CSE or a
dynamic-array spill) is a run of its own that fills its whole range (_write_array); whole
columns and rows end at the workbook's used range (_bound_whole).

Values follow Excel: numbers, text, booleans, empty cells and the errors #NULL! #DIV/0!
#VALUE! #REF! #NAME? #NUM! #N/A, which propagate per cell. Every value is an array of
shape (cells, rows, cols): (k, 1, 1) for one value per cell of a run, (k, R, C) for a range.
"""
from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from operator import itemgetter
from pathlib import Path

import numpy as np
import pandas as pd
from openpyxl.formula.tokenizer import Token, Tokenizer
from openpyxl.utils import column_index_from_string, get_column_letter

from . import functions as fx
from .functions import DIV0, ERROR_TEXT, ERRORS, NA, NAME, NULL, NUMERR, REF, VALUE  # noqa: F401
from .xlsxread import _MAX_COL, _MAX_ROW, Sheet, _Template, read_book
from .xlsxsafe import Limits, UnusableWorkbook, _show

NUM, BOOL, TEXT, EMPTY = 0, 1, 2, 3


class EvaluationError(ValueError):
    """A workbook that cannot be evaluated as a whole (circular reference, unsupported
    function with strict=True); str() names the file and the cells."""


# --------------------------------------------------------------------------- values
class Val:
    """A value per cell of a run: num float64 (k, R, C); tag int8, NUM BOOL TEXT EMPTY or
    an error code; txt an object array of str where tag == TEXT (or None); pure NUM or BOOL
    when every tag is that one, else -1 (the fast paths: no coercion, no error to carry).
    The tags of a pure value are made only when asked for."""
    __slots__ = ("num", "_tag", "txt", "pure")

    def __init__(self, num: np.ndarray, tag: np.ndarray | None, txt: np.ndarray | None = None, pure: int = -1):
        self.num, self._tag, self.txt, self.pure = num, tag, txt, pure

    @property
    def tag(self) -> np.ndarray:
        if self._tag is None:
            self._tag = np.full(self.num.shape, self.pure, np.int8)
        return self._tag

    @property
    def shape(self):
        return self.num.shape


def _pure(num: np.ndarray, kind: int = NUM) -> Val:
    """A result known to be all numbers (or all booleans), without errors."""
    return Val(num, None, None, kind)


_CONSTS: dict = {}


def _const(value, k=1) -> Val:
    if k == 1 and type(value) in (bool, float, int):
        key = (type(value), value)
        v = _CONSTS.get(key)
        if v is None:
            v = _const_new(value, 1)
            v.pure = BOOL if type(value) is bool else NUM
            v.num.setflags(write=False)
            v.tag.setflags(write=False)
            if len(_CONSTS) < 10000:
                _CONSTS[key] = v
        return v
    return _const_new(value, k)


def _const_new(value, k) -> Val:
    if isinstance(value, bool):
        return Val(np.full((k, 1, 1), float(value)), np.full((k, 1, 1), BOOL, np.int8))
    if isinstance(value, (int, float)):
        return Val(np.full((k, 1, 1), float(value)), np.zeros((k, 1, 1), np.int8))
    if isinstance(value, str) and value in ERRORS:
        return Val(np.zeros((k, 1, 1)), np.full((k, 1, 1), ERRORS[value], np.int8))
    txt = np.empty((k, 1, 1), dtype=object)
    txt[...] = value
    return Val(np.zeros((k, 1, 1)), np.full((k, 1, 1), TEXT, np.int8), txt)


def _error_of(*tags) -> np.ndarray:
    """The first error among the operands (Excel reports the leftmost), else 0."""
    out = np.zeros(np.broadcast_shapes(*(t.shape for t in tags)), np.int8)
    for t in reversed(tags):
        out = np.where(t >= 10, t, out)
    return out


def _texts(v: Val) -> np.ndarray:
    return v.txt if v.txt is not None else np.full(v.shape, None, dtype=object)


_NUMERIC_TEXT = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*$")


def _to_number(v: Val):
    """Arithmetic coercion: numbers, booleans; empty is 0; numeric text converts;
    other text is #VALUE!. Returns (num, error tags)."""
    num, err = v.num, np.where(v.tag >= 10, v.tag, 0).astype(np.int8)
    text = v.tag == TEXT
    if text.any():
        num = num.copy()
        for idx in zip(*np.nonzero(text)):
            t = str(v.txt[idx])
            if _NUMERIC_TEXT.match(t):          # not Python's float(): "1_000", "inf" are not numbers
                num[idx] = float(t)
            else:
                err[idx] = VALUE
    return num, err


def _result(num, err) -> Val:
    """A numeric result; NaN or infinity where no error is set yet becomes #NUM!."""
    bad = (err == 0) & ~np.isfinite(num)
    tag = np.where(bad, NUMERR, err).astype(np.int8)
    return Val(np.where(tag == 0, num, 0.0), tag, None, -1 if tag.any() else NUM)


def _to_bool(v: Val):
    """Logical coercion (IF, AND...): numbers non-zero, booleans, empty FALSE; text #VALUE!."""
    if v.pure != -1:
        return v.num != 0, np.zeros(v.shape, np.int8)
    err = np.where(v.tag >= 10, v.tag, np.where(v.tag == TEXT, VALUE, 0)).astype(np.int8)
    return v.num != 0, err


def _number_text(x: float) -> str:
    """A number as Excel's general format shows it in text (=2&"" is "2")."""
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    s = f"{x:.15g}"
    if "e" in s:
        mant, exp = s.split("e")
        s = f"{mant}E{int(exp):+03d}".replace("E+", "E+")
    return s


def _to_text(v: Val) -> tuple[np.ndarray, np.ndarray]:
    out = np.empty(v.shape, dtype=object)
    for idx in np.ndindex(v.shape):
        t = v.tag[idx]
        out[idx] = (v.txt[idx] if t == TEXT else "" if t == EMPTY else
                    ("TRUE" if v.num[idx] else "FALSE") if t == BOOL else _number_text(v.num[idx]))
    return out, np.where(v.tag >= 10, v.tag, 0).astype(np.int8)


# --------------------------------------------------------------------------- operators
_OPS = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide, "^": np.power}


def _arith(op: str, a: Val, b: Val) -> Val:
    if a.pure != -1 and b.pure != -1:            # numbers, booleans (1, 0): no coercion, no errors
        with np.errstate(all="ignore"):
            r = _OPS[op](a.num, b.num)
        # x/0, 0^-1 and overflow give NaN or infinity, and so a sum that is not finite (a
        # sum that overflows only sends finite values the general way): that path names the error
        if math.isfinite(r.sum()) and (op != "^" or not ((a.num == 0) & (b.num == 0)).any()):
            return _pure(r)
    an, ae = _to_number(a)
    bn, be = _to_number(b)
    err = _error_of(ae, be)
    with np.errstate(all="ignore"):
        if op == "+":
            r = an + bn
        elif op == "-":
            r = an - bn
        elif op == "*":
            r = an * bn
        elif op == "/":
            r = an / bn
            err = np.where((err == 0) & (bn == 0), DIV0, err).astype(np.int8)
        else:   # "^"
            r = np.power(an, bn)
            err = np.where((err == 0) & (an == 0) & (bn < 0), DIV0, err).astype(np.int8)
            err = np.where((err == 0) & (an == 0) & (bn == 0), NUMERR, err).astype(np.int8)   # Excel: 0^0
    return _result(r, err)


def _rank(tag):
    """Excel's order of types in comparisons: numbers < text < booleans."""
    return np.where(tag == TEXT, 1, np.where(tag == BOOL, 2, 0))


def _compare(op: str, a: Val, b: Val) -> Val:
    if a.pure == NUM and b.pure == NUM:          # the general path's arithmetic, without tags
        an, bn = a.num, b.num
        with np.errstate(all="ignore"):
            d = an - bn
            near = np.abs(d) <= 4 * np.finfo(float).eps * np.maximum(np.abs(an), np.abs(bn))
        diff = np.where(near, 0.0, np.sign(d))
        return _pure(_COMPARE[op](diff, 0).astype(float), BOOL)
    shape = np.broadcast_shapes(a.shape, b.shape)
    at, bt = np.broadcast_to(a.tag, shape), np.broadcast_to(b.tag, shape)
    # an empty cell takes the other side's type (0, "" or FALSE)
    at_eff = np.where(at == EMPTY, np.where(bt == EMPTY, NUM, bt), at)
    bt_eff = np.where(bt == EMPTY, at_eff, bt)
    an, bn = np.broadcast_to(a.num, shape), np.broadcast_to(b.num, shape)
    ra, rb = _rank(at_eff), _rank(bt_eff)
    # numbers compare as Excel shows them, to about 15 significant digits (=0.1+0.2=0.3 is TRUE)
    with np.errstate(all="ignore"):
        d = an - bn
        near = np.abs(d) <= 4 * np.finfo(float).eps * np.maximum(np.abs(an), np.abs(bn))
    diff = np.where(ra != rb, np.sign(ra - rb).astype(float), np.where(near, 0.0, np.sign(d)))
    text = (at_eff == TEXT) & (bt_eff == TEXT)
    if text.any():
        ta, tb = np.broadcast_to(_texts(a), shape), np.broadcast_to(_texts(b), shape)
        diff = diff.copy()
        for idx in zip(*np.nonzero(text)):
            x = "" if at[idx] == EMPTY else str(ta[idx]).casefold()
            y = "" if bt[idx] == EMPTY else str(tb[idx]).casefold()
            diff[idx] = (x > y) - (x < y)
    res = {"=": diff == 0, "<>": diff != 0, "<": diff < 0, ">": diff > 0,
           "<=": diff <= 0, ">=": diff >= 0}[op]
    err = _error_of(at, bt)
    return Val(np.where(err == 0, res.astype(float), 0.0), np.where(err == 0, BOOL, err).astype(np.int8))


_COMPARE = {"=": np.equal, "<>": np.not_equal, "<": np.less, ">": np.greater,
            "<=": np.less_equal, ">=": np.greater_equal}


def _concat(a: Val, b: Val) -> Val:
    ta, ea = _to_text(a)
    tb, eb = _to_text(b)
    shape = np.broadcast_shapes(ta.shape, tb.shape)
    ta, tb = np.broadcast_to(ta, shape), np.broadcast_to(tb, shape)
    out = np.empty(shape, dtype=object)
    for idx in np.ndindex(shape):
        out[idx] = ta[idx] + tb[idx]
    err = _error_of(ea, eb)
    return Val(np.zeros(shape), np.where(err == 0, TEXT, err).astype(np.int8), out)


def _select(cond: np.ndarray, a: Val, b: Val) -> Val:
    if a.pure == b.pure != -1:
        return _pure(np.where(cond, a.num, b.num), a.pure)
    shape = np.broadcast_shapes(cond.shape, a.shape, b.shape)
    txt = None
    if a.txt is not None or b.txt is not None:
        txt = np.where(cond, np.broadcast_to(_texts(a), shape), np.broadcast_to(_texts(b), shape))
    return Val(np.where(cond, a.num, b.num), np.where(cond, a.tag, b.tag).astype(np.int8), txt)


def _with_error(v: Val, err: np.ndarray) -> Val:
    if not err.any():
        return v
    shape = np.broadcast_shapes(v.shape, err.shape)
    return Val(np.where(err != 0, 0.0, v.num), np.where(err != 0, err, v.tag).astype(np.int8),
               None if v.txt is None else np.broadcast_to(v.txt, shape))


# --------------------------------------------------------------------------- functions
def _unary(fn, domain=None):
    def f(x: Val) -> Val:
        if x.pure != -1:
            with np.errstate(all="ignore"):
                r = fn(x.num)
            if math.isfinite(r.sum()) and (domain is None or domain(x.num).all()):
                return _pure(r)
        n, err = _to_number(x)
        with np.errstate(all="ignore"):
            r = fn(n)
            if domain is not None:
                err = np.where((err == 0) & ~domain(n), NUMERR, err).astype(np.int8)
        return _result(r, err)
    return f


def _binary(fn, check=None):
    def f(a: Val, b: Val) -> Val:
        if a.pure != -1 and b.pure != -1:
            with np.errstate(all="ignore"):
                r = fn(a.num, b.num)
                if math.isfinite(r.sum()) and (check is None or not np.any(check(a.num, b.num))):
                    return _pure(r)
        an, ae = _to_number(a)
        bn, be = _to_number(b)
        err = _error_of(ae, be)
        with np.errstate(all="ignore"):
            r = fn(an, bn)
            if check is not None:
                err = np.where(err == 0, check(an, bn), err).astype(np.int8)
        return _result(r, err)
    return f


def _round(x, n):
    """Excel's ROUND: half away from zero, on the number as its 15 significant digits show
    it (=ROUND(1.005, 2) is 1.01, although the binary 1.005 is a little less)."""
    from decimal import ROUND_HALF_UP, Decimal, InvalidOperation
    x, n = np.broadcast_arrays(np.asarray(x, float), np.asarray(n, float))
    out = np.empty(x.shape)
    for idx in np.ndindex(x.shape):
        v, d = x[idx], int(n[idx])
        if not math.isfinite(v):
            out[idx] = v
            continue
        try:
            out[idx] = float(Decimal(f"{v:.15g}").quantize(Decimal(1).scaleb(-d), rounding=ROUND_HALF_UP))
        except InvalidOperation:          # more digits than the number has: unchanged
            out[idx] = v if d > 0 else 0.0
    return out


def _TRIG_OK(x):
    return np.abs(x) < 134217728.0


SCALAR_FUNCS = {
    # Excel refuses trigonometry of |x| >= 2^27 (#NUM!): too few digits are left for the angle
    "SIN": _unary(np.sin, _TRIG_OK), "COS": _unary(np.cos, _TRIG_OK), "TAN": _unary(np.tan, _TRIG_OK),
    "ASIN": _unary(np.arcsin, lambda x: np.abs(x) <= 1), "ACOS": _unary(np.arccos, lambda x: np.abs(x) <= 1),
    "ATAN": _unary(np.arctan), "SQRT": _unary(np.sqrt, lambda x: x >= 0),
    "RADIANS": _unary(np.radians), "DEGREES": _unary(np.degrees), "ABS": _unary(np.abs),
    "SIGN": _unary(np.sign), "EXP": _unary(np.exp), "LN": _unary(np.log, lambda x: x > 0),
    "LOG10": _unary(np.log10, lambda x: x > 0),
    # Excel's ATAN2 takes (x, y); ATAN2(0, 0) is #DIV/0!
    "ATAN2": _binary(lambda x, y: np.arctan2(y, x), lambda x, y: np.where((x == 0) & (y == 0), DIV0, 0)),
    "MOD": _binary(lambda a, b: a - b * np.floor(a / b), lambda a, b: np.where(b == 0, DIV0, 0)),
    "POWER": _binary(np.power, lambda a, b: np.where((a == 0) & (b < 0), DIV0, np.where((a == 0) & (b == 0), NUMERR, 0))),
    "ROUND": _binary(lambda x, n: _round(x, np.trunc(n))),
    "INT": _unary(fx.int_), "FLOOR": _binary(fx.floor, fx.floor_check),
    "CEILING": _binary(fx.ceiling, fx.ceiling_check),
}


def _values_of(args: list[Val], ranges: list[bool], *, numbers_only_in_ranges=True):
    """The numbers an aggregate sees: in ranges only numbers (text, booleans, empty
    cells skipped); direct arguments coerced. Returns (num, use mask, first error), each
    with the per-cell axis first, concatenated over the other axes."""
    if all(v.pure == NUM for v in args):         # numbers only: every one counts, no errors
        k = max(v.shape[0] for v in args)
        nums = [v.num.reshape(k, -1) if v.shape[0] == k else
                np.broadcast_to(v.num.reshape(v.shape[0], -1), (k, v.num[0].size)) for v in args]
        n = nums[0] if len(nums) == 1 else np.concatenate(nums, axis=1)
        return n, np.ones(n.shape, bool), np.zeros(k, np.int8)
    nums, uses, errs = [], [], []
    for v, is_range in zip(args, ranges):
        k = v.shape[0]
        if is_range:
            use = v.tag == NUM if numbers_only_in_ranges else (v.tag == NUM) | (v.tag == BOOL)
            err = np.where(v.tag >= 10, v.tag, 0)
            n = v.num
        else:
            n, err = _to_number(v)
            use = v.tag != EMPTY
        nums.append(n.reshape(k, -1))
        uses.append(use.reshape(k, -1))
        errs.append(err.reshape(k, -1))
    k = max(x.shape[0] for x in nums)
    nums = np.concatenate([np.broadcast_to(x, (k, x.shape[1])) for x in nums], axis=1)
    uses = np.concatenate([np.broadcast_to(x, (k, x.shape[1])) for x in uses], axis=1)
    errs = np.concatenate([np.broadcast_to(x, (k, x.shape[1])) for x in errs], axis=1)
    return nums, uses, _first_error(errs)


def _first_error(errs: np.ndarray) -> np.ndarray:
    """Per row of a (k, n) array of error tags: the first non-zero one (Excel reports the
    first error it meets), else 0."""
    if errs.shape[1] == 0:
        return np.zeros(errs.shape[0], np.int8)
    idx = np.argmax(errs != 0, axis=1)
    return errs[np.arange(errs.shape[0]), idx].astype(np.int8)


def _scalar(num, err) -> Val:
    return _result(num.reshape(-1, 1, 1), err.reshape(-1, 1, 1))


def _one_block_for_all(args) -> bool:
    """Whether an argument is one block shared by the cells of a run (an absolute range)
    while others have a value per cell: then each argument is reduced on its own, never
    copied once per cell (=SUM(A5,$A$1:$Z$9999) filled over 4000 columns)."""
    k = max(v.shape[0] for v in args)
    return k > 1 and any(v.shape[0] != k and v.num[0].size > 1 for v in args)


def _by_argument(args, ranges, reduce):
    """reduce(num, use) -> tuple of (k_i,) arrays, for each argument; with the first error."""
    k = max(v.shape[0] for v in args)
    parts, errs = [], []
    for v, r in zip(args, ranges):
        n, use, err = _values_of([v], [r])
        parts.append(tuple(np.broadcast_to(x, (k,)) for x in reduce(n, use)))
        errs.append(np.broadcast_to(err, (k,)))
    return parts, _first_error(np.stack(errs, axis=1))


def _agg_sum(args, ranges):
    if _one_block_for_all(args):
        parts, err = _by_argument(args, ranges, lambda n, use: (np.where(use, n, 0.0).sum(axis=1),))
        return _scalar(sum(p[0] for p in parts), err)
    n, use, err = _values_of(args, ranges)
    return _scalar(np.where(use, n, 0.0).sum(axis=1), err)


def _agg_average(args, ranges):
    if _one_block_for_all(args):
        parts, err = _by_argument(args, ranges, lambda n, use: (np.where(use, n, 0.0).sum(axis=1), use.sum(axis=1)))
        total, cnt = sum(p[0] for p in parts), sum(p[1] for p in parts)
    else:
        n, use, err = _values_of(args, ranges)
        total, cnt = np.where(use, n, 0.0).sum(axis=1), use.sum(axis=1)
    with np.errstate(all="ignore"):
        r = total / cnt
    return _scalar(r, np.where((err == 0) & (cnt == 0), DIV0, err))


def _agg_minmax(fn, empty):
    def reduce(n, use):
        return getattr(np.where(use, n, empty), fn)(axis=1, initial=empty), use.any(axis=1)

    def f(args, ranges):
        if _one_block_for_all(args):
            parts, err = _by_argument(args, ranges, reduce)
            r = getattr(np, "minimum" if fn == "min" else "maximum").reduce([p[0] for p in parts])
            seen = np.logical_or.reduce([p[1] for p in parts])
        else:
            n, use, err = _values_of(args, ranges)
            r, seen = reduce(n, use)
        return _scalar(np.where(seen, r, 0.0), err)
    return f


def _agg_sumsq(args, ranges):
    n, use, err = _values_of(args, ranges)
    return _scalar(fx.sumsq(n, use), err)


def _agg_product(args, ranges):
    n, use, err = _values_of(args, ranges)
    return _scalar(fx.product(n, use), err)


def _agg_count(args, ranges):
    counts = None
    for v, is_range in zip(args, ranges):
        if is_range:
            hit = v.tag == NUM
        else:                               # typed: numbers, booleans and numeric text count
            hit = (v.tag == NUM) | (v.tag == BOOL)
            if (v.tag == TEXT).any():
                hit = hit | np.vectorize(lambda t, x: t == TEXT and bool(_NUMERIC_TEXT.match(str(x))),
                                         otypes=[bool])(v.tag, _texts(v))
        c = hit.reshape(v.shape[0], -1).sum(axis=1)
        counts = c if counts is None else counts + c
    return Val(counts.astype(float).reshape(-1, 1, 1), np.zeros((counts.size, 1, 1), np.int8), None, NUM)


def _agg_sumproduct(args, ranges):
    if len({v.shape[1:] for v in args}) > 1:      # arrays of different sizes
        return _const("#VALUE!", max(v.shape[0] for v in args))
    prod, err = None, None
    for v in args:
        n = np.where(v.tag == NUM, v.num, np.where(v.tag == BOOL, 0.0, 0.0))
        e = np.where(v.tag >= 10, v.tag, 0).astype(np.int8)
        prod = n if prod is None else prod * n
        err = e if err is None else _error_of(err, e)
    k = prod.shape[0]
    return _scalar(prod.reshape(k, -1).sum(axis=1), _first_error(err.reshape(k, -1)))


def _agg_logical(all_: bool):
    def f(args, ranges):
        acc, seen, err = None, None, None
        for v, is_range in zip(args, ranges):
            k = v.shape[0]
            if is_range:
                use = (v.tag == NUM) | (v.tag == BOOL)
                e = np.where(v.tag >= 10, v.tag, 0).astype(np.int8)
                b = v.num != 0
            else:
                b, e = _to_bool(v)
                use = v.tag != EMPTY
            b, use, e = b.reshape(k, -1), use.reshape(k, -1), e.reshape(k, -1)
            part = np.where(use, b, all_).all(axis=1) if all_ else np.where(use, b, False).any(axis=1)
            acc = part if acc is None else (acc & part if all_ else acc | part)
            s = use.any(axis=1)
            seen = s if seen is None else seen | s
            first = _first_error(e)
            err = first if err is None else _error_of(err, first)
        err = np.where((err == 0) & ~seen, VALUE, err).astype(np.int8)
        return Val(np.where(err == 0, acc.astype(float), 0.0).reshape(-1, 1, 1),
                   np.where(err == 0, BOOL, err).astype(np.int8).reshape(-1, 1, 1))
    return f


AGGREGATES = {
    "SUM": _agg_sum, "AVERAGE": _agg_average, "MIN": _agg_minmax("min", np.inf),
    "MAX": _agg_minmax("max", -np.inf), "COUNT": _agg_count, "SUMPRODUCT": _agg_sumproduct,
    "AND": _agg_logical(True), "OR": _agg_logical(False),
    "SUMSQ": _agg_sumsq, "PRODUCT": _agg_product,
}
SPECIAL = {"IF", "IFERROR", "NOT", "PI", "ISNUMBER", "ISERROR", "ISTEXT", "TRUE", "FALSE", "TRUNC",
           "INDEX", "CHOOSE", "ANCHORARRAY", "SINGLE", "NA", *fx.ROUNDING}
SUPPORTED = sorted(set(SCALAR_FUNCS) | set(AGGREGATES) | SPECIAL)


# --------------------------------------------------------------------------- parsing
_CELL = re.compile(r"^(\$?)([A-Za-z]{1,3})(\$?)(\d+)$")


@dataclass(frozen=True)
class Ref:
    """A cell or range reference; relative parts are offsets from the host cell."""
    sheet: str | None
    r1: int
    c1: int
    r2: int
    c2: int
    r1_abs: bool
    c1_abs: bool
    r2_abs: bool
    c2_abs: bool

    @property
    def is_range(self):
        return (self.r1, self.c1, self.r1_abs, self.c1_abs) != (self.r2, self.c2, self.r2_abs, self.c2_abs)


class ParseError(ValueError):
    """A formula that cannot be read; `code` is the error its cell gets."""

    def __init__(self, message: str, code: str = "#NAME?"):
        super().__init__(message)
        self.code = code


class Note(str):
    """A cell's problem as one line of text (Book.notes); `code` is the error value the
    cell gets (#NAME? for an unknown function, #VALUE! for a wrong number of arguments...)."""
    code: str

    def __new__(cls, text: str, code: str = "#NAME?"):
        self = super().__new__(cls, " ".join(str(text).split("\n")))
        self.code = code
        return self


def _split_sheet(text: str) -> tuple[str | None, str]:
    if "!" not in text:
        return None, text
    sheet, ref = text.rsplit("!", 1)
    if sheet.startswith("'") and sheet.endswith("'"):
        sheet = sheet[1:-1].replace("''", "'")
    if sheet.startswith("["):
        raise ParseError(f"a reference to another file ({text})")
    return sheet, ref


def _cell(text: str, host_r: int, host_c: int):
    m = _CELL.match(text)
    if not m:
        return None
    cabs, col, rabs, row = m.groups()
    r, c = int(row), column_index_from_string(col.upper())
    if not (1 <= r <= 1048576 and c <= 16384):     # past Excel's grid: a name (Excel: #NAME?)
        return None
    return (r if rabs else r - host_r, c if cabs else c - host_c, bool(rabs), bool(cabs))


def _operand_ref(text: str, host_r: int, host_c: int, names: dict):
    if text.upper().endswith("!#REF!"):     # Sheet1!#REF!: a reference to deleted cells
        return ("const", "#REF!")
    sheet, ref = _split_sheet(text)
    parts = ref.split(":")
    if len(parts) > 2:
        raise ParseError(f"unsupported reference {text}")
    ends = [_cell(p, host_r, host_c) for p in parts]
    if all(e is not None for e in ends):
        a, b = ends[0], ends[-1]
        return Ref(sheet, a[0], a[1], b[0], b[1], a[2], a[3], b[2], b[3])
    if sheet is None and len(parts) == 1 and ref.upper() in names:
        return ("name", ref.upper())
    if len(parts) == 2:
        whole = _whole(parts, host_r, host_c)
        if whole is None:
            raise ParseError(f"unsupported reference {text}")
        return Ref(sheet, *whole)
    return ("name", ref.upper())


_WHOLE_COL = re.compile(r"^(\$?)([A-Za-z]{1,3})$")
_WHOLE_ROW = re.compile(r"^(\$?)(\d{1,7})$")


def _whole(parts: list[str], host_r: int, host_c: int):
    """A whole-column (A:C, $A:$A) or whole-row (2:2) reference as the range of every row
    (column) of the sheet: r1 c1 r2 c2 and their absolute flags, like a Ref. The evaluator
    bounds it by the workbook's used range (_bound_whole)."""
    a, b = _WHOLE_COL.match(parts[0]), _WHOLE_COL.match(parts[1])
    if a and b:
        c1, c2 = column_index_from_string(a[2].upper()), column_index_from_string(b[2].upper())
        if max(c1, c2) > _MAX_COL:
            return None
        return (1, c1 if a[1] else c1 - host_c, _MAX_ROW, c2 if b[1] else c2 - host_c,
                True, bool(a[1]), True, bool(b[1]))
    a, b = _WHOLE_ROW.match(parts[0]), _WHOLE_ROW.match(parts[1])
    if a and b:
        r1, r2 = int(a[2]), int(b[2])
        if not (1 <= r1 <= _MAX_ROW and 1 <= r2 <= _MAX_ROW):
            return None
        return (r1 if a[1] else r1 - host_r, 1, r2 if b[1] else r2 - host_r, _MAX_COL,
                bool(a[1]), True, bool(b[1]), True)
    return None


_PREC = {"=": 1, "<>": 1, "<": 1, ">": 1, "<=": 1, ">=": 1, "&": 2, "+": 3, "-": 3, "*": 4, "/": 4, "^": 5}


# Excel's own limits for a formula (Microsoft, "Excel specifications and limits"): a cell
# whose formula exceeds one gets an error and a note. They also keep the parser (recursive
# descent, about 3 Python frames a level) and the evaluation (about 2) below Python's
# recursion limit: a sum of 4000 terms is a left-leaning chain, walked iteratively.
MAX_FORMULA_CHARS = 8192          # characters of a formula's text
MAX_NESTING = 64                  # nested functions and parentheses (and runs of + - %)
MAX_ARGS = 255                    # arguments of one function

# arguments each function takes (min, max); a call outside them is #VALUE! and a note
# (LibreOffice writes #VALUE! for =SIN(1,2)); functions not listed take 0..MAX_ARGS
ARITY = {
    **{f: (1, 1) for f in ("SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "RADIANS", "DEGREES",
                           "ABS", "SIGN", "EXP", "LN", "LOG10", "NOT", "ISNUMBER", "ISERROR", "ISTEXT")},
    **{f: (2, 2) for f in ("ATAN2", "MOD", "POWER", "ROUND", "IFERROR")},
    **{f: (1, MAX_ARGS) for f in ("SUM", "AVERAGE", "MIN", "MAX", "COUNT", "SUMPRODUCT", "AND", "OR")},
    "IF": (1, 3), "PI": (0, 0),
    # Excel's arities of functions other branches add (harmless until they are supported)
    "INT": (1, 1), "TRUNC": (1, 2), "FLOOR": (2, 2), "CEILING": (2, 2), "SUMSQ": (1, MAX_ARGS),
    "PRODUCT": (1, MAX_ARGS), "INDEX": (2, 4), "CHOOSE": (2, MAX_ARGS), "TRUE": (0, 0), "FALSE": (0, 0),
}


def _check_limits(tokens: list) -> None:
    """Refuse, before parsing, a formula nested deeper than MAX_NESTING levels (functions,
    parentheses, array braces, and runs of prefix or postfix operators, which the parser
    and the tree also nest)."""
    depth = run = 0
    for t in tokens:
        typ = t.type
        if typ in (Token.OP_PRE, Token.OP_POST):
            run += 1
            if depth + run > MAX_NESTING:
                raise ParseError(f"nesting deeper than {MAX_NESTING} levels (Excel's limit)", "#VALUE!")
            continue
        run = 0
        if t.subtype == Token.OPEN:
            depth += 1
            if depth > MAX_NESTING:
                raise ParseError(f"nesting deeper than {MAX_NESTING} levels (Excel's limit)", "#VALUE!")
        elif t.subtype == Token.CLOSE:
            depth -= 1


def arity_problem(tree) -> str | None:
    """The first call with a wrong number of arguments, as a note, else None."""
    for node in _nodes(tree):
        if node[0] == "fn":
            n = len(node[2])
            lo, hi = ARITY.get(node[1], (0, MAX_ARGS))
            if not lo <= n <= hi:
                want = f"{lo}" if lo == hi else f"{lo} to {hi}"
                return f"{node[1]} takes {want} argument{'s' if hi != 1 else ''}, not {n}"
    return None


_MANTISSA_E = re.compile(r"^(\d+\.?\d*|\.\d+)[Ee]$")


def _merge_exponents(tokens: list) -> list:
    """openpyxl's tokenizer reads =12.5E-1 as the name '12.5E', '-', 1: glue such a
    mantissa, its exponent's sign and digits back into one number."""
    out, i = [], 0
    while i < len(tokens):
        t = tokens[i]
        if (t.type == Token.OPERAND and _MANTISSA_E.match(t.value) and i + 2 < len(tokens)
                and tokens[i + 1].type == Token.OP_IN and tokens[i + 1].value in "+-"
                and tokens[i + 2].type == Token.OPERAND and tokens[i + 2].subtype == Token.NUMBER
                and tokens[i + 2].value.isdigit()):
            out.append(Token(t.value + tokens[i + 1].value + tokens[i + 2].value, Token.OPERAND, Token.NUMBER))
            i += 3
            continue
        out.append(t)
        i += 1
    return out


def parse_formula(formula: str, host_r: int, host_c: int, names: dict):
    """Expression tree of a formula (openpyxl's tokenizer, then precedence climbing).
    Excel's limits are enforced first (see _check_limits), so the recursive descent and
    every walk of the tree stay far from Python's recursion limit; anything unreadable is
    a ParseError."""
    if len(formula) > MAX_FORMULA_CHARS + 1:              # + 1: the "="
        raise ParseError(f"longer than {MAX_FORMULA_CHARS} characters (Excel's limit)", "#VALUE!")
    try:
        tokens = _merge_exponents([t for t in Tokenizer(formula).items if t.type != Token.WSPACE])
    except Exception as e:      # noqa: BLE001 - the tokenizer's own errors (TokenizerError, IndexError...)
        raise ParseError(f"not a formula ({type(e).__name__}: {_show(e, 100)})") from None
    _check_limits(tokens)
    pos = 0

    def peek():
        return tokens[pos] if pos < len(tokens) else None

    def take():
        nonlocal pos
        pos += 1
        return tokens[pos - 1]

    def primary():
        t = take() if peek() else None
        if t is None:
            raise ParseError("the formula ends too early")
        if t.type == Token.OP_PRE:
            node = ("neg", unary_operand()) if t.value == "-" else unary_operand()
            return postfix(node)
        if t.type == Token.OPERAND:
            if t.subtype == Token.NUMBER:
                x = float(t.value)
                node = ("const", x if math.isfinite(x) else "#NUM!")   # =1e999: past the largest double
            elif t.subtype == Token.TEXT:
                node = ("const", t.value[1:-1].replace('""', '"'))
            elif t.subtype == Token.LOGICAL:
                node = ("const", t.value.upper() == "TRUE")
            elif t.subtype == Token.ERROR:
                node = ("const", t.value.upper())
            else:
                node = _operand_ref(t.value, host_r, host_c, names)
                if isinstance(node, Ref):
                    node = ("ref", node)
            return postfix(node)
        if t.type == Token.PAREN and t.subtype == Token.OPEN:
            node = expression(0)
            close = take() if peek() else None
            if close is None or close.type != Token.PAREN:
                raise ParseError("unbalanced parentheses")
            return postfix(node)
        if t.type == Token.FUNC and t.subtype == Token.OPEN:
            name = t.value[:-1].upper().removeprefix("_XLFN.")
            args = []
            if peek() and peek().type == Token.FUNC and peek().subtype == Token.CLOSE:
                take()
                return postfix(("fn", name, args))
            while True:
                nxt = peek()
                if nxt and (nxt.type == Token.SEP or (nxt.type == Token.FUNC and nxt.subtype == Token.CLOSE)):
                    args.append(("missing",))      # =ROUND(2.5,) : an empty argument
                else:
                    args.append(expression(0))
                sep = take() if peek() else None
                if sep is None:
                    raise ParseError(f"{name}( is not closed")
                if sep.type == Token.FUNC and sep.subtype == Token.CLOSE:
                    return postfix(("fn", name, args))
                if not (sep.type == Token.SEP and sep.subtype == Token.ARG):
                    raise ParseError(f"unexpected {sep.value!r} in {name}(...)")
        raise ParseError(f"unexpected {t.value!r}")

    def unary_operand():
        # unary minus binds tighter than ^ in Excel: -2^2 = 4
        return primary()

    def postfix(node):
        while peek() and peek().type == Token.OP_POST:
            take()
            node = ("pct", node)
        return node

    def expression(min_prec):
        left = primary()
        while peek() and peek().type == Token.OP_IN and _PREC.get(peek().value, 0) > min_prec:
            op = take().value
            right = expression(_PREC[op])
            left = ("bin", op, left, right)
        return left

    tree = expression(0)
    if pos != len(tokens):
        raise ParseError(f"unexpected {tokens[pos].value!r}")
    return tree


def _nodes(tree):
    """Every node of a tree, parents first, left to right; iterative (a 4000-term sum is a
    tree 4000 deep)."""
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node
        kind = node[0]
        if kind == "fn":
            stack.extend(reversed(node[2]))
        elif kind in ("neg", "pct"):
            stack.append(node[1])
        elif kind == "bin":
            stack.append(node[3])
            stack.append(node[2])


def functions_of(tree) -> set[str]:
    return {node[1] for node in _nodes(tree) if node[0] == "fn"}


def refs_of(tree) -> list[Ref]:
    return [node[1] for node in _nodes(tree) if node[0] == "ref"]


# --------------------------------------------------------------------------- reading
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


_TEMPLATES: dict = {}           # (formula, column) -> _Template, for the rest of the process


def _group_runs(sheet: Sheet) -> list[Run]:
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
    code = rows * (_MAX_COL + 1) + cols
    if len(code) > 1 and not (np.diff(code) > 0).all():      # not in row, column order
        order = np.argsort(code, kind="stable")
        rows, cols, texts = rows[order], cols[order], [texts[i] for i in order.tolist()]
    bounds = [0, *(np.flatnonzero(np.diff(rows)) + 1).tolist(), len(keys)]
    col_list = cols.tolist()
    runs: list[Run] = []
    name = sheet.name
    for a, b in zip(bounds[:-1], bounds[1:]):
        r = int(rows[a])
        i = a
        while i < b:
            tpl = _TEMPLATES.get((texts[i], col_list[i]))
            if tpl is None:
                if len(_TEMPLATES) > 100_000:
                    _TEMPLATES.clear()
                tpl = _TEMPLATES[texts[i], col_list[i]] = _Template(texts[i], col_list[i])
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


def _split(run: Run) -> list[Run]:
    return [Run(run.sheet, run.row, np.array([c]), run.formula, run.tree, run.error, run.refs, run.array)
            for c in run.cols]


def _target_block(run: Run, ref: Ref):
    """Rows and columns (per cell of the run) a reference touches."""
    r1 = ref.r1 if ref.r1_abs else run.row + ref.r1
    r2 = ref.r2 if ref.r2_abs else run.row + ref.r2
    c1 = np.full(run.cols.shape, ref.c1) if ref.c1_abs else run.cols + ref.c1
    c2 = np.full(run.cols.shape, ref.c2) if ref.c2_abs else run.cols + ref.c2
    return min(r1, r2), max(r1, r2), np.minimum(c1, c2), np.maximum(c1, c2)


# --------------------------------------------------------------------------- hostile input
MAX_EVAL_DEPTH = 200     # levels of a formula with the names it uses expanded (~2 Python frames each)
CHUNK_READS = 1 << 22    # cells a piece of a run reads at once, per relative range (about 70 MB)


def _depth(tree, weights: dict | None = None) -> int:
    """How deep evaluating a tree recurses: levels of functions, parentheses and operators
    (a chain of + - ... leaning left counts once: _Context.eval walks it in a loop), plus
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


def _names_used(tree) -> list[str]:
    return [node[1] for node in _nodes(tree) if node[0] == "name"]


def _check_names(name_refs: dict) -> dict[str, Note]:
    """Defined names that cannot be evaluated, made constant errors (in place), with a note
    each: unknown functions (#NAME?), wrong numbers of arguments (#VALUE!), names that
    refer to each other in a circle or to themselves (#N/A, as LibreOffice gives), chains
    of names deeper than MAX_EVAL_DEPTH (#VALUE!). Iterative: a chain of 10,000 names is
    no recursion."""
    notes: dict[str, Note] = {}
    for n, tree in list(name_refs.items()):
        bad = sorted(f for f in functions_of(tree) if f not in SUPPORTED)
        wrong = None if bad else arity_problem(tree)
        if bad or wrong:
            code = "#NAME?" if bad else "#VALUE!"
            notes[n] = Note(f"the name {n}: " + (f"unsupported function {', '.join(bad)}" if bad else wrong), code)
            name_refs[n] = ("const", code)
    uses = {n: [m for m in _names_used(t) if m in name_refs] for n, t in name_refs.items()}
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
                        name_refs[n], weight[n] = ("const", "#VALUE!"), 1
                continue
            if state.get(m) == 1:                   # back to a name on the path: a circle
                circle = path[path.index(m):]
                text = " -> ".join(circle + [m])
                for x in circle:
                    notes[x] = Note(f"the names refer to each other in a circle ({_show(text, 200)}): #N/A", "#N/A")
                    name_refs[x], weight[x] = ("const", "#N/A"), 1
            elif m not in state:
                state[m] = 1
                path.append(m)
                stack.append((m, iter(uses[m])))
    return notes


def _run_notes(run: Run, sheets: dict, name_refs: dict, name_notes: dict) -> list[str]:
    """Notes for a run that parsed: a sheet that does not exist (#REF!), a name that could
    not be evaluated, formulas nested too deep through names (the run becomes #VALUE!)."""
    out = []
    for ref in run.refs:
        if ref.sheet is not None and ref.sheet not in sheets:
            out.append(f"{run.where()}: refers to the sheet '{_show(ref.sheet, 60)}', which does not exist: #REF!")
            break
    used = [n for n in _names_used(run.tree) if n in name_refs] if run.tree is not None else []
    for n in dict.fromkeys(used):
        if n in name_notes:
            out.append(f"{run.where()}: {name_notes[n]}")
    if used and _depth(run.tree, _name_depths(name_refs)) > MAX_EVAL_DEPTH:
        run.error = Note(f"nesting deeper than {MAX_EVAL_DEPTH} levels with its names", "#VALUE!")
        out.append(f"{run.where()}: {run.error}")
    return out


_DEPTHS: dict = {}


def _name_depths(name_refs: dict) -> dict:
    """Each name's own depth (after _check_names, no name is deeper than MAX_EVAL_DEPTH),
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


def _store_dims(path: str, sheets: dict, limits: Limits) -> dict[str, list[int]]:
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
        raise UnusableWorkbook(path, f"its sheets' used ranges span {total:,} cells (sheet '{_show(n, 60)}' "
                               f"A1:{get_column_letter(cols)}{rows}, {rows * cols:,})",
                               f"expected at most {limits.max_used_cells:,} cells (rows x columns from A1 "
                               "to the last cell that holds something): clear stray cells far from the table")
    return dims


def _ref_reads(run: Run, ref: Ref, dims: dict, k: int) -> tuple[int, int]:
    """(cells read once for the run, cells read for each cell of the run) by one
    reference, as _Context.ref reads it (small blocks whole, large ones clipped)."""
    d = dims.get(ref.sheet or run.sheet)
    if d is None:
        return 0, 0
    if not ref.is_range:
        return 0, 1
    r1, r2, c1, c2 = _span(run, ref)
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


def _run_reads(run: Run, dims: dict, name_refs: dict) -> tuple[int, int]:
    k = len(run.cols)
    once = per_cell = 0
    refs = list(run.refs or [])
    if run.tree is not None:
        for n in _names_used(run.tree):
            if n in name_refs:
                refs += refs_of(name_refs[n])
    for ref in refs:
        a, b = _ref_reads(run, ref, dims, k)
        once, per_cell = once + a, per_cell + b
    return once, per_cell


def _check_reads(path: str, runs: list[Run], dims: dict, name_refs: dict, limits: Limits) -> None:
    """Refuse (one line) a workbook whose formulas read more than limits.max_reads cells
    in all (the evaluation's time is about proportional)."""
    total = 0
    for run in runs:
        if run.error:
            continue
        once, per_cell = _run_reads(run, dims, name_refs)
        total += once + per_cell * len(run.cols)
        if total > limits.max_reads:
            raise UnusableWorkbook(path, f"its formulas read more than {limits.max_reads:,} cells in all "
                                   f"(at {run.where()}, among others)",
                                   f"expected at most {limits.max_reads:,} (sheetkin's limit for a workbook)")


def _check_formula_text(path: str, runs: list[Run], limits: Limits) -> None:
    """Refuse (one line) a workbook with more formula text to parse than
    limits.max_formula_chars (a run's formula counts once)."""
    total = sum(len(run.formula) for run in runs)
    if total > limits.max_formula_chars:
        raise UnusableWorkbook(path, f"its formulas hold {total:,} characters of text to read (each formula "
                               "once, a row of cells filled from a neighbour once)",
                               f"expected at most {limits.max_formula_chars:,} (sheetkin's limit for a workbook)")


def _chunks(run: Run, dims: dict, name_refs: dict) -> list[Run]:
    """A run in pieces small enough that its relative ranges, read for every cell at once,
    stay below CHUNK_READS cells (a row of =SUM(A1:A100000) filled right is read 1000
    columns at a time, not 4000)."""
    k = len(run.cols)
    if k == 1 or run.error:
        return [run]
    per_cell = _run_reads(run, dims, name_refs)[1]
    step = max(1, CHUNK_READS // max(per_cell, 1))
    if step >= k:
        return [run]
    return [dataclasses.replace(run, cols=run.cols[i:i + step]) for i in range(0, k, step)]


def evaluate(path: str | Path, *, strict: bool = True, limits: Limits = Limits()) -> Book:
    """Evaluate every formula of an .xlsx workbook (an .ods or .fods is converted by
    LibreOffice first, see xlsxread.read_book); `Book.value(sheet, row, col)` then gives any
    cell. With strict, an unsupported function or an unparsable formula raises
    EvaluationError naming the cells; otherwise those cells become #NAME? and the problem is
    listed in Book.problems."""
    raw = read_book(path, limits)
    return evaluate_sheets(raw.path, raw.sheets, raw.order, raw.names, strict=strict, limits=limits)


def evaluate_sheets(path: str, sheets: dict[str, Sheet], order: list[str], names: dict, *,
                    strict: bool = True, limits: Limits = Limits()) -> Book:
    problems: list[str] = []
    runs: list[Run] = []
    for sh in sheets.values():
        runs.extend(_array_runs(sh, _group_runs(sh)) if sh.arrays else _group_runs(sh))
    _check_formula_text(path, runs, limits)
    # whole columns and rows (A:A, 2:2) end at the workbook's used range
    bound = (max([sh.max_row for sh in sheets.values()] + [1]), max([sh.max_col for sh in sheets.values()] + [1]))
    name_notes: dict = {}                         # scope -> {NAME: Note} of names that cannot be evaluated
    scopes = _name_scopes(names, sheets, bound, name_notes)
    name_refs = {**scopes[None], **{n: t for sc in scopes.values() for n, t in sc.items()}}
    names_key = frozenset(name_refs)
    # parse each run once (its first cell)
    for run in runs:
        run.tree, run.error, run.refs = _parse_run(run.formula, run.row, int(run.cols[0]), name_refs, names_key)
        if run.error:
            problems.append(f"{run.where()}: {run.error}")
        else:
            if any(_is_whole(ref) for ref in run.refs):
                run.tree = _bound_whole(run.tree, bound)
                run.refs = refs_of(run.tree)
            problems.extend(_run_notes(run, sheets, name_refs,
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
    # reference past it reads as empty cells, a range is clipped to it (_Context.ref)
    dims = _store_dims(path, sheets, limits)
    num = {n: np.zeros(d) for n, d in dims.items()}
    tag = {n: np.full(d, EMPTY, np.int8) for n, d in dims.items()}
    txt = {n: np.empty(d, dtype=object) for n, d in dims.items()}
    for n, sh in sheets.items():
        for (r, c), v in sh.consts.items():
            store_value(num[n], tag[n], txt[n], r, c, v)
        for (r, c) in getattr(sh, "dangling", {}):
            tag[n][r, c] = NA
    _check_reads(path, runs, dims, name_refs, limits)      # before ordering: it scans the ranges too
    order_runs = _schedule(path, runs, dims, sheets, strict=strict, problems=problems)
    _check_reads(path, order_runs, dims, name_refs, limits)  # runs split into cells read more
    ctx = _Context(num, tag, txt, scopes)
    ctx.arrays = {n: sh.arrays for n, sh in sheets.items()}
    cells = 0
    with np.errstate(all="ignore"):
        for run in order_runs:
            cells += len(run.cols)
            for part in _chunks(run, dims, name_refs):
                k = len(part.cols)
                if part.error:
                    v = _const(getattr(part.error, "code", "#NAME?"), k)
                    if part.array is not None:          # the whole range holds the error
                        _write_array(_const(getattr(part.error, "code", "#NAME?")), part, num, tag, txt)
                        continue
                else:
                    try:
                        if part.array is not None:
                            _write_array(ctx.eval(part.tree, part), part, num, tag, txt)
                            continue
                        v = _as_cells(ctx.eval(part.tree, part), k)
                    except (EvaluationError, UnusableWorkbook):
                        raise
                    except Exception as e:      # noqa: BLE001 - the cell's problem, not the process's
                        note = f"{part.where()}: internal error of the evaluator ({type(e).__name__}: {_show(e, 120)}): #VALUE!"
                        if strict:
                            raise EvaluationError(f"{path}: {note}") from e
                        problems.append(note)
                        v = _const("#VALUE!", k)
                n = part.sheet
                where = (part.row, slice(int(part.cols[0]), int(part.cols[0]) + k)) if part.contiguous else (part.row, part.cols)
                num[n][where] = v.num[:, 0, 0]
                tag[n][where] = v.tag[:, 0, 0]
                if v.txt is not None:
                    txt[n][where] = v.txt[:, 0, 0]
    return Book(path, sheets, order, num, tag, txt, problems, len(order_runs), cells)


# --------------------------------------------------------------------------- names, arrays, whole columns
def _name_scopes(names: dict, sheets: dict[str, Sheet], bound, notes: dict | None = None) -> dict:
    """Parsed defined names by scope: None for the workbook's, a sheet's name for the names
    scoped to it (localSheetId). Names are case-insensitive. A name that cannot be read
    (#VALUE!, as LibreOffice), or cannot be evaluated (_check_names: names in a circle,
    unknown functions...) is a constant error where it is used, and notes[scope][NAME] says why."""
    notes = {} if notes is None else notes

    def parsed(table, scope):
        out = {}
        for n, text in table.items():
            try:
                tree = parse_formula("=" + text.removeprefix("="), 1, 1, {})
            except ParseError as e:
                tree = ("const", "#VALUE!")
                notes.setdefault(scope, {})[n.upper()] = Note(
                    f"the name {_show(n, 60)} is not a formula (={_show(text, 60)}: {e})", "#VALUE!")
            out[n.upper()] = _bound_whole(tree, bound)
        return out
    scopes = {None: parsed(names, None)}
    notes.setdefault(None, {}).update(_check_names(scopes[None]))
    for n, sh in sheets.items():
        scopes[n] = parsed(sh.names, n) if sh.names else {}
        if scopes[n]:
            # a sheet's names see the workbook's too: checked together, kept for the sheet
            seen = {**scopes[None], **scopes[n]}
            found = _check_names(seen)
            for name in scopes[n]:
                scopes[n][name] = seen[name]
                if name in found:
                    notes.setdefault(n, {})[name] = found[name]
    return scopes


def _lookup(scopes: dict, sheet: str, name: str):
    """A name's tree as a formula on `sheet` sees it: a name scoped to that sheet shadows the
    workbook's name (Excel); None if neither exists."""
    local = scopes.get(sheet)
    if local and name in local:
        return local[name]
    return scopes[None].get(name)


def _has_names(tree) -> bool:
    return any(node[0] == "name" for node in _nodes(tree))


def _names_in(tree, out: list):
    out.extend(_names_used(tree))
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
        target = _lookup(scopes, sheet, name)
        if target is not None:
            refs += refs_of(target)
            _names_in(target, todo)
    return refs


def _is_whole(ref: Ref) -> bool:
    return ((ref.r1_abs and ref.r2_abs and ref.r1 == 1 and ref.r2 == _MAX_ROW)
            or (ref.c1_abs and ref.c2_abs and ref.c1 == 1 and ref.c2 == _MAX_COL))


def _bound_whole(tree, bound: tuple[int, int]):
    """The tree with whole columns (rows 1 to 1,048,576) and whole rows (columns A to XFD)
    ending at the workbook's last used row (column): the same values, a store of the size
    the file holds. Rebuilt iteratively (children before parents): no recursion."""
    def fix(ref: Ref):
        r2, c2 = ref.r2, ref.c2
        if ref.r1_abs and ref.r2_abs and ref.r1 == 1 and ref.r2 == _MAX_ROW:
            r2 = bound[0]
        if ref.c1_abs and ref.c2_abs and ref.c1 == 1 and ref.c2 == _MAX_COL:
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
    r2, c2 = run.array
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
    """A typed value (number, bool, text, error text) into a sheet's value stores at (r, c)."""
    if isinstance(v, bool):
        num[r, c], tag[r, c] = float(v), BOOL
    elif isinstance(v, (int, float)):
        num[r, c], tag[r, c] = float(v), NUM
    elif isinstance(v, str) and v in ERRORS:
        tag[r, c] = ERRORS[v]
    elif isinstance(v, str):
        tag[r, c], txt[r, c] = TEXT, v


def _as_cells(v: Val, k: int) -> Val:
    """A cell holds one value: an array result that is not a single value is #VALUE!;
    a formula whose value is an empty cell holds 0 (=Z99 with Z99 empty is 0)."""
    if v.shape[1:] != (1, 1):
        return _const("#VALUE!", k)
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
    Err:522) and a note naming them."""
    while True:
        owner = {n: np.full(d, -1, np.int32) for n, d in dims.items()}
        for i, run in enumerate(runs):
            c0 = int(run.cols[0])
            owner[run.sheet][run.row, slice(c0, c0 + len(run.cols)) if run.contiguous else run.cols] = i
        for i, run in enumerate(runs):
            if run.array is not None:          # an array formula owns its whole range
                block = owner[run.sheet][run.row:run.array[0] + 1, int(run.cols[0]):run.array[1] + 1]
                block[block == -1] = i
        deps: list[set[int]] = []
        split = set()
        for i, run in enumerate(runs):
            d = set()
            for ref in (run.refs if not run.error else ()):
                target = ref.sheet or run.sheet
                if target not in owner:
                    continue
                r1, r2, c1, c2 = _span(run, ref)
                if r1 < 1 or c1 < 1:
                    continue
                block = owner[target][r1:r2 + 1, c1:c2 + 1]
                if block.size <= 4096:
                    ids = set(block.ravel().tolist())
                    ids.discard(-1)
                else:
                    ids = set(np.unique(block[block >= 0]).tolist())
                if len(run.cols) > 1 and (i in ids or ref.c1_abs != ref.c2_abs):
                    split.add(i)                # self-reference, or a range whose width varies
                d |= ids
            deps.append(d)
        if split:
            runs = [r for i, run in enumerate(runs) for r in (_split(run) if i in split else [run])]
            continue
        order, indeg = [], [len(d - {i}) for i, d in enumerate(deps)]
        users: list[list[int]] = [[] for _ in runs]
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
        stuck = [i for i in range(len(runs)) if indeg[i] > 0] + self_loops
        if not stuck:
            return [runs[i] for i in order]
        multi = [i for i in stuck if len(runs[i].cols) > 1]
        if multi:
            keep = set(multi)
            runs = [r for i, run in enumerate(runs) for r in (_split(run) if i in keep else [run])]
            continue
        cells = sorted({runs[i].where() for i in stuck})
        what = (f"circular reference among {', '.join(cells[:12])}"
                + (f" and {len(cells) - 12} more cells" if len(cells) > 12 else ""))
        if strict or problems is None:
            raise EvaluationError(f"{path}: {what}")
        problems.append(f"{cells[0]}: {what}: #VALUE!")
        note = Note(what, "#VALUE!")
        for i in set(stuck):
            runs[i].error = note                # no inputs now: ordered first in the next pass


def _span(run: Run, ref: Ref) -> tuple[int, int, int, int]:
    """The rows and columns a reference touches from all the cells of a run: first row,
    last row, first column, last column (the block _schedule and the stores consider)."""
    r1 = ref.r1 if ref.r1_abs else run.row + ref.r1
    r2 = ref.r2 if ref.r2_abs else run.row + ref.r2
    first, last = int(run.cols[0]), int(run.cols[-1])
    lo1, hi1 = (ref.c1, ref.c1) if ref.c1_abs else (first + ref.c1, last + ref.c1)
    lo2, hi2 = (ref.c2, ref.c2) if ref.c2_abs else (first + ref.c2, last + ref.c2)
    return min(r1, r2), max(r1, r2), min(lo1, lo2), max(hi1, hi2)


_PARSED: dict = {}


def _parse_run(formula: str, row: int, col: int, names: dict, names_key) -> tuple:
    """(tree, error, references) of a run's first formula; kept for the rest of the process
    (a class's workbooks share their formulas), keyed by the text, the cell and the names."""
    key = (formula, row, col, names_key)
    hit = _PARSED.get(key)
    if hit is not None:
        return hit
    tree, error = None, None
    try:
        tree = parse_formula("=" + formula, row, col, names)
        bad = sorted(f for f in functions_of(tree) if f not in SUPPORTED)
        if bad:
            error = Note(f"unsupported function{'s' if len(bad) > 1 else ''} {', '.join(bad)}")
        elif (wrong := arity_problem(tree)) is not None:
            error = Note(wrong, "#VALUE!")
    except ParseError as e:
        error = Note(f"cannot read the formula ={_show(formula, 80)}: {e}", e.code)
    hit = (tree, error, refs_of(tree) if tree is not None else [])
    if len(_PARSED) > 100_000:
        _PARSED.clear()
    _PARSED[key] = hit
    return hit


def _binary_op(op: str, a: Val, b: Val) -> Val:
    try:
        np.broadcast_shapes(a.shape, b.shape)
    except ValueError:                      # ranges of different sizes (=A1:B2+A1:C3): #VALUE!
        return _const("#VALUE!", max(a.shape[0], b.shape[0]))
    if op in ("+", "-", "*", "/", "^"):
        return _arith(op, a, b)
    if op == "&":
        return _concat(a, b)
    return _compare(op, a, b)


PAD_CELLS = 1 << 16      # a range up to this many cells keeps its shape past the used range


def _rows_cols(r1: int, r2: int, c1: int, c2: int, nr: int, nc: int) -> tuple[np.ndarray, np.ndarray]:
    """The rows and columns of a block that reaches past a store of nr x nc: all of them
    when the block is small (PAD_CELLS: its shape is kept, the cells outside read as
    empty), else clipped to the store (=SUM($A$1:$XFD$1048576) reads the used range)."""
    if (r2 - r1 + 1) * (c2 - c1 + 1) > PAD_CELLS:
        r2, c2 = min(r2, nr - 1), min(c2, nc - 1)
    return np.arange(r1, r2 + 1), np.arange(c1, c2 + 1)


class _Context:
    def __init__(self, num, tag, txt, scopes):
        self.num, self.tag, self.txt, self.scopes = num, tag, txt, scopes
        self.open_names: set = set()          # the names being evaluated (a cycle: #REF!)
        self.arrays: dict = {}                # sheet -> its array formulas (Sheet.arrays)

    def name(self, name: str, run: Run):
        """The tree a name stands for in a formula of run's sheet, or None."""
        return _lookup(self.scopes, run.sheet, name)

    def ref(self, ref: Ref, run: Run) -> Val:
        sheet = ref.sheet or run.sheet
        if sheet not in self.num:
            return _const("#REF!", len(run.cols))
        if (ref.r1, ref.c1, ref.r1_abs, ref.c1_abs) == (ref.r2, ref.c2, ref.r2_abs, ref.c2_abs) and run.contiguous:
            # one cell per cell of the run, adjacent: views of one stretch of a row
            r = ref.r1 if ref.r1_abs else run.row + ref.r1
            k = len(run.cols)
            c = ref.c1 if ref.c1_abs else int(run.cols[0]) + ref.c1
            if r < 1 or c < 1:
                return _const("#REF!", k)
            n = 1 if ref.c1_abs else k
            if r >= self.tag[sheet].shape[0] or c + n > self.tag[sheet].shape[1]:
                return self._gather(sheet, np.array([r]), (c + np.arange(n))[:, None])   # past the used range
            tag = self.tag[sheet][r, c:c + n].reshape(n, 1, 1)
            if not tag.any():
                return Val(self.num[sheet][r, c:c + n].reshape(n, 1, 1), tag, None, NUM)
            if (tag == BOOL).all():
                return Val(self.num[sheet][r, c:c + n].reshape(n, 1, 1), tag, None, BOOL)
            txt = self.txt[sheet][r, c:c + n].reshape(n, 1, 1) if (tag == TEXT).any() else None
            return Val(self.num[sheet][r, c:c + n].reshape(n, 1, 1), tag, txt)
        if len(run.cols) == 1 or (ref.c1_abs and ref.c2_abs):
            # one block for all the cells (a single cell's range, or absolute columns): a view
            r1, r2, c1, c2 = _span(run, ref)
            if r1 < 1 or c1 < 1:
                return _const("#REF!", len(run.cols))
            nr, nc = self.tag[sheet].shape
            if r2 >= nr or c2 >= nc:                   # past the used range
                rows, cols = _rows_cols(r1, r2, c1, c2, nr, nc)
                return self._gather(sheet, rows, cols[None, :])
            tag = self.tag[sheet][None, r1:r2 + 1, c1:c2 + 1]
            if not tag.any():
                return Val(self.num[sheet][None, r1:r2 + 1, c1:c2 + 1], tag, None, NUM)
            if (tag == BOOL).all():
                return Val(self.num[sheet][None, r1:r2 + 1, c1:c2 + 1], tag, None, BOOL)
            txt = self.txt[sheet][None, r1:r2 + 1, c1:c2 + 1] if (tag == TEXT).any() else None
            return Val(self.num[sheet][None, r1:r2 + 1, c1:c2 + 1], tag, txt)
        r1, r2, c1, c2 = _target_block(run, ref)
        if r1 < 1 or int(c1.min()) < 1:
            return _const("#REF!", len(run.cols))
        absolute = ref.c1_abs and ref.c2_abs
        width = int(c2[0] - c1[0]) + 1
        nr, nc = self.tag[sheet].shape
        if r2 >= nr or int(c1.max()) + width > nc:     # past the used range
            rows, offsets = _rows_cols(r1, r2, 0, width - 1, nr, max(0, nc - int(c1.min())))
            cols = (c1[:1] if absolute else c1)[:, None] + offsets[None, :]
            return self._gather(sheet, rows, cols)
        cols = (c1[:1] if absolute else c1)[:, None] + np.arange(width)[None, :]   # (k, C)
        rows = np.arange(r1, r2 + 1)
        num = self.num[sheet][rows[:, None, None], cols[None, :, :]].transpose(1, 0, 2)
        tag = self.tag[sheet][rows[:, None, None], cols[None, :, :]].transpose(1, 0, 2)
        txt = None
        if (tag == TEXT).any():
            txt = self.txt[sheet][rows[:, None, None], cols[None, :, :]].transpose(1, 0, 2)
        return Val(num, tag, txt)

    def _gather(self, sheet: str, rows: np.ndarray, cols: np.ndarray) -> Val:
        """Cells rows x cols[i] for each cell i of a run, shape (k, R, C); cells past the
        store (the used range) read as empty."""
        nr, nc = self.tag[sheet].shape
        inside = (rows < nr)[None, :, None] & (cols < nc)[:, None, :]
        idx = (np.where(rows < nr, rows, 0)[None, :, None], np.where(cols < nc, cols, 0)[:, None, :])
        tag = np.where(inside, self.tag[sheet][idx], EMPTY).astype(np.int8)
        num = np.where(inside, self.num[sheet][idx], 0.0)
        txt = np.where(inside, self.txt[sheet][idx], None) if (tag == TEXT).any() else None
        return Val(num, tag, txt, NUM if not tag.any() else -1)

    def eval(self, node, run: Run) -> Val:
        kind = node[0]
        if kind == "const":
            return _const(node[1])
        if kind == "ref":
            return self.ref(node[1], run)
        if kind == "name":
            tree = self.name(node[1], run)
            if tree is None:
                return _const("#NAME?")
            if node[1] in self.open_names:          # a name that refers back to itself
                return _const("#REF!")
            self.open_names.add(node[1])
            try:
                return self.eval(tree, run)
            finally:
                self.open_names.discard(node[1])
        if kind == "neg":
            return _arith("-", _const(0.0), self.eval(node[1], run))
        if kind == "pct":
            return _arith("/", self.eval(node[1], run), _const(100.0))
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
            return _const(0.0)
        if kind == "fn":
            return self.call(node[1], node[2], run)
        raise EvaluationError(f"cannot evaluate {node!r}")

    def call(self, name: str, args, run: Run) -> Val:
        if name == "PI":
            return _const(math.pi)
        if name == "IF":
            cond, err = _to_bool(self.eval(args[0], run))
            a = self.eval(args[1], run) if len(args) > 1 and args[1][0] != "missing" else _const(0.0)
            b = self.eval(args[2], run) if len(args) > 2 else _const(False)
            return _with_error(_select(cond, a, b), err)
        if name == "IFERROR":
            a, b = self.eval(args[0], run), self.eval(args[1], run)
            return _select(a.tag >= 10, b, a)
        if name == "NOT":
            b, err = _to_bool(self.eval(args[0], run))
            return Val(np.where(err == 0, (~b).astype(float), 0.0), np.where(err == 0, BOOL, err).astype(np.int8))
        if name in ("ISNUMBER", "ISERROR", "ISTEXT"):
            v = self.eval(args[0], run)
            test = {"ISNUMBER": v.tag == NUM, "ISERROR": v.tag >= 10, "ISTEXT": v.tag == TEXT}[name]
            return Val(test.astype(float), np.full(v.shape, BOOL, np.int8))
        if name == "NA":                          # the charts' gap: #N/A is not plotted
            return _const("#N/A", len(run.cols))
        if name in ("TRUE", "FALSE"):             # LibreOffice writes TRUE() and FALSE()
            return _const(name == "TRUE") if not args else _const("#VALUE!", len(run.cols))
        if name == "TRUNC":
            return self.trunc(args, run)
        if name == "INDEX":
            return self.index(args, run)
        if name == "CHOOSE":
            return self.choose(args, run)
        if name in fx.ROUNDING:
            return self.rounding(name, args, run)
        if name == "ANCHORARRAY":
            return self.spill(args, run)
        if name == "SINGLE":
            return self.single(args, run)
        if name in SCALAR_FUNCS:
            return SCALAR_FUNCS[name](*(self.eval(a, run) for a in args))
        if name in AGGREGATES:
            vals = [self.eval(a, run) for a in args]
            # a reference, even to one cell or through a defined name, is read like a range:
            # text and booleans skipped
            ranges = [a[0] == "ref" or (a[0] == "name" and (self.name(a[1], run) or ("",))[0] == "ref")
                      or (a[0] == "fn" and a[1] == "ANCHORARRAY") for a in args]
            return AGGREGATES[name](vals, ranges)
        return _const("#NAME?", len(run.cols))


    def trunc(self, args, run: Run) -> Val:
        if len(args) == 1:
            return _unary(fx.trunc)(self.eval(args[0], run))
        return _binary(fx.trunc)(self.eval(args[0], run), self.eval(args[1], run))

    def rounding(self, name: str, args, run: Run) -> Val:
        """FLOOR.MATH and kin: a number, then optional arguments with defaults."""
        fn, defaults = fx.ROUNDING[name]
        if not 1 <= len(args) <= fx.ROUNDING_ARITY[name]:
            return _const("#VALUE!", len(run.cols))
        vals = [self.eval(a, run) if a[0] != "missing" else _const(0.0) for a in args]
        vals += [_const(d) for d in defaults[len(args) - 1:]]
        nums, errs = zip(*(_to_number(v) for v in vals))
        with np.errstate(all="ignore"):
            r = fn(*np.broadcast_arrays(*nums))
        return _result(r, _error_of(*errs))

    def spill(self, args, run: Run) -> Val:
        """Excel 365's E1# (written _xlfn.ANCHORARRAY(E1)): the range an array formula at E1
        fills; #REF! where E1 holds no array formula."""
        if len(args) != 1 or args[0][0] != "ref" or args[0][1].is_range:
            return _const("#REF!", len(run.cols))
        ref = args[0][1]
        sheet = ref.sheet or run.sheet
        r = ref.r1 if ref.r1_abs else run.row + ref.r1
        cols = [ref.c1] if ref.c1_abs else [c + ref.c1 for c in run.cols.tolist()]
        ends = [self.arrays.get(sheet, {}).get((r, c)) for c in cols]
        if any(e is None for e in ends) or len({(e[0] - r, e[1] - c) for e, c in zip(ends, cols)}) != 1:
            return _const("#REF!", len(run.cols))
        (r2, c2), c = ends[0], cols[0]
        block = Ref(sheet, r, c if ref.c1_abs else c - int(run.cols[0]), r2,
                    c2 if ref.c1_abs else c2 - int(run.cols[0]), True, ref.c1_abs, True, ref.c1_abs)
        return self.ref(block, run)

    def single(self, args, run: Run) -> Val:
        """Excel 365's @ (written _xlfn.SINGLE(...)), implicit intersection: of a range, the
        cell in the formula's row (a column range) or column (a row range); of an array, its
        first element; #VALUE! where the formula's row or column misses the range."""
        if len(args) != 1:
            return _const("#VALUE!", len(run.cols))
        v = self.eval(args[0], run)
        k0, R, C = v.shape
        k = len(run.cols)
        if (R, C) == (1, 1):
            return v
        if args[0][0] != "ref":
            return Val(v.num[:, :1, :1], v.tag[:, :1, :1], None if v.txt is None else v.txt[:, :1, :1])
        r1, _, c1, _ = _target_block(run, args[0][1])
        i = np.full(k, run.row - r1) if R > 1 else np.zeros(k, np.int64)
        j = (run.cols - c1) if C > 1 else np.zeros(k, np.int64)
        bad = (i < 0) | (i >= R) | (j < 0) | (j >= C)
        i, j = np.where(bad, 0, i), np.where(bad, 0, j)
        cells = np.arange(k) if k0 == k else np.zeros(k, np.int64)
        pick = (cells, i, j)
        out = Val(v.num[pick].reshape(k, 1, 1), v.tag[pick].reshape(k, 1, 1).astype(np.int8),
                  None if v.txt is None else np.asarray(v.txt)[pick].reshape(k, 1, 1))
        return _with_error(out, np.where(bad, VALUE, 0).astype(np.int8).reshape(k, 1, 1))

    def choose(self, args, run: Run) -> Val:
        """CHOOSE(i, v1, v2, ...): the i-th value (per cell of the run)."""
        i, err = _to_number(self.eval(args[0], run))
        pos, bad = fx.choose_index(i, len(args) - 1)
        err = _error_of(err, bad)
        values = [self.eval(a, run) for a in args[1:]]
        shape = np.broadcast_shapes(pos.shape, *(v.shape for v in values))
        num = np.choose(np.broadcast_to(pos, shape), [np.broadcast_to(v.num, shape) for v in values])
        tags = np.choose(np.broadcast_to(pos, shape), [np.broadcast_to(v.tag, shape) for v in values])
        txt = None
        if any(v.txt is not None for v in values):
            txt = np.choose(np.broadcast_to(pos, shape), [np.broadcast_to(_texts(v), shape) for v in values])
        return _with_error(Val(num, tags.astype(np.int8), txt), np.broadcast_to(err, shape))

    def index(self, args, run: Run) -> Val:
        """INDEX(array, row, [column]): one element per cell of the run, or a whole row or
        column where an index is 0."""
        arr = self.eval(args[0], run)
        k0, R, C = arr.shape
        r, er = _to_number(self.eval(args[1], run)) if len(args) > 1 else (np.zeros((1, 1, 1)), np.zeros((1, 1, 1), np.int8))
        c, ec = (_to_number(self.eval(args[2], run)) if len(args) > 2 and args[2][0] != "missing"
                 else (None, np.zeros((1, 1, 1), np.int8)))
        ri, ci, bad = fx.index_positions(R, C, r, c)
        err = _error_of(er, ec, bad)
        k = max(k0, err.shape[0])
        ri, ci, err = (np.broadcast_to(x, (k, 1, 1)).reshape(k) for x in (ri, ci, err))
        if (ri >= 0).all() and (ci >= 0).all():
            cells = np.arange(k) if k0 == k else np.zeros(k, np.int64)
            pick = (cells, ri, ci)
            v = Val(arr.num[pick].reshape(k, 1, 1), arr.tag[pick].reshape(k, 1, 1).astype(np.int8),
                    None if arr.txt is None else np.asarray(arr.txt)[pick].reshape(k, 1, 1))
            return _with_error(v, err.reshape(k, 1, 1))
        if k == 1:                               # a whole row or column of the array
            rs = slice(None) if ri[0] < 0 else slice(ri[0], ri[0] + 1)
            cs = slice(None) if ci[0] < 0 else slice(ci[0], ci[0] + 1)
            v = Val(arr.num[:, rs, cs], arr.tag[:, rs, cs], None if arr.txt is None else arr.txt[:, rs, cs])
            return _with_error(v, err.reshape(1, 1, 1))
        return _const("#VALUE!", k)


# --------------------------------------------------------------------------- formulas over given values
def parse_rows(sheet: Sheet, rows: set[int]) -> list[Run]:
    """The formula cells of some rows of a sheet (no defined names) as parsed runs, for
    evaluate_runs: sheetkin.localjudge evaluates a generated sheet's formulas over a
    student's numbers. A run whose ranges change width from cell to cell is split into cells
    (as _schedule does); a formula that cannot be read is left out."""
    sub = Sheet(sheet.name, sheet.state, formulas={k: f for k, f in sheet.formulas.items() if k[0] in rows})
    out = []
    for run in _group_runs(sub):
        run.tree, run.error, run.refs = _parse_run(run.formula, run.row, int(run.cols[0]), {}, frozenset())
        if run.error:
            continue
        varies = len(run.cols) > 1 and any(ref.c1_abs != ref.c2_abs for ref in run.refs)
        out.extend(_split(run) if varies else [run])
    return out


def evaluate_runs(runs: list[Run], num: dict, tag: dict, txt: dict) -> list[tuple[Run, np.ndarray, np.ndarray]]:
    """(run, numbers, tags) of each run's formula evaluated over the given value stores
    (sheet -> arrays, as Book holds them), nothing written back: every run reads the
    stores as they are, whatever order the runs come in. An internal error of the
    evaluator is the cell's #VALUE!, as in evaluate_sheets without strict."""
    ctx = _Context(num, tag, txt, {None: {}})
    out = []
    with np.errstate(all="ignore"):
        for run in runs:
            k = len(run.cols)
            try:
                v = _as_cells(ctx.eval(run.tree, run), k)
            except Exception:      # noqa: BLE001 - the cell's problem, not the caller's
                v = _const("#VALUE!", k)
            out.append((run, v.num[:, 0, 0], v.tag[:, 0, 0]))
    return out


# --------------------------------------------------------------------------- results as tables
def rows_frame(book: Book, sheet: str | None = None, first_col: int = 5) -> pd.DataFrame:
    """One sheet as a table: rows named by column A, columns = positions (column E on).
    Rows without a name in column A are left out; values are floats, text, booleans or
    error texts such as '#NUM!'."""
    sheet = sheet or book.order[0]
    sh = book.sheets[sheet]
    last = max(max(map(itemgetter(1), sh.formulas), default=first_col),
               max(map(itemgetter(1), sh.consts), default=first_col), first_col)
    filled = {r for (r, c) in sh.formulas if c >= first_col} | {r for (r, c) in sh.consts if c >= first_col}
    num, tag = book.num[sheet], book.tag[sheet]
    stop = min(last + 1, num.shape[1])             # columns past the stores are empty
    names, data = [], []
    for r in range(1, sh.max_row + 1):
        label = book.value(sheet, r, 1)
        if not isinstance(label, str) or not label or r <= 4 or r not in filled:
            continue
        names.append(label)
        if r < num.shape[0] and not tag[r, first_col:stop].any():       # numbers only
            values = num[r, first_col:stop].tolist()
        else:
            values = [book.value(sheet, r, c) for c in range(first_col, stop)]
        data.append(values + [None] * (last + 1 - max(stop, first_col)))
    df = pd.DataFrame(data, index=names, columns=list(range(1, last - first_col + 2)), dtype=object)
    df.index.name = "name"
    return df


def evaluate_frame(path: str | Path, sheet: str | None = None) -> pd.DataFrame:
    """A workbook's named rows (column A) against its positions (column E onwards), every
    formula evaluated headlessly: the Python face of `sheetkin evaluate`."""
    return rows_frame(evaluate(path), sheet)
