"""`sheetkin validate FILES --grades grades.csv`: one line per submission, for the teacher
and for Moodle's gradebook import (Grades > Import > CSV file).

The score of a submission (README, "Running a class" > "Grades"):
    100 * rows correct / rows graded  -  CHECK_PENALTY per failing check row of the sheet,
    at least 0, to one decimal;
    0 when the given data differ from the issued variant (unless --accept-changed-inputs),
    when the workbook's seal fails (the hidden scene sheet edited), or when the file is
    unusable (the reason is in the "likely causes" column).
A possible copy (sheetkin/course/copies.py) does not change the score: it is flagged for the
teacher, who decides.

Moodle's CSV import maps one column to a user field (userid, username, useridnumber or
useremail: a name cannot identify a user) and one column to a grade item; it reads UTF-8
(a byte-order mark is removed), comma-separated, a header row, "." as the decimal point.
The identifier comes from a class list (`--class-list`, Moodle's participants or grades
export), matched to the name the student typed in their workbook; the other columns are
for the teacher and are ignored at import. Text cells that a spreadsheet would take for a
formula ("=", "+", "-", "@", tab, CR first) get a leading apostrophe (OWASP's advice for
CSV injection), so a student named "=cmd|..." stays text in Excel.
"""
from __future__ import annotations

import csv
import io
import os

# the class list is read and matched in sheetkin/course/classlist.py (Russian name forms,
# Moodle's folders); its names stay importable from here
from .classlist import ClassList, name_key, read_class_list  # noqa: F401
from .classlist import ClassListError as GradesError  # noqa: F401 (--grades, --class-list: one line)

CHECK_PENALTY = 2.0        # points off per failing check row (the sheet showed the mistake)
ID_HEADERS = ("Email address", "ID number", "Username")      # Moodle's export names them so
COLUMNS = ("student", "group", "variant", "file", "rows correct", "rows total", "checks passing",
           "checks total", "given data changed", "likely causes", "possible copy of", "score", "identity")
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")




def safe_text(text: object) -> str:
    """A CSV cell a spreadsheet keeps as text: an apostrophe before a leading =, +, -, @,
    tab or carriage return (Excel and LibreOffice hide it and show the text)."""
    s = "" if text is None else str(text)
    return "'" + s if s.startswith(_FORMULA_START) else s


def rows_correct(rep) -> tuple[int, int]:
    """(rows correct, rows graded): every computed row the reference has, except those the
    exercise gives filled in (phi_1, the guards): an empty exercise scores 0."""
    from sheetkin.sheet.workbook import prefilled_in_exercise
    graded = [r for r in rep.rows if not prefilled_in_exercise(r.name, r.kind)]
    return sum(r.status == "correct" for r in graded), len(graded)


def checks_counts(rep) -> tuple[int | None, int | None]:
    """(check rows passing, check rows that apply); None where unknown (unusable).

    Passing is a status 0 (green) only: "не заполнено" is not passing (an empty exercise
    passes no check), and "н/д" rows (numeric derivatives above 3 deg) are not counted."""
    total = getattr(rep, "checks_total", None)
    if rep.error or total is None:
        return None, None
    passing = getattr(rep, "checks_passing", None)
    if passing is None:                         # a report made without the statuses
        return max(0, total - len(rep.failing_checks)), total
    return passing, total - getattr(rep, "checks_na", 0)


def given_changed(rep, accept_changed: bool = False) -> bool:
    return bool(getattr(rep, "given_changed", None)) and not accept_changed


def seal_failed(rep) -> bool:
    return getattr(rep, "seal", "") not in ("", "ok", None)


def score(rep, accept_changed: bool = False) -> float:
    """The documented score (module docstring), 0..100, one decimal."""
    if rep.error or given_changed(rep, accept_changed) or seal_failed(rep):
        return 0.0
    correct, total = rows_correct(rep)
    if total == 0:
        return 0.0
    s = 100.0 * correct / total - CHECK_PENALTY * len(rep.failing_checks)
    return round(max(0.0, s), 1)


def who(rep) -> str:
    """The student as they named themselves (their own cell; A2 is the scheme's author)."""
    return str(getattr(rep, "student", "") or "")


def copy_text(reports, i: int, copies) -> str:
    """'b.xlsx (Petrov), c.xlsx and 3 more: byte-identical files; ...' for report i: at
    most MAX_LISTED others of its cluster (sheetkin/course/copies.py), a line stays short."""
    from .copies import MAX_LISTED
    others = copies.others(i) if hasattr(copies, "others") else []
    if not others:
        return ""
    names = [f"{reports[j].path}{f' ({who(reports[j])})' if who(reports[j]) else ''}" for j in others[:MAX_LISTED]]
    more = f" and {len(others) - MAX_LISTED} more" if len(others) > MAX_LISTED else ""
    return f"{', '.join(names)}{more}: {copies.why(i)}"


def causes_text(rep) -> str:
    if rep.error:
        return "unusable: " + rep.reason
    return ";".join(c.name for c in rep.causes)


# --------------------------------------------------------------------------- grades.csv
def grade_lines(reports, copies, class_list: ClassList | None = None,
                accept_changed: bool = False, identities: list | None = None) -> tuple[list[list[str]], list[str]]:
    """The header and one line per graded report (in their order), and warnings: the
    students the class list does not name, the older files of a student (not graded: one
    grade per Moodle user), the books handed in by someone other than their student.
    identities: sheetkin.course.identity.identify's (made here from class_list if None)."""
    from .identity import identify
    if identities is None:
        identities = identify(reports, class_list)
    id_header = class_list.id_header if class_list else ID_HEADERS[0]
    lines, unmatched, older, flagged = [[id_header, *COLUMNS]], [], [], []
    for i, rep in enumerate(reports):
        me = identities[i]
        if me.superseded_by is not None:
            older.append(f"{rep.path} (newer: {reports[me.superseded_by].path})")
            continue
        student = who(rep)
        if class_list is not None and not me.ident:
            unmatched.append(f"{rep.path} ({me.unmatched or 'no name typed'})")
        if me.flags and any(f.startswith(("issued to", "found in")) for f in me.flags):
            flagged.append(f"{rep.path}: {'; '.join(f for f in me.flags if f.startswith(('issued to', 'found in')))}")
        correct, total = rows_correct(rep)
        passing, checks = checks_counts(rep)
        lines.append([me.ident if class_list is not None else "", safe_text(student),
                      safe_text(getattr(rep, "group", "") or ""),
                      safe_text(getattr(rep, "variant", "") or ""), safe_text(rep.path),
                      "" if rep.error else str(correct), "" if rep.error else str(total),
                      "" if passing is None else str(passing), "" if checks is None else str(checks),
                      "yes" if given_changed(rep) else "no",             # a fact, accepted or not
                      safe_text(causes_text(rep)), safe_text(copy_text(reports, i, copies)),
                      f"{score(rep, accept_changed):.1f}", safe_text("; ".join(me.flags))])
    warnings = []

    def listed(items: list[str]) -> str:
        return ", ".join(items[:10]) + (" ..." if len(items) > 10 else "")
    if class_list is None:
        warnings.append(f"no --class-list: the column '{id_header}' is empty; Moodle identifies a student "
                        "by it, not by name (fill it in, or give Moodle's participants export as --class-list)")
    elif unmatched:
        warnings.append(f"{len(unmatched)} submission(s) not found (or found twice) in the class list, their "
                        f"'{id_header}' left empty: " + listed(unmatched))
    if older:
        warnings.append(f"one grade per student: {len(older)} older file(s) not graded: " + listed(older))
    if flagged:
        warnings.append(f"{len(flagged)} book(s) not handed in by their own student: " + listed(flagged))
    return lines, warnings


def grades_csv(lines: list[list[str]]) -> bytes:
    """UTF-8 with a byte-order mark (Excel then reads Cyrillic right; Moodle removes it),
    comma-separated, CRLF (RFC 4180), quoted where needed."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\r\n").writerows(lines)
    return ("\ufeff" + buf.getvalue()).encode("utf-8")


def check_writable(path: str) -> None:
    """Before validating a class: a --grades path whose folder is missing or read-only is
    one line now, not after minutes of work."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise OSError(2, "No such file or directory (the folder does not exist)", path)
    if os.path.isdir(path):
        raise OSError(21, "Is a directory", path)
    exists = os.path.exists(path)
    if exists and not os.access(path, os.W_OK):
        raise OSError(13, "Permission denied", path)
    # a regular file is written beside its final name, in its folder (a device as it is)
    if (not exists or os.path.isfile(path)) and not os.access(folder, os.W_OK):
        raise OSError(13, "Permission denied (its folder is read-only)", path)


def write_grades(path: str, data: bytes) -> None:
    """Written beside its final name and renamed when complete (sheetkin.views.output): a failure
    leaves an existing file as it was; an OSError names `path`."""
    from sheetkin.views.output import _Target
    target = None
    try:
        target = _Target(path)
        target.file.write(data)
        target.commit()
    except OSError as e:
        if target is not None:
            target.abandon()
        raise OSError(e.errno, e.strerror or str(e), path) from None
