"""Formula values, and what operators and functions do with them: the evaluator's Val
(numbers, text, booleans, empty cells and Excel's errors, one value per cell of a run),
the coercions, the operators, the scalar functions and the aggregates, the lazy functions
(LAZY: IF, IFERROR, CHOOSE, INDEX ..., each a table entry with its hook) and the list of
functions the evaluator supports (SUPPORTED).

Values follow Excel: numbers, text, booleans, empty cells and the errors #NULL! #DIV/0!
#VALUE! #REF! #NAME? #NUM! #N/A, which propagate per cell. Every value is an array of
shape (cells, rows, cols): (k, 1, 1) for one value per cell of a run, (k, R, C) for a range.

Separate from evaluator.py (reading a workbook, ordering and running its formulas) because
these are the semantics of single values, checked cell by cell against Excel and
LibreOffice, and need nothing of the workbook. functions.py holds the numeric kernels (plain
float arrays, error codes); this module wraps them with the coercions and the error
propagation. It imports functions.py, never the reverse, and nothing of the evaluator.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, cast

import numpy as np

from . import functions as fx
from .caches import Cache
from .functions import DIV0, ERRORS, FIRST_ERROR, MAX_TEXT, NA, NUMERR, VALUE, XlError

NUM, BOOL, TEXT, EMPTY = 0, 1, 2, 3


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


def pure_result(num: np.ndarray, kind: int = NUM) -> Val:
    """A result known to be all numbers (or all booleans), without errors."""
    return Val(num, None, None, kind)


_CONSTS = Cache("constants of one value: (type, value) -> Val", 10_000)


def constant(value, k=1) -> Val:
    if k == 1 and type(value) in (bool, float, int, str):
        # one Val per constant, read-only, shared by every formula that holds it (a text too:
        # the check rows compare with "" in every status cell)
        key = (type(value), value)
        v = _CONSTS.get(key)
        if v is None:
            v = _const_new(value, 1)
            if type(value) is not str:
                v.pure = BOOL if type(value) is bool else NUM
            for a in (v.num, v.tag, v.txt):
                if a is not None:
                    a.setflags(write=False)
            _CONSTS.put(key, v)
        return v
    return _const_new(value, k)


def _const_new(value, k) -> Val:
    if isinstance(value, bool):
        return Val(np.full((k, 1, 1), float(value)), np.full((k, 1, 1), BOOL, np.int8))
    if isinstance(value, (int, float)):
        return Val(np.full((k, 1, 1), float(value)), np.zeros((k, 1, 1), np.int8))
    if isinstance(value, XlError):           # an error; a plain str that spells one is text
        return Val(np.zeros((k, 1, 1)), np.full((k, 1, 1), ERRORS.get(value, VALUE), np.int8))
    txt = np.empty((k, 1, 1), dtype=object)
    txt[...] = value
    return Val(np.zeros((k, 1, 1)), np.full((k, 1, 1), TEXT, np.int8), txt)


def array_constant(rows: tuple) -> Val:
    """An array constant ({1,2;3,4}: a tuple of rows of constants) as one value of R x C
    cells, what a range of those values would be."""
    cells = [[constant(x) for x in row] for row in rows]
    num = np.array([[v.num[0, 0, 0] for v in row] for row in cells])[None]
    tag = np.array([[v.tag[0, 0, 0] for v in row] for row in cells], np.int8)[None]
    txt = None
    if (tag == TEXT).any():
        txt = np.full(tag.shape, None, dtype=object)
        for i, row in enumerate(rows):
            for j, x in enumerate(row):
                if tag[0, i, j] == TEXT:
                    txt[0, i, j] = x
    return Val(num, tag, txt)


def error_value(code: str, k: int = 1) -> Val:
    """The error `code` ("#VALUE!") in each of k cells."""
    return constant(XlError(code), k)


def first_error_of(*tags) -> np.ndarray:
    """The first error among the operands (Excel reports the leftmost), else 0."""
    out = np.zeros(np.broadcast_shapes(*(t.shape for t in tags)), np.int8)
    for t in reversed(tags):
        out = np.where(t >= FIRST_ERROR, t, out)
    return out


def texts_of(v: Val) -> np.ndarray:
    return v.txt if v.txt is not None else np.full(v.shape, None, dtype=object)


NUMERIC_TEXT = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*$")


def to_number(v: Val):
    """Arithmetic coercion: numbers, booleans; empty is 0; numeric text converts;
    other text is #VALUE!. Returns (num, error tags)."""
    num, err = v.num, np.where(v.tag >= FIRST_ERROR, v.tag, 0).astype(np.int8)
    text = v.tag == TEXT
    if text.any():
        num = num.copy()
        txt = cast(np.ndarray, v.txt)           # a TEXT tag: txt is set (Val's invariant)
        for idx in zip(*np.nonzero(text), strict=False):
            t = str(txt[idx])
            if NUMERIC_TEXT.match(t):          # not Python's float(): "1_000", "inf" are not numbers
                num[idx] = float(t)
            else:
                err[idx] = VALUE
    return num, err


def numeric_result(num, err) -> Val:
    """A numeric result; NaN or infinity where no error is set yet becomes #NUM!."""
    bad = (err == 0) & ~np.isfinite(num)
    tag = np.where(bad, NUMERR, err).astype(np.int8)
    return Val(np.where(tag == 0, num, 0.0), tag, None, -1 if tag.any() else NUM)


def to_bool(v: Val):
    """Logical coercion (IF, AND...): numbers non-zero, booleans, empty FALSE; text #VALUE!."""
    if v.pure != -1:
        return v.num != 0, np.zeros(v.shape, np.int8)
    err = np.where(v.tag >= FIRST_ERROR, v.tag, np.where(v.tag == TEXT, VALUE, 0)).astype(np.int8)
    return v.num != 0, err


def number_text(x: float) -> str:
    """A number as Excel's general format shows it in text (=2&"" is "2")."""
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    s = f"{x:.15g}"
    if "e" in s:
        mant, exp = s.split("e")
        s = f"{mant}E{int(exp):+03d}".replace("E+", "E+")
    return s


def to_text(v: Val) -> tuple[np.ndarray, np.ndarray]:
    out = np.empty(v.shape, dtype=object)
    for idx in np.ndindex(v.shape):
        t = v.tag[idx]
        # txt is read only where the tag is TEXT, so it is set (Val's invariant); a full
        # index into num gives one float64, a float
        out[idx] = (cast(np.ndarray, v.txt)[idx] if t == TEXT else "" if t == EMPTY else
                    ("TRUE" if v.num[idx] else "FALSE") if t == BOOL
                    else number_text(cast(float, v.num[idx])))
    return out, np.where(v.tag >= FIRST_ERROR, v.tag, 0).astype(np.int8)


# --------------------------------------------------------------------------- operators
_OPS = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide, "^": np.power}


def arith(op: str, a: Val, b: Val) -> Val:
    if a.pure != -1 and b.pure != -1:            # numbers, booleans (1, 0): no coercion, no errors
        with np.errstate(all="ignore"):
            r = _OPS[op](a.num, b.num)
        # x/0, 0^-1 and overflow give NaN or infinity, and so a sum that is not finite (a
        # sum that overflows only sends finite values the general way): that path names the error
        if math.isfinite(r.sum()) and (op != "^" or not ((a.num == 0) & (b.num == 0)).any()):
            return pure_result(r)
    an, ae = to_number(a)
    bn, be = to_number(b)
    err = first_error_of(ae, be)
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
    return numeric_result(r, err)


def result_shape(a: Val, b: Val) -> tuple:
    """The shape of an operation's result: numpy's broadcast_shapes (ValueError for shapes
    that do not broadcast), without its cost where the shapes are equal or one side is a
    single value (a constant against a range: most operations, issue 32)."""
    if a.shape == b.shape or b.shape == (1, 1, 1):
        return a.shape
    if a.shape == (1, 1, 1):
        return b.shape
    return np.broadcast_shapes(a.shape, b.shape)


def _rank(tag):
    """Excel's order of types in comparisons: numbers < text < booleans."""
    return np.where(tag == TEXT, 1, np.where(tag == BOOL, 2, 0))


def _all_text(v: Val) -> bool:
    return v.pure == -1 and v.tag.size <= 4096 and bool((v.tag == TEXT).all())


def compare(op: str, a: Val, b: Val) -> Val:
    if a.pure == NUM and b.pure == NUM:          # the general path's arithmetic, without tags
        an, bn = a.num, b.num
        with np.errstate(all="ignore"):
            d = an - bn
            near = np.abs(d) <= 4 * np.finfo(float).eps * np.maximum(np.abs(an), np.abs(bn))
        diff = np.where(near, 0.0, np.sign(d))
        return pure_result(_COMPARE[op](diff, 0).astype(float), BOOL)
    if (a.pure == NUM and _all_text(b)) or (b.pure == NUM and _all_text(a)):
        # numbers against text (a generated sheet's checks: E34:Q34="" in every status
        # formula, 85% of a book's evaluation): never equal, numbers rank below text,
        # no error on either side: the general path's answer without its arrays (issue 24)
        sign = -1.0 if a.pure == NUM else 1.0
        return pure_result(np.full(result_shape(a, b), float(_COMPARE[op](sign, 0))), BOOL)
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
        ta, tb = np.broadcast_to(texts_of(a), shape), np.broadcast_to(texts_of(b), shape)
        diff = diff.copy()
        for idx in zip(*np.nonzero(text), strict=False):
            x = "" if at[idx] == EMPTY else str(ta[idx]).casefold()
            y = "" if bt[idx] == EMPTY else str(tb[idx]).casefold()
            diff[idx] = (x > y) - (x < y)
    res = {"=": diff == 0, "<>": diff != 0, "<": diff < 0, ">": diff > 0,
           "<=": diff <= 0, ">=": diff >= 0}[op]
    err = first_error_of(at, bt)
    return Val(np.where(err == 0, res.astype(float), 0.0), np.where(err == 0, BOOL, err).astype(np.int8))


_COMPARE = {"=": np.equal, "<>": np.not_equal, "<": np.less, ">": np.greater,
            "<=": np.less_equal, ">=": np.greater_equal}


def concat(a: Val, b: Val) -> Val:
    ta, ea = to_text(a)
    tb, eb = to_text(b)
    shape = np.broadcast_shapes(ta.shape, tb.shape)
    ta, tb = np.broadcast_to(ta, shape), np.broadcast_to(tb, shape)
    out = np.empty(shape, dtype=object)
    err = first_error_of(ea, eb)
    for idx in np.ndindex(shape):
        # Excel's cap on a cell's text: longer is #VALUE! (a text doubled 40 times by `&`
        # reached 2 GB before this)
        if len(ta[idx]) + len(tb[idx]) > MAX_TEXT:
            out[idx] = ""
            if not err[idx]:
                err[idx] = VALUE
        else:
            out[idx] = ta[idx] + tb[idx]
    return Val(np.zeros(shape), np.where(err == 0, TEXT, err).astype(np.int8), out)


def select(cond: np.ndarray, a: Val, b: Val) -> Val:
    if a.pure == b.pure != -1:
        return pure_result(np.where(cond, a.num, b.num), a.pure)
    shape = np.broadcast_shapes(cond.shape, a.shape, b.shape)
    txt = None
    if a.txt is not None or b.txt is not None:
        txt = np.where(cond, np.broadcast_to(texts_of(a), shape), np.broadcast_to(texts_of(b), shape))
    return Val(np.where(cond, a.num, b.num), np.where(cond, a.tag, b.tag).astype(np.int8), txt)


def with_error(v: Val, err: np.ndarray) -> Val:
    if not err.any():
        return v
    shape = np.broadcast_shapes(v.shape, err.shape)
    return Val(np.where(err != 0, 0.0, v.num), np.where(err != 0, err, v.tag).astype(np.int8),
               None if v.txt is None else np.broadcast_to(v.txt, shape))


# --------------------------------------------------------------------------- functions
def unary(fn, domain=None):
    def f(x: Val) -> Val:
        if x.pure != -1:
            with np.errstate(all="ignore"):
                r = fn(x.num)
            if math.isfinite(r.sum()) and (domain is None or domain(x.num).all()):
                return pure_result(r)
        n, err = to_number(x)
        with np.errstate(all="ignore"):
            r = fn(n)
            if domain is not None:
                err = np.where((err == 0) & ~domain(n), NUMERR, err).astype(np.int8)
        return numeric_result(r, err)
    return f


def binary(fn, check=None):
    def f(a: Val, b: Val) -> Val:
        if a.pure != -1 and b.pure != -1:
            with np.errstate(all="ignore"):
                r = fn(a.num, b.num)
                if math.isfinite(r.sum()) and (check is None or not np.any(check(a.num, b.num))):
                    return pure_result(r)
        an, ae = to_number(a)
        bn, be = to_number(b)
        err = first_error_of(ae, be)
        with np.errstate(all="ignore"):
            r = fn(an, bn)
            if check is not None:
                err = np.where(err == 0, check(an, bn), err).astype(np.int8)
        return numeric_result(r, err)
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


def _rept(a: Val, b: Val) -> Val:
    """REPT(text, times): #VALUE! for a negative count or past MAX_TEXT characters, known
    from the lengths before any text is built."""
    ta, ea = to_text(a)
    n, eb = to_number(b)
    shape = np.broadcast_shapes(ta.shape, n.shape)
    ta, n = np.broadcast_to(ta, shape), np.broadcast_to(n, shape)
    err = first_error_of(ea, eb)
    out = np.empty(shape, dtype=object)
    for idx in np.ndindex(shape):
        x = float(n[idx])
        times = math.trunc(x) if math.isfinite(x) else -1
        if times < 0 or len(ta[idx]) * times > MAX_TEXT:
            out[idx] = ""
            if not err[idx]:
                err[idx] = VALUE
        else:
            out[idx] = ta[idx] * times if ta[idx] else ""
    return Val(np.zeros(shape), np.where(err == 0, TEXT, err).astype(np.int8), out)


def _TRIG_OK(x):
    return np.abs(x) < 134217728.0


SCALAR_FUNCS = {
    # Excel refuses trigonometry of |x| >= 2^27 (#NUM!): too few digits are left for the angle
    "SIN": unary(np.sin, _TRIG_OK), "COS": unary(np.cos, _TRIG_OK), "TAN": unary(np.tan, _TRIG_OK),
    "ASIN": unary(np.arcsin, lambda x: np.abs(x) <= 1), "ACOS": unary(np.arccos, lambda x: np.abs(x) <= 1),
    "ATAN": unary(np.arctan), "SQRT": unary(np.sqrt, lambda x: x >= 0),
    "RADIANS": unary(np.radians), "DEGREES": unary(np.degrees), "ABS": unary(np.abs),
    "SIGN": unary(np.sign), "EXP": unary(np.exp), "LN": unary(np.log, lambda x: x > 0),
    "LOG10": unary(np.log10, lambda x: x > 0),
    # Excel's ATAN2 takes (x, y); ATAN2(0, 0) is #DIV/0!
    "ATAN2": binary(lambda x, y: np.arctan2(y, x), lambda x, y: np.where((x == 0) & (y == 0), DIV0, 0)),
    "MOD": binary(lambda a, b: a - b * np.floor(a / b), lambda a, b: np.where(b == 0, DIV0, 0)),
    "POWER": binary(np.power,
                     lambda a, b: np.where((a == 0) & (b < 0), DIV0, np.where((a == 0) & (b == 0), NUMERR, 0))),
    "ROUND": binary(lambda x, n: _round(x, np.trunc(n))),
    "REPT": _rept, "INT": unary(fx.int_), "FLOOR": binary(fx.floor, fx.floor_check),
    "CEILING": binary(fx.ceiling, fx.ceiling_check),
}


def values_of(args: list[Val], ranges: list[bool], *, numbers_only_in_ranges=True):
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
    for v, is_range in zip(args, ranges, strict=False):
        k = v.shape[0]
        if is_range:
            use = v.tag == NUM if numbers_only_in_ranges else (v.tag == NUM) | (v.tag == BOOL)
            err = np.where(v.tag >= FIRST_ERROR, v.tag, 0)
            n = v.num
        else:
            n, err = to_number(v)
            use = v.tag != EMPTY
        nums.append(n.reshape(k, -1))
        uses.append(use.reshape(k, -1))
        errs.append(err.reshape(k, -1))
    k = max(x.shape[0] for x in nums)
    num_cols = np.concatenate([np.broadcast_to(x, (k, x.shape[1])) for x in nums], axis=1)
    use_cols = np.concatenate([np.broadcast_to(x, (k, x.shape[1])) for x in uses], axis=1)
    err_cols = np.concatenate([np.broadcast_to(x, (k, x.shape[1])) for x in errs], axis=1)
    return num_cols, use_cols, first_error(err_cols)


def first_error(errs: np.ndarray) -> np.ndarray:
    """Per row of a (k, n) array of error tags: the first non-zero one (Excel reports the
    first error it meets), else 0."""
    if errs.shape[1] == 0:
        return np.zeros(errs.shape[0], np.int8)
    idx = np.argmax(errs != 0, axis=1)
    return errs[np.arange(errs.shape[0]), idx].astype(np.int8)


def scalar_result(num, err) -> Val:
    return numeric_result(num.reshape(-1, 1, 1), err.reshape(-1, 1, 1))


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
    for v, r in zip(args, ranges, strict=False):
        n, use, err = values_of([v], [r])
        parts.append(tuple(np.broadcast_to(x, (k,)) for x in reduce(n, use)))
        errs.append(np.broadcast_to(err, (k,)))
    return parts, first_error(np.stack(errs, axis=1))


def _pure_scalars(num: np.ndarray) -> Val:
    """A numeric aggregate of numbers only, per cell (k,): pure when finite (no error to
    carry: the tags are not built), else the general path names the #NUM! (an overflow)."""
    if np.isfinite(num).all():
        return pure_result(num.reshape(-1, 1, 1))
    return scalar_result(num, np.zeros(num.shape, np.int8))


def _all_numbers(args) -> bool:
    """Every argument numbers only, and not empty: the aggregates' fast paths (the check
    rows' SUMPRODUCT(--(E72:MZ72="")), AND(...) of a generated sheet: 43 status cells
    took 60 % of evaluating the 360-column shaper through the general paths, issue 32)."""
    return all(v.pure == NUM and v.num.size for v in args)


def _agg_sum(args, ranges):
    if _all_numbers(args) and not _one_block_for_all(args):
        # contiguous, as the general path's array: numpy's pairwise sums follow the layout
        return _pure_scalars(np.ascontiguousarray(values_of(args, ranges)[0]).sum(axis=1))
    if _one_block_for_all(args):
        parts, err = _by_argument(args, ranges, lambda n, use: (np.where(use, n, 0.0).sum(axis=1),))
        return scalar_result(sum(p[0] for p in parts), err)
    n, use, err = values_of(args, ranges)
    return scalar_result(np.where(use, n, 0.0).sum(axis=1), err)


def _agg_average(args, ranges):
    if _one_block_for_all(args):
        parts, err = _by_argument(args, ranges, lambda n, use: (np.where(use, n, 0.0).sum(axis=1), use.sum(axis=1)))
        total, cnt = sum(p[0] for p in parts), sum(p[1] for p in parts)
    else:
        n, use, err = values_of(args, ranges)
        total, cnt = np.where(use, n, 0.0).sum(axis=1), use.sum(axis=1)
    with np.errstate(all="ignore"):
        r = total / cnt
    return scalar_result(r, np.where((err == 0) & (cnt == 0), DIV0, err))


def _agg_minmax(fn, empty):
    def reduce(n, use):
        return getattr(np.where(use, n, empty), fn)(axis=1, initial=empty), use.any(axis=1)

    def f(args, ranges):
        if _all_numbers(args) and not _one_block_for_all(args):
            # the general path's reduction exactly (contiguous, from `empty`): numpy's
            # vectorized min and max tell 0.0 from -0.0 by where they lie (ATAN2 shows it)
            n = np.ascontiguousarray(values_of(args, ranges)[0])
            return _pure_scalars(getattr(n, fn)(axis=1, initial=empty))
        if _one_block_for_all(args):
            parts, err = _by_argument(args, ranges, reduce)
            r = getattr(np, "minimum" if fn == "min" else "maximum").reduce([p[0] for p in parts])
            seen = np.logical_or.reduce([p[1] for p in parts])
        else:
            n, use, err = values_of(args, ranges)
            r, seen = reduce(n, use)
        return scalar_result(np.where(seen, r, 0.0), err)
    return f


def _agg_sumsq(args, ranges):
    n, use, err = values_of(args, ranges)
    return scalar_result(fx.sumsq(n, use), err)


def _agg_product(args, ranges):
    n, use, err = values_of(args, ranges)
    return scalar_result(fx.product(n, use), err)


def _agg_count(args, ranges):
    counts = None
    for v, is_range in zip(args, ranges, strict=False):
        if is_range:
            hit = v.tag == NUM
        else:                               # typed: numbers, booleans and numeric text count
            hit = (v.tag == NUM) | (v.tag == BOOL)
            if (v.tag == TEXT).any():
                hit = hit | np.vectorize(lambda t, x: t == TEXT and bool(NUMERIC_TEXT.match(str(x))),
                                         otypes=[bool])(v.tag, texts_of(v))
        c = hit.reshape(v.shape[0], -1).sum(axis=1)
        counts = c if counts is None else counts + c
    counts = cast(np.ndarray, counts)       # COUNT has at least one argument (the parser's rule)
    return Val(counts.astype(float).reshape(-1, 1, 1), np.zeros((counts.size, 1, 1), np.int8), None, NUM)


def _agg_sumproduct(args, ranges):
    if len({v.shape[1:] for v in args}) > 1:      # arrays of different sizes
        return error_value("#VALUE!", max(v.shape[0] for v in args))
    if _all_numbers(args):
        prod = args[0].num
        for v in args[1:]:
            prod = prod * v.num
        return _pure_scalars(np.ascontiguousarray(prod).reshape(prod.shape[0], -1).sum(axis=1))
    prod, err = None, None
    for v in args:
        n = np.where(v.tag == NUM, v.num, np.where(v.tag == BOOL, 0.0, 0.0))
        e = np.where(v.tag >= FIRST_ERROR, v.tag, 0).astype(np.int8)
        prod = n if prod is None else prod * n
        err = e if err is None else first_error_of(err, e)
    # SUMPRODUCT has at least one argument (the parser's rule): both are set
    prod, err = cast(np.ndarray, prod), cast(np.ndarray, err)
    k = prod.shape[0]
    return scalar_result(prod.reshape(k, -1).sum(axis=1), first_error(err.reshape(k, -1)))


def _agg_logical(all_: bool):
    def f(args, ranges):
        acc, seen, err = None, None, None
        if all(v.pure != -1 and v.num.size for v in args):     # numbers and booleans: all count
            for v in args:
                b = (v.num != 0).reshape(v.shape[0], -1)
                part = b.all(axis=1) if all_ else b.any(axis=1)
                acc = part if acc is None else (acc & part if all_ else acc | part)
            return pure_result(cast(np.ndarray, acc).astype(float).reshape(-1, 1, 1), BOOL)
        for v, is_range in zip(args, ranges, strict=False):
            k = v.shape[0]
            if is_range:
                use = (v.tag == NUM) | (v.tag == BOOL)
                e = np.where(v.tag >= FIRST_ERROR, v.tag, 0).astype(np.int8)
                b = v.num != 0
            else:
                b, e = to_bool(v)
                use = v.tag != EMPTY
            b, use, e = b.reshape(k, -1), use.reshape(k, -1), e.reshape(k, -1)
            part = np.where(use, b, all_).all(axis=1) if all_ else np.where(use, b, False).any(axis=1)
            acc = part if acc is None else (acc & part if all_ else acc | part)
            s = use.any(axis=1)
            seen = s if seen is None else seen | s
            first = first_error(e)
            err = first if err is None else first_error_of(err, first)
        # AND/OR have at least one argument (the parser's rule): all three are set
        acc, seen, err = cast(np.ndarray, acc), cast(np.ndarray, seen), cast(np.ndarray, err)
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


# ---------------------------------------------------------------- lazy functions
class Evaluates(Protocol):
    """What a lazy function's hook may ask of the evaluator (sheetkin.xlsx.context's
    context): evaluate an argument's tree, and the hooks that need the workbook itself."""

    def eval(self, node: Any, run: Any) -> Val: ...
    def index(self, args: Sequence[Any], run: Any) -> Val: ...
    def spill(self, args: Sequence[Any], run: Any) -> Val: ...
    def single(self, args: Sequence[Any], run: Any) -> Val: ...
    def range_value(self, args: Sequence[Any], run: Any) -> Val: ...
    def name(self, name: str, run: Any) -> Any: ...
    def reference(self, node: Any, run: Any) -> Any: ...
    def read_reference(self, ref: Any, run: Any, function: str) -> Val: ...


Hook = Callable[[Evaluates, Sequence[Any], Any], Val]


@dataclass(frozen=True)
class Lazy:
    """A function that takes its arguments as formula trees, unevaluated, the way the
    `formulas` package registers IF: `hook(ctx, args, run)` evaluates what it needs
    (IF one condition and its branches; INDEX a range as a block, not its values) and
    returns the result. `why`: what makes it lazy (one line)."""
    hook: Hook
    why: str


def argument(ctx: Evaluates, args: Sequence[Any], i: int, run: Any, default: Val) -> Val:
    """Argument i evaluated, or `default` where it is left out (IF(c,,b)) or missing."""
    return ctx.eval(args[i], run) if len(args) > i and args[i][0] != "missing" else default


def _if(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    cond, err = to_bool(ctx.eval(args[0], run))
    a = argument(ctx, args, 1, run, constant(0.0))
    b = ctx.eval(args[2], run) if len(args) > 2 else constant(False)
    return with_error(select(cond, a, b), err)


def _iferror(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    a, b = ctx.eval(args[0], run), ctx.eval(args[1], run)
    return select(a.tag >= FIRST_ERROR, b, a)


def _not(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    b, err = to_bool(ctx.eval(args[0], run))
    return Val(np.where(err == 0, (~b).astype(float), 0.0), np.where(err == 0, BOOL, err).astype(np.int8))


def _is(test: Callable[[Val], np.ndarray]) -> Hook:
    def hook(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
        v = ctx.eval(args[0], run)
        return Val(test(v).astype(float), np.full(v.shape, BOOL, np.int8))
    return hook


# ERROR.TYPE's numbers, Excel's documented table; any other error (Excel 365's newer ones)
# and any value that is not an error: #N/A
_ERROR_TYPE = {code: i for i, code in enumerate(
    ("#NULL!", "#DIV/0!", "#VALUE!", "#REF!", "#NAME?", "#NUM!", "#N/A", "#GETTING_DATA"), 1)}
_ERROR_TYPE_OF = np.zeros(max(ERRORS.values()) + 1)
for _code, _n in _ERROR_TYPE.items():
    _ERROR_TYPE_OF[ERRORS[_code]] = _n


def _error_type(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    v = ctx.eval(args[0], run)
    n = _ERROR_TYPE_OF[np.clip(v.tag, 0, _ERROR_TYPE_OF.size - 1)]
    return Val(n, np.where(n > 0, NUM, NA).astype(np.int8))


def _concatenate(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """CONCATENATE(a, b, ...): `&` over its arguments, capped the same way."""
    out = constant("")
    for a in args:
        out = concat(out, ctx.eval(a, run))
    return out


def _boolean(value: bool) -> Hook:
    def hook(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
        return constant(value) if not args else error_value("#VALUE!", len(run.cols))
    return hook


def _trunc(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    if len(args) == 1:
        return unary(fx.trunc)(ctx.eval(args[0], run))
    return binary(fx.trunc)(ctx.eval(args[0], run), ctx.eval(args[1], run))


def _rounding(name: str) -> Hook:
    """FLOOR.MATH and kin: a number, then optional arguments with defaults."""
    fn, defaults = fx.ROUNDING[name]

    def hook(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
        if not 1 <= len(args) <= fx.ROUNDING_ARITY[name]:
            return error_value("#VALUE!", len(run.cols))
        vals = [argument(ctx, args, i, run, constant(0.0)) for i in range(len(args))]
        vals += [constant(d) for d in defaults[len(args) - 1:]]
        nums, errs = zip(*(to_number(v) for v in vals), strict=False)
        with np.errstate(all="ignore"):
            r = fn(*np.broadcast_arrays(*nums))
        return numeric_result(r, first_error_of(*errs))
    return hook


def _choose(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """CHOOSE(i, v1, v2, ...): the i-th value (per cell of the run)."""
    i, err = to_number(ctx.eval(args[0], run))
    pos, bad = fx.choose_index(i, len(args) - 1)
    err = first_error_of(err, bad)
    values = [ctx.eval(a, run) for a in args[1:]]
    shape = np.broadcast_shapes(pos.shape, *(v.shape for v in values))
    num = np.choose(np.broadcast_to(pos, shape), [np.broadcast_to(v.num, shape) for v in values])
    tags = np.choose(np.broadcast_to(pos, shape), [np.broadcast_to(v.tag, shape) for v in values])
    txt = None
    if any(v.txt is not None for v in values):
        txt = np.choose(np.broadcast_to(pos, shape), [np.broadcast_to(texts_of(v), shape) for v in values])
    return with_error(Val(num, tags.astype(np.int8), txt), np.broadcast_to(err, shape))


def _where(which: str):
    """ROW, COLUMN, ROWS, COLUMNS: where a reference is (or the formula's own cell), not
    what it holds; ROW and COLUMN of a range give its first row or column, as Excel does
    outside an array formula."""
    def hook(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
        k = len(run.cols)
        node = args[0] if args and args[0][0] != "missing" else None
        if node is not None and node[0] == "name":
            node = ctx.name(node[1], run)
        if node is not None and node[0] == "fn":          # OFFSET, INDIRECT, INDEX: the reference made
            made = ctx.reference(node, run)
            node = ("ref", made) if made is not None else None
            if node is None:
                return error_value("#REF!", k)
        if node is None and which in ("ROW", "COLUMN"):
            at = np.full(k, float(run.row)) if which == "ROW" else run.cols.astype(float)
        elif node is not None and node[0] == "array" and which in ("ROWS", "COLUMNS"):   # {1,2;3,4}
            at = np.full(k, float(len(node[1]) if which == "ROWS" else len(node[1][0])))
        elif node is None or node[0] != "ref":
            return error_value("#VALUE!", k)
        else:
            ref = node[1]
            if which == "ROWS":
                at = np.full(k, float(ref.r2 - ref.r1 + 1))
            elif which == "COLUMNS":
                at = np.full(k, float(ref.c2 - ref.c1 + 1))
            elif which == "ROW":
                at = np.full(k, float(ref.r1 if ref.r1_abs else run.row + ref.r1))
            else:
                at = np.full(k, float(ref.c1)) if ref.c1_abs else (run.cols + ref.c1).astype(float)
        return Val(at.reshape(k, 1, 1), np.zeros((k, 1, 1), np.int8), None, NUM)
    return hook


def _n_of(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """N(x): a number as it is, TRUE 1, text and empty 0, an error as it is."""
    if len(args) != 1:
        return error_value("#VALUE!", len(run.cols))
    v = ctx.eval(args[0], run)
    v = Val(v.num[:, :1, :1], v.tag[:, :1, :1], None if v.txt is None else v.txt[:, :1, :1])
    num = np.where((v.tag == NUM) | (v.tag == BOOL), v.num, 0.0)
    return with_error(Val(num, np.zeros(v.shape, np.int8), None, NUM), np.where(v.tag >= FIRST_ERROR, v.tag, 0))


def _value_of(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """VALUE(text): numeric text as its number, a number as it is; other text, and a
    boolean, #VALUE!."""
    if len(args) != 1:
        return error_value("#VALUE!", len(run.cols))
    v = ctx.eval(args[0], run)
    num, err = to_number(v)
    err = np.where((err == 0) & (v.tag == BOOL), VALUE, err).astype(np.int8)
    return numeric_result(num, err)


# name -> its entry; the evaluator asks this table before SCALAR_FUNCS and AGGREGATES
LAZY: dict[str, Lazy] = {
    "PI": Lazy(lambda ctx, args, run: constant(math.pi), "no arguments"),
    "IF": Lazy(_if, "a branch is evaluated only where it is given (IF(c,,b) is 0 where c holds)"),
    "IFERROR": Lazy(_iferror, "its first argument's errors are a value, not propagated"),
    "NOT": Lazy(_not, "a condition, coerced to a boolean with its own errors"),
    "ISNUMBER": Lazy(_is(lambda v: v.tag == NUM), "asks a value's type: errors are an answer"),
    "ISERROR": Lazy(_is(lambda v: v.tag >= FIRST_ERROR), "asks a value's type: errors are an answer"),
    "ISTEXT": Lazy(_is(lambda v: v.tag == TEXT), "asks a value's type: errors are an answer"),
    "ISERR": Lazy(_is(lambda v: (v.tag >= FIRST_ERROR) & (v.tag != NA)), "asks a value's type: errors are an answer"),
    "ISNA": Lazy(_is(lambda v: v.tag == NA), "asks a value's type: errors are an answer"),
    "ERROR.TYPE": Lazy(_error_type, "asks which error: errors are an answer"),
    "CONCATENATE": Lazy(_concatenate, "any number of arguments, joined as `&` joins two"),
    "NA": Lazy(lambda ctx, args, run: error_value("#N/A", len(run.cols)), "the charts' gap: #N/A is not plotted"),
    "TRUE": Lazy(_boolean(True), "LibreOffice writes TRUE() and FALSE()"),
    "FALSE": Lazy(_boolean(False), "LibreOffice writes TRUE() and FALSE()"),
    "TRUNC": Lazy(_trunc, "an optional second argument"),
    "INDEX": Lazy(lambda ctx, args, run: ctx.index(args, run), "its first argument is a block of cells"),
    "CHOOSE": Lazy(_choose, "picks among its arguments per cell"),
    **{name: Lazy(_where(name), "asks where a reference is, not what it holds")
       for name in ("ROW", "COLUMN", "ROWS", "COLUMNS")},
    "N": Lazy(_n_of, "text is 0, not #VALUE!"),
    "VALUE": Lazy(_value_of, "a boolean is #VALUE!, not its number"),
    "ANCHORARRAY": Lazy(lambda ctx, args, run: ctx.spill(args, run), "E1#: the range an array formula fills"),
    "SINGLE": Lazy(lambda ctx, args, run: ctx.single(args, run), "@: implicit intersection with a range"),
    ":": Lazy(lambda ctx, args, run: ctx.range_value(args, run), "A1:INDEX(...): a range made while it runs"),
    **{name: Lazy(_rounding(name), "optional arguments with defaults") for name in fx.ROUNDING},
}
SUPPORTED = sorted(set(SCALAR_FUNCS) | set(AGGREGATES) | set(LAZY))
