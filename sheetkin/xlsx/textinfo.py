"""Text, Logical and Information functions beyond the generated sheets' own: each a kernel
of the function table (table.py), after Excel's page of the function.

Text functions count characters as Python does (a character outside the Basic
Multilingual Plane is one, as in LibreOffice; Excel counts two: no such text in a
student's book is expected). TEXT and FIXED format numbers with the codes students use
(0, 0.00, #,##0.0, 0%, 0.00E+00, General); a format code with dates or conditions is
#VALUE! with a note in the docs, not a guess.
"""
from __future__ import annotations

import math
import re
from collections.abc import Sequence
from decimal import ROUND_HALF_UP, Decimal
from typing import Any

import numpy as np

from .cellwise import Fail, cellwise, per_cell
from .functions import FIRST_ERROR, MAX_TEXT, NA, REF, VALUE
from .values import (
    BOOL,
    EMPTY,
    NUM,
    TEXT,
    Evaluates,
    Val,
    compare,
    constant,
    error_value,
    first_error_of,
    select,
    to_bool,
    with_error,
)


# ------------------------------------------------------------------ text
def _count(n: float, low: int = 0) -> int:
    if n < low:
        raise Fail(VALUE)
    return math.trunc(min(n, MAX_TEXT + 1))


def _left(s: str, n: float = 1.0) -> str:
    return s[:_count(n)]


def _right(s: str, n: float = 1.0) -> str:
    k = _count(n)
    return s[len(s) - k:] if k else ""


def _mid(s: str, start: float, n: float) -> str:
    a = math.trunc(start)
    if a < 1:
        raise Fail(VALUE)
    return s[a - 1:a - 1 + _count(n)]


def _trim(s: str) -> str:
    return " ".join(s.split(" ")).strip(" ") if "  " not in s else re.sub(" +", " ", s).strip(" ")


def _proper(s: str) -> str:
    out, prev = [], False
    for ch in s:
        out.append(ch.lower() if prev else ch.upper())
        prev = ch.isalpha()
    return "".join(out)


def _substitute(s: str, old: str, new: str, which: float | None = None) -> str:
    if old == "":
        return s
    if which is None:
        out = s.replace(old, new)
    else:
        n = math.trunc(which)
        if n < 1:
            raise Fail(VALUE)
        i = -1
        for _ in range(n):
            i = s.find(old, i + 1)
            if i < 0:
                return s
        out = s[:i] + new + s[i + len(old):]
    if len(out) > MAX_TEXT:
        raise Fail(VALUE)
    return out


def _find(case: bool):
    def fn(needle: str, hay: str, start: float = 1.0) -> float:
        a = math.trunc(start)
        if a < 1 or a > len(hay) + 1:
            raise Fail(VALUE)
        if case:
            i = hay.find(needle, a - 1)
        else:
            pattern = _search_pattern(needle)
            m = pattern.search(hay, a - 1)
            i = m.start() if m else -1
        if i < 0:
            raise Fail(VALUE)
        return float(i + 1)
    return fn


def _search_pattern(needle: str) -> re.Pattern:
    out, i = [], 0
    while i < len(needle):
        ch = needle[i]
        if ch == "~" and i + 1 < len(needle) and needle[i + 1] in "*?~":
            out.append(re.escape(needle[i + 1]))
            i += 2
            continue
        out.append(".*?" if ch == "*" else "." if ch == "?" else re.escape(ch))
        i += 1
    return re.compile("".join(out), re.S | re.I)


def _replace(s: str, start: float, n: float, new: str) -> str:
    a = math.trunc(start)
    if a < 1:
        raise Fail(VALUE)
    out = s[:a - 1] + new + s[a - 1 + _count(n):]
    if len(out) > MAX_TEXT:
        raise Fail(VALUE)
    return out


def _char(n: float) -> str:
    c = math.trunc(n)
    if not 1 <= c <= 255:
        raise Fail(VALUE)
    return bytes([c]).decode("cp1252", errors="replace") if c >= 128 else chr(c)


def _code(s: str) -> float:
    if s == "":
        raise Fail(VALUE)
    ch = s[0]
    if ord(ch) < 128:
        return float(ord(ch))
    try:
        return float(ch.encode("cp1252")[0])
    except UnicodeEncodeError:
        return 63.0                       # Excel shows "?" for a character outside its code page


def _unichar(n: float) -> str:
    c = math.trunc(n)
    if not 1 <= c <= 0x10FFFF or 0xD800 <= c <= 0xDFFF:
        raise Fail(VALUE)
    return chr(c)


def _unicode(s: str) -> float:
    if s == "":
        raise Fail(VALUE)
    return float(ord(s[0]))


def _clean(s: str) -> str:
    return "".join(ch for ch in s if ord(ch) >= 32)


def _t(x: Any) -> Any:
    return x if isinstance(x, str) else ""


def _exact(a: str, b: str) -> bool:
    return a == b


def _rounded(x: float, digits: int) -> Decimal:
    return Decimal(f"{x:.15g}").quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_UP) if digits >= 0 else \
        (Decimal(f"{x:.15g}").scaleb(digits).quantize(Decimal(1), rounding=ROUND_HALF_UP)).scaleb(-digits)


def _fixed(x: float, decimals: float = 2.0, no_commas: Any = False) -> str:
    d = math.trunc(decimals)
    if d > 127:
        raise Fail(VALUE)
    q = _rounded(x, d)
    places = max(d, 0)
    body = f"{abs(q):,.{places}f}" if not no_commas else f"{abs(q):.{places}f}"
    return ("-" if q < 0 else "") + body


_FORMAT = re.compile(r"^(?P<pre>[^0#.,%Ee]*)(?P<int>[0#,]*)(?:\.(?P<dec>[0#]*))?(?P<exp>[Ee][+-]0+)?"
                     r"(?P<pct>%?)(?P<post>[^0#.,%]*)$")


def _text(x: Any, fmt: str) -> str:
    """TEXT(value, format) for the number formats of a lab report: General, 0, 0.00,
    #,##0.00, 0%, 0.0E+00, #.##, with literal text before or after and a section for
    negatives; a text value is kept."""
    from .cellwise import NUMERIC_TEXT
    if isinstance(x, str):
        if not NUMERIC_TEXT.match(x):
            return x
        x = float(x)
    if isinstance(x, bool):
        return "TRUE" if x else "FALSE"
    n = 0.0 if x is None else float(x)
    if fmt.strip().lower() in ("general", ""):
        from .values import number_text
        return number_text(n) if fmt else ""
    if ";" in fmt:
        parts = fmt.split(";")
        fmt = parts[1] if n < 0 and len(parts) > 1 else parts[0]
        if n < 0 and len(parts) > 1:
            n = -n
    # literal text ("m", \x) keeps its digits and # out of the number's pattern
    plain = re.sub(r'"([^"]*)"', lambda m: m.group(1).replace("0", "\x00").replace("#", "\x01"), fmt)
    plain = re.sub(r"\\(.)", lambda m: m.group(1), plain)
    m = _FORMAT.match(plain)
    if not m or (not m.group("int") and m.group("dec") is None):
        raise Fail(VALUE)
    pct = m.group("pct") == "%"
    if pct:
        n *= 100
    body = _scientific(n, m) if m.group("exp") else _fixed_point(n, m)
    out = m.group("pre") + body + ("%" if pct else "") + m.group("post")
    return out.replace("\x00", "0").replace("\x01", "#")


def _scientific(n: float, m: re.Match) -> str:
    """A number as 0.00E+00 shows it."""
    dec = len(m.group("dec") or "")
    digits = len(m.group("exp")) - 2
    exp = 0 if n == 0 else math.floor(math.log10(abs(n)))
    if n != 0 and round(abs(n) / 10 ** exp, dec) >= 10:
        exp += 1
    body = f"{_rounded(n / 10 ** exp, dec):.{dec}f}"
    return body + m.group("exp")[0] + ("-" if exp < 0 else "+") + str(abs(exp)).rjust(digits, "0")


def _fixed_point(n: float, m: re.Match) -> str:
    """A number as 0.00, #,##0.0 or #.## shows it (a 0 is a digit always shown, a # one
    shown where it is not a leading or trailing zero)."""
    places = len(m.group("dec") or "")
    q = _rounded(n, places)
    body = f"{abs(q):,.{places}f}" if "," in m.group("int") else f"{abs(q):.{places}f}"
    ip, _, fp = body.partition(".")
    if m.group("int").replace(",", "").count("0") == 0 and ip.replace(",", "") == "0":
        ip = ""
    keep = len((m.group("dec") or "").rstrip("#"))
    while len(fp) > keep and fp.endswith("0"):
        fp = fp[:-1]
    body = ip + ("." + fp if places else "")
    return "-" + body if q < 0 else body


def _concat_all(args) -> str:
    from .cellwise import text
    out = "".join(text(x) for values, _ in args for x in values)
    if len(out) > MAX_TEXT:
        raise Fail(VALUE)
    return out


def _textjoin(args) -> str:
    from .cellwise import boolean, text
    (sep_values, _), (ignore_values, _) = args[0], args[1]
    seps = [text(s) for s in sep_values] or [""]
    ignore = boolean(ignore_values[0])
    items = [text(x) for values, _ in args[2:] for x in values]
    if ignore:
        items = [t for t in items if t != ""]
    out = ""
    for i, t in enumerate(items):
        out += (seps[(i - 1) % len(seps)] if i else "") + t
    if len(out) > MAX_TEXT:
        raise Fail(VALUE)
    return out


TEXT_SCALAR = {
    "LEFT": cellwise(_left, "tn", (1.0,)), "RIGHT": cellwise(_right, "tn", (1.0,)),
    "MID": cellwise(_mid, "tnn"), "LEN": cellwise(lambda s: float(len(s)), "t"),
    "TRIM": cellwise(_trim, "t"), "UPPER": cellwise(str.upper, "t"), "LOWER": cellwise(str.lower, "t"),
    "PROPER": cellwise(_proper, "t"),
    "SUBSTITUTE": cellwise(_substitute, "tttn", (None,)),
    "FIND": cellwise(_find(True), "ttn", (1.0,)), "SEARCH": cellwise(_find(False), "ttn", (1.0,)),
    "REPLACE": cellwise(_replace, "tnnt"), "EXACT": cellwise(_exact, "tt"),
    "CHAR": cellwise(_char, "n"), "CODE": cellwise(_code, "t"),
    "UNICHAR": cellwise(_unichar, "n"), "UNICODE": cellwise(_unicode, "t"),
    "CLEAN": cellwise(_clean, "t"), "T": cellwise(_t, "s"),
    "FIXED": cellwise(_fixed, "nnb", (2.0, False)), "TEXT": cellwise(_text, "st"),
}

TEXT_RANGES = {"CONCAT": per_cell(_concat_all), "TEXTJOIN": per_cell(_textjoin)}


# ------------------------------------------------------------------ logical (lazy: trees)
def _k(run: Any) -> int:
    return len(run.cols)


def ifna(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    a, b = ctx.eval(args[0], run), ctx.eval(args[1], run)
    return select(a.tag == NA, b, a)


def ifs(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """IFS(c1, v1, c2, v2, ...): the value of the first condition TRUE per cell; an error
    in a condition met before that is the cell's; none TRUE: #N/A."""
    if len(args) % 2:
        return error_value("#VALUE!", _k(run))
    out = error_value("#N/A")
    done = np.zeros((1, 1, 1), bool)
    for i in range(0, len(args), 2):
        cond, err = to_bool(ctx.eval(args[i], run))
        value = ctx.eval(args[i + 1], run)
        take = ~done & cond & (err == 0)
        out = select(take, value, out)
        out = with_error(out, np.where(~done & (err != 0), err, 0).astype(np.int8))
        done = done | cond | (err != 0)
    return out


def switch(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """SWITCH(expr, v1, r1, ..., [default]): the result of the first value equal to expr
    (compared as `=` compares), else the default, else #N/A; an error in expr is the cell's."""
    if len(args) < 3:
        return error_value("#VALUE!", _k(run))
    expr = ctx.eval(args[0], run)
    pairs = (len(args) - 1) // 2
    out = ctx.eval(args[-1], run) if (len(args) - 1) % 2 else error_value("#N/A")
    for i in reversed(range(pairs)):
        hit = compare("=", expr, ctx.eval(args[1 + 2 * i], run))
        out = select((hit.tag == BOOL) & (hit.num != 0), ctx.eval(args[2 + 2 * i], run), out)
    return with_error(out, np.where(expr.tag >= FIRST_ERROR, expr.tag, 0).astype(np.int8))


def xor(vals: Sequence[Val], ranges: Sequence[bool]) -> Val:
    """XOR(...): TRUE where an odd number of arguments is TRUE (ranges: their numbers and
    booleans; text skipped); #VALUE! where nothing counts."""
    k = max(v.shape[0] for v in vals)
    count = np.zeros(k)
    seen = np.zeros(k, bool)
    errs = []
    for v, is_range in zip(vals, ranges, strict=True):
        if is_range or v.shape[1:] != (1, 1):
            use = (v.tag == NUM) | (v.tag == BOOL)
            b = v.num != 0
            e = np.where(v.tag >= FIRST_ERROR, v.tag, 0)
        else:
            b, e = to_bool(v)
            use = v.tag != EMPTY
        n = v.shape[0]
        count = count + np.broadcast_to(np.where(use, b, False).reshape(n, -1).sum(axis=1), (k,))
        seen = seen | np.broadcast_to(use.reshape(n, -1).any(axis=1), (k,))
        errs.append(np.broadcast_to(first_error_row(e.reshape(n, -1)), (k,)))
    err = first_error_of(*errs) if errs else np.zeros(k, np.int8)
    err = np.where((err == 0) & ~seen, VALUE, err).astype(np.int8)
    return Val(np.where(err == 0, count % 2 == 1, 0.0).astype(float).reshape(k, 1, 1),
               np.where(err == 0, BOOL, err).astype(np.int8).reshape(k, 1, 1))


def first_error_row(e: np.ndarray) -> np.ndarray:
    if e.shape[1] == 0:
        return np.zeros(e.shape[0], np.int8)
    idx = np.argmax(e != 0, axis=1)
    return e[np.arange(e.shape[0]), idx].astype(np.int8)


# ------------------------------------------------------------------ information
def _is(test):
    def hook(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
        v = ctx.eval(args[0], run)
        return Val(test(v).astype(float), np.full(v.shape, BOOL, np.int8))
    return hook


def is_ref(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    node = args[0]
    if node[0] == "name":
        target = ctx.name(node[1], run)
        node = target if target is not None else node
    yes = node[0] == "ref" or (node[0] == "fn" and node[1] in ("OFFSET", "INDIRECT", "INDEX", ":"))
    if node[0] == "fn" and node[1] in ("OFFSET", "INDIRECT", ":"):
        v = ctx.eval(node, run)
        return Val(np.where(v.tag[:, :1, :1] == REF, 0.0, 1.0), np.full((v.shape[0], 1, 1), BOOL, np.int8))
    return constant(bool(yes))


def type_of(ctx: Evaluates, args: Sequence[Any], run: Any) -> Val:
    """TYPE(value): 1 number (and empty), 2 text, 4 boolean, 16 error, 64 an array."""
    v = ctx.eval(args[0], run)
    if v.shape[1:] != (1, 1):
        return constant(64.0)
    t = v.tag
    n = np.where(t == TEXT, 2.0, np.where(t == BOOL, 4.0, np.where(t >= FIRST_ERROR, 16.0, 1.0)))
    return Val(n.astype(float), np.zeros(v.shape, np.int8), None, NUM)


INFORMATION_LAZY = {
    "ISBLANK": _is(lambda v: v.tag == EMPTY),
    "ISLOGICAL": _is(lambda v: v.tag == BOOL),
    "ISNONTEXT": _is(lambda v: v.tag != TEXT),
}

