"""The HTML page shows what the text report, --json and grades.csv say of who handed a book
in (sheetkin.course.identity): a book in another student's folder, one student's older file,
a name the class list does not know, and each group of possible copies on one line; in the
page's language."""
from __future__ import annotations

import html
import os

import pytest

from sheetkin.course.classlist import read_class_list
from sheetkin.course.copies import possible_copies
from sheetkin.course.identity import identify
from sheetkin.course.report import html_report
from sheetkin.course.report_model import Report, RowReport


def _rep(path: str, student: str) -> Report:
    rep = Report(path, rows=[RowReport("ok", 10, "correct")], positions=13, student=student)
    rep.checks_total, rep.marks = 10, {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}, "values": {}}
    return rep


@pytest.fixture
def klass(tmp_path):
    cl_path = tmp_path / "class.csv"
    cl_path.write_text("Имя,Фамилия,Адрес электронной почты\nОльга,Попова,popova@example.ru\n"
                       "Мария,Смирнова,smirnova@example.ru\nДмитрий,Иванов,ivanov@example.ru\n", "utf-8")
    cl = read_class_list(str(cl_path))
    files = {}
    for folder, name, t in (("Ольга Попова_5508_assignsubmission_file_", "popova.xlsx", 1e9),
                            ("Ольга Попова_5508_assignsubmission_file_", "smirnova.xlsx", 1e9 + 3600),
                            ("Дмитрий Иванов_5507_assignsubmission_file_", "lab.xlsx", 1e9),
                            ("Дмитрий Иванов_5507_assignsubmission_file_", "lab_v2.xlsx", 1e9 + 60)):
        p = tmp_path / folder / name
        p.parent.mkdir(exist_ok=True)
        p.write_bytes(str(p).encode())
        os.utime(p, (t, t))
        files[name] = str(p)
    unknown = tmp_path / "loose.xlsx"
    unknown.write_bytes(b"loose")
    reps = [_rep(files["popova.xlsx"], "Попова Ольга"), _rep(files["smirnova.xlsx"], "Смирнова Мария"),
            _rep(files["lab.xlsx"], "Иванов Дмитрий"), _rep(files["lab_v2.xlsx"], "Иванов Дмитрий"),
            _rep(str(unknown), "Петров Пётр"), _rep(str(tmp_path / "copy.xlsx"), "Попова Ольга")]
    ids = identify(reps, cl)
    return reps, ids, possible_copies(reps, who=[m.who for m in ids])


def _summary_cells(page: str, k: int) -> str:
    return page.split("<tbody>")[1].split("</tr>")[k]


@pytest.mark.parametrize("lang,found,older,unknown,copies", [
    ("en", "found in the folder of Попова Ольга, but Смирнова Мария's name is typed in it",
     "not graded: ivanov@example.ru handed in", "no one in the class list is named 'Петров Пётр'",
     "Possible copies"),
    ("ru", "найдена в папке Попова Ольга, но в ней введено имя Смирнова Мария",
     "не оценена: ivanov@example.ru сдал(а) и", "в списке группы нет никого с именем 'Петров Пётр'",
     "Возможное списывание"),
])
def test_html_shows_identity_flags(klass, lang, found, older, unknown, copies):
    reps, ids, groups = klass
    page = html_report(reps, groups, lang, ids)
    found, unknown = html.escape(found), html.escape(unknown)
    assert found in _summary_cells(page, 1) and older in _summary_cells(page, 2)
    assert unknown in _summary_cells(page, 4)
    details = page.split("<details id='s1'>")[1].split("</details>")[0]
    assert found in details
    # the group of copies: one line naming its books (the same student name twice)
    assert copies in page
    line = page.split("id='copy-groups'>")[1].split("</ul>")[0]
    assert line.count("<li>") == len(groups.clusters) >= 1
    if lang == "ru":
        assert "found in the folder" not in page and "одно и то же имя студента" in line


def test_html_without_identities_has_no_identity_column(klass):
    reps, ids, groups = klass
    assert "found in the folder" not in html_report(reps, groups, "en")
