"""Issue 30, the fourth round of hostile input: what students type reaches the teacher
harmless, and one student never blocks the class. Each test makes the attacker's file."""
from __future__ import annotations

import csv
import io
import json
import re
import unicodedata
from pathlib import Path

import pytest
from classbooks import fill, issue_variants

from sheetkin.cli.commands import main
from sheetkin.course.classlist import moodle_submitter, read_class_list
from sheetkin.course.copies import Copies
from sheetkin.course.grades import grade_lines, grades_csv
from sheetkin.course.identity import assignment_text, identify, read_assignment, same_name_loosely
from sheetkin.course.issued import parse_roster, roster_text
from sheetkin.course.validator import Report, RowReport
from sheetkin.untrusted import compare_key, csv_cell, from_csv_cell, plain_text, shown_text

FORMULA = ("=", "+", "-", "@", "\t", "\r")
# what must never reach a terminal, a report or a CSV cell raw
RAW = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u061c\u200b-\u200f\u202a-\u202e\u2060-\u2069\ufeff\u2028\u2029]")
FORGED = "\x1b[2K\r\x1b[1Aall correct; score 100.0\n\u202eevil\u2066\x9b2J"


def _rep(path, student="", variant="", error=None):
    rep = Report(path, rows=[RowReport("ok", 10, "correct")], positions=13, student=student, variant=variant,
                 error=error)
    rep.checks_total, rep.marks = 10, {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}, "values": {}}
    return rep


def _csv(data: bytes) -> list[list[str]]:
    return list(csv.reader(io.StringIO(data.decode("utf-8-sig"), newline="")))


# --------------------------------------------------------------------------- 1. neutralized text
@pytest.mark.parametrize("text", ["=cmd|'/Ccalc'!A0@x.ru", "+7-1", "-1", "@Петров", "\t=1", "\r=1",
                                  "  =HYPERLINK(\"http://x\")", "=1+1"])
def test_csv_cell_keeps_a_formula_as_text(text):
    cell = csv_cell(text)
    assert cell.startswith("'") and not RAW.search(cell)
    assert from_csv_cell(cell) == shown_text(text)      # read back as typed (controls as escapes)


@pytest.mark.parametrize("text", ["Иванов Иван", "a=b", "v07", "", "1.5", "ivanov@example.org"])
def test_csv_cell_leaves_plain_text(text):
    assert csv_cell(text) == text and from_csv_cell(text) == text


def test_shown_text_escapes_every_hidden_character():
    shown = shown_text(FORGED)
    assert not RAW.search(shown) and "\n" not in shown
    assert "\\x1b" in shown and "\\u202e" in shown and "\\x9b" in shown and "\\r" in shown
    # the escape is the mark: the raw text can be read back from it
    assert shown.isascii() and shown.encode().decode("unicode_escape") == FORGED


def test_look_alike_names_compare_equal():
    plain = "Иванов Иван"
    for look_alike in ("Ива\u200bнов Иван", "\u202dИванов\u202c Иван", "Иванов\u00a0Иван", "ИВАНОВ  иван",
                       "Ива\ufeffнов\u2060 Иван"):
        assert compare_key(look_alike) == compare_key(plain), look_alike
        assert compare_key(shown_text(look_alike)) == compare_key(plain)     # also as reports show it
    assert compare_key("Ｉｖａｎｏｖ") == compare_key("ivanov")                   # NFKC
    assert plain_text("a\u0301") == unicodedata.normalize("NFKC", "a\u0301")


def test_class_list_email_is_neutralized_in_grades_csv(tmp_path):
    """A student's e-mail in the class list (editable in a Moodle profile) was written raw
    into grades.csv's identifier column."""
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,=cmd|'/Ccalc'!A0@x.ru\n"
                  "Анна,Петрова,+7-1@x.ru\n", encoding="utf-8")
    class_list = read_class_list(str(cl))
    reps = [_rep("a.xlsx", "Иванов Иван"), _rep("b.xlsx", "Петрова Анна")]
    lines, _ = grade_lines(reps, Copies(), class_list, identities=identify(reps, class_list, mtimes=[0, 0]))
    rows = _csv(grades_csv(lines))
    assert [r[0] for r in rows[1:]] == ["'=cmd|'/Ccalc'!A0@x.ru", "'+7-1@x.ru"]
    for row in rows:
        for cell in row:
            assert not cell.startswith(FORMULA) and not RAW.search(cell), cell


def test_assignment_csv_cells_neutralized_and_read_back(tmp_path):
    """`variants --class-list` wrote every cell of assignment.csv raw."""
    rows = [("=HYPERLINK(\"http://x\",\"Иванов\")", "=cmd|'/Ccalc'!A0@x.ru", "v1", "v1-x-exercise.xlsx"),
            ("@Петров", "+7-1", "v2", "v2-Петров-exercise.xlsx"),
            ("Сидоров\u202eвор", "-1", "v3", "v3-exercise.xlsx")]
    text = assignment_text("Email address", rows)
    for row in csv.reader(io.StringIO(text)):
        for cell in row:
            assert not cell.startswith(FORMULA) and not RAW.search(cell), cell
    path = tmp_path / "assignment.csv"
    path.write_text(text, encoding="utf-8")
    got = read_assignment(path)
    assert got.people["=cmd|'/Ccalc'!A0@x.ru"][0] == "=HYPERLINK(\"http://x\",\"Иванов\")"
    assert got.people["+7-1"] == ("@Петров", "v2", "v2-Петров-exercise.xlsx")
    assert got.people["-1"][0] == "Сидоров\\u202eвор"          # marked, never raw


def test_roster_text_cells_neutralized_numbers_kept():
    text = roster_text(["L1"], [("=v1", {"exercise": "=v1-exercise.xlsx", "key": "k.xlsx", "scene": "@v1.toml"},
                                 {"L1": -0.5})])
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[1][0] == "'=v1" and rows[1][3] == "'@v1.toml" and rows[1][-1] == "-0.5"
    roster = parse_roster(text)
    assert "=v1" in roster.rows and roster.files["=v1"]["scene"] == "@v1.toml"


# --------------------------------------------------------------------------- 2. identity
def test_participant_id_from_the_folder_names_last_fields():
    """A full name embedding 'Петров_102_assignsubmission_file_' gave the attacker's book
    Петров's participant number."""
    folder = "Петров_102_assignsubmission_file_x_5501_assignsubmission_file_"
    sub = moodle_submitter(f"{folder}/lab.xlsx")
    assert sub is not None and sub.participant == "5501"
    assert moodle_submitter("Иван Иванов_12_assignsubmission_file_/a.xlsx").participant == "12"
    # flat: the name Moodle writes has no underscore; a flat name holding the pattern twice names no one
    assert moodle_submitter("Иван Иванов_12_assignsubmission_file_lab.xlsx").participant == "12"
    assert moodle_submitter("Иван Иванов_12_assignsubmission_file_Петров_102_assignsubmission_file_.xlsx") is None
    # a student's own sub-folder named after a classmate's does not count: the outermost does
    inner = moodle_submitter("Иван Иванов_12_assignsubmission_file_/Петров_102_assignsubmission_file_/a.xlsx")
    assert inner.participant == "12"


def test_attackers_book_does_not_take_over_petrovs_grade(tmp_path):
    """One grade per student dropped Петров's real book as 'not graded'."""
    petrov = _rep("class.zip/Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Петров Пётр")
    evil = _rep("class.zip/Петров_102_assignsubmission_file_x_5501_assignsubmission_file_/lab.xlsx", "Петров Пётр")
    ids = identify([petrov, evil], None, mtimes=[1, 2])
    assert ids[0].superseded_by is None and ids[1].superseded_by is None
    assert ids[0].who != ids[1].who


def test_name_typed_in_another_students_folder_flagged_without_class_list():
    reps = [_rep("Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Иванов Иван"),
            _rep("Ivan Ivanov_103_assignsubmission_file_/lab.xlsx", "Иванов И.И."),       # transliterated: fine
            _rep("Participant_104_assignsubmission_file_/lab.xlsx", "Сидоров")]         # blind marking: cannot tell
    ids = identify(reps, None, mtimes=[0, 0, 0])
    assert any(f.startswith("found in the folder of Пётр Петров") and "Иванов Иван" in f for f in ids[0].flags)
    assert not ids[1].flags and not ids[2].flags
    lines, warnings = grade_lines(reps, Copies(), None, identities=ids)
    assert "1 book(s) not handed in by their own student" in " ".join(warnings)


def test_same_name_loosely():
    assert same_name_loosely("Щукин А.", "Schukin Alexey") and same_name_loosely("Петров", "Пётр Петров")
    assert not same_name_loosely("Иванов Иван", "Пётр Петров")
    assert same_name_loosely("Ива\u200bнов", "Иван Иванов")


def test_zero_width_and_override_names_match_the_class_list(tmp_path):
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,ivanov@x.ru\nПётр,Петров,petrov@x.ru\n",
                  encoding="utf-8")
    class_list = read_class_list(str(cl))
    for typed in ("Ива\u200bнов Иван", "\u202eИванов Иван", "Иванов\u3000Иван", shown_text("Ива\u200bнов Иван")):
        assert class_list.ident_of(typed) == "ivanov@x.ru", typed
    # "found in the folder of": the zero-width space no longer hides the classmate's name
    reps = [_rep("Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Ива\u200bнов Иван")]
    ids = identify(reps, class_list, mtimes=[0])
    assert ids[0].flags and ids[0].flags[0].startswith("found in the folder of Петров Пётр")


def test_name_matching_is_precomputed_once_per_class_list(tmp_path):
    """800 books against a 100,000-line class list took 94 s (every name compared with
    every line); the list is indexed once."""
    import time
    cl = tmp_path / "class.csv"
    lines = ["First name,Last name,Email address"]
    lines += [f"Имя{k},Фамилия{k},s{k}@x.ru" for k in range(100_000)]
    cl.write_text("\n".join(lines) + "\n", encoding="utf-8")
    class_list = read_class_list(str(cl))
    start = time.perf_counter()
    got = [class_list.ident_of(f"Фамилия{k * 97} Имя{k * 97}") for k in range(800)]
    got += [class_list.ident_of(f"Фамилия{k * 89} И.") for k in range(800)]
    took = time.perf_counter() - start
    assert got[:800] == [f"s{k * 97}@x.ru" for k in range(800)]
    assert got[800:] == [f"s{k * 89}@x.ru" for k in range(800)]
    assert took < 10, took


# --------------------------------------------------------------------------- 1. the terminal
def _with_text(book: Path, placeholder: str, text: str) -> Path:
    """The book with `text` where `placeholder` was, written as Excel escapes a control
    character in its XML (_x001B_): what openpyxl refuses to write, an attacker writes."""
    import zipfile
    xml = "".join(f"_x{ord(c):04X}_" if ord(c) < 0x20 or 0x7f <= ord(c) <= 0x9f else c for c in text)
    tmp = book.with_suffix(".tmp")
    with zipfile.ZipFile(book) as src, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename.endswith(".xml"):
                data = data.replace(placeholder.encode(), xml.encode())
            dst.writestr(info, data)
    tmp.replace(book)
    return book


@pytest.fixture(scope="module")
def books(tmp_path_factory):
    return issue_variants(tmp_path_factory.mktemp("issued"))


def test_forged_line_never_reaches_the_terminal(tmp_path, books, capsys):
    """ESC, CR/LF, C1 CSI and a bidi override typed in D1 and put in a zip entry's name
    reached the terminal raw: a forged 'all correct; score 100.0' line was printed."""
    import zipfile
    ex, key = books["v1"]
    book = _with_text(fill(ex, key, tmp_path / "b.xlsx", student="ZZFORGEDZZ"), "ZZFORGEDZZ", FORGED)
    z = tmp_path / "class.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.write(book, f"Иван Иванов_12_assignsubmission_file_/\x1b[2Kok\r\u202e{'x' * 3}.xlsx")
        zf.write(book, "Пётр Петров_13_assignsubmission_file_/lab.xlsx")
    html, grades = tmp_path / "r.html", tmp_path / "g.csv"
    code = main(["validate", str(z), "--html", str(html), "--grades", str(grades), "--jobs", "1"])
    out = capsys.readouterr()
    assert code in (0, 1, 2)
    for text in (out.out, out.err, html.read_text(encoding="utf-8"), grades.read_text(encoding="utf-8-sig")):
        assert not RAW.search(text.replace("\r\n", "").replace("\n", "")), RAW.search(text.replace("\n", ""))
    assert "\\x1b" in out.out                                       # shown, marked
    for line in out.out.splitlines():
        assert not line.startswith("all correct")
    main(["validate", str(z), "--json", "--jobs", "1"])
    data = capsys.readouterr().out
    assert not RAW.search(json.loads(data)[0]["student"] if isinstance(json.loads(data), list) else data)
