"""Issue 31, item 5: the teacher's side. Namesakes are two students, a plain file sealed to one
student is graded under their identifier, a given value typed as a Russian decimal text is a
remark, another class's book says so first, a class list with a stray BOM or a blank-looking
last line is read. The books are the issued corpus's (tests/data/issued/, made in LibreOffice)."""
from __future__ import annotations

import csv
import io
from pathlib import Path

import pytest
from openpyxl import load_workbook

from sheetkin.cli.commands import main
from sheetkin.course import issued
from sheetkin.course.classlist import read_class_list
from sheetkin.course.copies import pairs_of, possible_copies
from sheetkin.course.grades import grade_lines, score, seal_failed
from sheetkin.course.report import text_report
from sheetkin.course.report_model import Report, RowReport
from sheetkin.course.validator import validate

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "tests" / "data" / "issued" / "0.2.0" / "fourbar"
CRANK = ROOT / "tests" / "data" / "issued" / "0.2.0" / "crank_slider"
CLASS = "First name;Last name;Email address\nИван;Иванов;ivan@x.ru\nИлья;Иванов;ilya@x.ru\nПётр;Петров;petr@x.ru\n"


def _options(folder: Path) -> issued.Options:
    return issued.Options(roster=issued.read_roster(folder / "roster.csv"),
                          key=issued.read_key(folder / ".sheetkin-key"))


def _report(path: str, student: str, issued_to: str = "") -> Report:
    rep = Report(path, rows=[RowReport("x_A", 40, "correct")], positions=13, student=student, issued_to=issued_to)
    rep.checks_total = 0
    rep.marks = {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}}
    return rep


def test_namesakes_sealed_to_different_students_are_no_copies():
    reps = [_report("a.xlsx", "Иванов И.", "ivan@x.ru"), _report("b.xlsx", "Иванов И.", "ilya@x.ru")]
    assert pairs_of(possible_copies(reps, [None, None])) == {}
    # the same name with nothing to tell them apart is still listed
    same = [_report("a.xlsx", "Иванов И."), _report("b.xlsx", "Иванов И.")]
    assert pairs_of(possible_copies(same, [None, None])) == {(0, 1): "the same student name"}


def test_namesakes_in_different_moodle_folders_are_no_copies():
    reps = [_report("sub/Иван Иванов_5501_assignsubmission_file_/lab.xlsx", "Иванов И."),
            _report("sub/Илья Иванов_5502_assignsubmission_file_/lab.xlsx", "Иванов И.")]
    assert pairs_of(possible_copies(reps, [None, None])) == {}


def test_a_plain_file_sealed_to_a_namesake_takes_its_seals_identifier(tmp_path):
    (tmp_path / "class.csv").write_text(CLASS, encoding="utf-8")
    cl = read_class_list(str(tmp_path / "class.csv"))
    reps = [_report("ilya.xlsx", "Иванов И.", "ilya@x.ru"), _report("ivan.xlsx", "Иванов И.", "ivan@x.ru"),
            _report("nobody.xlsx", "Иванов И.")]
    lines, _ = grade_lines(reps, None, cl)
    file = lines[0].index("file")      # by name: Moodle's Identifier column stands before it
    # every student of the class list has a line (Пётр handed nothing in: no file)
    idents = {row[file]: row[0] for row in lines[1:] if row[file]}
    assert idents == {"ilya.xlsx": "ilya@x.ru", "ivan.xlsx": "ivan@x.ru", "nobody.xlsx": ""}


@pytest.fixture(scope="module")
def text_l1(tmp_path_factory) -> Path:
    """The honest 0.2.0 four-bar book with its given L1 stored as the text "0,129" (as a
    student of a Russian Calc may leave it: Calc computes with it)."""
    wb = load_workbook(FOURBAR / "honest.xlsx")
    ws = wb.worksheets[0]
    row = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "L1")
    assert ws.cell(row, 4).value == pytest.approx(0.129)          # the roster's L1
    ws.cell(row, 4).value = "0,129"
    ws.cell(row, 4).data_type = "s"
    out = tmp_path_factory.mktemp("text") / "text-l1.xlsx"
    wb.save(out)
    return out


def test_a_given_value_as_russian_text_is_a_remark(text_l1):
    rep = validate(text_l1, options=_options(FOURBAR))
    assert not rep.given_changed and rep.seal == "ok"
    assert score(rep) == 100.0
    assert any("L1" in n and "'0,129'" in n and "text" in n for n in rep.notes), rep.notes


def test_a_given_text_of_another_number_is_still_changed(tmp_path):
    wb = load_workbook(FOURBAR / "honest.xlsx")
    ws = wb.worksheets[0]
    row = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "L1")
    ws.cell(row, 4).value = "0,5"
    ws.cell(row, 4).data_type = "s"
    wb.save(tmp_path / "b.xlsx")
    rep = validate(tmp_path / "b.xlsx", options=_options(FOURBAR))
    assert [c["name"] for c in rep.given_changed] == ["L1"] and rep.given_changed[0]["got"] == 0.5
    assert score(rep) == 0.0


def test_check_given_reads_a_decimal_comma_text_as_a_remark():
    assert issued.as_text_number("0,144") == 0.144 and issued.as_text_number(" 0.144 ") == 0.144
    assert issued.as_text_number("1,2,3") is None and issued.as_text_number("abc") is None
    assert issued.as_text_number(0.144) is None


def test_a_book_of_another_scheme_says_so_first():
    rep = validate(CRANK / "honest.xlsx", options=_options(FOURBAR))
    assert seal_failed(rep) and rep.seal.startswith("this book is of another scheme"), rep.seal
    first = [ln for ln in text_report(rep).splitlines() if ln.strip().startswith("!!")][0]
    assert "another scheme" in first and "roster.csv" in first


def test_a_book_of_another_class_of_the_same_scheme_says_so_first(tmp_path):
    other = tmp_path / "other"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "1", "--seed", "7",
                 "--out", str(other)]) == 0
    rep = validate(FOURBAR / "honest.xlsx", options=_options(other))
    assert rep.seal.startswith("this book is of a class issued with another roster"), rep.seal
    # its given data are its own class's: not "given data changed" against the other roster
    assert not rep.given_changed and seal_failed(rep)
    first = [ln for ln in text_report(rep).splitlines() if ln.strip().startswith("!!")][0]
    assert "another roster" in first


@pytest.mark.parametrize("text", [
    "\ufeff" + CLASS + ";\n",                                    # a BOM, a lone ';' last
    CLASS.replace(";", ",") + "   \n",                           # spaces last
    "\ufeff\ufeff" + CLASS.replace(";", ",") + ",\n",            # a stray second BOM, a lone ','
    CLASS.replace("Иван;", "\ufeffИван;") + " ; \n",             # a BOM inside (files joined)
])
def test_a_class_list_with_a_stray_bom_or_blank_looking_last_line_is_read(tmp_path, text):
    (tmp_path / "class.csv").write_text(text, encoding="utf-8")
    cl = read_class_list(str(tmp_path / "class.csv"))
    want = [(r["Last name"] + " " + r["First name"], r["Email address"])
            for r in csv.DictReader(io.StringIO(CLASS), delimiter=";")]
    assert [(p.name, p.ident) for p in cl.people] == want
    assert cl.id_header == "Email address"

