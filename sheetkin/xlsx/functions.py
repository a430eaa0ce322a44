"""Excel's worksheet functions as pure numpy kernels, for the evaluator.

The evaluator's values.py owns the values (numbers, text, booleans, errors per cell)
and their coercion; the kernels here see plain float arrays (and, for INDEX and CHOOSE,
integer positions) and return results with an array of error codes, 0 where there is none.
Each follows Excel's definition (support.microsoft.com, the function's page); where
LibreOffice differs, the differential tests compare errors only as "an error".
"""
from __future__ import annotations

import numpy as np

# Excel's error values and the codes the evaluator tags them with (>= 10: an error)
ERRORS = {"#NULL!": 10, "#DIV/0!": 11, "#VALUE!": 12, "#REF!": 13, "#NAME?": 14, "#NUM!": 15, "#N/A": 16,
          # Excel 365's newer errors: no formula here makes them, but a saved value or a
          # literal may hold one, and ISERROR/IFERROR must see an error, not a text
          "#SPILL!": 17, "#CALC!": 18, "#GETTING_DATA": 19, "#FIELD!": 20, "#BLOCKED!": 21,
          "#CONNECT!": 22, "#BUSY!": 23, "#UNKNOWN!": 24, "#PYTHON!": 25}


class XlError(str):
    """An error value (#N/A, #DIV/0! ...) as a cell holds it: a saved error (t="e"), an error
    literal in a formula, an evaluated error. A str equal to its text (callers compare it with
    "#N/A"), but a type of its own: a *text* that spells an error (a typed "#N/A", a shared
    string, a formula's text result, ="#N/A") is a plain str, and is text to every function
    (=ISERROR("#N/A") is FALSE in Excel, LibreOffice and Gnumeric)."""
    __slots__ = ()


def is_error(v: object) -> bool:
    """Whether a value read or computed is an error (not a text that spells one)."""
    return isinstance(v, XlError)


ERROR_TEXT = {v: XlError(k) for k, v in ERRORS.items()}
FIRST_ERROR = min(ERRORS.values())      # a value's tag from here on is an error (below: NUM, BOOL, TEXT, EMPTY)
NULL, DIV0, VALUE, REF, NAME, NUMERR, NA = (ERRORS[k] for k in list(ERRORS)[:7])
MAX_TEXT = 32_767          # characters of one cell's text, Excel's limit (#VALUE! past it)


def capped(text: str) -> str:
    """A text as a cell may hold it: itself, or #VALUE! (an XlError) past MAX_TEXT characters
    (a file holding a longer text: read as #VALUE! in that cell, as a formula making one gives)."""
    return text if len(text) <= MAX_TEXT else ERROR_TEXT[VALUE]


def _approx(q: np.ndarray) -> np.ndarray:
    """A quotient as its 15 significant digits show it, so that FLOOR(0.3, 0.1) is 0.3
    (0.3/0.1 is 2.9999999999999996 in binary; Excel and LibreOffice round it to 3 first)."""
    with np.errstate(all="ignore"):
        mag = np.where((q == 0) | ~np.isfinite(q), 0, np.floor(np.log10(np.abs(np.where(q == 0, 1, q)))))
        scale = 10.0 ** (14 - mag)
        r = np.round(q * scale) / scale
    return np.where(np.isfinite(r), r, q)


# ---------------------------------------------------------------- rounding
def int_(x):
    """INT: the next integer down (INT(-2.5) is -3)."""
    return np.floor(x)


def trunc(x, digits=None):
    """TRUNC(x, [digits]): toward zero, keeping `digits` decimals (negative: tens, ...)."""
    if digits is None:
        return np.trunc(x)
    d = np.trunc(digits)
    with np.errstate(all="ignore"):
        f = 10.0 ** d
        r = np.trunc(_approx(x * f)) / f
        # x * f past the largest double (TRUNC(1E308, 2)), or x an integer already (|x| >=
        # 2**52 has no fraction): x itself, as in Excel; 10**d below the smallest: 0
        r = np.where(np.isfinite(r), r, np.where(d > 0, x, 0.0))
        r = np.where((d > 0) & (np.abs(x) >= 2.0 ** 52), x, r)
        return np.where(d == 0, np.trunc(x), r)


def floor_check(x, s):
    """FLOOR(x, s), Excel's two arguments: s = 0 is #DIV/0! (0 when x is 0); a positive x
    with a negative s is #NUM!."""
    return np.where(s == 0, np.where(x == 0, 0, DIV0), np.where((x > 0) & (s < 0), NUMERR, 0))


def floor(x, s):
    """FLOOR(x, s): x rounded to a multiple of s, down (toward minus infinity for a
    positive s; for x, s both negative toward zero: FLOOR(-2.5, -2) is -2)."""
    with np.errstate(all="ignore"):
        return np.where(s == 0, 0.0, np.floor(_approx(x / s)) * s)


def ceiling_check(x, s):
    """CEILING(x, s), Excel's two arguments: a positive x with a negative s is #NUM!;
    s = 0 gives 0."""
    return np.where((x > 0) & (s < 0), NUMERR, 0)


def ceiling(x, s):
    """CEILING(x, s): x rounded to a multiple of s, up (CEILING(-2.5, 2) is -2, and with
    both negative away from zero: CEILING(-2.5, -2) is -4)."""
    with np.errstate(all="ignore"):
        return np.where(s == 0, 0.0, np.ceil(_approx(x / s)) * s)


def floor_math(x, s, mode):
    """FLOOR.MATH(x, [s=1], [mode=0]) (also FLOOR.PRECISE): down to a multiple of |s|; a
    negative x goes toward zero when mode is not 0. s = 0 gives 0. LibreOffice writes its
    own FLOOR(x; s) to .xlsx as this function."""
    s = np.abs(s)
    with np.errstate(all="ignore"):
        q = _approx(x / s)
        r = np.where((x < 0) & (mode != 0), np.ceil(q), np.floor(q)) * s
    return np.where(s == 0, 0.0, r)


def ceiling_math(x, s, mode):
    """CEILING.MATH(x, [s=1], [mode=0]) (also CEILING.PRECISE, ISO.CEILING): up to a
    multiple of |s|; a negative x goes away from zero when mode is not 0. s = 0 gives 0."""
    s = np.abs(s)
    with np.errstate(all="ignore"):
        q = _approx(x / s)
        r = np.where((x < 0) & (mode != 0), np.floor(q), np.ceil(q)) * s
    return np.where(s == 0, 0.0, r)


# the rounding functions with optional arguments: (kernel, defaults of the optional ones)
ROUNDING = {"FLOOR.MATH": (floor_math, (1.0, 0.0)), "FLOOR.PRECISE": (floor_math, (1.0, 0.0)),
            "CEILING.MATH": (ceiling_math, (1.0, 0.0)), "CEILING.PRECISE": (ceiling_math, (1.0, 0.0)),
            "ISO.CEILING": (ceiling_math, (1.0, 0.0))}
ROUNDING_ARITY = {"FLOOR.MATH": 3, "CEILING.MATH": 3, "FLOOR.PRECISE": 2, "CEILING.PRECISE": 2, "ISO.CEILING": 2}


# ---------------------------------------------------------------- aggregates
def sumsq(n: np.ndarray, use: np.ndarray) -> np.ndarray:
    """SUMSQ over (k, n) values, per row, of the values in use."""
    return np.where(use, n * n, 0.0).sum(axis=1)


def product(n: np.ndarray, use: np.ndarray) -> np.ndarray:
    """PRODUCT per row; 0 when no value is in use (Excel: =PRODUCT(A1:A3) of empty cells)."""
    return np.where(use.any(axis=1), np.where(use, n, 1.0).prod(axis=1), 0.0)


# ---------------------------------------------------------------- lookup
def choose_index(i: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """CHOOSE's index (truncated) as a 0-based position, and the errors: below 1 or past
    the last value is #VALUE!."""
    t = np.trunc(i)
    bad = ~((t >= 1) & (t <= count))
    return np.where(bad, 0, t - 1).astype(np.int64), np.where(bad, VALUE, 0).astype(np.int8)


def index_positions(rows: int, cols: int, r: np.ndarray, c: np.ndarray | None):
    """INDEX(array, r, [c]) over an array of rows x cols: the 0-based (row, column) of one
    element per cell (-1 for "the whole row/column": r or c = 0), and the errors.

    A single row or column is indexed by the one number given (INDEX(A1:E1, 3) is C1);
    a negative index is #VALUE!, past the end #REF!."""
    r = np.trunc(r)
    if c is None:
        if rows == 1 and cols > 1:
            r, c = np.zeros_like(r) + 1, r
        else:
            c = np.zeros_like(r) if cols > 1 else np.ones_like(r)
    c = np.trunc(c)
    err = np.where((r < 0) | (c < 0), VALUE, np.where((r > rows) | (c > cols), REF, 0)).astype(np.int8)
    # a single-column (single-row) array ignores a row (column) index of 0 in Excel too
    ri = np.where(r == 0, -1 if rows > 1 else 0, r - 1).astype(np.int64)
    ci = np.where(c == 0, -1 if cols > 1 else 0, c - 1).astype(np.int64)
    return np.where(err == 0, ri, 0), np.where(err == 0, ci, 0), err
