"""Crank angles from the command line without a list: `--range START:STOP:STEP` and
`--at-file FILE[:COLUMN]`. Every mistake is one line: a UsageError naming the option (--range),
or an InputError naming the file and line (--at-file).

--range is numpy's arange in degrees: START, START + STEP, ... up to STOP, STOP excluded
(0:360:30 is the 12 positions of a revolution, 360 = 0 not repeated). The angles are exact
decimal multiples: START + i STEP is computed in units of the smallest decimal place given,
so 0:1:0.1 gives 0.3 (as typed), not 0.30000000000000004.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from sheetkin.errors import InputError, UsageError
from sheetkin.files import MAX_AT_FILE_BYTES, read_text
from sheetkin.kinematics.caps import one_line
from sheetkin.kinematics.table import AngleRange

# --range and --at-file refuse more positions than this: 1e8 positions is ~40 GB of CSV
MAX_POSITIONS = 100_000_000
_MAX_DECIMALS = 9


def _decimal(text: str, what: str, spec: str):
    from decimal import Decimal, InvalidOperation
    try:
        d = Decimal(text.strip())
    except InvalidOperation:
        raise UsageError(f"--range {spec}: {what} {text!r} is not a number of degrees") from None
    if not d.is_finite():
        raise UsageError(f"--range {spec}: {what} {text!r} is not a finite number")
    # by its exponent alone, before any arithmetic: 1E+1000000 overflows the decimal context,
    # 1E-999999999 underflows to 0 (each was an internal error)
    if d and d.adjusted() >= 12:
        raise UsageError(f"--range {spec}: {what} {text!r}: expected a magnitude below 1e12 degrees")
    if d and d.adjusted() < -_MAX_DECIMALS:
        raise UsageError(f"--range {spec}: {what} {text!r}: at most {_MAX_DECIMALS} decimal places")
    return d


def parse_range(spec: str) -> AngleRange:
    """START:STOP:STEP in degrees, STOP excluded; refuses a step of 0, a step that never
    reaches STOP, and more than MAX_POSITIONS positions."""
    parts = spec.split(":")
    if len(parts) != 3:
        raise UsageError(f"--range {spec}: expected START:STOP:STEP in degrees, e.g. 0:360:0.5")
    start, stop, step = (_decimal(t, w, spec) for t, w in zip(parts, ("START", "STOP", "STEP"), strict=False))
    if step == 0:
        raise UsageError(f"--range {spec}: STEP is 0")
    decimals = max(0, *(-d.normalize().as_tuple().exponent for d in (start, stop, step)))
    if decimals > _MAX_DECIMALS:
        raise UsageError(f"--range {spec}: at most {_MAX_DECIMALS} decimal places")
    scale = 10 ** decimals
    first, last, delta = (int(d * scale) for d in (start, stop, step))
    count = -((first - last) // delta)                 # ceil((last - first) / delta)
    if count <= 0:
        raise UsageError(f"--range {spec}: no positions (STOP is excluded; with "
                         f"STEP {'> 0' if delta > 0 else '< 0'}, STOP must be "
                         f"{'above' if delta > 0 else 'below'} START)")
    if count > MAX_POSITIONS:
        raise UsageError(f"--range {spec}: {count:,} positions, more than {MAX_POSITIONS:,}")
    if max(abs(first), abs(first + delta * (count - 1))) >= 2 ** 53:
        raise UsageError(f"--range {spec}: angles too large for exact steps")
    return AngleRange(first, delta, scale, count)


def _number(text: str, where: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{where}: expected a number of degrees, got {text.strip()!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{where}: expected a finite number, got {text.strip()!r}")
    return v


def split_column(spec: str) -> tuple[Path, str | None]:
    """FILE or FILE:COLUMN (the file as given wins when it exists, so a ':' in a name works)."""
    if Path(spec).exists() or ":" not in spec:
        return Path(spec), None
    name, column = spec.rsplit(":", 1)
    return Path(name), column


def read_angles(spec: str) -> np.ndarray:
    """--at-file FILE (one angle a line; blank lines and lines starting with # skipped),
    or a CSV file with a header row: the column named COLUMN (FILE:COLUMN) or phi_1."""
    path, column = split_column(spec)
    try:
        text = read_text(path, MAX_AT_FILE_BYTES, "file of angles (--at-file)")
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected a file of angles") from None
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (--at-file)") from None
    except OSError as e:
        raise InputError(one_line(f"{path}: cannot read: {e.strerror or e}")) from None
    lines = text.splitlines()
    first = next((i for i, s in enumerate(lines) if s.strip() and not s.lstrip().startswith("#")), None)
    if first is None:
        raise InputError(f"{path}: no angles in the file")
    head = lines[first]
    is_number = re.fullmatch(r"\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*", head) is not None
    if column is None and is_number:
        return _one_a_line(path, lines)
    return _csv_column(path, lines, first, column)


def _one_a_line(path: Path, lines: list[str]) -> np.ndarray:
    keep = [i for i, s in enumerate(lines) if s.strip() and not s.lstrip().startswith("#")]
    _check_count(path, len(keep))
    texts = [lines[i] for i in keep]
    try:                                    # numpy parses a million lines in C
        values = np.array(texts, dtype=np.str_).astype(np.float64)
        if np.isfinite(values).all():
            return values
    except ValueError:
        pass
    for i, t in zip(keep, texts, strict=False):           # the first bad line, named
        _number(t, f"{path}:{i + 1}")
    raise InputError(f"{path}: unreadable angles")  # pragma: no cover (numpy refused, float() did not)


def _csv_column(path: Path, lines: list[str], first: int, column: str | None) -> np.ndarray:
    import csv
    import io
    rows = csv.reader(io.StringIO("\n".join(lines[first:])))
    header = [h.strip() for h in next(rows)]
    want = column or "phi_1"
    if want not in header:
        shown = ", ".join(header[:12]) + (" ..." if len(header) > 12 else "")
        hint = "" if column else "; name one as FILE:COLUMN"
        raise InputError(one_line(f"{path}:{first + 1}: no column {want!r} in the header ({shown}){hint}"))
    j = header.index(want)
    out = []
    for k, row in enumerate(rows):
        line = first + 2 + k
        if not row or not "".join(row).strip():
            continue
        if j >= len(row):
            raise InputError(f"{path}:{line}: no value in column {want!r} ({len(row)} fields)")
        out.append(_number(row[j], f"{path}:{line}"))
        if len(out) > MAX_POSITIONS:
            _check_count(path, len(out))
    if not out:
        raise InputError(f"{path}: no angles under the header's column {want!r}")
    return np.array(out)


def _check_count(path: Path, n: int):
    if n > MAX_POSITIONS:
        raise InputError(f"{path}: {n:,} angles, more than {MAX_POSITIONS:,}")
