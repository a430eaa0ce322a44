"""grades.csv read back the way Moodle reads it (../shared/moodle-formats.md): the gradebook
import (a user-field column, a grade column of numbers in the item's range, one line per
user) and the assignment's offline grading worksheet (Identifier "Participant N", Grade not
above Maximum grade, the worksheet's own columns kept), for named and blind marking."""
from __future__ import annotations

import csv
import io
import re

import pytest

from sheetkin.course.copies import Copies, possible_copies
from sheetkin.course.grades import (
    COLUMNS,
    fill_worksheet,
    grade_lines,
    grades_csv,
    read_class_list,
    read_worksheet,
    worksheet_csv,
)
from sheetkin.course.identity import identify
from sheetkin.course.report_model import Report, RowReport

CLASS = ("First name,Last name,ID number,Email address\r\n"
         "Иван,Иванов,1001,ivanov@example.org\r\n"
         "Анна,Петрова,1002,petrova@example.org\r\n"
         "Пётр,Сидоров,1003,sidorov@example.org\r\n"
         "Олег,Кузнецов,1004,kuznetsov@example.org\r\n")
# Moodle's "Download grading worksheet" (English site), participant numbers as in the zip
WORKSHEET = ("Identifier,Full name,Email address,Status,Grade,Maximum grade,Grade can be changed,"
             "Last modified (submission),Last modified (grade),Feedback comments\r\n"
             "Participant 501,Иван Иванов,ivanov@example.org,Submitted for grading,,10.00,Yes,-,-,\r\n"
             "Participant 502,Анна Петрова,petrova@example.org,Submitted for grading,,10.00,Yes,-,-,\r\n"
             "Participant 503,Пётр Сидоров,sidorov@example.org,Submitted for grading,,10.00,Yes,-,-,\r\n"
             "Participant 504,Олег Кузнецов,kuznetsov@example.org,No submission,,10.00,Yes,-,-,\r\n")


def _rep(path, student, correct=4, wrong=0):
    rows = ([RowReport(f"ok{k}", 10 + k, "correct") for k in range(correct)]
            + [RowReport(f"w{k}", 30 + k, "wrong", wrong_cells=list(range(1, 14))) for k in range(wrong)])
    rep = Report(path, rows=rows, positions=13, student=student)
    rep.checks_total = 10
    rep.marks = {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}, "values": {}}
    return rep


def _class(tmp_path, blind: bool, with_list: bool = True):
    """Ivanov hands in an old and a new version, Petrova a book with mistakes, Sidorov a
    copy of Ivanov's, Kuznetsov nothing."""
    def folder(name, pid):
        return f"{'Participant' if blind else name}_{pid}_assignsubmission_file_"
    reps = [_rep(f"{folder('Иван Иванов', 501)}/old.xlsx", "Иванов Иван", correct=1, wrong=3),
            _rep(f"{folder('Иван Иванов', 501)}/new.xlsx", "Иванов Иван"),
            _rep(f"{folder('Анна Петрова', 502)}/a.xlsx", "Петрова Анна", correct=2, wrong=2),
            _rep(f"{folder('Пётр Сидоров', 503)}/s.xlsx", "Сидоров Пётр")]
    path = tmp_path / "class.csv"
    path.write_text(CLASS, encoding="utf-8")
    cl = read_class_list(str(path)) if with_list else None
    ids = identify(reps, cl, mtimes=[1.0, 2.0, 3.0, 4.0])
    # Sidorov's file is byte for byte Ivanov's old one
    copies = possible_copies(reps, [b"old", b"new", b"a", b"old"], [m.who for m in ids], None)
    return reps, copies, cl, ids


def moodle_gradebook_import(data: bytes, user_field: str, grade_column: str,
                            grade_max: float) -> dict[str, float | None]:
    """What Moodle's CSV gradebook import does with the file: UTF-8, the BOM dropped, ","
    between fields, a header row; each line's user found by the mapped field; an empty grade
    is skipped; a grade must be a number (the decimal point ".") in 0..grade_max. A user
    twice is an error here (Moodle would keep the last line silently)."""
    rows = list(csv.DictReader(io.StringIO(data.decode("utf-8").removeprefix("\ufeff"), newline="")))
    out: dict[str, float | None] = {}
    for row in rows:
        user = row[user_field].strip()
        assert user, row                      # Moodle: "user not found"; every line names a user
        assert user not in out, f"{user} twice"
        text = row[grade_column].strip()
        if not text:
            out[user] = None
            continue
        assert re.fullmatch(r"\d+(\.\d+)?", text), text
        value = float(text)
        assert 0 <= value <= grade_max, value
        out[user] = value
    return out


def moodle_worksheet_upload(data: bytes, prefix: str = "Participant ") -> dict[int, float | None]:
    """Moodle's offline grading worksheet upload (assignfeedback_offline): the columns found
    by their names; the participant number is the Identifier less Moodle's hiddenuser
    prefix; a grade is a number not above the line's Maximum grade."""
    rows = list(csv.DictReader(io.StringIO(data.decode("utf-8").removeprefix("\ufeff"), newline="")))
    out: dict[int, float | None] = {}
    for row in rows:
        assert row["Identifier"].startswith(prefix), row["Identifier"]
        number = int(row["Identifier"][len(prefix):])
        text = row["Grade"].strip()
        out[number] = float(text) if text else None
        if text:
            assert 0 <= out[number] <= float(row["Maximum grade"])
    return out


@pytest.mark.parametrize("blind", [False, True])
def test_gradebook_import_takes_every_student_once(tmp_path, blind):
    reps, copies, cl, ids = _class(tmp_path, blind)
    lines, warnings = grade_lines(reps, copies, cl, identities=ids)
    got = moodle_gradebook_import(grades_csv(lines), "Email address", "score", 100.0)
    # one grade each, Ivanov's newer book; Kuznetsov handed nothing in: a line, no grade
    assert set(got) == {"ivanov@example.org", "petrova@example.org", "sidorov@example.org", "kuznetsov@example.org"}
    assert got["ivanov@example.org"] == 100.0 and got["petrova@example.org"] == 50.0
    assert got["kuznetsov@example.org"] is None
    assert got["sidorov@example.org"] is None          # a copy: held for review, not 100
    status = {r["Email address"]: r["status"] for r in csv.DictReader(io.StringIO(
        grades_csv(lines).decode("utf-8-sig"), newline=""))}
    assert status["kuznetsov@example.org"] == "not handed in"
    # blind marking: no "handed in by someone else" from the nameless "Participant" folders
    assert not any("not handed in by their own student" in w for w in warnings)
    idents = [r[1] for r in lines[1:4]]
    assert idents == ["Participant 501", "Participant 502", "Participant 503"]


def test_blind_marking_without_a_class_list_one_grade_per_participant(tmp_path):
    reps, copies, _, ids = _class(tmp_path, blind=True, with_list=False)
    lines, _ = grade_lines(reps, copies, None, identities=ids)
    files = [r[2 + COLUMNS.index("file")] for r in lines[1:]]
    assert [f.split("/")[-1] for f in files] == ["new.xlsx", "a.xlsx", "s.xlsx"]      # old.xlsx reduced away


@pytest.mark.parametrize("blind", [False, True])
def test_worksheet_filled_as_moodle_uploads_it(tmp_path, blind):
    reps, copies, cl, ids = _class(tmp_path, blind)
    sheet = tmp_path / "worksheet.csv"
    sheet.write_text(WORKSHEET, encoding="utf-8")
    lines, _ = grade_lines(reps, copies, cl, identities=ids)
    filled, warnings = fill_worksheet(read_worksheet(str(sheet)), lines)
    data = worksheet_csv(filled)
    # the worksheet's own cells as Moodle wrote them ("-": no date; its upload compares it)
    assert data.decode("utf-8-sig").split("\r\n")[1].endswith(",Yes,-,-,")
    header = next(csv.reader(io.StringIO(data.decode("utf-8-sig"))))
    assert header == WORKSHEET.split("\r\n")[0].split(",")             # its own columns, in order
    got = moodle_worksheet_upload(data)
    # scaled to the worksheet's Maximum grade (10): 100 -> 10, 50 -> 5; nothing handed in: empty
    assert got[501] == 10.0 and got[502] == 5.0 and got[503] is None and got[504] is None and not warnings


def test_copies_held_for_review_by_default_kept_or_zero_on_request():
    a, b = _rep("a.xlsx", "A"), _rep("b.xlsx", "B")
    copies = possible_copies([a, b], [b"same", b"same"], ["a", "b"], None)
    assert copies.others(0) == [1]                                    # byte-identical: a copy
    score = 2 + COLUMNS.index("score")
    status = 2 + COLUMNS.index("status")
    held, _ = grade_lines([a, b], copies)
    assert [r[score] for r in held[1:]] == ["", ""] and held[1][status] == "held for review: possible copy"
    kept, _ = grade_lines([a, b], copies, copies_policy="keep")
    assert [r[score] for r in kept[1:]] == ["100.0", "100.0"]
    zero, _ = grade_lines([a, b], copies, copies_policy="zero")
    assert [r[score] for r in zero[1:]] == ["0.0", "0.0"]


def test_grade_out_of_n_and_the_five_point_scale():
    from sheetkin.course.grades import five_point_scale, mark, with_course_grade
    reps = [_rep("a.xlsx", "A"), _rep("b.xlsx", "B", correct=3, wrong=1), _rep("c.xlsx", "C", correct=1, wrong=3)]
    lines = with_course_grade(grade_lines(reps, None, lang="ru")[0], 5, five_point_scale("ru"), "ru")
    at = 2 + COLUMNS.index("score")
    assert lines[0][at + 1:at + 3] == ["оценка (/5)", "оценка по шкале"]
    # no check rows issued: the rows share 100; 3 of 4 right: 75 -> 3.75 of 5, хорошо (70..85);
    # 1 of 4: 25 -> неудовлетворительно (below 50)
    assert [line[at:at + 3] for line in lines[1:]] == [["100.0", "5.00", "отлично"], ["75.0", "3.75", "хорошо"],
                                                       ["25.0", "1.25", "неудовлетворительно"]]
    own = five_point_scale("ru", "отлично=90,хорошо=75,удовлетворительно=25,неудовлетворительно=0")
    assert mark(75.0, own) == "хорошо" and mark(25.0, own) == "удовлетворительно" and mark(0, own).startswith("не")
    from sheetkin.course.grades import GradesError
    with pytest.raises(GradesError, match="no mark for a score below 50"):
        five_point_scale("ru", "отлично=90,удовлетворительно=50")
    with pytest.raises(GradesError, match="expected NAME=LEAST SCORE"):
        five_point_scale("ru", "отлично:90")


@pytest.mark.parametrize("fmt", ["csv", "csv-excel", "xlsx"])
def test_every_grades_format_round_trips(tmp_path, fmt):
    from sheetkin.course.grades import five_point_scale, grades_data, read_grades, with_course_grade
    reps, copies, cl, ids = _class(tmp_path, blind=False)
    lines = with_course_grade(grade_lines(reps, copies, cl, identities=ids, lang="ru")[0], 10,
                              five_point_scale("ru"), "ru")
    data = grades_data(lines, fmt)
    back = read_grades(data, fmt)

    def same(a: str, b: str) -> bool:
        try:
            return float(a) == float(b)
        except ValueError:
            return a == b
    assert len(back) == len(lines)
    for mine, theirs in zip(lines, back, strict=True):
        assert len(theirs) == len(mine) and all(same(a, b) for a, b in zip(mine, theirs, strict=True)), (mine, theirs)
    if fmt == "csv-excel":               # what a Russian Excel needs: ";" between fields, "," decimals
        text = data.decode("utf-8-sig")
        assert text.split("\r\n")[0].count(";") == len(lines[0]) - 1 and ";100,0;10,00;отлично;" in text
    if fmt == "csv":                     # the one Moodle reads
        got = moodle_gradebook_import(data, "Email address", "балл", 100.0)
        assert got["ivanov@example.org"] == 100.0


def test_csv_excel_is_utf8_with_a_bom_and_no_sep_line(tmp_path):
    """--grades-format csv-excel, byte by byte as docs/class.md states it: UTF-8 after a
    byte-order mark (EF BB BF: Excel 2007 and later on Windows then read it as UTF-8 on a
    double click, whatever the code page; without it a Russian Excel would read cp1251),
    no `sep=;` line (it makes Excel ignore the BOM), `;` between fields (a Russian Windows'
    list separator), `,` decimals, CRLF; the default csv stays Moodle's (`,`, `.`)."""
    from sheetkin.course.grades import grades_data
    reps, copies, cl, ids = _class(tmp_path, blind=False)
    lines = grade_lines(reps, copies, cl, identities=ids, lang="ru")[0]
    data = grades_data(lines, "csv-excel")
    assert data.startswith(b"\xef\xbb\xbf") and not data.startswith(b"\xef\xbb\xbfsep=")
    text = data[3:].decode("utf-8")                    # strict UTF-8 after the mark
    assert "студент".encode() in data and "студент".encode("cp1251") not in data
    rows = text.split("\r\n")
    assert rows[-1] == "" and all("\n" not in r for r in rows)
    assert next(csv.reader(io.StringIO(rows[0]), delimiter=";")) == lines[0]
    assert re.search(r";\d+,\d;", text) and not re.search(r";\d+\.\d;", text)
    default = grades_data(lines, "csv")
    assert default.startswith(b"\xef\xbb\xbf")
    assert next(csv.reader(io.StringIO(default[3:].decode("utf-8").split("\r\n")[0]))) == lines[0]
    assert re.search(r",\d+\.\d,", default.decode("utf-8-sig"))


def test_a_graded_line_is_never_nameless(tmp_path):
    """No name typed in the book: grades.csv's student is the class list's name of the
    identifier, else the Moodle folder's name; blind marking's stays empty (it has none)."""
    path = tmp_path / "class.csv"
    path.write_text(CLASS, encoding="utf-8")
    cl = read_class_list(str(path))
    reps = [_rep("Иван Иванов_501_assignsubmission_file_/a.xlsx", ""),
            _rep("Ольга Орлова_509_assignsubmission_file_/b.xlsx", ""),
            _rep("Participant_510_assignsubmission_file_/c.xlsx", "")]
    student = 2 + COLUMNS.index("student")
    for class_list, names in ((cl, ["Иванов Иван", "Ольга Орлова", ""]),
                              (None, ["Иван Иванов", "Ольга Орлова", ""])):
        ids = identify(reps, class_list, mtimes=[1.0, 2.0, 3.0])
        lines, _ = grade_lines(reps, Copies(), class_list, identities=ids)
        assert [line[student] for line in lines[1:4]] == names
