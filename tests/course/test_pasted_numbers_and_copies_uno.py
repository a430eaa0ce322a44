"""A fresh-eyes pass over running a class (teacher, students, attacker): the defects found,
each with the books that show it, made as students make them (LibreOffice through UNO).

1. Numbers pasted as "=0.1234" (a formula of constants) counted as computed work: a book
   of the key's values, each with an "=" before it, scored 98; a check status typed as
   "=0" passed as a computed one.
2. Two honest students who typed their own variant's numbers were reported as copying
   each other: 0 and 1 (sin 0, a component at a dead centre) are right on any given data.
3. A classmate's book found in a student's folder, uploaded after the student's own, was
   graded as the student's, and the student's own book was dropped as "older"."""
from __future__ import annotations

import os
from pathlib import Path

import openpyxl
import pytest
from helpers.studentbooks import Recipe, key_formulas, key_values, make_books, rows_by_name, uno_available
from openpyxl.utils import get_column_letter

from sheetkin.course import grades
from sheetkin.course.copies import Copies, pairs_of, possible_copies
from sheetkin.course.grades import all_correct
from sheetkin.course.identity import identify
from sheetkin.course.report_model import Report, RowReport
from sheetkin.course.validator import validate
from sheetkin.xlsx.evaluator import evaluate

ROOT = Path(__file__).resolve().parents[2]
uno = pytest.mark.skipif(not uno_available(), reason="LibreOffice with python3-uno (/usr/bin/python3) needed")


def _computed_rows(ex: Path, key: Path) -> list[str]:
    ws, kws = openpyxl.load_workbook(ex).worksheets[0], openpyxl.load_workbook(key).worksheets[0]
    at = rows_by_name(ws)
    return [n for n in rows_by_name(kws) if n in at and at[n] > at["phi_1"] and not n.startswith(("chk", "fd_"))
            and ws.cell(at[n], 5).value is None and isinstance(kws.cell(at[n], 5).value, str)]


def _as_constants(ex: Path, key: Path) -> list[list]:
    """Every cell the key computes, its value written as a formula of one constant
    ("=0.1234..."): what a student pastes with an "=" before it. Text cells keep the key's
    formula."""
    b = evaluate(key)
    sheet = b.order[0]
    out = []
    for r, c, f in key_formulas(ex, key):
        v = b.value(sheet, r, c)
        out.append([r, c, f"={v!r}" if isinstance(v, float) else f])
    return out


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@pytest.fixture(scope="module")
def books(tmp_path_factory, soffice):
    d = tmp_path_factory.mktemp("review")
    from sheetkin.cli.commands import main
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "2", "--out", str(d / "issued"),
                 "--seed", "5"]) == 0
    issued = d / "issued"
    ex1, key1 = next(issued.glob("*-01-exercise.xlsx")), next(issued.glob("*-01-key.xlsx"))
    ex2, key2 = next(issued.glob("*-02-exercise.xlsx")), next(issued.glob("*-02-key.xlsx"))
    rows1, rows2 = _computed_rows(ex1, key1), _computed_rows(ex2, key2)
    chk = rows_by_name(openpyxl.load_workbook(ex1).worksheets[0])["chk_OA"]
    consts = Recipe(ex1, key1)
    consts.ops.append(["formulas", "main", _as_constants(ex1, key1)])
    scratch = Recipe(ex1, key1).scratch_sheet_first()
    constants = _as_constants(ex1, key1)
    scratch.ops.append(["values", "Лист1", [[n + 1, 3, float(f[1:])] for n, (_, _, f) in enumerate(constants)
                                            if _is_number(f[1:])]])
    scratch.ops.append(["formulas", "main", [[r, c, f"=$Лист1.C{n + 1}" if _is_number(f[1:]) else f]
                                             for n, (r, c, f) in enumerate(constants)]])
    # honest habits: Fi computed on a scratch sheet (real formulas reading the main sheet's
    # phi_1, PI() and 180), read back by the main sheet; cos_1 through helper cells right of
    # the table
    at = rows_by_name(openpyxl.load_workbook(ex1).worksheets[0])
    title = openpyxl.load_workbook(ex1).worksheets[0].title
    cols = [get_column_letter(5 + k) for k in range(13)]
    helpers = Recipe(ex1, key1).honest().scratch_sheet_first()
    helpers.ops.append(["formulas", "Лист1", [[5, 5 + k, f"=${title}.{c}{at['phi_1']}*PI()/180"]
                                              for k, c in enumerate(cols)]])
    helpers.ops.append(["formulas", "main", [[at["Fi"], 5 + k, f"=$Лист1.{c}5"] for k, c in enumerate(cols)]
                        + [[at["cos_1"], 30 + k, f"=COS({c}{at['Fi']})"] for k, c in enumerate(cols)]
                        + [[at["cos_1"], 5 + k, f"={get_column_letter(30 + k)}{at['cos_1']}"]
                           for k in range(13)]])
    recipes = {
        "honest": Recipe(ex1, key1).honest(),
        "helpers": helpers,
        "scratch_refs": scratch,
        "consts": consts,
        "check_const": Recipe(ex1, key1).honest().note(f"D{chk}", "=0"),
        "rounded1": Recipe(ex1, key1).type_values(key_values(key1, rows1, 4)),
        "rounded2": Recipe(ex2, key2).type_values(key_values(key2, rows2, 4)),
        "copied": Recipe(ex2, key2).type_values(key_values(key1, rows1, 4)),
    }
    paths = {n: d / f"{n}.xlsx" for n in recipes}
    make_books({paths[n]: r for n, r in recipes.items()})
    from sheetkin.course.issued import KEY_FILE, Options, read_key, read_roster
    options = Options(read_roster(str(issued / "roster.csv")), read_key(issued / KEY_FILE))
    return {n: validate(p, options=options) for n, p in paths.items()}


@uno
def test_constant_formulas_are_typed_numbers(books):
    """The key's values pasted as "=0.1234" earn what typed numbers earn (at most 10, a
    fail); the honest book of formulas keeps full marks; a check status "=0" is typed over."""
    assert grades.score(books["honest"]) == 100.0 and all_correct(books["honest"])
    rep = books["consts"]
    assert len(rep.typed) >= 50 and grades.score(rep) <= 10 and not all_correct(rep)
    assert grades.verdict(rep) == "typed, not computed"
    check = books["check_const"]
    assert check.checks_typed == ["chk_OA"] and grades.score(check) < 100 and not all_correct(check)


@uno
def test_formulas_reading_pasted_numbers_are_typed(books):
    """The key's values pasted on a scratch sheet, each computed cell "=$Лист1.C7": nothing
    is computed (no formula reaches the given data), so it earns what typed numbers earn."""
    rep = books["scratch_refs"]
    assert grades.score(rep) <= 10 and not all_correct(rep)
    assert grades.verdict(rep) == "typed, not computed"
    assert len(rep.typed) >= 50 and all(r.reads_typed for r in rep.typed)


@uno
def test_scratch_formulas_and_helper_cells_are_computed(books):
    """A scratch sheet of real formulas and helper cells right of the table reach the given
    data through formulas: the book keeps full marks (tracing penalizes pasted numbers only)."""
    rep = books["helpers"]
    assert not rep.typed, [(r.name, r.typed_cells) for r in rep.typed]
    assert grades.score(rep) == 100.0 and all_correct(rep)


@uno
def test_own_numbers_typed_on_two_variants_are_no_copy(books):
    """Two students typing their own variant's numbers (rounded) share 0, 1, -1 at the dead
    centres: not a copy. A classmate's numbers typed into the other variant still are."""
    order = ["rounded1", "rounded2", "copied"]
    copies = possible_copies([books[n] for n in order], who=["a", "b", "c"])
    pairs = pairs_of(copies)
    assert (0, 1) not in pairs
    assert "identical typed numbers" in pairs[0, 2]


def _rep(path: str, student: str) -> Report:
    rep = Report(path, rows=[RowReport("ok", 10, "correct")], positions=13, student=student)
    rep.checks_total, rep.marks = 10, {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}, "values": {}}
    return rep


def test_classmates_book_in_a_folder_is_not_the_students_grade(tmp_path):
    """Попова's folder holds her book and, uploaded later, Смирнова's: Попова is graded on
    her own book, and Смирнова's is listed as not handed in by its student."""
    from sheetkin.course.classlist import read_class_list
    cl_path = tmp_path / "class.csv"
    cl_path.write_text("Имя,Фамилия,Адрес электронной почты\nОльга,Попова,popova@example.ru\n"
                       "Мария,Смирнова,smirnova@example.ru\n", "utf-8")
    cl = read_class_list(str(cl_path))
    folder = tmp_path / "Ольга Попова_5508_assignsubmission_file_"
    folder.mkdir()
    own, other = folder / "popova.xlsx", folder / "smirnova.xlsx"
    for p, t in ((own, 1e9), (other, 1e9 + 3600)):
        p.write_bytes(b"x")
        os.utime(p, (t, t))
    reps = [_rep(str(own), "Попова Ольга"), _rep(str(other), "Смирнова Мария")]
    ids = identify(reps, cl)
    assert ids[0].superseded_by is None and ids[1].superseded_by == 0
    lines, warnings = grades.grade_lines(reps, Copies(), cl, identities=ids)
    f = lines[0].index("file")        # by name; a class-list student who handed nothing in has no file
    assert [(r[0], Path(r[f]).name) for r in lines[1:] if r[f]] == [("popova@example.ru", "popova.xlsx")]
    text = " ".join(warnings)
    assert "smirnova.xlsx: found in the folder of Попова Ольга" in text and "not graded" in text
    assert "older file" not in text


def test_one_students_two_versions_are_no_copy(tmp_path):
    """Дмитрий's old and new versions in his own Moodle folder carry his name twice: one
    grade is kept and the other listed, but they are not "possible copies" of each other.
    The same name in two students' folders still is."""
    def at(folder: str, name: str) -> str:
        p = tmp_path / folder / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(str(p).encode())        # every file its own bytes
        return str(p)
    mine = "Дмитрий Иванов_5507_assignsubmission_file_"
    reps = [_rep(at(mine, "lab.xlsx"), "Иванов Дмитрий"), _rep(at(mine, "lab_v2.xlsx"), "Иванов Дмитрий"),
            _rep(at("Ольга Попова_5508_assignsubmission_file_", "lab.xlsx"), "Иванов Дмитрий")]
    assert pairs_of(possible_copies(reps[:2])) == {}
    got = pairs_of(possible_copies(reps))
    # the third book lies in another participant's folder: namesakes of different Moodle folders
    # are never copies (issue 31); the identity check flags the typed name there instead
    assert (0, 2) not in got and (1, 2) not in got


def test_a_corrupt_reupload_does_not_replace_a_usable_book(tmp_path):
    """Иван's folder: his book, then a corrupt re-upload (a broken copy, a locked file): the
    readable book is graded, the unusable one listed."""
    from sheetkin.course.classlist import read_class_list
    cl_path = tmp_path / "class.csv"
    cl_path.write_text("Имя,Фамилия,Адрес электронной почты\nИван,Иванов,ivanov@example.ru\n", "utf-8")
    cl = read_class_list(str(cl_path))
    folder = tmp_path / "Иван Иванов_5501_assignsubmission_file_"
    folder.mkdir()
    good, bad = folder / "lab.xlsx", folder / "lab (2).xlsx"
    for p, t in ((good, 1e9), (bad, 1e9 + 60)):
        p.write_bytes(b"x")
        os.utime(p, (t, t))
    broken = _rep(str(bad), "")
    broken.error = f"{bad}: corrupt or truncated zip archive"
    reps = [_rep(str(good), "Иванов Иван"), broken]
    ids = identify(reps, cl)
    assert ids[0].superseded_by is None and ids[1].superseded_by == 0
    lines, _ = grades.grade_lines(reps, Copies(), cl, identities=ids)
    f = lines[0].index("file")
    assert [(r[0], Path(r[f]).name) for r in lines[1:] if r[f]] == [("ivanov@example.ru", "lab.xlsx")]


def test_a_file_named_like_a_classmates_folder_is_still_its_folders(tmp_path):
    """Кузнецов uploads "Иван Иванов_5501_assignsubmission_file_lab.xlsx": Moodle puts it in
    Кузнецов's folder (or prefixes his name), and it is his submission, not Иванов's."""
    from sheetkin.course.classlist import moodle_submitter
    forged = "Иван Иванов_5501_assignsubmission_file_lab.xlsx"
    in_folder = moodle_submitter(f"subs.zip/Сергей Кузнецов_5505_assignsubmission_file_/{forged}")
    flat = moodle_submitter(f"subs.zip/Сергей Кузнецов_5505_assignsubmission_file_{forged}")
    assert (in_folder.name, in_folder.participant) == (flat.name, flat.participant) == ("Сергей Кузнецов", "5505")
    own = moodle_submitter(f"subs.zip/{forged}")
    assert (own.name, own.participant) == ("Иван Иванов", "5501")
