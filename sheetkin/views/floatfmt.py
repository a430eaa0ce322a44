"""Python's `repr` of float64 arrays, in bulk with numpy: the shortest decimal that reads
back as the same double (what `float.__repr__`, `json.dumps` and pandas' CSV writer give),
byte for byte, about 6x faster than formatting one float at a time.

Why: `sheetkin compute` writes millions of numbers; Python formats one float in about
0.5 us on this machine, so 1e5 positions x 40 columns took 2-7 s. Here a number costs
~75 ns on one core (~100 numpy operations over chunks of CHUNK numbers, no branches: a
np.where on a mixed mask costs 7 ns an element, mispredicted). The digits come from
integer arithmetic over whole arrays:
  1. the decimal exponent e = floor(log10|x|), corrected after rounding;
  2. m17 = round(|x| 10^(16-e)), the 17-digit mantissa, with the product computed exactly
     as a double-double (Dekker's two-product; 10^k as a double-double from exact
     fractions), and d17, m17's distance to the exact value;
  3. 16 and 15 digits from m17's last two digits and d17: the nearest multiple of 10
     (100); the shortest that reads back as x (its distance under half the gap to the
     neighbouring double, in the same scaled units) is repr's: any decimal of <= 15 digits
     survives double -> 15 digits, and among 16 (17) digit decimals repr picks the nearest
     that reads back (at a power of two, where the gap below is narrower, that can be the
     one above the nearest);
  4. the digits (SWAR: eight decimal digits a uint64 word) laid out as repr does, by
     tables indexed by the exponent and the number of digits: positional for
     1e-4 <= |x| < 1e16 ("30.0", "0.0001"), otherwise "1.5e-05", "1e+16".
Where step 2 or 3 is within 1e-7 of a last digit of a tie to decide (about one number in a
million: 6 of the four-bar's 4e6), and for |x| outside [1e-200, 1e200], the element is
formatted by `repr` itself. Non-finite values are reported to the caller, who decides what
to write (sheetkin never writes "nan"/"inf").
"""
from __future__ import annotations

import contextlib
import sys
import threading

import numpy as np

WIDTH = 32                      # bytes per number (unused ones are 0, dropped later)
_KMIN, _KMAX = -240, 240        # powers of ten kept as double-doubles
_LO, _HI = 1e-200, 1e200        # |x| formatted here; outside, by repr


def _powers_of_ten():
    """10^k for _KMIN <= k <= _KMAX as double-doubles (hi + lo, to ~1e-32), from exact
    integers: int / int is correctly rounded in Python."""
    hi, lo = [], []
    for k in range(_KMIN, _KMAX + 1):
        if k >= 0:
            p = 10 ** k
            h = float(p)
            a, b = h.as_integer_ratio()          # b = 1
            rest_num, rest_den = p - a, 1
        else:
            q = 10 ** -k
            h = 1 / q
            a, b = h.as_integer_ratio()
            rest_num, rest_den = b - a * q, b * q  # 1/q - a/b
        hi.append(h)
        lo.append(rest_num / rest_den)
    return np.array(hi), np.array(lo)


_POW_HI, _POW_LO = _powers_of_ten()
_SPLIT = 134217729.0            # 2^27 + 1: Veltkamp's split of a double into two halves
_INT10 = 10 ** np.arange(18, dtype=np.int64)
_MARGIN = 1e-7                  # closer than this (in units of the last digit) to a tie: repr
# The text is built in four little-endian uint64 words (byte i of the text = bits 8i..8i+7):
# word 0: a byte left 0 for the caller (a separator), the sign, then "0.000" up to the
# leading zeros (1e-4 <= |x| < 1); words 1-3: the 17 digits with the point inserted;
# word 3's bytes 3-7: "e", its sign, three exponent digits. Unused bytes are 0.
_U = np.uint64
CHUNK = 8192                    # numbers per pass: the temporaries stay in the L2 cache


def _split(a):
    """Veltkamp's split: a = hi + lo, each with at most 26 significant bits."""
    c = _SPLIT * a
    hi = c - (c - a)
    return hi, a - hi


_POW_SPLIT = _split(_POW_HI)


def _mantissa(a, idx):
    """(m, delta): m = a 10^k rounded to an integer (int64) and delta = m - a 10^k, with
    a 10^k computed to about 1e-32 relative (so delta is right to ~1e-15 in these units);
    idx = k - _KMIN. a * 10^k = p + err exactly by Dekker's two-product (no FMA in numpy),
    with the powers' halves from a table."""
    h = _POW_HI[idx]
    p = a * h
    ah, al = _split(a)
    bh, bl = _POW_SPLIT[0][idx], _POW_SPLIT[1][idx]
    err = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    p_int = np.rint(p)
    r = (p - p_int) + (err + a * _POW_LO[idx])
    rr = np.rint(r)
    return p_int.astype(np.int64) + rr.astype(np.int64), rr - r, h


def _eight(v):
    """The 8 decimal digits of v < 1e8 (uint64) as 8 bytes (values 0-9) in text order,
    SWAR: split in lanes of 4, 2, 1 digits, dividing every lane at once by a multiply-shift.
    A lane's quotient q and remainder w - q d go to q | (w - q d) << s, which is
    (w << s) - q (d 2^s - 1): no lane borrows from the next."""
    a = v // _U(10000)
    w = (v << _U(32)) - a * _U((10000 << 32) - 1)
    q = ((w * _U(10486)) >> _U(20)) & _U(0x0000007F0000007F)     # lanes < 1e4: // 100
    w = (w << _U(16)) - q * _U((100 << 16) - 1)
    q = ((w * _U(103)) >> _U(10)) & _U(0x000F000F000F000F)       # lanes < 100: // 10
    return (w << _U(8)) - q * _U((10 << 8) - 1)


def _select(cond, a, b):
    """np.where(cond, a, b) for floats without branches: np.where's loop mispredicts on
    masks that are not all one way (7 ns an element here against 1 ns for this)."""
    c = cond.astype(np.float64)
    return a * c + b * (1.0 - c)


def _shortest(t, d17, up, down, pow2):
    """The last two of the 17 digits as repr keeps them: t in [0, 100], rounded to a
    multiple of 100 (15 digits) or 10 (16) where that decimal reads back as x, else as is;
    and where that is too close to call. t - d17 is the true value's part modulo 100 (in
    units of the 17th digit), up and down half the gaps to the neighbouring doubles in the
    same units (down < up at a power of two, where the gap below is half as wide; pow2 marks
    those, None if there are none)."""
    v = t - d17
    ad = np.abs(d17)
    unsure = np.abs(ad - 0.5) < _MARGIN          # 17 digits: a tie
    dists = []
    for cut in (10.0, 100.0):                   # 16 digits, then 15: the shortest that reads back
        r = np.rint(v * (1.0 / cut)) * cut      # the nearest multiple of cut
        delta = r - v                           # > 0: the decimal is above x
        dist = np.abs(delta)
        if pow2 is None:
            half = up
            ok = dist < half
        else:
            half = _select(delta >= 0.0, up, down)
            ok = dist < half
            # at a power of two the gap below is half the gap above: the nearest decimal below
            # may miss where the next one up still reads back (2^-44 is 5.684341886080802e-14)
            alt = ~ok & (delta < 0.0) & pow2
            ok_up = alt & (delta + cut < up)
            unsure |= alt & (np.abs(delta + cut - up) < _MARGIN * cut)
            r = r + cut * ok_up
            ok |= ok_up
        unsure |= np.abs(dist - half) < _MARGIN * cut
        dists.append(dist)
        t = t + ok * (r - t)                    # small integers: exact
    # a tie at 16 or 15 digits (a distance of half a cut) needs x within ~1e-6 of the 17th
    # digit's unit from a 17-digit decimal (d17 near 0): checked on those only
    near = np.flatnonzero(ad < 1e-4)
    if near.size:
        unsure[near] |= ((np.abs(dists[0][near] - 5.0) < _MARGIN * 10.0)
                         | (np.abs(dists[1][near] - 50.0) < _MARGIN * 100.0))
    return t, unsure


# The layout of a number's 32 bytes, by its decimal exponent X (index X + _XOFF):
# word 0: separator, sign, "0.000" (1e-4 <= |x| < 1); words 1-3: the digits with the point;
# word 3's bytes 3-7: "e", the exponent's sign and digits.
_XOFF = 210


def _layout_tables():
    """Built once at import: by X, the point's byte, the digits shown at least, word 0 and
    the exponent word; by (digits shown, point), the masks and characters of words 1-3."""
    xs = range(-_XOFF, _XOFF + 1)
    point = np.empty(len(xs), np.intp)        # the point after digit q - 1 (17: no point)
    least = np.empty(len(xs), np.intp)        # digits shown at least (x >= 1: one after the point)
    word0 = np.zeros(len(xs), np.uint64)
    expo = np.zeros(len(xs), np.uint64)
    for i, x in enumerate(xs):
        if 0 <= x < 16:
            point[i], least[i] = x + 1, x + 2
        elif -4 <= x < 0:
            point[i], least[i] = 17, 1
            word0[i] = int.from_bytes(b"\0\0" + b"0." + b"0" * (-x - 1), "little")
        else:
            point[i], least[i] = 1, 1
            e = b"e" + (b"-" if x < 0 else b"+") + (b"%03d" % abs(x) if abs(x) >= 100 else b"\0%02d" % abs(x))
            expo[i] = int.from_bytes(b"\0\0\0" + e, "little")
    # by code = 18 * keep + q (keep: digits shown; q: the point's byte, 17: none; keep = 1
    # with q = 1, a single digit in exponent form, has no point either), for each of the
    # three digit words: the bytes before the point (the digits after it move one byte on),
    # and the characters added ("0" to the digits shown, the point)
    before = np.zeros((3, 18 * 18), np.uint64)
    chars = np.zeros((3, 18 * 18), np.uint64)
    for keep in range(1, 18):
        for q in range(1, 18):
            code = 18 * keep + q
            if q == 17 or (q == 1 and keep == 1):
                text = b"0" * keep
                mask = (1 << 192) - 1
            else:
                text = b"0" * q + b"." + b"0" * (keep - q)
                mask = (1 << (8 * q)) - 1
            text_word = int.from_bytes(text, "little")
            for w in range(3):
                before[w, code] = (mask >> (64 * w)) & ((1 << 64) - 1)
                chars[w, code] = (text_word >> (64 * w)) & ((1 << 64) - 1)
    return point, least * 18, word0, expo, before, chars


_POINT, _LEAST18, _WORD0, _EXPO, _BEFORE, _CHARS = _layout_tables()
_ZERO_WORD0 = _U(int.from_bytes(b"\0\0" + b"0.0", "little"))
_EXP_BITS, _MANT_BITS = _U(0x7FF0000000000000), _U(0x000FFFFFFFFFFFFF)
_MINUS = _U(ord("-") << 8)


def _digits_out(big_m: np.ndarray, e: np.ndarray, x: np.ndarray,
                out: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The 17-digit mantissas big_m with their decimal exponents e written as text into out
    ((n, WIDTH) uint8; made if None), sign included: (out, its uint64 words)."""
    big_m = big_m.view(np.uint64)
    # the 17 digits as three words (byte j = digit j, values 0-9)
    hi = big_m // _U(1_000_000_000)
    lo = big_m - hi * _U(1_000_000_000)
    lo1 = lo // _U(100_000_000)
    c = _eight(lo - lo1 * _U(100_000_000))
    b0 = _eight(hi)
    b1 = lo1 | (c << _U(8))
    b2 = c >> _U(56)
    # digits up to the last nonzero one: its byte from the float exponent of each word (the
    # bytes are digits, so a word is far from a power of 256 and the conversion is exact)
    top = np.maximum(np.maximum(b0.view(np.int64).astype(np.float64).view(np.int64) >> 52,
                                (b1.view(np.int64).astype(np.float64).view(np.int64) >> 52) + 64),
                     (b2.view(np.int64).astype(np.float64).view(np.int64) >> 52) + 128)
    xi = e + _XOFF
    code = np.maximum(((top - 1015) >> 3) * 18, _LEAST18[xi]) + _POINT[xi]
    # the digits before the point stay, the rest move one byte on (as one 192-bit number)
    out = np.empty((x.size, WIDTH), np.uint8) if out is None else out
    words = out.view(np.uint64)
    carried = None
    for i, b in enumerate((b0, b1, b2)):
        keep = b & _BEFORE[i][code]
        moved = b ^ keep
        w = keep | (moved << _U(8)) | _CHARS[i][code]
        if carried is not None:
            w |= carried >> _U(56)
        if i == 2:
            w |= _EXPO[xi]
        words[:, i + 1] = w
        carried = moved
    words[:, 0] = _WORD0[xi] | (x.view(np.uint64) >> _U(63)) * _MINUS
    return out, words


def _slots_chunk(x: np.ndarray, out: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """repr_slots of one cache-sized chunk, into out ((n, WIDTH) uint8) if given."""
    n = x.size
    a = np.abs(x)
    here = (a >= _LO) & (a <= _HI)              # finite, nonzero and in range: formatted here
    every = bool(here.all())
    # the rest formatted as 1.5 (not a power of two), replaced below
    az = a if every else np.where(here, a, 1.5)
    ef = np.floor(np.log10(az))
    idx = (16 - _KMIN - ef).astype(np.intp)     # 10^(16 - e)
    m17, d17, h = _mantissa(az, idx)
    e = ef.astype(np.int64)
    off = (m17 >= _INT10[17]) | (m17 < _INT10[16])
    if off.any():                                # log10 rounded across a power of ten: redo those
        fix = np.flatnonzero(off)
        e[fix] += (m17[fix] >= _INT10[17]).astype(np.int64) - (m17[fix] < _INT10[16])
        m17[fix], d17[fix], h[fix] = _mantissa(az[fix], 16 - _KMIN - e[fix])
        off[fix] = (m17[fix] >= _INT10[17]) | (m17[fix] < _INT10[16])
    # half the gaps to the neighbouring doubles in units of the 17th digit: 2^E (az's
    # exponent bits) * 2^-53 * 10^(16 - e); below is half as wide at a power of two
    bits = az.view(np.uint64)
    up = (bits & _EXP_BITS).view(np.float64) * h * 2.0 ** -53
    pow2 = (bits & _MANT_BITS) == 0
    if pow2.any():
        down = up * (1.0 - 0.5 * pow2)
    else:
        down, pow2 = up, None
    high = m17 // 100
    t, unsure = _shortest((m17 - high * 100).astype(np.float64), d17, up, down, pow2)
    big_m = high * 100 + t.astype(np.int64)
    carry = big_m >= _INT10[17]                  # 9.99..95 -> 10.0...: one more decade
    if carry.any():
        fix = np.flatnonzero(carry)
        big_m[fix] = _INT10[16]
        e[fix] += 1
    out, words = _digits_out(big_m, e, x, out)
    if every:
        finite = np.ones(n, bool)
    else:
        finite = np.isfinite(x)
        zero = np.flatnonzero(a == 0.0)
        words[zero, 0] = _ZERO_WORD0 | (x[zero].view(np.uint64) >> _U(63)) * _MINUS
        words[zero, 1:] = 0
        out[~finite] = 0
        unsure = (unsure & here) | (finite & ~here & (a != 0.0))
    # what could not be decided here: repr itself
    unsure |= off
    if unsure.any():
        slow = np.flatnonzero(unsure)
        out[slow] = 0
        for i in slow.tolist():
            text = repr(float(x[i])).encode()        # after byte 0, the separator's
            out[i, 1:1 + len(text)] = np.frombuffer(text, np.uint8)
    return out, finite


@contextlib.contextmanager
def heap_kept(pad: int = 16 << 20):
    """Keep `pad` bytes of freed memory in the C heap while formatting (glibc's M_TOP_PAD;
    elsewhere nothing). Why: a chunk's temporaries (~60 arrays of 64 kB) are freed at its
    end, glibc gives the top of the heap back to the system beyond 128 kB, and the next
    chunk faults every page in again: that took 40% of the time (71 against 124 ns a number,
    measured in consecutive runs). Restored when the outermost block ends."""
    global _kept, _mallopt
    with _kept_lock:
        if _mallopt is None:
            _mallopt = _find_mallopt()       # ctypes on first use: not at start-up
        if _kept == 0 and _mallopt:
            _mallopt(_M_TOP_PAD, pad)
        _kept += 1
    try:
        yield
    finally:
        with _kept_lock:
            _kept -= 1
            if _kept == 0 and _mallopt:
                _mallopt(_M_TOP_PAD, _DEFAULT_TOP_PAD)


def _find_mallopt():
    """glibc's mallopt, or False (another platform or C library)."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes
        f = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError, ImportError):
        return False
    f.argtypes, f.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return f


_M_TOP_PAD, _DEFAULT_TOP_PAD = -2, 128 * 1024      # glibc's malloc.h and mallopt(3)
_mallopt = None                                     # found on first use (False: none)
_kept = 0                                           # formatting calls under way (any thread)
_kept_lock = threading.Lock()


def repr_slots(x: np.ndarray, threads: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(slots, finite): slots[i] is repr(float(x[i])) in WIDTH uint8 slots, with 0 bytes
    where a slot is unused (drop them: slots.tobytes().translate(None, b"\\0")); byte 0 is
    always 0 (for a separator); non-finite elements get no characters, and finite is False
    there. Large arrays are done in cache-sized chunks, on `threads` threads if asked (the
    default is one: numpy releases the GIL in each loop, but a chunk's ~100 loops of 8192
    numbers hand the GIL back and forth so often that two threads took as long as one)."""
    x = np.asarray(x, dtype=np.float64).reshape(-1)
    if x.size <= CHUNK:
        return _slots_chunk(x)
    out = np.empty((x.size, WIDTH), np.uint8)
    finite = np.empty(x.size, dtype=bool)

    def run(a):
        finite[a:a + CHUNK] = _slots_chunk(x[a:a + CHUNK], out[a:a + CHUNK])[1]

    starts = range(0, x.size, CHUNK)
    threads = threads or 1
    with heap_kept():
        if threads > 1 and len(starts) > 2:
            from concurrent.futures import ThreadPoolExecutor
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(run, starts))
        else:
            for a in starts:
                run(a)
    return out, finite
