"""Functions written one cell at a time, in plain Python, for the functions that are not on
a hot path (text, combinatorics, lookups, statistics over a range): a Val becomes an array
of Python values per cell (float, bool, str, None for an empty cell, XlError), a kernel maps
them, and the results become a Val again.

Excel's coercions, as the one-value functions apply them (`number`, `text`, `boolean`),
raise Fail with the error a cell gets; `cellwise` turns a Python function of plain values
into a function of Vals that broadcasts over the cells of a run and over arrays, with the
first error among the arguments (left to right) winning, as in Excel.

Separate from values.py, whose numpy paths carry the generated sheets' formulas: these
functions are about a hundred, each short, and none is worth a vectorised path.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from typing import Any, cast

import numpy as np

from .functions import DIV0, ERRORS, NA, NUMERR, VALUE, XlError
from .values import BOOL, EMPTY, NUM, NUMERIC_TEXT, TEXT, Val, number_text

CODE_TEXT = {code: XlError(text) for text, code in ERRORS.items()}


class Fail(Exception):
    """An Excel error from inside a kernel: the cell gets `code` (an error tag)."""

    def __init__(self, code: int):
        super().__init__(code)
        self.code = code


def py_values(v: Val) -> np.ndarray:
    """The Val's cells as Python values: float, bool, str, None (empty), XlError."""
    out = np.empty(v.shape, dtype=object)
    tag, num = v.tag, v.num
    txt = v.txt
    for idx in np.ndindex(v.shape):
        t = int(tag[idx])
        out[idx] = (float(num[idx]) if t == NUM else bool(num[idx]) if t == BOOL
                    else (txt[idx] if txt is not None else "") if t == TEXT else None if t == EMPTY
                    else CODE_TEXT.get(t, XlError("#VALUE!")))
    return out


def from_py(values: np.ndarray) -> Val:
    """Python values (per cell, any shape with the cell axis first) as a Val; a float that
    is not finite is #NUM!, None an empty cell."""
    shape = values.shape
    num = np.zeros(shape)
    tag = np.zeros(shape, np.int8)
    txt = None
    for idx in np.ndindex(shape):
        x = values[idx]
        if isinstance(x, XlError):
            tag[idx] = ERRORS.get(x, VALUE)
        elif isinstance(x, bool):
            num[idx], tag[idx] = float(x), BOOL
        elif isinstance(x, (int, float)):
            if math.isfinite(x):
                num[idx] = float(x)
            else:
                tag[idx] = NUMERR
        elif x is None:
            tag[idx] = EMPTY
        else:
            if txt is None:
                txt = np.full(shape, None, dtype=object)
            if len(x) > 32_767:
                tag[idx] = VALUE
            else:
                tag[idx], txt[idx] = TEXT, x
    return Val(num, tag, txt)


# ------------------------------------------------------------------ coercions of one value
def number(x: Any) -> float:
    """A value as a number, as arithmetic takes it: empty 0, booleans 1 and 0, numeric
    text its number; other text #VALUE!, an error itself."""
    if isinstance(x, XlError):
        raise Fail(ERRORS.get(x, VALUE))
    if x is None:
        return 0.0
    if isinstance(x, str):
        if NUMERIC_TEXT.match(x):
            return float(x)
        raise Fail(VALUE)
    return float(x)


def text(x: Any) -> str:
    """A value as text, as `&` makes it: a number in Excel's general format, TRUE/FALSE."""
    if isinstance(x, XlError):
        raise Fail(ERRORS.get(x, VALUE))
    if x is None:
        return ""
    if isinstance(x, bool):
        return "TRUE" if x else "FALSE"
    if isinstance(x, float):
        return number_text(x)
    return str(x)


def boolean(x: Any) -> bool:
    """A value as a condition: numbers non-zero, empty FALSE, the texts TRUE and FALSE;
    other text #VALUE!."""
    if isinstance(x, XlError):
        raise Fail(ERRORS.get(x, VALUE))
    if x is None:
        return False
    if isinstance(x, str):
        if x.upper() in ("TRUE", "FALSE"):
            return x.upper() == "TRUE"
        raise Fail(VALUE)
    return bool(x)


def integer(x: Any) -> int:
    """A number truncated toward zero (Excel's whole-number arguments); #NUM! past 2^53."""
    n = number(x)
    if not math.isfinite(n) or abs(n) >= 2.0 ** 53:
        raise Fail(NUMERR)
    return math.trunc(n)


def raw(x: Any) -> Any:
    """A value as it is (errors too: ISBLANK, TYPE ...)."""
    return x


def strict(x: Any) -> Any:
    """A value as it is, an error raised."""
    if isinstance(x, XlError):
        raise Fail(ERRORS.get(x, VALUE))
    return x


COERCE: dict[str, Callable[[Any], Any]] = {"n": number, "t": text, "b": boolean, "i": integer, "v": raw,
                                          "s": strict}


def cellwise(fn: Callable[..., Any], kinds: str, defaults: Sequence[Any] = ()) -> Callable[..., Val]:
    """A function of Vals from fn of plain values: `kinds` one letter per argument (n number,
    i integer, t text, b boolean, s any value but an error, v any value); the last
    len(defaults) arguments are optional, each default used where it is left out."""
    def kernel(*vals: Val) -> Val:
        given = len(vals)
        pys = [py_values(v) for v in vals]
        shape = np.broadcast_shapes(*(p.shape for p in pys)) if pys else (1, 1, 1)
        pys = [np.broadcast_to(p, shape) for p in pys]
        out = np.empty(shape, dtype=object)
        coerce = [COERCE[k] for k in kinds]
        lead = len(kinds) - len(defaults)
        for idx in np.ndindex(shape):
            try:
                args = [coerce[i](p[idx]) for i, p in enumerate(pys)]
                args += [defaults[i - lead] for i in range(given, len(kinds))]
                out[idx] = fn(*args)
            except Fail as e:
                out[idx] = CODE_TEXT.get(e.code, XlError("#VALUE!"))
            except (OverflowError, ValueError, ZeroDivisionError):
                out[idx] = CODE_TEXT[NUMERR]
        return from_py(out)
    return kernel


# ------------------------------------------------------------------ values of ranges per cell
def cell_lists(vals: Sequence[Val], ranges: Sequence[bool]) -> list[list[tuple[list, bool]]]:
    """For each cell of the run, each argument as (its Python values in reading order, is
    it a reference): what the functions of ranges walk one value at a time."""
    k = max(v.shape[0] for v in vals)
    per = [py_values(v) for v in vals]
    out = []
    for i in range(k):
        out.append([(list(p[i if p.shape[0] > 1 else 0].ravel()), r) for p, r in zip(per, ranges, strict=True)])
    return out


def numbers_of(args: list[tuple[list, bool]], *, count_text: bool = False,
               booleans_in_ranges: bool = False) -> list[float]:
    """The numbers a statistical function sees: in references only numbers (text, booleans,
    empty cells skipped; with booleans_in_ranges booleans as 1 and 0, text as 0, the A-forms);
    typed arguments coerced (text that is not a number: #VALUE!); an error raised."""
    out: list[float] = []
    for values, is_ref in args:
        for x in values:
            if isinstance(x, XlError):
                raise Fail(ERRORS.get(x, VALUE))
            if is_ref or len(values) > 1:
                if isinstance(x, bool):
                    if booleans_in_ranges:
                        out.append(float(x))
                elif isinstance(x, float):
                    out.append(x)
                elif isinstance(x, str) and count_text:
                    out.append(0.0)
            elif x is not None:
                out.append(number(x))
    return out


def per_cell(fn: Callable[[list[tuple[list, bool]]], Any]) -> Callable[[Sequence[Val], Sequence[bool]], Val]:
    """A function of ranges (vals, is-reference flags) from fn of one cell's argument lists."""
    def kernel(vals: Sequence[Val], ranges: Sequence[bool]) -> Val:
        cells = cell_lists(vals, ranges)
        out = np.empty((len(cells), 1, 1), dtype=object)
        for i, args in enumerate(cells):
            try:
                out[i, 0, 0] = fn(args)
            except Fail as e:
                out[i, 0, 0] = CODE_TEXT.get(e.code, XlError("#VALUE!"))
            except (OverflowError, ValueError):
                out[i, 0, 0] = CODE_TEXT[NUMERR]
            except ZeroDivisionError:
                out[i, 0, 0] = CODE_TEXT[DIV0]
        return from_py(out)
    return kernel


# ------------------------------------------------------------------ criteria (SUMIF, COUNTIF, ...)
_OPERATOR = re.compile(r"^(<=|>=|<>|=|<|>)?(.*)$", re.S)


def _wildcard(pattern: str) -> re.Pattern | None:
    """Excel's wildcards (* any text, ? one character, ~ escapes) as a regex, or None
    where the pattern has none."""
    if not any(ch in pattern for ch in "*?~"):
        return None
    out, i = [], 0
    while i < len(pattern):
        ch = pattern[i]
        if ch == "~" and i + 1 < len(pattern) and pattern[i + 1] in "*?~":
            out.append(re.escape(pattern[i + 1]))
            i += 2
            continue
        out.append(".*" if ch == "*" else "." if ch == "?" else re.escape(ch))
        i += 1
    return re.compile("".join(out), re.S | re.I)


def _as_number(x: Any) -> float | None:
    if isinstance(x, str) and NUMERIC_TEXT.match(x):
        return float(x)
    return None


def criterion(c: Any) -> Callable[[Any], bool]:
    """Excel's criteria of COUNTIF and its kin as a test of one cell: a number (or TRUE)
    matches equal values; a text may start with = <> < > <= >=, and compares numbers with
    numbers and text with text (case-insensitively, with the wildcards * ? ~ for = and <>);
    "" and "=" match empty cells, "<>" any cell that is not empty."""
    if isinstance(c, XlError):
        raise Fail(ERRORS.get(c, VALUE))
    if c is None:
        c = 0.0
    if isinstance(c, bool):
        return lambda x: isinstance(x, bool) and x == c
    if isinstance(c, float):
        return lambda x: isinstance(x, float) and not isinstance(x, bool) and x == c
    m = cast(re.Match, _OPERATOR.match(c))       # the pattern matches any text
    op, operand = (m.group(1) or "="), m.group(2)
    value: Any = _as_number(operand)
    if value is None and operand.upper() in ("TRUE", "FALSE"):
        value = operand.upper() == "TRUE"
    if value is None and operand in ERRORS:
        value = XlError(operand)
    if value is None:
        value = operand
    if isinstance(value, float):
        def test_number(x: Any) -> bool:
            if isinstance(x, bool) or not isinstance(x, float):     # text, booleans, empty: never equal
                return op == "<>"
            return _cmp(op, (x > value) - (x < value))
        return test_number
    if isinstance(value, (bool, XlError)):
        return lambda x: (op == "<>") != (type(x) is type(value) and x == value) if op in ("=", "<>") else False
    if operand == "" and op == "=":
        return lambda x: x is None or x == ""
    if operand == "" and op == "<>":
        return lambda x: not (x is None or x == "")
    pattern = _wildcard(operand) if op in ("=", "<>") else None
    low = operand.casefold()

    def test_text(x: Any) -> bool:
        if op in ("=", "<>"):
            hit = isinstance(x, str) and (pattern.fullmatch(x) is not None if pattern else x.casefold() == low)
            return hit if op == "=" else not hit
        if not isinstance(x, str):
            return False
        y = x.casefold()
        return _cmp(op, (y > low) - (y < low))
    return test_text


def _cmp(op: str, sign: int) -> bool:
    return {"=": sign == 0, "<>": sign != 0, "<": sign < 0, ">": sign > 0, "<=": sign <= 0, ">=": sign >= 0}[op]


def not_available() -> XlError:
    return CODE_TEXT[NA]
