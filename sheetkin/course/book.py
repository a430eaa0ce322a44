"""The issued book as sheetkin reads it back: the scene embedded in its hidden sheet (with
caps on its size), the student's identity cells, the book's language, the student's sheets
evaluated."""
from __future__ import annotations

import re

from sheetkin.errors import InputError
from sheetkin.kinematics.scene import Scene, SceneError, parse_scene
from sheetkin.messages import message
from sheetkin.sheet.charts import PATHS_SHEET, PLOTTED_SHEET
from sheetkin.sheet.workbook import (
    SCENE_SHEET,
    SHEET_TITLES,
    embedded_scene_text,
)
from sheetkin.xlsx.evaluator import Book, evaluate_sheets
from sheetkin.xlsx.functions import NAME as NAME_ERROR

from . import issued
from .caches import scene_rows
from .layout import VALUE_COL, without_unread

# Caps on the scene embedded in a book, for validation (docs/reliability.md): the course's
# scenes have 1-3 groups and 0-3 points; a reference of rows x positions cells is built
# and evaluated for each variant, so these bound a book's work whatever its scene sheet says.
MAX_EMBEDDED_GROUPS = 12
MAX_EMBEDDED_POINTS = 40
MAX_REFERENCE_CELLS = 1_000_000


def check_embedded_size(scene_text: str, path: str) -> None:
    """Count the tables before parsing (a 400-group scene sheet took minutes to read)."""
    heads = re.findall(r"(?m)^\s*\[\[\s*(group|point)\s*\]\]", scene_text)
    for kind, cap in (("group", MAX_EMBEDDED_GROUPS), ("point", MAX_EMBEDDED_POINTS)):
        n = heads.count(kind)
        if n > cap:
            raise UnusableInput(f"{path}: the embedded scene has {n} [[{kind}]] tables; a book "
                                f"sheetkin validates may have at most {cap}")


def check_embedded_scene(scene: Scene, path: str) -> None:
    rows = len(scene_rows(scene))
    cells = rows * scene.crank.positions
    if cells > MAX_REFERENCE_CELLS:
        raise UnusableInput(f"{path}: the embedded scene needs a reference of {rows:,} rows x "
                            f"{scene.crank.positions:,} positions = {cells:,} cells; sheetkin validates "
                            f"books of at most {MAX_REFERENCE_CELLS:,}")


class UnusableInput(InputError):
    """A workbook that cannot be validated at all; str() is one line naming the file."""


def embedded_scene(book, path: str, options: issued.Options | None) -> tuple[Scene, str]:
    """The scene of the book's hidden sheet, and its text."""
    if SCENE_SHEET not in book.sheets:
        raise UnusableInput(f"{path}: " + message("no_embedded_scene", sheet=SCENE_SHEET))
    scene_text = embedded_scene_text(book.sheets[SCENE_SHEET])
    check_embedded_size(scene_text, path)
    try:
        scene = parse_scene(scene_text, f"{path} (embedded scene)")
    except SceneError as e:
        # an issued book whose hidden sheet was edited until it no longer reads: say so
        # (the seal) rather than only the line that does not parse
        vid, found = issued.marks(book.sheets[SCENE_SHEET].consts)
        broken = issued.seal_status(options.key if options else None, vid, scene_text, found) if vid else ""
        if broken in (message("seal_missing"), message("seal_mismatch")):
            raise UnusableInput(f"{path}: " + message("no_longer_reads", what=broken) + str(e)) from e
        raise
    check_embedded_scene(scene, path)
    return scene, scene_text


TITLE_AT = (1, 5)       # E1: the scheme's title (sheetkin.sheet.workbook.TITLE_CELL)


def book_lang(sheet_title: str) -> str:
    """The language a book was written in, told by its first sheet's title; ru otherwise."""
    return next((lang for lang, (kin, _) in SHEET_TITLES.items() if kin == sheet_title), "ru")


def identity_text(evaluated, main: str, sh, row: int | None) -> str:
    """The student's own name or group cell as text; a formula typed there that sheetkin
    cannot compute (=HYPERLINK(...)) is what the spreadsheet saved, not "#NAME?"."""
    if row is None:
        return ""
    v = evaluated.value(main, row, VALUE_COL)
    at = (row, VALUE_COL)
    if sh.computed(*at) and evaluated.tag[main][at] == NAME_ERROR and at in sh.cached:
        v = sh.cached[(row, VALUE_COL)]
    return _text(v)


def _text(v) -> str:
    """A typed identity cell as text (a group typed as a number: 101.0 -> "101")."""
    if v is None or isinstance(v, bool):
        return ""
    if isinstance(v, float):
        return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)
    return " ".join(str(v).split())[:200]


def evaluate_student(raw, layout=None) -> Book:
    # the charts' hidden `paths` and `plotted` sheets (360 positions of the coordinates; the
    # plotted rows as numbers or #N/A) are not graded and nothing on the kinematics sheet
    # refers to them: leaving them out halves the work
    sheets = {n: sh for n, sh in raw.sheets.items() if n not in (PATHS_SHEET, PLOTTED_SHEET)}
    if layout is not None:        # cells no formula can read, outside the table: not evaluated
        sheets = without_unread(sheets, raw.names, layout, {SCENE_SHEET})
    return evaluate_sheets(raw.path, sheets, [n for n in raw.order if n in sheets], raw.names, strict=False)


# The reference of a variant is the workbook sheetkin generates for it, evaluated. Only the
# input block (column D of the input rows) differs between variants of one mechanism with
# the same number of positions: the generated sheet is kept per structure (its rows'
# names, kinds and formulas, and the positions), and each variant's reference is that
# sheet with the variant's inputs, evaluated (the evaluator keeps the parsed formulas).
