"""Issue 31, item 4: every issued book grades by the rules of the version that issued it.

tests/data/issued/<version>/<scheme>/ holds what each released version's `sheetkin variants`
issued and students' books made from it in LibreOffice (tools/issued_corpus.py): honest.xlsx
(every row the key's formula), wrong.xlsx (vx_A 10% off), typed.xlsx (x_A typed as numbers),
last-empty.xlsx (the last position, 360 deg = 0 deg, left empty). They are graded here as a
teacher grades them (the folder's roster.csv and key); no LibreOffice runs at test time.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from sheetkin.course import issued
from sheetkin.course.checks import added_after
from sheetkin.course.grades import all_correct, counts, score
from sheetkin.course.validator import validate

CORPUS = Path(__file__).resolve().parent.parent / "data" / "issued"
FOLDERS = sorted(p for p in CORPUS.glob("*/*") if p.is_dir())
BOOKS = ("honest", "wrong", "typed", "last-empty")


def _graded(folder: Path) -> dict:
    options = issued.Options(roster=issued.read_roster(folder / issued.ROSTER_FILE),
                             key=issued.read_key(folder / issued.KEY_FILE))
    return {b: validate(folder / f"{b}.xlsx", options=options) for b in BOOKS}


@pytest.fixture(scope="module")
def corpus() -> dict[str, dict]:
    """Every book of the corpus graded once, shared by the tests: {"0.1.0/fourbar": {book: Report}}."""
    return {f"{f.parent.name}/{f.name}": _graded(f) for f in FOLDERS}


def test_the_corpus_holds_every_released_version_and_scheme():
    # 0.1.0 and 0.2.0 are the released versions before the version mark (CHANGELOG.md)
    assert {f.parent.name for f in FOLDERS} >= {"0.1.0", "0.2.0"}
    assert {f.name for f in FOLDERS} == {"fourbar", "crank_slider", "slotted_lever", "shaper"}
    for f in FOLDERS:
        assert all((f / f"{b}.xlsx").is_file() for b in BOOKS), f


@pytest.mark.parametrize("folder", [f"{f.parent.name}/{f.name}" for f in FOLDERS])
def test_every_issued_book_grades_by_its_version(corpus, folder):
    reports = corpus[folder]
    for name, rep in reports.items():
        assert not rep.error, (folder, name, rep.error)
        assert rep.seal == "ok", (folder, name, rep.seal)
        c = counts(rep)
        # a count never exceeds its total ("33 of 30 that apply passing" was once possible)
        assert c["checks_passing"] <= c["checks_apply"] <= c["checks_issued"], (folder, name, c)
        assert c["correct"] + c["typed"] + c["wrong"] + c["missing"] <= c["total"], (folder, name, c)
        assert not rep.checks_deleted, (folder, name, rep.checks_deleted)
    honest = reports["honest"]
    assert score(honest) == 100.0, (folder, honest.notes)
    assert all_correct(honest) and counts(honest)["checks_passing"] == counts(honest)["checks_apply"] > 0
    # the mistake each book was made with is named, and only it
    assert [r.name for r in reports["wrong"].causes] == ["vx_A"], folder
    assert [r.name for r in reports["typed"].typed] == ["x_A"], folder
    assert score(reports["wrong"]) < 90 and 90 < score(reports["typed"]) < 100
    # 12 of 13 positions right: the row keeps the share of its right positions (item 3)
    assert score(reports["last-empty"]) > 85, folder


def test_books_written_from_now_on_carry_their_version():
    from sheetkin import __version__, load_scene
    from sheetkin.sheet.workbook import SCENE_SHEET, build_workbook

    wb = build_workbook(load_scene(Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml"),
                        charts=False)
    sc = wb[SCENE_SHEET]
    consts = {(c.row, c.column): c.value for row in sc.iter_rows() for c in row if c.value is not None}
    assert issued.version_mark(consts) == __version__
    # the corpus's books were written before the mark: read back as none
    from sheetkin.xlsx import read_book
    old = read_book(CORPUS / "0.1.0" / "fourbar" / "honest.xlsx").sheets[SCENE_SHEET].consts
    assert issued.version_mark(old) == ""


def test_check_rows_a_later_release_added_are_not_part_of_an_older_book(monkeypatch):
    import sheetkin.course.checks as checks
    monkeypatch.setattr(checks, "CHECK_ROWS_ADDED", {"0.2.0": frozenset({"chk_a"}), "0.3.0": frozenset({"chk_b"})})
    assert added_after("0.1.0") == {"chk_a", "chk_b"}
    assert added_after("") == {"chk_b"}           # unmarked: written by 0.2.0 or earlier
    assert added_after("0.3.0") == set() and added_after("0.3.0.dev1") == set()
    assert added_after("nonsense") == set()


def test_an_older_book_without_a_check_row_a_later_release_added_is_not_deleted(monkeypatch, corpus):
    """A release that adds a check row (here: pretending the running one added a row the
    0.1.0 book lacks) grades the older book without it: not "deleted", not in the totals."""
    import sheetkin.course.checks as checks
    folder = CORPUS / "0.1.0" / "fourbar"
    before = counts(corpus["0.1.0/fourbar"]["honest"])
    # a check row of the current sheet, deleted from a copy of the honest book's names by
    # claiming that the next release added it
    monkeypatch.setattr(checks, "CHECK_ROWS_ADDED", {"99.0.0": frozenset({"chk_Fi"})})
    rep = _graded(folder)["honest"]
    c = counts(rep)
    assert c["checks_issued"] == before["checks_issued"] - 1
    assert c["checks_passing"] <= c["checks_apply"] and not rep.checks_deleted and score(rep) == 100.0
