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
import re
from dataclasses import dataclass

from sheetkin.files import MAX_CLASS_LIST_BYTES, read_text

CHECK_PENALTY = 2.0        # points off per failing check row (the sheet showed the mistake)
ID_HEADERS = ("Email address", "ID number", "Username")      # Moodle's export names them so
COLUMNS = ("student", "group", "variant", "file", "rows correct", "rows total", "checks passing",
           "checks total", "given data changed", "likely causes", "possible copy of", "score")
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


class GradesError(ValueError):
    """A problem with --grades or --class-list: one line naming the file."""


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


def copy_text(reports, i: int, copies: dict) -> str:
    """'b.xlsx (Petrov): byte-identical files; c.xlsx: ...' for report i."""
    out = []
    for j, why in copies.get(i, []):
        name = who(reports[j])
        out.append(f"{reports[j].path}{f' ({name})' if name else ''}: {why}")
    return "; ".join(out)


def causes_text(rep) -> str:
    if rep.error:
        return "unusable: " + rep.reason
    return ";".join(c.name for c in rep.causes)


# --------------------------------------------------------------------------- the class list
@dataclass
class ClassList:
    id_header: str                       # Moodle's name of the identifier column
    ids: dict                            # name key -> identifier
    ambiguous: set                       # name keys of two people or more


_NAME_HEADERS = {"first": ("first name", "имя"), "last": ("last name", "surname", "фамилия"),
                 "full": ("full name", "student", "фио", "студент")}
_ID_ALIASES = {"Email address": ("email address", "email", "e-mail", "адрес электронной почты"),
               "ID number": ("id number", "idnumber", "индивидуальный номер", "идентификационный номер"),
               "Username": ("username", "логин", "имя пользователя")}


def name_key(text: str) -> frozenset:
    """A name in any word order, case, with or without commas, ё as е: 'Иванов, Иван' ==
    'иван иванов'."""
    words = re.findall(r"[^\W\d_]+(?:[-'][^\W\d_]+)*", str(text).casefold().replace("ё", "е"))
    return frozenset(words)


def read_class_list(path: str) -> ClassList:
    """The teacher's list of students: a CSV file with a header, its name columns ("First
    name" and "Last name"/"Surname", or "Full name") and an identifier column ("Email
    address", "ID number" or "Username"), as Moodle exports them; comma, semicolon or tab."""
    try:
        text = read_text(path, MAX_CLASS_LIST_BYTES, "class list")
    except UnicodeDecodeError as e:
        raise GradesError(f"{path}: --class-list: not UTF-8 text (byte {e.start}); save it as CSV UTF-8") from None
    first = text.split("\n", 1)[0]
    delim = max((",", ";", "\t"), key=first.count)
    try:
        rows = list(csv.reader(io.StringIO(text), delimiter=delim))
    except csv.Error as e:
        raise GradesError(f"{path}: --class-list: not a CSV file this reads ({e})") from None
    if not rows:
        raise GradesError(f"{path}: --class-list: empty; expected a header and one line per student")
    head = [h.strip().casefold() for h in rows[0]]

    def column(aliases):
        return next((k for k, h in enumerate(head) if h in aliases), None)
    id_header, id_col = next(((h, column(a)) for h, a in _ID_ALIASES.items() if column(a) is not None), (None, None))
    first_col, last_col, full_col = (column(_NAME_HEADERS[k]) for k in ("first", "last", "full"))
    if id_col is None or (full_col is None and (first_col is None or last_col is None)):
        raise GradesError(f"{path}:1: --class-list: expected columns 'First name' and 'Last name' (or "
                          f"'Full name') and one of {', '.join(repr(h) for h in ID_HEADERS)}; got "
                          f"{', '.join(repr(h) for h in rows[0])}")
    ids, ambiguous = {}, set()
    for line, row in enumerate(rows[1:], 2):
        if not any(c.strip() for c in row):
            continue

        def cell(k):
            return row[k].strip() if k is not None and k < len(row) else ""
        name = cell(full_col) if full_col is not None else f"{cell(first_col)} {cell(last_col)}"
        key, ident = name_key(name), cell(id_col)
        if not key or not ident:
            raise GradesError(f"{path}:{line}: --class-list: a line without a name or a {id_header}")
        if key in ids and ids[key] != ident:
            ambiguous.add(key)
        ids[key] = ident
    return ClassList(id_header, ids, ambiguous)


# --------------------------------------------------------------------------- grades.csv
def grade_lines(reports, copies: dict, class_list: ClassList | None = None,
                accept_changed: bool = False) -> tuple[list[list[str]], list[str]]:
    """The header and one line per report (in their order), and warnings (students the
    class list does not name)."""
    id_header = class_list.id_header if class_list else ID_HEADERS[0]
    lines, unmatched = [[id_header, *COLUMNS]], []
    for i, rep in enumerate(reports):
        student = who(rep)
        ident = ""
        if class_list is not None:
            key = name_key(student)
            ident = "" if key in class_list.ambiguous else class_list.ids.get(key, "")
            if not ident:
                unmatched.append(f"{rep.path} ({student or 'no name typed'})")
        correct, total = rows_correct(rep)
        passing, checks = checks_counts(rep)
        lines.append([ident, safe_text(student), safe_text(getattr(rep, "group", "") or ""),
                      safe_text(getattr(rep, "variant", "") or ""), safe_text(rep.path),
                      "" if rep.error else str(correct), "" if rep.error else str(total),
                      "" if passing is None else str(passing), "" if checks is None else str(checks),
                      "yes" if given_changed(rep) else "no",             # a fact, accepted or not
                      safe_text(causes_text(rep)), safe_text(copy_text(reports, i, copies)),
                      f"{score(rep, accept_changed):.1f}"])
    warnings = []
    if class_list is None:
        warnings.append(f"no --class-list: the column '{id_header}' is empty; Moodle identifies a student "
                        "by it, not by name (fill it in, or give Moodle's participants export as --class-list)")
    elif unmatched:
        warnings.append(f"{len(unmatched)} submission(s) not found (or found twice) in the class list, their "
                        f"'{id_header}' left empty: " + ", ".join(unmatched[:10]) + (" ..." if len(unmatched) > 10 else ""))
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
    """Written beside its final name and renamed when complete (sheetkin.files): a failure
    leaves an existing file as it was; an OSError names `path`."""
    from sheetkin.files import write_file  # also an interruption leaves no temporary file
    try:
        write_file(path, data)
    except OSError as e:
        raise OSError(e.errno, e.strerror or str(e), path) from None
