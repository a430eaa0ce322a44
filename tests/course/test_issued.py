"""Given data checked against the issued variant (issue 13, item 2): roster.csv, the
embedded scene, the seal of the hidden scene sheet, the student's own identity cells,
--accept-changed-inputs; roster.csv's reader fuzzed (only our errors come out); a book
saved by LibreOffice still validates with the roster."""
from __future__ import annotations

from pathlib import Path

import openpyxl
import pytest
from helpers.clirun import run
from helpers.realbooks import row_numbers
from hypothesis import given, settings
from hypothesis import strategies as st

from sheetkin.cli.commands import main
from sheetkin.course.grades import all_correct
from sheetkin.course.issued import (
    KEY_FILE,
    Options,
    RosterError,
    changed_line,
    parse_roster,
    read_key,
    read_roster,
    seal,
)
from sheetkin.course.report import text_report
from sheetkin.course.validator import validate

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def issued(tmp_path_factory):
    """Two issued fourbar variants (key and exercise books, roster, key file)."""
    out = tmp_path_factory.mktemp("issued") / "class"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "2", "--out", str(out),
                 "--seed", "4"]) == 0
    return out


def edited(src: Path, dst: Path, inputs: dict | None = None, scene_line: tuple[str, str] | None = None,
           drop_id: bool = False) -> Path:
    """A copy of `src` with input cells (by row name) set, a line of the hidden scene sheet
    replaced, or the variant id removed: what a student could do with openpyxl or by hand."""
    wb = openpyxl.load_workbook(src)
    ws = wb.worksheets[0]
    at = {**row_numbers(ws), "student": 1, "group": 2}     # the student's own cells: D1, D2
    for name, v in (inputs or {}).items():
        ws.cell(at[name], 4).value = v
    sc = wb["scene"]
    if scene_line:
        for r in range(1, sc.max_row + 1):
            if str(sc.cell(r, 1).value or "").startswith(scene_line[0]):
                sc.cell(r, 1).value = scene_line[1]
    if drop_id:
        sc["C1"] = None
    wb.save(dst)
    return dst


def given_of(issued: Path, vid: str) -> dict[str, float]:
    return read_roster(issued / "roster.csv").rows[vid]


def opts(issued: Path, **kw) -> Options:
    return Options(read_roster(issued / "roster.csv"), read_key(issued / KEY_FILE), **kw)


# --------------------------------------------------------------------------- the case
def test_changed_given_data_fail_and_are_graded_against_the_issued_variant(issued, tmp_path, capsys):
    l1 = given_of(issued, "fourbar-01")["L1"]
    book = edited(issued / "fourbar-01-key.xlsx", tmp_path / "cheat.xlsx",
                  {"L1": 0.05, "Fi_t0": 1, "student": "Иванов Иван", "group": "ГИ-21"})
    rep = validate(book, options=opts(issued))
    assert [(c["name"], c["issued"], c["got"]) for c in rep.given_changed] == [("L1", l1, 0.05), ("Fi_t0", 20.0, 1.0)]
    assert rep.given_changed[0]["cell"].endswith(f"!D{row_numbers(openpyxl.load_workbook(book).worksheets[0])['L1']}")
    assert not all_correct(rep) and rep.seal == "ok" and rep.variant == "fourbar-01"
    assert (rep.student, rep.group) == ("Иванов Иван", "ГИ-21") and rep.author == "sheetkin example"
    # graded against the issued variant: the crank's rows now disagree with it
    by = {r.name: r for r in rep.rows}
    assert by["Fi_t"].status == "wrong" and by["Fi_t"].expected == 20.0 and by["Fi_t"].got == 1.0
    assert by["x_A"].status == "wrong" and by["x_A"].expected == pytest.approx(l1)
    assert by["phi_1"].status == "correct"
    text = text_report(rep).splitlines()
    assert text[1] == (f"  !! given data changed: L1 {l1:g} -> 0.05, Fi_t0 20 -> 1 "
                       "(FAIL; graded against the issued variant)")
    code, out, err = run(capsys, "validate", "--lang", "en", book, "--roster", issued / "roster.csv")
    assert code == 1 and "given data changed: L1" in out.splitlines()[1]
    # without a roster: the scene embedded at generation is the issued variant
    rep2 = validate(book)
    assert [c["name"] for c in rep2.given_changed] == ["L1", "Fi_t0"] and not all_correct(rep2) and rep2.seal == ""
    # --accept-changed-inputs: graded against the student's own inputs, as before issue 13
    rep3 = validate(book, options=opts(issued, accept_changed=True))
    assert rep3.given_changed and all_correct(rep3) and all(r.status == "correct" for r in rep3.rows)
    code, out, _ = run(capsys, "validate", "--lang", "en", book, "--roster", issued / "roster.csv",
                       "--accept-changed-inputs")
    assert code == 0 and "(graded against the student's own inputs" in out


def test_unchanged_key_book_passes_with_its_seal(issued, capsys):
    rep = validate(issued / "fourbar-02-key.xlsx", options=opts(issued))
    assert all_correct(rep) and rep.given_changed == [] and rep.seal == "ok" and rep.variant == "fourbar-02"
    assert (rep.student, rep.group) == ("", "")
    code, out, err = run(capsys, "validate", "--lang", "en", issued / "fourbar-02-key.xlsx", "--roster",
                         issued / "roster.csv")
    assert code == 0 and "seal ok" in out and "note" not in err      # the key found next to the roster


def test_the_seal_catches_an_edited_scene_sheet(issued, tmp_path, capsys):
    """The student changes L1 in the input block and in the hidden scene: without a roster
    the given data look unchanged, but the seal fails under the teacher's key."""
    book = edited(issued / "fourbar-01-key.xlsx", tmp_path / "sealed.xlsx", {"L1": 0.05},
                  scene_line=("length = ", "length = 0.05"))
    key = read_key(issued / KEY_FILE)
    rep = validate(book, options=Options(key=key))
    assert rep.given_changed == [] and rep.seal.startswith("scene sheet edited") and not all_correct(rep)
    assert "  !! scene sheet edited" in text_report(rep)
    code, out, err = run(capsys, "validate", "--lang", "en", book, "--key", issued / KEY_FILE)
    assert code == 1 and "scene sheet edited" in out
    # without a key the seal is not checked, and the command says so once
    code, out, err = run(capsys, "validate", "--lang", "en", book, book)
    assert code == 0 and err.count("seals are not checked") == 1
    # with the roster the issued values come from it: the change shows too
    rep = validate(book, options=opts(issued))
    assert [c["name"] for c in rep.given_changed] == ["L1"] and rep.seal.startswith("scene sheet edited")
    # a removed variant id: the roster row cannot be found, and that fails
    gone = edited(issued / "fourbar-01-key.xlsx", tmp_path / "noid.xlsx", drop_id=True)
    rep = validate(gone, options=opts(issued))
    assert not all_correct(rep) and "names no variant" in rep.seal


def test_a_plain_workbook_is_its_own_variant(tmp_path):
    """A book made by `sheetkin workbook` (no variant id, no seal): its embedded scene is the
    issued data; unchanged, it passes (a changed one: tests/course/test_validator.py)."""
    book = edited(ROOT / "workbooks" / "fourbar.xlsx", tmp_path / "plain.xlsx", {"student": "Сидоров"})
    rep = validate(book)
    assert all_correct(rep) and rep.variant == "" and rep.seal == "" and rep.student == "Сидоров"


def test_seal_is_keyed_and_covers_id_and_text():
    k1, k2 = b"1" * 32, b"2" * 32
    assert seal(k1, "a", "x = 1\n") == seal(k1, "a", "x = 1\n\n\n")    # a spreadsheet drops the empty tail
    assert len({seal(k1, "a", "x = 1"), seal(k2, "a", "x = 1"), seal(k1, "b", "x = 1"), seal(k1, "a", "x = 2")}) == 4


def test_changed_line():
    assert changed_line([{"name": "L1", "issued": 0.14, "got": 0.05}, {"name": "Fi_t0", "issued": 20.0, "got": 1.0},
                         {"name": "L2", "issued": 0.5, "got": None}]) == \
        "given data changed: L1 0.14 -> 0.05, Fi_t0 20 -> 1, L2 0.5 -> empty"


# --------------------------------------------------------------------------- roster.csv
HEAD = "variant,exercise,key,scene,L1,L2\n"


@pytest.mark.parametrize("text, where, what", [
    ("", ":1:1:", "empty"),
    ("variant,key\n", ":1:2:", "expected column 'exercise'"),
    (HEAD + "v1,a,b,c,0.1\n", ":2:6:", "5 fields, expected 6"),
    (HEAD + "v1,a,b,c,0.1,abc\n", ":2:6:", "L2: expected a number, got 'abc'"),
    (HEAD + "v1,a,b,c,0.1,nan\n", ":2:6:", "expected a number"),
    (HEAD + "v1,a,b,c,0.1,0.2\nv1,a,b,c,0.1,0.2\n", ":3:1:", "appears twice"),
    (HEAD, ":2:", "no variants"),
    ("variant,exercise,key,scene,L1,L1\n", ":1:6:", "repeated"),
    (HEAD + ",a,b,c,1,2\n", ":2:1:", "empty variant id"),
])
def test_roster_errors_name_file_line_column(text, where, what):
    with pytest.raises(RosterError) as e:
        parse_roster(text, "r.csv")
    msg = str(e.value)
    assert msg.startswith("r.csv" + where) and what in msg and "\n" not in msg


def test_roster_file_errors(tmp_path):
    with pytest.raises(RosterError, match="no such roster file"):
        read_roster(tmp_path / "none.csv")
    (tmp_path / "bin.csv").write_bytes(HEAD.encode() + b"\x98\x98,1\n")   # not Windows-1251 either
    with pytest.raises(RosterError, match=r"bin.csv:2: not UTF-8"):
        read_roster(tmp_path / "bin.csv")
    (tmp_path / "k").write_text("not hex")
    with pytest.raises(RosterError, match=r"k:1:1: expected a key"):
        read_key(tmp_path / "k")


def test_roster_error_is_an_input_error_not_a_scene_error():
    """A roster is not a scene: RosterError sits directly under InputError (issue 29), which
    is what the command line catches, so its exit code and one line stay the same."""
    from sheetkin.errors import InputError
    from sheetkin.kinematics.scene import SceneError
    assert issubclass(RosterError, InputError) and not issubclass(RosterError, SceneError)


def test_cli_roster_errors_are_one_line(issued, tmp_path, capsys):
    bad = tmp_path / "roster.csv"
    bad.write_text(HEAD + "v1,a,b,c,0.1,x\n", encoding="utf-8")
    code, _, err = run(capsys, "validate", "--lang", "en", issued / "fourbar-01-key.xlsx", "--roster", bad)
    assert code == 2 and err.count("\n") == 1 and f"{bad}:2:6: L2: expected a number" in err


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("variant,exercisekyL12.0-e\n\r\"' \x00\ufeffé")), max_size=120))
def test_roster_reader_fuzz_only_our_errors(text):
    try:
        r = parse_roster(text, "f.csv")
    except RosterError as e:
        assert "\n" not in str(e) and str(e).startswith("f.csv")
    else:
        assert r.rows and all(isinstance(v, float) for row in r.rows.values() for v in row.values())


@settings(max_examples=200, deadline=None)
@given(st.lists(st.lists(st.text(max_size=8), max_size=7), max_size=5))
def test_roster_reader_fuzz_fields(rows):
    import csv
    import io
    buf = io.StringIO()
    csv.writer(buf).writerows([["variant", "exercise", "key", "scene", "L1"]] + rows)
    try:
        parse_roster(buf.getvalue(), "f.csv")
    except RosterError as e:
        assert "\n" not in str(e)


# --------------------------------------------------------------------------- LibreOffice
def test_books_saved_by_libreoffice_validate_with_the_roster(issued, tmp_path, soffice):
    """One soffice run saves three books: an exercise filled in by a student (formulas
    copied from the key) with name and group, the same with L1 changed, and one whose scene
    sheet was edited. Read back, the roster and key still tell each case."""
    from helpers.libreoffice import recalculate
    src = tmp_path / "src"
    src.mkdir()
    key_wb = openpyxl.load_workbook(issued / "fourbar-02-key.xlsx")
    filled = openpyxl.load_workbook(issued / "fourbar-02-exercise.xlsx")
    kws, fws = key_wb.worksheets[0], filled.worksheets[0]
    for row in kws.iter_rows(min_row=5, min_col=4):
        for c in row:
            if isinstance(c.value, str) and c.value.startswith("="):
                fws.cell(c.row, c.column).value = c.value
    fws["D1"] = "Петров Пётр"             # the student's own cells, rows 1-2
    fws["D2"] = "101"
    filled.save(src / "filled.xlsx")
    edited(src / "filled.xlsx", src / "changed.xlsx", {"L1": 0.05})
    edited(src / "filled.xlsx", src / "tampered.xlsx", scene_line=("length = ", "length = 0.05"))
    saved = recalculate([src / "filled.xlsx", src / "changed.xlsx", src / "tampered.xlsx"], tmp_path / "lo")
    by = {p.name: validate(out, options=opts(issued)) for p, out in saved.items()}
    ok = by["filled.xlsx"]
    assert ok.error is None and all_correct(ok) and ok.seal == "ok", text_report(ok)
    assert (ok.student, ok.group, ok.variant) == ("Петров Пётр", "101", "fourbar-02")
    ch = by["changed.xlsx"]
    assert [c["name"] for c in ch.given_changed] == ["L1"] and not all_correct(ch) and ch.seal == "ok"
    assert by["tampered.xlsx"].seal.startswith("scene sheet edited") and not all_correct(by["tampered.xlsx"])


def test_summary_table_names_an_unusable_scene_whole():
    """The reason of an error that does not start "path: " (an embedded scene that does not
    read: "x.xlsx (embedded scene):23: ...") was cut two characters into it."""
    from sheetkin.course.report import summary_table
    from sheetkin.course.report_model import Report
    rep = Report("b.xlsx", error="b.xlsx (embedded scene):23: [[group]] #1 key 'length': unknown key")
    assert rep.reason == rep.error
    assert "b.xlsx (embedded scene):23:" in summary_table([rep]).splitlines()[1]
    rep = Report("b.xlsx", error="b.xlsx: not a zip file")
    assert rep.reason == "not a zip file"
    assert summary_table([rep]).splitlines()[1].split()[-4:] == ["not", "a", "zip", "file"]


def test_student_cell_with_a_formula_sheetkin_cannot_compute_is_the_saved_text():
    """A student who typed =HYPERLINK("http://x";"click") as their name was listed as
    "#NAME?" although the validator said the saved values were used."""
    import numpy as np

    from sheetkin.course.book import identity_text

    class Sheet:
        cached = {(6, 4): "click"}

        def computed(self, r, c):
            return True

    class Evaluated:
        tag = {"s": np.full((8, 8), 14)}

        def value(self, sheet, r, c):
            return "#NAME?"
    assert identity_text(Evaluated(), "s", Sheet(), 6) == "click"
    assert identity_text(Evaluated(), "s", Sheet(), None) == ""


def test_an_edited_scene_sheet_that_no_longer_reads_says_edited(issued, tmp_path):
    """A student who breaks the hidden scene sheet's TOML was told only the line that does
    not parse; with the key the validator says the sheet was edited (and why it is unusable)."""
    book = edited(issued / "fourbar-01-key.xlsx", tmp_path / "broken.xlsx",
                  scene_line=("lengths = ", "length = 0.05"))
    rep = validate(book, options=opts(issued))
    assert rep.error and "scene sheet edited" in rep.error and "no longer reads" in rep.error
    assert "unknown key" in rep.error and "\n" not in rep.error
    rep = validate(book)                       # no key: the parse error as before
    assert rep.error and "scene sheet edited" not in rep.error and "unknown key" in rep.error


def test_empty_and_missing_rows_are_one_line_each():
    """An empty exercise printed one line per row (60 lines "empty: Fi (row 32)" ...)."""
    from sheetkin.course.report_model import Report, RowReport
    rep = Report("e.xlsx", positions=13,
                 rows=[RowReport(f"r{k}", 30 + k, "empty") for k in range(60)]
                 + [RowReport("omega_3", None, "missing")])
    lines = text_report(rep).splitlines()
    assert sum(line.startswith("  empty (60): r0 (row 30), r1 (row 31), ") for line in lines) == 1
    assert "  missing (1): omega_3 (no row of that name in column A)" in lines
    assert len(lines) == 5          # the file, the counts, the verdict and score (issue 21), empty, missing


def test_another_class_key_or_roster_is_one_warning(issued, tmp_path, capsys):
    """The teacher gives another class's key (or roster): every book's seal fails, and one
    warning says what is the likely cause, rather than only a class of "edited" books."""
    other = tmp_path / "other"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "2", "--out", str(other),
                 "--seed", "5"]) == 0
    capsys.readouterr()
    books = sorted(str(p) for p in issued.glob("*-key.xlsx"))
    code, out, err = run(capsys, "validate", "--lang", "en", *books, "--roster", issued / "roster.csv",
                         "--key", other / KEY_FILE)
    assert code == 1 and "none of the 2 issued books' seals matches the key" in err
    assert "scene sheet edited" in out
    code, out, err = run(capsys, "validate", "--lang", "en", *books, "--roster", issued / "roster.csv")
    assert code == 0 and "warning" not in err                      # the right key: no warning
