"""Judging the student's check rows (issue 21, item 3): their statuses, which fail, which
were deleted or typed over, and how many of the issued ones apply to the variant."""
from __future__ import annotations

import itertools
import math

from sheetkin.messages import message
from sheetkin.sheet.checks import STATUS as CHECK_STATUS
from sheetkin.sheet.checks import failing as check_fails
from sheetkin.sheet.checks import not_applicable as check_na
from sheetkin.sheet.checks import passing as check_passes
from sheetkin.sheet.workbook import (
    FIRST_COL,
)
from sheetkin.xlsx.cells import Sheet
from sheetkin.xlsx.evaluator import Book

from .layout import VALUE_COL
from .localjudge import TURN, angle_difference
from .report_model import Report
from .rows import computes

# issue 31, item 4: every book grades by the rules of the version that issued it. The check
# rows each release added to the sheet (sheetkin/sheet/checks.py), by the release that added
# them: a book written by an older release never had them, so they are not "deleted" there.
# A book without a version mark (scene!C4) was written by 0.2.0 or earlier; 0.1.0 and 0.2.0
# wrote the same check rows (tests/data/issued/ holds books of both).
UNMARKED = "0.2.0"
CHECK_ROWS_ADDED: dict[str, frozenset[str]] = {}     # e.g. {"0.3.0": frozenset({"chk_..."})}


def _release(version: str) -> tuple[int, ...]:
    """(0, 2, 0) for "0.2.0" (a suffix such as ".dev1" or "rc1" is dropped); () unreadable."""
    parts = []
    for p in version.split(".")[:3]:
        digits = "".join(itertools.takewhile(str.isdigit, p))
        if not digits:
            break
        parts.append(int(digits))
    return tuple(parts)


def added_after(issued_by: str) -> frozenset[str]:
    """The check rows that releases later than `issued_by` added: not part of that book's
    work (a version newer than the running one, or unreadable, adds none)."""
    book = _release(issued_by or UNMARKED)
    if not book:
        return frozenset()
    return frozenset().union(*(rows for v, rows in CHECK_ROWS_ADDED.items() if _release(v) > book))


def read_checks(report: Report, evaluated: Book, main: str, sh: Sheet, names: dict[str, int], ref_rows,
                 ref_book: Book, ref_names: dict) -> None:
    """The student's check rows (issue 21, item 3): their statuses, which fail, which were
    deleted or typed over, and how many of the issued ones apply to the variant."""
    kinds = {r.name: r.kind for r in ref_rows}
    ref_sheet, positions = ref_book.order[0], report.positions
    # status 1 or an error fails; 0, n/a and "not filled in" do not (sheetkin/sheet/checks.py)
    # a status typed over its formula (a 0 typed to make the row green) says nothing: it
    # fails, as an error would (it once hid the failing checks and raised the score)
    statuses = {n: evaluated.value(main, r, VALUE_COL) if computes(sh, r, VALUE_COL) else "#TYPED"
                for n, r in names.items()
                if n.startswith(("chk", "fd_")) and kinds.get(n) in ("check", "fdcheck")}
    _turns_pass(statuses, evaluated, main, names, ref_rows, ref_book, ref_names, positions)
    # issue 21: the check rows are part of the work (the lecture's step 10): a check row
    # deleted, or its status typed over, loses its share of the grade
    later = added_after(report.issued_by)
    issued_checks = [r.name for r in ref_rows if r.kind in ("check", "fdcheck") and r.name not in later]
    statuses = {n: s for n, s in statuses.items() if n not in later}
    report.checks_issued = len(issued_checks)
    # the check rows that apply: those with a number at some position of the reference (the
    # others are "н/д" in every book of the variant: numeric derivatives above 3 deg ...)
    applying = {n for n in issued_checks if n in ref_names
                and any(isinstance(ref_book.value(ref_sheet, ref_names[n], FIRST_COL + k), float)
                        for k in range(positions))}
    report.checks_apply = len(applying)
    report.checks_deleted = [n for n in issued_checks if n not in names]
    report.checks_typed = [n for n, v in statuses.items() if v == "#TYPED"]
    if report.checks_typed:
        report.notes.append(message("check_status_typed_over", names=", ".join(report.checks_typed)))
    if report.checks_deleted:
        report.notes.append(message("check_rows_deleted_counted", names=", ".join(report.checks_deleted)))
    # deleted or typed over, a check row also counts as failing: hiding a failing check
    # must never pay (it costs its share and the failing check's points)
    report.failing_checks = [n for n, s in statuses.items() if check_fails(s)] + report.checks_deleted
    # not fields: grades count the checks that pass (0) of those that apply (not "н/д"), as the
    # sheet's summary does; "не заполнено" and "н/д" are not passing (an empty book passes none)
    # of those that apply only: a count never exceeds its total ("33 of 30 that apply")
    report.checks_passing = sum(check_passes(s) for n, s in statuses.items() if n in applying)
    report.checks_na = sum(check_na(s) for s in statuses.values())
    unfilled = {t["unfilled"] for t in CHECK_STATUS.values()}
    report.checks_unfilled = sum(isinstance(s, str) and s in unfilled for s in statuses.values())


def _turns_pass(statuses: dict, evaluated: Book, main: str, names: dict[str, int], ref_rows, ref_book: Book,
                ref_names: dict, positions: int) -> None:
    """A check row of an angle (chk_Fi: Fi - (Fi0 + i Delta_Fi), in radians) whose status
    fails only because its residuals are whole turns (Fi taken MOD 2*PI()) passes: angles are
    compared modulo a full turn everywhere else, so the check is judged the same way (its
    residuals within the sheet's Tol of a multiple of the turn, numbers where the reference
    has numbers). Sets the status to 0 in `statuses`."""
    units = {r.name: r.unit for r in ref_rows}
    tol = evaluated.value(main, names["Tol"], VALUE_COL) if "Tol" in names else None
    tol = tol if isinstance(tol, float) and not isinstance(tol, bool) and math.isfinite(tol) and tol >= 0 else 1e-9
    ref_sheet = ref_book.order[0]
    for n, status in statuses.items():
        period = TURN.get(units.get(n, ""))
        if not period or not check_fails(status) or status == "#TYPED" or n not in ref_names:
            continue
        cells = [(evaluated.value(main, names[n], FIRST_COL + k),
                  ref_book.value(ref_sheet, ref_names[n], FIRST_COL + k)) for k in range(positions)]
        if all(isinstance(v, float) and float(angle_difference(abs(v), period)) <= tol if isinstance(e, float)
               else not isinstance(v, float) for v, e in cells):
            statuses[n] = 0.0
