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
teacher, who decides; grades.csv holds its grade (empty) unless told otherwise (--copies).

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
import dataclasses
import io
import os
import re
from typing import TYPE_CHECKING, Any

# the class list is read and matched in sheetkin/course/classlist.py (Russian name forms,
# Moodle's folders); its names stay importable from here
from sheetkin.messages import message, say

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
           "score explained", "identity", "not judged",   # issue 31: rows + check rows to check by hand
           "status")                                      # issue 34: graded, held for review, not handed in
PARTICIPANT_HEADER = "Identifier"   # Moodle's offline grading worksheet: "Participant N" (its own name, kept)
# Moodle's string hiddenuser, the Identifier's word, in the site's language (its import skips it)
PARTICIPANT_WORD = {"en": "Participant", "ru": "Участник", "uk": "Учасник"}
COPY_POLICIES = ("hold", "keep", "zero")   # a possible copy's grade: empty (for review), its score, 0
STATUS_GRADED, STATUS_HELD, STATUS_ABSENT = "graded", "held for review: possible copy", "not handed in"
STATUS_ZERO = "possible copy: 0 (--copies zero)"
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


def typed_accepted(rep, accept_typed: bool | None) -> bool:
    """Whether typed values earn credit for this book: the teacher's choice, else the book's."""
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
    acc = typed_accepted(rep, accept_typed)
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
        parts.append(message("not_judged_check_by_hand", r=c["not_judged"], c=c["checks_not_judged"]))
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
        parts.append(message("n_check_row_failing" if n == 1 else "n_check_rows_failing", n=n)
                     + f": -{CHECK_PENALTY * n:g}")
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


def all_correct(rep) -> bool:
    """"all correct": full marks (the one rule every report uses; exit 0 of `validate`)."""
    return verdict(rep) == "all correct"


def report_dict(rep) -> dict:
    """A report as --json writes it: its fields (not the INTERNAL ones), what the grading
    rule makes of them (ok, verdict, score, score_explained) and the summary counts."""
    internal = [f.name for f in dataclasses.fields(rep) if f.metadata.get("to_dict", True) is False]
    blank: dict[str, Any] = dict.fromkeys(internal)     # not copied by asdict (a Scene, a Layout)
    d = dataclasses.asdict(dataclasses.replace(rep, **blank))
    for name in internal:
        del d[name]
    v = verdict(rep)                                    # made once: all_correct(rep) is v's test
    d["ok"] = v == "all correct"
    d["verdict"] = v
    d["score"] = None if rep.error else score(rep)
    d["score_explained"] = explain(rep)
    d["summary"] = {**counts(rep), "causes": [r.name for r in rep.causes]}
    return d


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
    more = message("and_more", n=len(others) - MAX_LISTED) if len(others) > MAX_LISTED else ""
    return f"{', '.join(names)}{more}: {copies.why(i)}"


def causes_text(rep) -> str:
    if rep.error:
        return "unusable: " + rep.reason
    return ";".join(c.name for c in rep.causes)


# --------------------------------------------------------------------------- grades.csv
def grade_lines(reports, copies: Copies | None, class_list: ClassList | None = None, accept_changed: bool = False,
                identities: list | None = None, lang: str = "en",
                copies_policy: str = "hold") -> tuple[list[list[str]], list[str]]:
    """The header and one line per graded report (in their order), then one per student of
    the class list who handed nothing in (empty score, status "not handed in"); and warnings: the
    students the class list does not name, the older files of a student (not graded: one
    grade per Moodle user), the books handed in by someone other than their student.
    identities: sheetkin.course.identity.identify's (made here from class_list if None).
    lang: the headers and the words of the cells (ru, uk, en); the identifier column keeps
    Moodle's own name (its import matches it), the numbers stay numbers; the warnings (for
    the operator's terminal) stay English. The second column, Identifier, is Moodle's
    "Participant N" from the folder a book came in (the offline grading worksheet's key,
    blind marking's only one). copies_policy (COPY_POLICIES): a possible copy's score is
    left empty and held for review (hold), kept (keep) or 0 (zero); the status says which."""

    from .copies import Copies
    from .identity import identify
    from .report_texts import column_name
    copies = copies if copies is not None else Copies()
    if identities is None:
        identities = identify(reports, class_list)
    id_header = class_list.id_header if class_list else ID_HEADERS[0]

    def said(text: str, grading: bool = False) -> str:       # the grading vocabulary, or a message
        return safe_text(say(text, lang, "grading") if grading else say(text, lang))
    if copies_policy not in COPY_POLICIES:
        raise ValueError(f"copies_policy: one of {', '.join(COPY_POLICIES)}, not {copies_policy!r}")
    lines = [[id_header, PARTICIPANT_HEADER, *(column_name(c, lang) for c in COLUMNS)]]
    unmatched, older, flagged, held = [], [], [], []
    graded_ids: set[str] = set()
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
                older.append(f"{rep.path}{message('newer')}{reports[me.superseded_by].path})")
            continue
        # the name typed in the book; none typed: the class list's name of the identifier,
        # else who handed it in (the Moodle folder's name), so that no graded line is nameless
        person = class_list.by_ident(me.ident) if class_list is not None and me.ident else None
        student = who(rep) or (person.name if person else "") or me.folder_name
        if class_list is not None and not me.ident:
            unmatched.append(f"{rep.path} ({me.unmatched or 'no name typed'})")
        c = counts(rep)
        passing, checks = checks_counts(rep)
        value, _ = score_parts(rep, accept_changed or None)
        copied = copy_text(reports, i, copies)
        shown_score, status = f"{value:.1f}", STATUS_GRADED
        if copied and copies_policy == "hold":
            shown_score, status = "", STATUS_HELD
            held.append(rep.path)
        elif copied and copies_policy == "zero":
            shown_score, status = "0.0", STATUS_ZERO
        graded_ids.add(me.ident)
        lines.append([me.ident if class_list is not None else "",
                      f"{PARTICIPANT_WORD.get(lang, 'Participant')} {me.participant}" if me.participant else "",
                      safe_text(student),
                      safe_text(rep.group or ""),
                      safe_text(rep.variant or ""), safe_text(rep.path), said(verdict(rep), True),
                      "" if rep.error else str(c["correct"]), "" if rep.error else str(c["typed"]),
                      "" if rep.error else str(c["total"]),
                      "" if passing is None else str(passing), "" if checks is None else str(checks),
                      column_name("yes" if given_changed(rep) else "no", lang),   # a fact, accepted or not
                      said(causes_text(rep)), said(copied),
                      shown_score, said(explain(rep), not rep.error), said("; ".join(me.flags)),
                      "" if rep.error else str(c["not_judged"] + c["checks_not_judged"]),   # issue 31
                      column_name(status, lang)])
    absent = _not_handed_in(class_list, graded_ids) if class_list is not None else []
    for person in absent:
        lines.append([person.ident, "", safe_text(person.name), *[""] * (len(COLUMNS) - 2),
                      column_name(STATUS_ABSENT, lang)])
    warnings = []

    def listed(items: list[str]) -> str:
        return ", ".join(items[:10]) + (" ..." if len(items) > 10 else "")
    if class_list is None:
        warnings.append(message("no_class_list_column", c=f"'{id_header}'"))
    elif unmatched:
        warnings.append(message("unmatched_submissions", n=len(unmatched), c=f"'{id_header}'", list=listed(unmatched)))
    if older:
        warnings.append(message("one_grade_per_student", n=len(older), list=listed(older)))
    if flagged:
        warnings.append(message("books_not_own", n=len(flagged), list=listed(flagged)))
    if held:
        warnings.append(message("copies_held", n=len(held), list=listed(held)))
    if absent:
        warnings.append(message("students_absent", n=len(absent), list=listed([p.name for p in absent])))
    return lines, warnings


def _not_handed_in(class_list: ClassList, graded_ids: set[str]) -> list:
    """The class list's students (one each) no graded book is identified with."""
    seen, out = set(graded_ids), []
    for person in class_list.people:
        if person.ident and person.ident not in seen:
            seen.add(person.ident)
            out.append(person)
    return out


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


# --------------------------------------------------------------------------- Moodle's grading worksheet
# its headers in the site languages the course meets (Moodle's strings recordid, grade, maximumgrade)
WORKSHEET_IDENTIFIER = ("identifier", "идентификатор", "ідентифікатор")
WORKSHEET_GRADE = ("grade", "оценка", "оцінка")
WORKSHEET_MAXIMUM = ("maximum grade", "максимальная оценка", "максимальна оцінка")
MAX_WORKSHEET_BYTES = 5_000_000


def read_worksheet(path: str) -> list[list[str]]:
    """Moodle's offline grading worksheet (Download grading worksheet) as rows of text;
    one-line errors naming the file when it is not one."""
    from .classlist import decode_table, delimiter, read_bounded
    text = decode_table(read_bounded(path, MAX_WORKSHEET_BYTES, "worksheet"), path, "worksheet")
    rows = [r for r in csv.reader(io.StringIO(text, newline=""), delimiter=delimiter(text.split("\n", 1)[0]))
            if any(c.strip() for c in r)]
    header = [h.strip().casefold() for h in rows[0]] if rows else []
    if not any(h in WORKSHEET_IDENTIFIER for h in header) or not any(h in WORKSHEET_GRADE for h in header):
        raise GradesError(f"{path}:1: --worksheet: expected Moodle's grading worksheet with the columns "
                          "'Identifier' and 'Grade' (the assignment's Download grading worksheet)")
    return rows


def _column(header: list[str], names: tuple[str, ...]) -> int | None:
    folded = [h.strip().casefold() for h in header]
    return next((k for k, h in enumerate(folded) if h in names), None)


def _number(text: str) -> float | None:
    try:
        return float(text.strip().replace("\u00a0", "").replace(",", "."))
    except ValueError:
        return None


def worksheet_csv(rows: list[list[str]]) -> bytes:
    """The filled worksheet as Moodle wrote it (UTF-8, ",", CRLF): its own cells unchanged
    (an apostrophe before Moodle's "-" for "no date" would spoil its upload's date check;
    they came from Moodle as they are), the grades written here are numbers."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\r\n").writerows(rows)
    return ("\ufeff" + buf.getvalue()).encode("utf-8")


def fill_worksheet(rows: list[list[str]], lines: list[list[str]]) -> tuple[list[list[str]], list[str]]:
    """The worksheet with its own columns and lines, each participant's Grade written from
    grades.csv's lines (its Identifier "Participant N" to the score, scaled from 0..100 to
    the line's Maximum grade, "." as the decimal point); a line with an empty score (held
    for review, not handed in) keeps the worksheet's grade. Warnings: the graded books
    whose participant the worksheet does not hold."""
    header = rows[0]
    ident_col, grade_col = _column(header, WORKSHEET_IDENTIFIER), _column(header, WORKSHEET_GRADE)
    max_col = _column(header, WORKSHEET_MAXIMUM)
    assert ident_col is not None and grade_col is not None       # read_worksheet checked them
    score_col = 2 + COLUMNS.index("score")
    scores = {line[1].split()[-1]: line[score_col] for line in lines[1:] if line[1]}
    out, found = [list(header)], set()
    for row in rows[1:]:
        row = row + [""] * (len(header) - len(row))
        number = (row[ident_col].split() or [""])[-1]
        value = _number(scores.get(number, ""))
        if value is not None:
            found.add(number)
            maximum = _number(row[max_col]) if max_col is not None else None
            grade = value * (maximum if maximum else 100.0) / 100.0
            row[grade_col] = f"{grade:.2f}"
        out.append(row)
    missing = sorted(set(scores) - found - {n for n, s in scores.items() if _number(s) is None}, key=int)
    warnings = [message("worksheet_missing_participants", list=", ".join(missing))] if missing else []
    return out, warnings


# --------------------------------------------------------------------------- the course's own grade
# the Russian five-point scale: (the least score, the mark's name, its number); a teacher
# changes the thresholds with --scale "отлично=90,хорошо=75,удовлетворительно=60,неудовлетворительно=0"
FIVE_POINT = {
    "ru": ("отлично", "хорошо", "удовлетворительно", "неудовлетворительно"),
    "uk": ("відмінно", "добре", "задовільно", "незадовільно"),
    "en": ("excellent", "good", "satisfactory", "unsatisfactory"),
}
FIVE_POINT_THRESHOLDS = (85.0, 70.0, 50.0, 0.0)


def five_point_scale(lang: str = "ru", spec: str | None = None) -> list[tuple[float, str]]:
    """[(least score, mark)] best first: the five-point scale in `lang` with the default
    thresholds, or `spec` ("name=least score,..." in any order, any names). A spec that is
    not that is a one-line GradesError."""
    if not spec:
        return list(zip(FIVE_POINT_THRESHOLDS, FIVE_POINT.get(lang, FIVE_POINT["ru"]), strict=True))
    scale = []
    for part in spec.split(","):
        name, eq, least = part.rpartition("=")
        value = _number(least) if eq else None
        if not name.strip() or value is None or not 0 <= value <= 100:
            raise GradesError(message("scale_expected", v=repr(part.strip()),
                                      e="'отлично=85,хорошо=70,удовлетворительно=50,неудовлетворительно=0'"))
        scale.append((value, name.strip()))
    scale.sort(reverse=True)
    if scale[-1][0] > 0:
        raise GradesError(f"--scale: no mark for a score below {scale[-1][0]:g}: give one with =0")
    return scale


def mark(score_value: float, scale: list[tuple[float, str]]) -> str:
    """The scale's mark for a 0..100 score (its least score reached, best first)."""
    return next(name for least, name in scale if score_value >= least - 1e-9)


def with_course_grade(lines: list[list[str]], out_of: float | None, scale: list[tuple[float, str]] | None,
                      lang: str = "en") -> list[list[str]]:
    """grades.csv's lines with, beside the score, the grade out of `out_of` points (the
    Moodle grade item's maximum) and the scale's mark; an empty score stays empty."""
    from .report_texts import column_name
    at = 2 + COLUMNS.index("score") + 1
    heads = ([f"{column_name('grade', lang)} (/{out_of:g})"] if out_of else []) + \
        ([column_name("mark", lang)] if scale else [])
    out = [lines[0][:at] + heads + lines[0][at:]]
    for line in lines[1:]:
        value = _number(line[at - 1])
        extra = []
        if out_of:
            extra.append("" if value is None else f"{value * out_of / 100.0:.2f}")
        if scale:
            extra.append("" if value is None else mark(value, scale))
        out.append(line[:at] + extra + line[at:])
    return out


GRADES_FORMATS = ("csv", "csv-excel", "xlsx")    # Moodle's CSV (default); ";" and "," decimals; a workbook


def grades_data(lines: list[list[str]], fmt: str = "csv") -> bytes:
    """grades.csv's lines as the format asks: csv (Moodle's import: ",", "." decimals,
    UTF-8 with a BOM), csv-excel (a Russian Excel's: ";" between fields, "," decimals, the
    same UTF-8 with a BOM, which Excel 2007+ reads on a double click whatever the code page,
    and no "sep=" line, which would make it ignore the BOM: docs/class.md says why not
    cp1251), xlsx (numbers as numbers)."""
    if fmt == "csv":
        return grades_csv(lines)
    if fmt == "csv-excel":
        buf = io.StringIO()
        from sheetkin.untrusted import csv_cell
        w = csv.writer(buf, delimiter=";", lineterminator="\r\n")
        w.writerows([_decimal_comma(csv_cell(c)) for c in row] for row in lines)
        return ("\ufeff" + buf.getvalue()).encode("utf-8")
    if fmt == "xlsx":
        return _grades_xlsx(lines)
    raise ValueError(f"grades format: one of {', '.join(GRADES_FORMATS)}, not {fmt!r}")


def _decimal_comma(cell: str) -> str:
    # an identifier ("1001") has no point, so it is unchanged; a score "72.5" becomes "72,5"
    return cell.replace(".", ",") if _NUMBER.fullmatch(cell) else cell


def _grades_xlsx(lines: list[list[str]]) -> bytes:
    from openpyxl import Workbook

    from sheetkin.untrusted import csv_cell
    book = Workbook()
    sheet = book.active
    sheet.title = "grades"
    first_number = 2 + COLUMNS.index("rows correct")     # the identifiers, names, groups, variants stay text
    for row in lines:
        # numbers as numbers (a spreadsheet sums them); text stays text: openpyxl would take
        # a leading "=" for a formula, so every text cell is neutralized as in the CSV
        sheet.append([float(c) if k >= first_number and _NUMBER.fullmatch(c) else csv_cell(c)
                      for k, c in enumerate(row)])
    buf = io.BytesIO()
    book.save(buf)
    return buf.getvalue()


def read_grades(data: bytes, fmt: str = "csv") -> list[list[str]]:
    """The lines back from grades_data's bytes (numbers in "." form), for the round trip."""
    if fmt == "xlsx":
        from openpyxl import load_workbook
        sheet = load_workbook(io.BytesIO(data)).active
        return [["" if c is None else (f"{c:.2f}".rstrip("0").rstrip(".") if isinstance(c, float) else str(c))
                 for c in row] for row in sheet.iter_rows(values_only=True)]
    text = data.decode("utf-8-sig")
    rows = list(csv.reader(io.StringIO(text, newline=""), delimiter=";" if fmt == "csv-excel" else ","))
    if fmt == "csv-excel":
        rows = [[c.replace(",", ".") if _NUMBER_COMMA.fullmatch(c) else c for c in row] for row in rows]
    return rows


_NUMBER = re.compile(r"-?\d+\.\d+|-?\d+")
_NUMBER_COMMA = re.compile(r"-?\d+,\d+|-?\d+")
