"""`sheetkin validate FILES --grades grades.csv`: one line per submission, for the teacher
and for Moodle's gradebook import (Grades > Import > CSV file).

The score of a submission (`sheetkin docs grading`), 0..100 to one decimal:
    ROWS_SHARE (90) x rows computed right / rows graded
  + CHECKS_SHARE (10) x check rows intact and filled in / check rows issued
  - CHECK_PENALTY (2) per check row of the sheet that fails, at least 0;
  * a row is computed right when every cell holds a formula (or an array formula's value)
    that reaches the given data through formulas (sheetkin.xlsx.precedents) and equals the
    reference; a cell with a typed value and no formula, or a formula reading only typed
    numbers, earns nothing, whatever its value ("typed, not computed"), unless the teacher
    gives --accept-typed (then a typed number right to its last digit counts as right);
    the derived values of column D (Alfa_A ...) are graded rows of one cell;
  * a check row earns its share when it is there with its status formula and the rows it
    checks are filled in (its status is not "не заполнено"): deleted, its status typed over,
    or checking empty rows, it does not; deleted or typed over, it also counts as failing
    (hiding a failing check never pays);
  * a book with no formula in its computed rows scores at most NO_FORMULA_CAP (10) and fails;
  * 0 when the given data differ from the issued variant (unless --accept-changed-inputs),
    when the workbook's seal fails (the hidden scene sheet edited), or when the file is
    unusable (the reason is in the "likely causes" column).
"all correct" means full marks (verdict); every report (text, HTML, JSON, grades.csv) takes
its counts, verdict and score from here, and explain() says what cost how much.
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
from typing import TYPE_CHECKING

# the class list is read and matched in sheetkin/course/classlist.py (Russian name forms,
# Moodle's folders); its names stay importable from here
from .classlist import ClassList, name_key, read_class_list  # noqa: F401
from .classlist import ClassListError as GradesError  # noqa: F401 (--grades, --class-list: one line)

if TYPE_CHECKING:
    from .copies import Copies
    from .report_model import RowReport, RowVerdict

CHECK_PENALTY = 2.0        # points off per failing check row (the sheet showed the mistake)
ROWS_SHARE = 90.0          # the computed rows' share of the score
CHECKS_SHARE = 10.0        # the check rows' share: lost by the rows deleted or typed over
NO_FORMULA_CAP = 10.0      # the most a book with no formula in its computed rows scores
ID_HEADERS = ("Email address", "ID number", "Username")      # Moodle's export names them so
COLUMNS = ("student", "group", "variant", "file", "verdict", "rows correct", "rows typed", "rows total",
           "checks passing", "checks total", "given data changed", "likely causes", "possible copy of", "score",
           "score explained", "identity", "not judged")   # issue 31: rows + check rows to check by hand
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")




def safe_text(text: object) -> str:
    """A CSV cell a spreadsheet keeps as text: an apostrophe before a leading =, +, -, @,
    tab or carriage return (Excel and LibreOffice hide it and show the text)."""
    s = "" if text is None else str(text)
    return "'" + s if s.startswith(_FORMULA_START) else s


def graded_rows(rep) -> list:
    """Every computed row the reference has, except those the exercise gives filled in
    (phi_1, the guards): an empty exercise scores 0."""
    from sheetkin.sheet.workbook import prefilled_in_exercise
    return [r for r in rep.rows if not prefilled_in_exercise(r.name, r.kind)]


def _typed_ok(rep, accept_typed: bool | None) -> bool:
    return bool(rep.accepted_typed if accept_typed is None else accept_typed)


def row_verdict(row: RowReport, accept_typed: bool = False) -> RowVerdict:
    """One graded row: correct (computed right) | typed (a typed value where a formula
    belongs; with accept_typed, a typed row right to its digits is correct) | wrong | missing."""
    if row.status in ("missing", "empty"):
        return "missing"
    typed = row.is_typed
    if typed and not (accept_typed and row.status == "correct"):
        return "typed"
    return "correct" if row.status == "correct" else "wrong"


def counts(rep, accept_typed: bool | None = None) -> dict:
    """The graded rows by verdict: correct + typed + wrong + missing == total; the check
    rows: issued, passing, failing, n/a, deleted, typed over (every report shows these)."""
    rows = graded_rows(rep)
    # issue 31 (behaviour.py): rows sheetkin cannot evaluate are not judged, not graded
    out_of_score = [r for r in rows if r.not_judged]
    rows = [r for r in rows if not r.not_judged]
    acc = _typed_ok(rep, accept_typed)
    by = [row_verdict(r, acc) for r in rows]
    out: dict = {k: by.count(k) for k in ("correct", "typed", "wrong", "missing")}
    out["total"] = len(rows)
    out["not_judged"] = len(out_of_score)
    out["checks_not_judged"] = len(rep.checks_not_judged)
    # issue 31: credit per position, the rows' shares (behaviour.row_share)
    from .behaviour import row_share
    out["earned"] = sum(row_share(r, rep.positions, acc) for r in rows)
    # rows of positions holding a formula somewhere (a row of typed values only is not one;
    # the derived values of column D are graded, but three formulas there do not make a book
    # of typed positions computed work: NO_FORMULA_CAP)
    out["formula_rows"] = sum(1 for r in rows if r.status not in ("missing", "empty")
                              and r.kind != "derived"
                              and (bool(r.formula_cells)
                                   or not (r.typed_cells or r.source == "typed")))
    out["checks_issued"] = rep.checks_issued or 0
    out["checks_passing"] = rep.checks_passing or 0
    out["checks_apply"] = (rep.checks_apply if rep.checks_apply is not None else out["checks_issued"])
    out["checks_na"] = rep.checks_na or 0
    out["checks_failing"] = len(rep.failing_checks)
    out["checks_deleted"] = len(rep.checks_deleted or [])
    out["checks_typed"] = len(rep.checks_typed or [])
    out["checks_unfilled"] = rep.checks_unfilled or 0
    return out


def checks_counts(rep) -> tuple[int | None, int | None]:
    """(check rows passing, check rows that apply); None where unknown (unusable).

    Passing is a status 0 (green) only: "не заполнено" is not passing (an empty exercise
    passes no check); the total is the issued check rows that apply to the variant (not
    "н/д" in its reference), the same for every book of the variant, deleted ones included."""
    if rep.error or rep.checks_total is None:
        return None, None
    total = rep.checks_apply
    if total is None:                           # a report made without the reference's checks
        total = rep.checks_total - rep.checks_na
    passing = rep.checks_passing
    if passing is None:                         # a report made without the statuses
        passing = max(0, total - len(rep.failing_checks))
    return passing, total


def given_changed(rep, accept_changed: bool = False) -> bool:
    return bool(rep.given_changed) and not accept_changed


def seal_failed(rep) -> bool:
    return rep.seal not in ("", "ok", None)


def _accept_changed(rep, accept_changed: bool | None) -> bool:
    return bool(rep.accepted_changes if accept_changed is None else accept_changed)


def score_parts(rep, accept_changed: bool | None = None, accept_typed: bool | None = None) -> tuple[float, list[str]]:
    """(score, what cost how much: one phrase each), the module docstring's rule."""
    if rep.error:
        return 0.0, ["unusable: " + rep.reason]
    if given_changed(rep, _accept_changed(rep, accept_changed)):
        return 0.0, ["given data changed: 0 (graded against the issued variant)"]
    if seal_failed(rep):
        return 0.0, ["seal broken: 0"]
    c = counts(rep, accept_typed)
    if c["total"] == 0:
        return 0.0, ["no computed rows to grade"]
    issued = c["checks_issued"]
    share = ROWS_SHARE if issued else ROWS_SHARE + CHECKS_SHARE     # a sheet without check rows: all rows
    unit = share / c["total"]
    # what is earned, with what was not earned in brackets, so the numbers add up to the score
    # (earned rows + earned check rows - the penalty for failing checks)
    lost_rows = [f"{c[key]} {what}" for key, what in (("typed", "typed, not computed"), ("wrong", "wrong"),
                                                        ("missing", "missing or empty")) if c[key]]
    partly = c["earned"] - c["correct"]          # issue 31: the right positions of rows not all right
    if partly > 1e-9:
        lost_rows.append(f"their right positions: {unit * partly:.1f}")
    parts = [f"{c['correct']} of {c['total']} rows computed right: {unit * c['earned']:.1f} of {share:g}"
             + (f" ({', '.join(lost_rows)})" if lost_rows else "")]
    if c["not_judged"] or c["checks_not_judged"]:
        parts.append(f"not judged, check by hand: {c['not_judged']} rows, {c['checks_not_judged']} check rows")
    # issue 31: a check row not filled in keeps the share of the sheet's cells that are filled
    lost = c["checks_deleted"] + c["checks_typed"] + c["checks_unfilled"] * (1 - rep.filled_share)
    checks = CHECKS_SHARE * (issued - lost) / issued if issued else 0.0
    if issued:
        lost_checks = [f"{c[key]} {what}" for key, what in (
            ("checks_deleted", "deleted"), ("checks_typed", "status typed over"),
            ("checks_unfilled", "not filled in (rows they check are empty)")) if c[key]]
        parts.append(f"{issued - lost:.4g} of {issued} check rows intact and filled in: "
                     f"{checks:.1f} of {CHECKS_SHARE:g}"
                     + (f" ({', '.join(lost_checks)})" if lost_checks else ""))
    s = unit * c["earned"] + checks
    if c["checks_failing"]:
        s -= CHECK_PENALTY * c["checks_failing"]
        n = c["checks_failing"]
        parts.append(f"{n} check row{'' if n == 1 else 's'} failing: -{CHECK_PENALTY * n:g}")
    s = max(0.0, s)
    if c["formula_rows"] == 0 and s > NO_FORMULA_CAP:
        s = NO_FORMULA_CAP
        parts.append(f"no formula in the computed rows: at most {NO_FORMULA_CAP:g}")
    return round(s, 1), parts


def score(rep, accept_changed: bool | None = None, accept_typed: bool | None = None) -> float:
    """The documented score (module docstring), 0..100, one decimal."""
    return score_parts(rep, accept_changed, accept_typed)[0]


def explain(rep) -> str:
    """'72.5: 50 of 60 rows computed right: 75.0 of 90; 5 typed, not computed: -7.5; ...'."""
    s, parts = score_parts(rep)
    return f"{s:.1f}: " + "; ".join(parts)


VERDICTS = ("all correct", "mistakes", "typed, not computed", "given data changed", "seal broken", "unusable")


def verdict(rep) -> str:
    """The one verdict every report gives: unusable, seal broken, given data changed, typed,
    not computed (no formula in the computed rows), all correct (full marks), or mistakes."""
    if rep.error:
        return "unusable"
    if seal_failed(rep):
        return "seal broken"
    if given_changed(rep, _accept_changed(rep, None)):
        return "given data changed"
    c = counts(rep)
    if c["formula_rows"] == 0 and any(r.typed_cells or r.is_typed
                                      for r in graded_rows(rep)):
        return "typed, not computed"           # with --accept-typed too: no formula at all
    return "all correct" if score(rep) >= 100.0 else "mistakes"


def who(rep) -> str:
    """The student as they named themselves (their own cell; A2 is the scheme's author)."""
    return str(rep.student or "")


def copy_text(reports, i: int, copies) -> str:
    """'b.xlsx (Petrov), c.xlsx and 3 more: byte-identical files; ...' for report i: at
    most MAX_LISTED others of its cluster (sheetkin/course/copies.py), a line stays short."""
    from .copies import MAX_LISTED
    others = copies.others(i)
    if not others:      # a source that is no submission (a variant's key): the reason names it
        return copies.why(i) if copies.sources.get(i) else ""
    names = [f"{reports[j].path}{f' ({who(reports[j])})' if who(reports[j]) else ''}" for j in others[:MAX_LISTED]]
    more = f" and {len(others) - MAX_LISTED} more" if len(others) > MAX_LISTED else ""
    return f"{', '.join(names)}{more}: {copies.why(i)}"


def causes_text(rep) -> str:
    if rep.error:
        return "unusable: " + rep.reason
    return ";".join(c.name for c in rep.causes)


# --------------------------------------------------------------------------- grades.csv
def grade_lines(reports, copies: Copies | None, class_list: ClassList | None = None, accept_changed: bool = False,
                identities: list | None = None, lang: str = "en") -> tuple[list[list[str]], list[str]]:
    """The header and one line per graded report (in their order), and warnings: the
    students the class list does not name, the older files of a student (not graded: one
    grade per Moodle user), the books handed in by someone other than their student.
    identities: sheetkin.course.identity.identify's (made here from class_list if None).
    lang: the headers and the words of the cells (ru, uk, en); the identifier column keeps
    Moodle's own name (its import matches it), the numbers stay numbers; the warnings (for
    the operator's terminal) stay English."""
    from .copies import Copies
    from .identity import identify
    from .report_messages import column_name, say
    from .report_texts import say_grading
    copies = copies if copies is not None else Copies()
    if identities is None:
        identities = identify(reports, class_list)
    id_header = class_list.id_header if class_list else ID_HEADERS[0]

    def said(text: str, grading: bool = False) -> str:       # the grading vocabulary, or a message
        return safe_text(say_grading(text, lang) if grading else say(text, lang))
    lines = [[id_header, *(column_name(c, lang) for c in COLUMNS)]]
    unmatched, older, flagged = [], [], []
    for i, rep in enumerate(reports):
        me = identities[i]
        # a classmate's book in a student's folder is listed as such, graded or not (it is
        # not an older version of the student's own)
        foreign = [f for f in me.flags if f.startswith(("issued to", "found in"))]
        if foreign:
            tail = "; not graded" if me.superseded_by is not None else ""
            flagged.append(f"{rep.path}: {'; '.join(foreign)}{tail}")
        if me.superseded_by is not None:
            if not foreign:
                older.append(f"{rep.path} (newer: {reports[me.superseded_by].path})")
            continue
        student = who(rep)
        if class_list is not None and not me.ident:
            unmatched.append(f"{rep.path} ({me.unmatched or 'no name typed'})")
        c = counts(rep)
        passing, checks = checks_counts(rep)
        value, _ = score_parts(rep, accept_changed or None)
        lines.append([me.ident if class_list is not None else "", safe_text(student),
                      safe_text(rep.group or ""),
                      safe_text(rep.variant or ""), safe_text(rep.path), said(verdict(rep), True),
                      "" if rep.error else str(c["correct"]), "" if rep.error else str(c["typed"]),
                      "" if rep.error else str(c["total"]),
                      "" if passing is None else str(passing), "" if checks is None else str(checks),
                      column_name("yes" if given_changed(rep) else "no", lang),   # a fact, accepted or not
                      said(causes_text(rep)), said(copy_text(reports, i, copies)),
                      f"{value:.1f}", said(explain(rep), not rep.error), said("; ".join(me.flags)),
                      "" if rep.error else str(c["not_judged"] + c["checks_not_judged"])])   # issue 31
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
    from sheetkin.untrusted import csv_cell  # issue 30: every cell, the identifier too, neutralized
    csv.writer(buf, lineterminator="\r\n").writerows([csv_cell(c) for c in row] for row in lines)
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
