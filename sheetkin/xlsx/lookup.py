"""Lookup & Reference functions and the functions of criteria (SUMIF, COUNTIFS, MAXIFS ...):
kernels of the function table (table.py), one cell of a run at a time.

Lookups compare as Excel does: a number matches only numbers, a text only text
(case-insensitively, with the wildcards * ? ~ in an exact match), a boolean only booleans;
an approximate match (MATCH's 1 and -1, VLOOKUP's TRUE, LOOKUP) finds the last value not
past the one sought in a sorted range, as Excel's binary search does on sorted data (on
unsorted data Excel's and LibreOffice's answers differ from each other: do not rely on it).
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from .cellwise import CODE_TEXT, Fail, criterion, from_py, number, per_cell, py_values
from .functions import DIV0, NA, REF, VALUE, XlError
from .values import Val


# ------------------------------------------------------------------ matching
def _kind(x: Any) -> int:
    return 0 if isinstance(x, float) and not isinstance(x, bool) else 1 if isinstance(x, str) else \
        2 if isinstance(x, bool) else -1


def _order(x: Any, y: Any) -> int:
    """Sign of x - y for two values of one kind (text case-insensitively)."""
    if isinstance(x, str):
        x, y = x.casefold(), y.casefold()
    return (x > y) - (x < y)


def match_position(x: Any, values: list, how: int) -> int:
    """The 0-based position MATCH finds (how: 1 last <=, 0 exact, -1 last >=); Fail(#N/A)."""
    if isinstance(x, XlError):
        raise Fail(_code(x))
    if x is None:
        x = 0.0
    kind = _kind(x)
    if how == 0:
        test = criterion("=" + x) if isinstance(x, str) else None
        for i, v in enumerate(values):
            if _kind(v) == kind and (test(v) if test is not None else v == x):
                return i
        raise Fail(NA)
    found = -1
    for i, v in enumerate(values):
        if _kind(v) != kind:
            continue
        s = _order(v, x)
        if (how > 0 and s > 0) or (how < 0 and s < 0):
            break
        found = i
    if found < 0:
        raise Fail(NA)
    return found


def _code(e: XlError) -> int:
    from .functions import ERRORS
    return ERRORS.get(e, VALUE)


def _lookups(fn):
    """A lookup kernel per cell: fn(values as 2-D object arrays per argument) -> value."""
    def kernel(*vals: Val) -> Val:
        k = max(v.shape[0] for v in vals)
        pys = [py_values(v) for v in vals]
        out = np.empty((k, 1, 1), dtype=object)
        for i in range(k):
            try:
                out[i, 0, 0] = fn(*(p[i if p.shape[0] > 1 else 0] for p in pys))
            except Fail as e:
                out[i, 0, 0] = CODE_TEXT.get(e.code, XlError("#VALUE!"))
        return from_py(out)
    return kernel


def _scalar(a: np.ndarray) -> Any:
    return a[0, 0]


def _match(x, arr, how=None) -> float:
    how_n = 1 if how is None else math.trunc(number(_scalar(how)))
    if arr.shape[0] > 1 and arr.shape[1] > 1:
        raise Fail(NA)
    return float(match_position(_scalar(x), list(arr.ravel()), 0 if how_n == 0 else (1 if how_n > 0 else -1)) + 1)


def _vlookup(horizontal: bool):
    def fn(x, table, col, approx=None):
        t = table.T if horizontal else table
        j = math.trunc(number(_scalar(col)))
        if j < 1:
            raise Fail(VALUE)
        if j > t.shape[1]:
            raise Fail(REF)
        approximate = True if approx is None else _truth(_scalar(approx))
        i = match_position(_scalar(x), list(t[:, 0]), 1 if approximate else 0)
        return t[i, j - 1]
    return fn


def _truth(x: Any) -> bool:
    from .cellwise import boolean
    return boolean(x)


def _lookup(x, vector, result=None):
    if result is None:
        if vector.shape[1] > vector.shape[0]:        # wider than tall: the first row, the last row's value
            i = match_position(_scalar(x), list(vector[0, :]), 1)
            return vector[-1, i]
        i = match_position(_scalar(x), list(vector[:, 0]), 1)
        return vector[i, -1]
    keys = list(vector.ravel()) if 1 in vector.shape else list(vector[:, 0])
    i = match_position(_scalar(x), keys, 1)
    flat = list(result.ravel())
    if i >= len(flat):
        raise Fail(NA)
    return flat[i]


LOOKUPS = {"MATCH": _lookups(_match), "VLOOKUP": _lookups(_vlookup(False)), "HLOOKUP": _lookups(_vlookup(True)),
           "LOOKUP": _lookups(_lookup)}


# ------------------------------------------------------------------ criteria
def _pairs(args, first: int):
    """(range values, criterion test) pairs from args[first:]; ranges of unequal size: #VALUE!."""
    pairs = []
    for j in range(first, len(args) - 1, 2):
        values, _ = args[j]
        crit, _ = args[j + 1]
        pairs.append((values, criterion(crit[0])))
    if len({len(v) for v, _ in pairs}) > 1:
        raise Fail(VALUE)
    return pairs


def _hits(pairs) -> list[int]:
    n = len(pairs[0][0])
    return [i for i in range(n) if all(test(values[i]) for values, test in pairs)]


def _numbers_at(values: list, positions: list[int]) -> list[float]:
    out = []
    for i in positions:
        x = values[i] if i < len(values) else None
        if isinstance(x, XlError):
            raise Fail(_code(x))
        if isinstance(x, float) and not isinstance(x, bool):
            out.append(x)
    return out


def _sumif(args) -> float:
    pairs = _pairs(args[:2], 0)
    target = args[2][0] if len(args) > 2 else args[0][0]
    return math.fsum(_numbers_at(target, _hits(pairs)))


def _averageif(args) -> float:
    pairs = _pairs(args[:2], 0)
    target = args[2][0] if len(args) > 2 else args[0][0]
    xs = _numbers_at(target, _hits(pairs))
    if not xs:
        raise Fail(DIV0)
    return math.fsum(xs) / len(xs)


def _countifs(args) -> float:
    if len(args) % 2:
        raise Fail(VALUE)
    return float(len(_hits(_pairs(args, 0))))


def _over_criteria(reduce):
    def fn(args) -> float:
        if len(args) % 2 == 0:
            raise Fail(VALUE)
        target = args[0][0]
        pairs = _pairs(args, 1)
        if len(target) != len(pairs[0][0]):
            raise Fail(VALUE)
        return reduce(_numbers_at(target, _hits(pairs)))
    return fn


def _average_or_div0(xs: list[float]) -> float:
    if not xs:
        raise Fail(DIV0)
    return math.fsum(xs) / len(xs)


CRITERIA = {
    "SUMIF": per_cell(_sumif), "AVERAGEIF": per_cell(_averageif), "COUNTIF": per_cell(_countifs),
    "COUNTIFS": per_cell(_countifs),
    "SUMIFS": per_cell(_over_criteria(math.fsum)), "AVERAGEIFS": per_cell(_over_criteria(_average_or_div0)),
    "MAXIFS": per_cell(_over_criteria(lambda xs: max(xs) if xs else 0.0)),
    "MINIFS": per_cell(_over_criteria(lambda xs: min(xs) if xs else 0.0)),
}


# ------------------------------------------------------------------ addresses
def _address(row: float, col: float, kind: float = 1.0, a1: Any = True, sheet: Any = None) -> str:
    from .coords import get_column_letter
    r, c, k = math.trunc(row), math.trunc(col), math.trunc(kind)
    if r < 1 or c < 1 or r > 1048576 or c > 16384 or k not in (1, 2, 3, 4):
        raise Fail(VALUE)
    if a1:
        ra, ca = k in (1, 2), k in (1, 3)
        text = f"{'$' if ca else ''}{get_column_letter(c)}{'$' if ra else ''}{r}"
    else:
        text = (f"R{r}" if k in (1, 2) else f"R[{r}]") + (f"C{c}" if k in (1, 3) else f"C[{c}]")
    if sheet:
        s = str(sheet)
        quoted = s if s.replace("_", "").isalnum() and not s[0].isdigit() else "'" + s.replace("'", "''") + "'"
        text = f"{quoted}!{text}"
    return text


def _cellwise_address():
    from .cellwise import cellwise
    return cellwise(_address, "nnnbt", (1.0, True, None))


cellwise_address = _cellwise_address()


def offset(ctx, args, run) -> Val:
    """OFFSET(reference, rows, cols, [height], [width]): the values of the block made."""
    return ctx.read_reference(ctx.reference(("fn", "OFFSET", args), run), run, "OFFSET")


def indirect(ctx, args, run) -> Val:
    """INDIRECT(text, [a1]): the values of the reference the text names (A1 style)."""
    return ctx.read_reference(ctx.reference(("fn", "INDIRECT", args), run), run, "INDIRECT")
