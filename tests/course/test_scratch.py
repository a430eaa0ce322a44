"""Issue 33: workbooks a student built from scratch (a new file in LibreOffice, their own
layout and Russian labels, either orientation, degrees or radians) are found by value and
graded by the lecture's required quantities; every book is typed in LibreOffice through UNO
(tests/helpers/scratchbooks.py), all of them in one soffice session shared by the module's tests."""
from __future__ import annotations

import csv
import io
import json
import zipfile
from pathlib import Path

import pytest
from helpers.scratchbooks import (
    StudentBook,
    blank_book,
    distinct_leaves,
    student_book,
    with_draft_sheet,
    write_openpyxl,
)
from helpers.studentbooks import make_books, uno_available

from sheetkin.cli import main
from sheetkin.course.grades import counts, row_verdict, score, verdict
from sheetkin.course.report import json_report, text_report
from sheetkin.course.scratch import ScratchOptions, ScratchReport, _Index, grade_book
from sheetkin.course.validator import validate
from sheetkin.kinematics.scene import load_scene
from sheetkin.sheet.workbook import write_workbook

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"

# (scene, orientation, angles): the lecture's schemes, both orientations, degrees and radians;
# the Scotch yoke is the RPP group
RIGHT = {
    "fourbar-row-deg": ("fourbar", "row", "deg"),
    "fourbar-col-rad": ("fourbar", "col", "rad"),
    "slider-col-deg": ("crank_slider", "col", "deg"),
    "slotted-row-rad": ("slotted_lever", "row", "rad"),
    "shaper-col-deg": ("shaper", "col", "deg"),
    "yoke-row-rad": ("scotch_yoke", "row", "rad"),
}
MUTATED = {"fourbar-row-deg-mut": ("fourbar", "row", "deg"), "shaper-col-rad-mut": ("shaper", "col", "rad")}


def scene(name: str):
    return load_scene(str(WORKBOOKS / f"{name}.toml"))


def mutations(name: str) -> dict[str, str]:
    """One wrong, one typed, one missing row: leaves no other quantity equals."""
    leaves = distinct_leaves(scene(name))
    return {"wrong": leaves[0], "typed": leaves[1], "missing": leaves[2]}


@pytest.fixture(scope="module")
def books(tmp_path_factory, soffice) -> dict[str, Path]:
    if not uno_available():
        pytest.skip("python3-uno is not installed")
    tmp = tmp_path_factory.mktemp("scratch")
    blank = blank_book(tmp / "blank.xlsx")
    recipes: dict[Path, StudentBook] = {}
    out: dict[str, Path] = {}
    for key, (name, orient, angles) in {**RIGHT, **MUTATED}.items():
        b = student_book(scene(name), orient, angles, **(mutations(name) if key in MUTATED else {}))
        b.exercise = str(blank)
        recipes[tmp / f"{key}.xlsx"] = b
        out[key] = tmp / f"{key}.xlsx"
    # the issued exercise, its sheet left empty, the student's own table on a sheet of their own
    ex = tmp / "fourbar-exercise.xlsx"
    text = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    write_workbook(scene("fourbar"), ex, exercise=True, scene_text=text)
    own = student_book(scene("fourbar"), "row", "deg", sheet="Мой расчёт")
    own.exercise = str(ex)
    recipes[tmp / "issued-own-sheet.xlsx"] = own
    out["issued-own-sheet"] = tmp / "issued-own-sheet.xlsx"
    # a class: variants with a class list; Petrova builds hers from scratch (columns)
    cl = tmp / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,s0@example.org\nАнна,Петрова,s1@example.org\n",
                  encoding="utf-8")
    issued = tmp / "issued"
    assert main(["variants", str(WORKBOOKS / "fourbar.toml"), "-n", "2", "--class-list", str(cl), "--out",
                 str(issued), "--seed", "5"]) == 0
    issued = issued / "teacher"            # issue 34: roster, assignment, scenes: the teacher's folder
    rows = list(csv.reader(io.StringIO((issued / "assignment.csv").read_text(encoding="utf-8"))))
    # student, identifier (named by its header since issue 34), variant, exercise
    vid = next(r[2] for r in rows[1:] if r[1] == "s1@example.org")
    mine = student_book(load_scene(str(issued / f"{vid}.toml")), "col", "deg", student="Петрова Анна")
    mine.exercise = str(blank)
    recipes[tmp / "petrova.xlsx"] = mine
    out["petrova"] = tmp / "petrova.xlsx"
    out["issued"] = issued
    out["class"] = cl
    make_books(recipes)  # type: ignore[arg-type]
    return out


@pytest.fixture(scope="module")
def reports(books) -> dict[str, ScratchReport]:
    out = {}
    for key, (name, _, _) in {**RIGHT, **MUTATED}.items():
        rep = validate(books[key], options=ScratchOptions(scene=scene(name)))
        assert rep.error is None, rep.error
        out[key] = rep
    return out


@pytest.mark.parametrize("key", sorted(RIGHT))
def test_right_books_score_100(reports, key):
    rep = reports[key]
    assert isinstance(rep, ScratchReport)
    c = counts(rep)
    assert (c["correct"], c["typed"], c["wrong"], c["missing"]) == (c["total"], 0, 0, 0), text_report(rep)
    assert score(rep) == 100.0 and verdict(rep) == "all correct"
    # the lecture's quantities are all there: the crank, joint A, each group's angles
    names = {r.name for r in rep.rows}
    assert {"Fi", "Fi_t", "x_A", "y_A", "vx_A", "ax_A"} <= names
    assert any(n.startswith("phi_") for n in names) and any(n.startswith("omega_") for n in names)


def test_the_mapping_names_the_students_cells(reports):
    """Each required quantity is mapped to the student's own line, labelled as they labelled it."""
    rep = reports["fourbar-row-deg"]
    m = {x["quantity"]: x for x in rep.mapping}
    assert m["x_B"]["status"] == "found" and m["x_B"]["label"] == "x B, м" and m["x_B"]["axis"] == "row"
    assert m["omega_2"]["label"] == "ω2, рад/с" and m["phi_2"]["unit"] == "deg"
    col = {x["quantity"]: x for x in reports["fourbar-col-rad"].mapping}
    assert col["phi_2"]["unit"] == "rad" and col["phi_2"]["axis"] == "col"     # radians, a column
    assert col["x_B"]["cells"].startswith("Лист1!") and col["x_B"]["cells"][-2:] != col["x_B"]["cells"][5:7]
    given = {g["name"]: g for g in rep.given_found}
    assert given["L1"]["cell"] == "Лист1!B5" and given["Fi_t0"]["label"].startswith("Fi t0")
    text = text_report(rep, "ru")
    assert "таблица студента" in text and "x_B: найдено Лист1!" in text
    d = json.loads(json_report([rep]))["reports"][0]
    assert d["mapping"] and d["given_found"] and d["score"] == 100.0


@pytest.mark.parametrize("key", sorted(MUTATED))
def test_one_wrong_one_typed_one_missing_row_are_named(reports, key):
    name = MUTATED[key][0]
    mut = mutations(name)
    rep = reports[key]
    by = {r.name: r for r in rep.rows}
    verdicts = {n: row_verdict(r) for n, r in by.items()}
    assert verdicts[mut["wrong"]] == "wrong"
    assert verdicts[mut["typed"]] == "typed"
    assert verdicts[mut["missing"]] == "missing"
    # nothing else is blamed: the three mutated rows are leaves
    assert sorted(n for n, v in verdicts.items() if v != "correct") == sorted(mut.values()), text_report(rep)
    wrong = by[mut["wrong"]]
    assert wrong.first_wrong == 4 and wrong.wrong_cells[0] == 4    # the formula times 1.05 from position 4
    assert "departs at position 4" in wrong.note
    label = mut["wrong"].replace("_", " ")
    assert f"«{label}, " in wrong.note                            # the nearest line: the student's own row
    text = text_report(rep, "en")
    assert mut["typed"] in text.split("typed, not computed (1): ")[1]
    assert f"missing (1): {mut['missing']}" in text


def test_issued_exercise_with_its_own_table_on_another_sheet(books):
    """The issued sheet left empty, the student's table on a sheet of their own: found."""
    rep = validate(books["issued-own-sheet"])
    assert rep.error is None
    assert isinstance(rep, ScratchReport), text_report(rep)
    assert score(rep) == 100.0, text_report(rep)
    assert "the issued sheet" in rep.notes[0] and "Мой расчёт" in rep.notes[0]
    assert all(x["cells"].startswith("Мой расчёт!") for x in rep.mapping if x["status"] == "found"
               and x["quantity"] not in ("Fi", "dFi"))


def test_a_book_without_scene_and_without_variant_is_unusable(books, capsys):
    assert main(["validate", str(books["fourbar-row-deg"]), "--progress", "never", "--lang", "en"]) == 2
    assert "no embedded scene" in capsys.readouterr().out


def test_cli_scene(books, capsys):
    code = main(["validate", str(books["fourbar-row-deg"]), "--scene", str(WORKBOOKS / "fourbar.toml"),
                 "--progress", "never", "--lang", "en"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "all correct; score 100.0" in out and "x_B: found Лист1!" in out


def test_moodle_zip_graded_with_the_students_identifier(books, tmp_path, capsys):
    """The roster and assignment.csv name Petrova's variant; her from-scratch book comes in
    her Moodle folder and is graded under her e-mail."""
    zpath = tmp_path / "submissions.zip"
    with zipfile.ZipFile(zpath, "w") as zf:
        zf.write(books["petrova"], "Анна Петрова_701_assignsubmission_file_/lab.xlsx")
    grades = tmp_path / "grades.csv"
    code = main(["validate", str(zpath), "--roster", str(books["issued"] / "roster.csv"), "--grades", str(grades),
                 "--progress", "never", "--lang", "en"])
    out = capsys.readouterr().out
    assert code == 0, out
    rows = [r for r in csv.DictReader(io.StringIO(grades.read_text(encoding="utf-8-sig"))) if r["file"]]  # handed in
    assert len(rows) == 1 and rows[0]["Email address"] == "s1@example.org" and rows[0]["score"] == "100.0", rows


def test_the_search_is_bounded_on_a_large_book(tmp_path):
    """A right book beside 100,000 other numbers (a scratch sheet of measurements): still
    found whole, and the look-ups stay a binary search each (no pairwise comparison)."""
    import time

    s = scene("fourbar")
    path = with_draft_sheet(write_openpyxl(student_book(s, "row", "deg"), tmp_path / "big.xlsx"))
    from sheetkin.xlsx.cells import read_book
    raw = read_book(path)
    t = time.perf_counter()
    rep = grade_book(raw, str(path), ScratchOptions(scene=s))
    elapsed = time.perf_counter() - t
    assert score(rep) == 100.0, text_report(rep)
    assert elapsed < 30, elapsed
    idx = _Index.of(__import__("sheetkin.course.scratch", fromlist=["_evaluate"])._evaluate(raw))
    assert len(idx.values) > 100_000


def test_given_data_typed_as_russian_texts_are_found(tmp_path):
    """A given value typed as the text "0,14" (a Russian decimal comma in a book whose cell was
    formatted as text) is found where it is, and the behavioural check still runs on the
    others; the student's formulas reading the number copies are graded as usual."""
    s = scene("fourbar")
    b = student_book(s, "row", "deg")
    b.cells["main"].append([5, 4, "0,14"])              # D5: L1 again, as Russian text
    b.cells["main"] = [c for c in b.cells["main"] if (c[0], c[1]) != (6, 2)] + [[6, 2, "0,5"]]   # L2 only as text
    path = write_openpyxl(b, tmp_path / "texts.xlsx")
    from sheetkin.xlsx.cells import read_book
    rep = grade_book(read_book(path), str(path), ScratchOptions(scene=s))
    given = {g["name"]: g["cell"] for g in rep.given_found}
    assert given["L2"] == "Лист1!B6"                    # found as the text "0,5"
    assert given["L1"] == "Лист1!B5"                    # the number, first in reading order
    by = {r.name: row_verdict(r) for r in rep.rows}
    # L2 as text: the rows reading it are errors in the spreadsheet too (#VALUE!), so not found
    assert by["x_A"] == "correct" and by["x_B"] in ("wrong", "missing")


def test_a_table_stopping_before_the_full_turn(tmp_path):
    """0 ... 330 degrees where 0 ... 360 was issued (the last position repeats the first): the
    table is found and graded on its 12 positions, and the report says so."""
    s = scene("fourbar")
    b = student_book(s, "row", "deg")
    last = 3 + s.crank.positions - 1                     # the table's columns start at C
    b.cells["main"] = [c for c in b.cells["main"] if c[1] != last]
    path = write_openpyxl(b, tmp_path / "short.xlsx")
    from sheetkin.xlsx.cells import read_book
    rep = grade_book(read_book(path), str(path), ScratchOptions(scene=s))
    assert rep.positions == s.crank.positions - 1 and score(rep) == 100.0, text_report(rep)
    assert any("one position before the full turn" in n for n in rep.notes)
    # the student's check rows are recognised, not graded
    checks = [m for m in rep.mapping if m["status"] == "check row"]
    assert any(m["label"].startswith("chk OA") for m in checks)
    assert all(m["cells"].startswith("Лист1!C") for m in checks)
