"""Math & Trig and Statistical functions beyond the generated sheets' own (those are in
values.py, on numpy paths): each a kernel of the function table (table.py), following
Excel's page of the function (support.microsoft.com) for its domain and its errors.

Scalar ones are numpy kernels wrapped by values.unary/binary where they are one formula of
the argument, else Python per cell (cellwise.cellwise); functions of ranges read each
cell's numbers as Excel does (numbers in references, typed arguments coerced).
"""
from __future__ import annotations

import math
from decimal import ROUND_DOWN, ROUND_UP, Decimal, InvalidOperation
from typing import Any

import numpy as np

from .cellwise import CODE_TEXT, Fail, cellwise, from_py, numbers_of, per_cell
from .functions import DIV0, FIRST_ERROR, NA, NUMERR, VALUE, XlError
from .values import NUM, Val, unary


def _trig(x):
    return np.abs(x) < 134217728.0


def _trig_recip(den):
    def kernel(v: Val) -> Val:
        from .values import numeric_result, to_number
        n, err = to_number(v)
        with np.errstate(all="ignore"):
            d = den(n)
            r = 1.0 / d
        err = np.where((err == 0) & ~_trig(n), NUMERR, err)
        err = np.where((err == 0) & (d == 0), DIV0, err).astype(np.int8)
        return numeric_result(r, err)
    return kernel


def _hyp_recip(den):
    def kernel(v: Val) -> Val:
        from .values import numeric_result, to_number
        n, err = to_number(v)
        with np.errstate(all="ignore"):
            d = den(n)
            r = 1.0 / d
        err = np.where((err == 0) & (d == 0), DIV0, err).astype(np.int8)
        return numeric_result(r, err)
    return kernel


TRIG = {
    "ACOT": unary(lambda x: np.pi / 2 - np.arctan(x)),
    "ACOTH": unary(lambda x: 0.5 * np.log((x + 1) / (x - 1)), lambda x: np.abs(x) > 1),
    "COT": _trig_recip(np.tan), "CSC": _trig_recip(np.sin), "SEC": _trig_recip(np.cos),
    "COTH": _hyp_recip(np.tanh), "CSCH": _hyp_recip(np.sinh), "SECH": _hyp_recip(np.cosh),
    "SINH": unary(np.sinh), "COSH": unary(np.cosh), "TANH": unary(np.tanh),
    "ASINH": unary(np.arcsinh), "ACOSH": unary(np.arccosh, lambda x: x >= 1),
    "ATANH": unary(np.arctanh, lambda x: np.abs(x) < 1),
    "SQRTPI": unary(lambda x: np.sqrt(x * np.pi), lambda x: x >= 0),
}


# ------------------------------------------------------------------ rounding and integers
def _decimal_round(mode_pos, mode_neg):
    def fn(x: float, digits: float) -> float:
        d = math.trunc(digits)
        try:
            q = Decimal(f"{x:.15g}").quantize(Decimal(1).scaleb(-d), rounding=mode_pos if x >= 0 else mode_neg)
        except InvalidOperation:
            return x if d > 0 else 0.0
        return float(q)
    return fn


ROUNDUP = cellwise(_decimal_round(ROUND_UP, ROUND_UP), "nn")
ROUNDDOWN = cellwise(_decimal_round(ROUND_DOWN, ROUND_DOWN), "nn")


def _log(x: float, base: float) -> float:
    if x <= 0 or base <= 0:
        raise Fail(NUMERR)
    if base == 1:
        raise Fail(DIV0)
    return math.log(x) / math.log(base)


def _even_odd(odd: bool):
    def fn(x: float) -> float:
        s = -1.0 if x < 0 else 1.0
        a = math.ceil(abs(x))
        return s * (a if a % 2 == odd else a + 1)
    return fn


def _fact(n: float) -> float:
    if n < 0:
        raise Fail(NUMERR)
    return float(math.factorial(math.trunc(n))) if n < 171 else math.inf


def _factdouble(n: float) -> float:
    if n < -1:
        raise Fail(NUMERR)
    m, out = math.trunc(n), 1.0
    while m > 1:
        out *= m
        m -= 2
    return out


def _combin(n: float, k: float) -> float:
    n, k = math.trunc(n), math.trunc(k)
    if n < 0 or k < 0 or k > n:
        raise Fail(NUMERR)
    return float(math.comb(n, k))


def _combina(n: float, k: float) -> float:
    n, k = math.trunc(n), math.trunc(k)
    if n < 0 or k < 0 or (n == 0 and k > 0):
        raise Fail(NUMERR)
    return float(math.comb(n + k - 1, k)) if n + k - 1 >= k else 1.0


def _permut(n: float, k: float) -> float:
    n, k = math.trunc(n), math.trunc(k)
    if n < 0 or k < 0 or k > n:
        raise Fail(NUMERR)
    return float(math.perm(n, k))


def _mround(x: float, m: float) -> float:
    if m == 0:
        return 0.0
    if (x > 0 and m < 0) or (x < 0 and m > 0):
        raise Fail(NUMERR)
    q = Decimal(f"{x / m:.15g}").quantize(Decimal(1), rounding="ROUND_HALF_UP")
    return float(q) * m


def _quotient(a: float, b: float) -> float:
    if b == 0:
        raise Fail(DIV0)
    return float(math.trunc(a / b))


_ROMAN = ((1000, "M"), (900, "CM"), (500, "D"), (400, "CD"), (100, "C"), (90, "XC"), (50, "L"), (40, "XL"),
          (10, "X"), (9, "IX"), (5, "V"), (4, "IV"), (1, "I"))


def _roman(n: float, form: float = 0.0) -> str:
    n = math.trunc(n)
    if not 0 <= n <= 3999 or form != 0:       # the concise forms 1-4: not computed here
        raise Fail(VALUE)
    out = []
    for value, letters in _ROMAN:
        while n >= value:
            out.append(letters)
            n -= value
    return "".join(out)


def _arabic(s: str) -> float:
    t = s.strip().upper()
    sign = -1.0 if t.startswith("-") else 1.0
    t = t.lstrip("-")
    if len(s) > 255 or any(ch not in "MDCLXVI" for ch in t):
        raise Fail(VALUE)
    vals = {"M": 1000, "D": 500, "C": 100, "L": 50, "X": 10, "V": 5, "I": 1}
    total = 0
    for i, ch in enumerate(t):
        v = vals[ch]
        total += -v if i + 1 < len(t) and vals[t[i + 1]] > v else v
    return sign * total


def _base(n: float, radix: float, width: float = 0.0) -> str:
    n, radix, width = math.trunc(n), math.trunc(radix), math.trunc(width)
    if n < 0 or n >= 2 ** 53 or not 2 <= radix <= 36 or width < 0 or width > 255:
        raise Fail(NUMERR)
    digits = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"
    out = ""
    while n:
        n, r = divmod(n, radix)
        out = digits[r] + out
    return (out or "0").rjust(width, "0")


def _decimal(s: str, radix: float) -> float:
    radix = math.trunc(radix)
    if not 2 <= radix <= 36 or len(s) > 255:
        raise Fail(NUMERR)
    t = s.strip()
    if radix == 16 and t[:2].lower() == "0x":
        t = t[2:]
    try:
        return float(int(t, radix)) if t else 0.0
    except ValueError:
        raise Fail(NUMERR) from None


def _ints_of(args) -> list[int]:
    out = []
    for x in numbers_of(args):
        if x < 0 or x >= 2 ** 53:
            raise Fail(NUMERR)
        out.append(math.trunc(x))
    return out


def _gcd(args) -> float:
    return float(math.gcd(*_ints_of(args)))


def _lcm(args) -> float:
    ints = _ints_of(args)
    return float(math.lcm(*ints)) if all(ints) else 0.0


def _multinomial(args) -> float:
    ints = _ints_of(args)
    return float(math.factorial(sum(ints)) // math.prod(math.factorial(i) for i in ints))


def _paired(args, fn) -> float:
    """SUMX2MY2 and kin: pairs of the two arrays where both hold numbers."""
    (xs, _), (ys, _) = args
    if len(xs) != len(ys):
        raise Fail(NA)
    total, seen = 0.0, False
    for x, y in zip(xs, ys, strict=True):
        for z in (x, y):
            if isinstance(z, XlError):
                raise Fail(int(_code(z)))
        if isinstance(x, float) and isinstance(y, float) and not isinstance(x, bool) and not isinstance(y, bool):
            total += fn(x, y)
            seen = True
    if not seen:
        raise Fail(DIV0)
    return total


def _code(e: XlError) -> int:
    from .functions import ERRORS
    return ERRORS.get(e, VALUE)


def _seriessum(args) -> float:
    (x,), (n,), (m,) = (numbers_of([a]) for a in args[:3])
    coeffs = numbers_of([args[3]])
    return sum(a * x ** (n + i * m) for i, a in enumerate(coeffs))


# ------------------------------------------------------------------ statistics
def _median(args) -> float:
    xs = sorted(numbers_of(args))
    if not xs:
        raise Fail(NUMERR)
    m = len(xs) // 2
    return xs[m] if len(xs) % 2 else (xs[m - 1] + xs[m]) / 2


def _var(sample: bool, a_form: bool = False):
    def fn(args) -> float:
        xs = numbers_of(args, count_text=a_form, booleans_in_ranges=a_form)
        n = len(xs)
        if n - sample <= 0:
            raise Fail(DIV0)
        mean = math.fsum(xs) / n
        return math.fsum((x - mean) ** 2 for x in xs) / (n - sample)
    return fn


def _stdev(sample: bool, a_form: bool = False):
    var = _var(sample, a_form)
    return lambda args: math.sqrt(var(args))


def _kth(largest: bool):
    def fn(args) -> float:
        xs = sorted(numbers_of(args[:1]), reverse=largest)
        k = numbers_of(args[1:])
        if len(k) != 1:
            raise Fail(VALUE)
        i = math.ceil(k[0])
        if not xs or not 1 <= i <= len(xs):
            raise Fail(NUMERR)
        return xs[i - 1]
    return fn


def _percentile(exclusive: bool):
    def fn(args) -> float:
        xs = sorted(numbers_of(args[:1]))
        p = numbers_of(args[1:])[0]
        n = len(xs)
        if not xs:
            raise Fail(NUMERR)
        if exclusive:
            h = p * (n + 1) - 1
            if not 0 <= h <= n - 1 or p <= 0 or p >= 1:
                raise Fail(NUMERR)
        else:
            if not 0 <= p <= 1:
                raise Fail(NUMERR)
            h = p * (n - 1)
        lo = math.floor(h)
        return xs[lo] + (h - lo) * (xs[min(lo + 1, n - 1)] - xs[lo])
    return fn


def _quartile(exclusive: bool):
    pct = _percentile(exclusive)

    def fn(args) -> float:
        q = math.trunc(numbers_of(args[1:])[0])
        if not (0 <= q <= 4) or (exclusive and not 1 <= q <= 3):
            raise Fail(NUMERR)
        return pct([args[0], ([q / 4], False)])
    return fn


def _rank(average: bool):
    def fn(args) -> float:
        x = numbers_of(args[:1])[0]
        xs = numbers_of(args[1:2])
        if not args[1][1]:
            raise Fail(VALUE)        # a reference, not an array (Excel refuses typed arrays too)
        order = numbers_of(args[2:3])[0] if len(args) > 2 else 0.0
        if x not in xs:
            raise Fail(NA)
        before = sum(1 for y in xs if (y < x if order else y > x))
        if not average:
            return float(before + 1)
        same = xs.count(x)
        return before + (same + 1) / 2
    return fn


def _mode(args) -> float:
    xs = numbers_of(args)
    best, count = None, 1
    for x in xs:
        c = xs.count(x)
        if c > count:
            best, count = x, c
    if best is None:
        raise Fail(NA)
    return best


def _averagea(args) -> float:
    xs = numbers_of(args, count_text=True, booleans_in_ranges=True)
    if not xs:
        raise Fail(DIV0)
    return math.fsum(xs) / len(xs)


def _extreme_a(fn):
    def f(args) -> float:
        xs = numbers_of(args, count_text=True, booleans_in_ranges=True)
        return fn(xs) if xs else 0.0
    return f


def _avedev(args) -> float:
    xs = numbers_of(args)
    if not xs:
        raise Fail(NUMERR)
    mean = math.fsum(xs) / len(xs)
    return math.fsum(abs(x - mean) for x in xs) / len(xs)


def _devsq(args) -> float:
    xs = numbers_of(args)
    if not xs:
        raise Fail(NUMERR)
    mean = math.fsum(xs) / len(xs)
    return math.fsum((x - mean) ** 2 for x in xs)


def _geomean(args) -> float:
    xs = numbers_of(args)
    if not xs or any(x <= 0 for x in xs):
        raise Fail(NUMERR)
    return math.exp(math.fsum(math.log(x) for x in xs) / len(xs))


def _harmean(args) -> float:
    xs = numbers_of(args)
    if not xs or any(x <= 0 for x in xs):
        raise Fail(NUMERR)
    return len(xs) / math.fsum(1 / x for x in xs)


def _counta(args) -> float:
    return float(sum(1 for values, _ in args for x in values if x is not None))


def _countblank(args) -> float:
    return float(sum(1 for values, _ in args for x in values if x is None or x == ""))


STATISTICAL = {
    "MEDIAN": per_cell(_median),
    "STDEV": per_cell(_stdev(True)), "STDEV.S": per_cell(_stdev(True)),
    "STDEVP": per_cell(_stdev(False)), "STDEV.P": per_cell(_stdev(False)),
    "STDEVA": per_cell(_stdev(True, True)), "STDEVPA": per_cell(_stdev(False, True)),
    "VAR": per_cell(_var(True)), "VAR.S": per_cell(_var(True)),
    "VARP": per_cell(_var(False)), "VAR.P": per_cell(_var(False)),
    "VARA": per_cell(_var(True, True)), "VARPA": per_cell(_var(False, True)),
    "LARGE": per_cell(_kth(True)), "SMALL": per_cell(_kth(False)),
    "PERCENTILE": per_cell(_percentile(False)), "PERCENTILE.INC": per_cell(_percentile(False)),
    "PERCENTILE.EXC": per_cell(_percentile(True)),
    "QUARTILE": per_cell(_quartile(False)), "QUARTILE.INC": per_cell(_quartile(False)),
    "QUARTILE.EXC": per_cell(_quartile(True)),
    "RANK": per_cell(_rank(False)), "RANK.EQ": per_cell(_rank(False)), "RANK.AVG": per_cell(_rank(True)),
    "MODE": per_cell(_mode), "MODE.SNGL": per_cell(_mode),
    "AVERAGEA": per_cell(_averagea), "MAXA": per_cell(_extreme_a(max)), "MINA": per_cell(_extreme_a(min)),
    "AVEDEV": per_cell(_avedev), "DEVSQ": per_cell(_devsq), "GEOMEAN": per_cell(_geomean),
    "HARMEAN": per_cell(_harmean), "COUNTA": per_cell(_counta), "COUNTBLANK": per_cell(_countblank),
}

MATH_SCALAR = {
    **TRIG,
    "ROUNDUP": ROUNDUP, "ROUNDDOWN": ROUNDDOWN,
    "EVEN": cellwise(_even_odd(False), "n"), "ODD": cellwise(_even_odd(True), "n"),
    "FACT": cellwise(_fact, "n"), "FACTDOUBLE": cellwise(_factdouble, "n"),
    "COMBIN": cellwise(_combin, "nn"), "COMBINA": cellwise(_combina, "nn"), "PERMUT": cellwise(_permut, "nn"),
    "MROUND": cellwise(_mround, "nn"), "QUOTIENT": cellwise(_quotient, "nn"),
    "ROMAN": cellwise(_roman, "nn", (0.0,)), "ARABIC": cellwise(_arabic, "t"),
    "BASE": cellwise(_base, "nnn", (0.0,)), "DECIMAL": cellwise(_decimal, "tn"),
}

MATH_RANGES = {
    "GCD": per_cell(_gcd), "LCM": per_cell(_lcm), "MULTINOMIAL": per_cell(_multinomial),
    "SUMX2MY2": per_cell(lambda a: _paired(a, lambda x, y: x * x - y * y)),
    "SUMX2PY2": per_cell(lambda a: _paired(a, lambda x, y: x * x + y * y)),
    "SUMXMY2": per_cell(lambda a: _paired(a, lambda x, y: (x - y) ** 2)),
    "SERIESSUM": per_cell(_seriessum),
}


def log(x: Val, base: Val | None = None) -> Val:
    """LOG(x, [base=10])."""
    if base is None:
        return unary(np.log10, lambda n: n > 0)(x)
    return cellwise(_log, "nn")(x, base)


# ------------------------------------------------------------------ matrices
def _matrix(v: Val, i: int) -> np.ndarray:
    """Cell i's array as numbers; #VALUE! if any element is not a number."""
    c = i if v.shape[0] > 1 else 0
    tag = v.tag[c]
    if (tag != NUM).any():
        errs = tag[tag >= FIRST_ERROR]
        raise Fail(int(errs[0]) if errs.size else VALUE)
    return np.asarray(v.num[c], float)


def _per_matrix(fn, *vals: Val) -> Val:
    k = max(v.shape[0] for v in vals)
    outs: list[Any] = []
    for i in range(k):
        try:
            outs.append(fn(*(_matrix(v, i) for v in vals)))
        except Fail as e:
            outs.append(CODE_TEXT.get(e.code, XlError("#VALUE!")))
        except np.linalg.LinAlgError:
            outs.append(CODE_TEXT[NUMERR])
    shapes = {o.shape for o in outs if isinstance(o, np.ndarray)}
    if len(shapes) > 1:
        return from_py(np.array([[[CODE_TEXT[VALUE]]]] * k, dtype=object))
    shape = shapes.pop() if shapes else (1, 1)
    out = np.empty((k, *shape), dtype=object)
    for i, o in enumerate(outs):
        if isinstance(o, np.ndarray):
            out[i] = o.astype(object)
        else:
            out[i] = o
    return from_py(out)


def _square(m: np.ndarray) -> np.ndarray:
    if m.shape[0] != m.shape[1]:
        raise Fail(VALUE)
    return m


def mdeterm(v: Val) -> Val:
    return _per_matrix(lambda m: np.array([[float(np.linalg.det(_square(m)))]]), v)


def minverse(v: Val) -> Val:
    def inv(m):
        m = _square(m)
        if np.linalg.det(m) == 0:
            raise Fail(NUMERR)
        return np.linalg.inv(m)
    return _per_matrix(inv, v)


def mmult(a: Val, b: Val) -> Val:
    def mul(x, y):
        if x.shape[1] != y.shape[0]:
            raise Fail(VALUE)
        return x @ y
    return _per_matrix(mul, a, b)


def munit(v: Val) -> Val:
    def unit(n):
        d = math.trunc(float(n[0, 0]))
        if d < 1:
            raise Fail(VALUE)
        return np.eye(d)
    return _per_matrix(unit, v)


def transpose(v: Val) -> Val:
    """TRANSPOSE(array): rows as columns, whatever the values (text, errors) are."""
    return Val(np.swapaxes(v.num, 1, 2), np.swapaxes(v.tag, 1, 2),
               None if v.txt is None else np.swapaxes(v.txt, 1, 2))


def _is_parity(odd: bool):
    def fn(x: Any) -> bool:
        if isinstance(x, bool):
            raise Fail(VALUE)
        if isinstance(x, XlError):
            raise Fail(_code(x))
        if x is None:
            n = 0.0
        elif isinstance(x, str):         # text, a number's text too: #VALUE! (Excel's page)
            raise Fail(VALUE)
        else:
            n = x
        return (math.trunc(n) % 2 == 1) == odd
    return fn


ISEVEN = cellwise(_is_parity(False), "v")
ISODD = cellwise(_is_parity(True), "v")

