"""Three spreadsheet engines on one book: sheetkin's evaluator, LibreOffice and Gnumeric.

`formula_values` reads what each engine computed for every formula cell of a workbook; the
differential tests (tests/xlsx/test_three_engines.py) compare them cell by cell. Gnumeric
recalculates with `ssconvert --recalc in.xlsx out.xlsx`, one process per book (it takes one
input file); LibreOffice with one soffice run for all books (sheetkin.xlsx.libreoffice).
"""
from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import openpyxl

from helpers.libreoffice import is_error

GNUMERIC_HINT = "Gnumeric (ssconvert) not found: run `bash tests/setup.sh` (as root, Debian/Ubuntu)"


def ssconvert_path() -> str | None:
    """Gnumeric's ssconvert on PATH, or None."""
    return shutil.which("ssconvert")


def gnumeric_recalc(path: Path, outdir: Path, timeout: float = 120) -> Path:
    """`path` recalculated by Gnumeric and saved as xlsx in `outdir` (same name)."""
    exe = ssconvert_path()
    if exe is None:
        raise RuntimeError(GNUMERIC_HINT)
    outdir.mkdir(parents=True, exist_ok=True)
    out = outdir / Path(path).name
    if out.resolve() == Path(path).resolve():
        raise ValueError(f"output would overwrite its input: {path}")
    out.unlink(missing_ok=True)
    res = subprocess.run([exe, "--recalc", str(path), str(out)], capture_output=True, text=True,
                         timeout=timeout, stdin=subprocess.DEVNULL)
    if res.returncode != 0 or not out.is_file():
        raise RuntimeError(f"ssconvert --recalc {path} failed ({res.returncode}):\n{res.stdout}{res.stderr}")
    return out


def formula_cells(path: Path) -> dict[tuple[str, str], str]:
    """{(sheet, coordinate): formula} of every formula cell of the book as written."""
    wb = openpyxl.load_workbook(path, read_only=False)
    try:
        return {(ws.title, c.coordinate): c.value for ws in wb.worksheets for row in ws.iter_rows()
                for c in row if c.data_type == "f"}
    finally:
        wb.close()


def cached_values(path: Path, cells) -> dict[tuple[str, str], object]:
    """The cached values a recalculated book holds in `cells` (None: empty or "")."""
    wb = openpyxl.load_workbook(path, data_only=True)
    try:
        return {(s, a): wb[s][a].value for s, a in cells}
    finally:
        wb.close()


def evaluator_values(path: Path, cells) -> dict[tuple[str, str], object]:
    """What sheetkin's own evaluator computes in `cells` ("" as None, like a cached value)."""
    from openpyxl.utils.cell import column_index_from_string, coordinate_from_string

    from sheetkin.xlsx.evaluator import evaluate
    book = evaluate(path)
    out = {}
    for s, a in cells:
        col, row = coordinate_from_string(a)
        v = book.value(s, row, column_index_from_string(col))
        out[(s, a)] = None if v == "" else v
    return out


def normal(v: object) -> object:
    """A value as the comparison sees it: every error is "an error" (the engines name some
    differently, see sheetkin.xlsx.libreoffice), booleans stay booleans, "" is empty."""
    if is_error(v):
        return "#ERROR"
    if v == "":
        return None
    return v


def same(a: object, b: object, rel: float = 1e-9, abs_: float = 1e-12) -> bool:
    """Whether two engines' values of one cell agree: numbers to `rel` (LibreOffice writes 15
    significant digits; Gnumeric 17) or `abs_` near zero, anything else exactly."""
    a, b = normal(a), normal(b)
    num = (int, float)
    if isinstance(a, num) and isinstance(b, num) and not isinstance(a, bool) and not isinstance(b, bool):
        return math.isclose(a, b, rel_tol=rel, abs_tol=abs_)
    return a == b


def differences(formulas: dict, engines: dict[str, dict], limit: int = 20) -> list[str]:
    """One line per formula cell where the engines disagree (at most `limit`)."""
    names = list(engines)
    out = []
    for key, f in formulas.items():
        first = engines[names[0]][key]
        if all(same(first, engines[n][key]) for n in names[1:]):
            continue
        vals = ", ".join(f"{n} {engines[n][key]!r}" for n in names)
        out.append(f"{key[0]}!{key[1]} {f[:80]}: {vals}")
        if len(out) >= limit:
            break
    return out
