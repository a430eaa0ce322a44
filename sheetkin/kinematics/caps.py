"""Scene files' generic limits: the caps on what a TOML scene may hold and the checks that
apply to every value whatever its key (`sheetkin docs mechanisms`, "Caps").

`load_toml` reads the text (every tomllib failure one SceneError line), `check_values`
walks the document once, iteratively, and refuses NaN and inf, magnitudes above
MAX_MAGNITUDE (400-digit integers included), control characters and overlong text, and
nesting deeper than MAX_DEPTH; `one_line` and `shown` make any text or value fit a one-line
message. sheetkin.kinematics.scene does the per-key checks.
"""
from __future__ import annotations

import math
import re
import reprlib
from typing import Any

from sheetkin.errors import InputError

# Caps on what a scene may hold (`sheetkin docs mechanisms`, "Caps"); a file past them gets one line.
# Magnitudes: a kinematic chain multiplies up to about six of its numbers (mass x length x
# omega^2 x velocity ...), so 1e12 keeps every product far below float overflow (1e308)
# while no real mechanism (metres, rad/s, kg) comes near it.
MAX_MAGNITUDE = 1e12
MAX_POSITIONS = 100_000_000      # compute: 1e8 crank positions (streamed output is linear)
WORKBOOK_MAX_POSITIONS = 16_380  # Excel's 16,384 columns (XFD) less the label columns A-D
MAX_DEPTH = 8                    # arrays/tables inside each other (a scene needs 3)
MAX_SCENE_BYTES = 8_000_000      # a scene is a few KB; 20,000 [[point]]s are about 2 MB
MAX_LINE = 10_000                # characters of one line of the file
MAX_TEXT = 1000                  # characters of one string (a title, a name)
MAX_MESSAGE = 300                # characters of a value shown in an error line


class SceneError(InputError):
    """A scene file that cannot be used; str() is one line naming file, line and key."""


def one_line(text: object, limit: int = 2 * MAX_MESSAGE) -> str:
    """`text` fit for a one-line message: control characters escaped (a quoted TOML key
    or a path may hold a newline), cut to `limit` characters."""
    s = str(text)
    if not s.isprintable():
        s = "".join(c if c.isprintable() else repr(c)[1:-1] for c in s)
    return s if len(s) <= limit else s[:limit - 3] + "..."


def shown(value) -> str:
    """repr of a scene value for a message, short (a 20,000-number array, a 400-digit
    integer) and one line."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10 ** 30:
        try:
            return f"an integer of {len(str(abs(value)))} digits"
        except ValueError:      # past sys.get_int_max_str_digits()
            return f"an integer of about {int(abs(value).bit_length() * math.log10(2)) + 1} digits"
    return one_line(_REPR.repr(value), MAX_MESSAGE)


_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxdict, _REPR.maxstring, _REPR.maxother = 3, 8, 8, 60, 60
_REPR.maxlong = 40


_LONG_LINE = re.compile(rf"^[^\n]{{{MAX_LINE + 1}}}", re.M)


def load_toml(text: str, source: str = "<scene>") -> dict:
    """tomllib.loads, with every failure one SceneError line: invalid TOML (with its line),
    an integer too long to read, or arrays/inline tables nested past Python's recursion
    limit (tomllib recurses once per level). Lines longer than MAX_LINE are refused first:
    tomllib's time grows with the square of a dotted key's length (a header of 20,000
    dotted parts takes seconds)."""
    import tomllib  # here: the command line imports the caps, not always a scene
    long_line = _LONG_LINE.search(text)
    if long_line:
        no = text.count("\n", 0, long_line.start()) + 1
        raise SceneError(f"{one_line(source)}:{no}: a line of more than {MAX_LINE:,} characters; "
                         "a scene's lines are short (split long arrays over several lines)")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(e))
        msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(e))
        where = f"{source}:{m.group(1)}" if m else source
        if m and "overwrite" in msg.lower():
            # tomllib says "Cannot overwrite a value": name the key written twice
            line = text.splitlines()[int(m.group(1)) - 1]
            k = re.match(r"^\s*\[*\s*([A-Za-z0-9_.\"-]+)", line)
            if k:
                raise SceneError(one_line(f"{where}: key '{k.group(1)}' is defined twice (not valid TOML)")) from None
        raise SceneError(one_line(f"{where}: not valid TOML: {msg}")) from None
    except RecursionError:
        raise SceneError(one_line(f"{source}: arrays or inline tables nested too deep to read; a scene "
                                  f"nests at most {MAX_DEPTH} levels")) from None
    except ValueError as e:
        # int() of more than 4300 digits (sys.get_int_max_str_digits)
        m = re.search(r"[0-9_]{1000,}", text)
        where = f"{source}:{text.count(chr(10), 0, m.start()) + 1}" if m else source
        raise SceneError(one_line(f"{where}: a number of thousands of digits; numbers in a scene are "
                                  f"at most {MAX_MAGNITUDE:g} in magnitude ({e})", MAX_MESSAGE)) from None


def _control_char(text: str) -> str:
    """The first control character of `text` (the caller found one)."""
    found = _CONTROL_RE.search(text)
    return found.group() if found else ""


def check_values(data: dict, fail_at) -> None:
    """Every value of the document, whatever its key: finite, |x| <= MAX_MAGNITUDE, text
    without control characters, at most MAX_TEXT characters, nesting at most MAX_DEPTH.
    Iterative, so no document reaches the recursion limit; runs before the typed getters,
    which can then convert any number to float (a 400-digit integer would raise
    OverflowError). One pass, a few type tests per value (20,000 [[point]]s: 0.1 s).
    `fail_at(path, message)` raises the error for the value at `path` (keys and indices)."""
    big = MAX_MAGNITUDE
    stack: list[tuple[Any, tuple[str | int, ...]]] = [(data, ())]
    while stack:
        node, path = stack.pop()
        for k, v in (node.items() if type(node) is dict else enumerate(node)):
            t = type(v)
            if t is float or t is int:
                if -big <= v <= big:            # False for NaN
                    continue
                if t is float and not math.isfinite(v):
                    bad = f"expected a finite number, got {v!r}"
                else:
                    bad = (f"{shown(v)} is too large: numbers in a scene are at most {big:g} in "
                           "magnitude (metres, degrees, rad/s, kg, N)")
            elif t is str:
                if len(v) <= MAX_TEXT and (v.isprintable() or not _CONTROL_RE.search(v)):
                    continue
                if len(v) > MAX_TEXT:
                    bad = f"text of {len(v):,} characters; expected at most {MAX_TEXT:,}"
                else:
                    bad = (f"text with a control character ({_control_char(v)!r}) in "
                           f"{shown(v)}; expected one line of printable text")
            elif t is dict or t is list:
                if len(path) + 1 >= MAX_DEPTH:
                    bad = f"nested deeper than {MAX_DEPTH} levels of arrays and tables"
                else:
                    if t is dict:
                        for key in v:
                            if not key.isprintable() and _CONTROL_RE.search(key):
                                fail_at(path + (k, key), "a key with a control character")
                    stack.append((v, path + (k,)))
                    continue
            else:                   # booleans, dates: the typed getters say what they expected
                continue
            fail_at(path + (k,), bad)


_CONTROL_RE = re.compile(r"[\x00-\x08\x0a-\x1f\x7f-\x9f\u2028\u2029]")   # tab is allowed
