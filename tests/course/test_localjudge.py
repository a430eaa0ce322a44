"""Each row judged on its own inputs (issue 13, item 3): the four-bar's workbook filled with
the mistakes users made (a rounded typed number, a sign error, a number typed over a
formula, a wrong intermediate formula, two mistakes at once) names exactly the rows at
fault, with the typed number's cell and digits, and never a row that is right on its inputs;
the same after LibreOffice saved the books; and for a sign flipped in any accepted row of
any bundled workbook, that row is the only cause."""
from __future__ import annotations

import dataclasses
import html
import re
import zipfile
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.libreoffice import recalculate
from helpers.sheetrows import rows_of
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from openpyxl.utils import get_column_letter

import sheetkin
from sheetkin.course.grades import all_correct
from sheetkin.course.localjudge import judge, magnitude, name_causes, typed_digits, typed_text, typed_tolerance
from sheetkin.course.reference import reference_book, row_ancestors
from sheetkin.course.report import json_report, text_report
from sheetkin.course.report_model import RowReport
from sheetkin.course.validator import validate
from sheetkin.sheet.workbook import sheet_rows
from sheetkin.xlsx.evaluator import evaluate

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
POSITIONS = range(5, 18)             # columns E..Q: the four-bar's 13 positions
OMEGA_COL = 12                       # column L, position 8: omega_2 = -3.22936...


def flip(ws, row: int, cols=POSITIONS) -> None:
    for c in cols:
        ws.cell(row, c).value = "=-(" + ws.cell(row, c).value[1:] + ")"


@pytest.fixture(scope="module")
def values(fourbar):
    """The correct book's values: (row name, column) -> value."""
    book = evaluate(fourbar)
    ws = openpyxl.load_workbook(fourbar).worksheets[0]
    return {(n, c): book.value(book.order[0], r, c) for n, r in rows_of(ws).items() for c in range(4, 18)}


# ------------------------------------------------------------------ the mistakes
def rounded_omega(ws, rows, v):
    """(a) omega_2 typed rounded to 3 significant digits at one position (-3.23 for -3.22936)."""
    ws.cell(rows["omega_2"], OMEGA_COL).value = float(f"{v['omega_2', OMEGA_COL]:.3g}")


def sign_vx_S2(ws, rows, v):
    """(b) a sign error in the velocity of a point on the coupler (the issue's vx_E)."""
    flip(ws, rows["vx_S2"])


def sign_vx_A(ws, rows, v):
    """(b') a sign error in hinge A's velocity, which every velocity below reads."""
    flip(ws, rows["vx_A"])


def full_digits_over_formula(ws, rows, v):
    """(c) omega_2's true values typed over its formulas, every digit (repr)."""
    for c in POSITIONS:
        ws.cell(rows["omega_2"], c).value = v["omega_2", c]


def wrong_number_over_formula(ws, rows, v):
    """(c') a wrong number typed over a formula (omega_3 at position 8 off by 10 %)."""
    ws.cell(rows["omega_3"], OMEGA_COL).value = round(1.1 * v["omega_3", OMEGA_COL], 3)


def wrong_F(ws, rows, v):
    """(d) the group's F row with the coupler's length where the rocker's belongs."""
    for c in POSITIONS:
        cell = ws.cell(rows["F_g1"], c)
        old = f"-$D${rows['L3']}^2)"
        assert old in cell.value
        cell.value = cell.value.replace(old, f"-$D${rows['L2']}^2)")


def wrong_P(ws, rows, v):
    """(d') the group's P row with a sign error (x_O1 + x_A)."""
    for c in POSITIONS:
        cell = ws.cell(rows["P_g1"], c)
        assert "-" in cell.value
        cell.value = cell.value.replace("-", "+", 1)


def two_mistakes(ws, rows, v):
    """omega_2 rounded at one position and omega_3's sign flipped everywhere."""
    rounded_omega(ws, rows, v)
    flip(ws, rows["omega_3"])


def hand_calculation(ws, rows, v):
    """omega_2 rounded (3 digits) and f1_g1, which reads it, typed to 6 digits as a
    calculator gives it from the unrounded omega_2: f1_g1 is right (its digits plus what
    omega_2's carry into it), omega_2 is the cause."""
    rounded_omega(ws, rows, v)
    ws.cell(rows["f1_g1"], OMEGA_COL).value = float(f"{v['f1_g1', OMEGA_COL]:.6g}")


def copied_over_broken_chain(ws, rows, v):
    """vx_A's sign flipped, and omega_2's true value (every digit, as from the answer key)
    typed at one position: omega_2 is right but not on the student's own inputs; it carries
    no error down, so vx_A alone is the cause."""
    sign_vx_A(ws, rows, v)
    ws.cell(rows["omega_2"], OMEGA_COL).value = v["omega_2", OMEGA_COL]


def derived_typed(ws, rows, v):
    """A derived value of the input block (column D) typed wrong: Alfa_A = L1 cos Fi0."""
    ws.cell(rows["Alfa_A"], 4).value = 0.15


MISTAKES = {f.__name__: f for f in (rounded_omega, sign_vx_S2, sign_vx_A, full_digits_over_formula,
                                    wrong_number_over_formula, wrong_F, wrong_P, two_mistakes,
                                    hand_calculation, copied_over_broken_chain, derived_typed)}
CAUSES = {"rounded_omega": {"omega_2"}, "sign_vx_S2": {"vx_S2"}, "sign_vx_A": {"vx_A"},
          "full_digits_over_formula": set(), "wrong_number_over_formula": {"omega_3"},
          "wrong_F": {"F_g1"}, "wrong_P": {"P_g1"}, "two_mistakes": {"omega_2", "omega_3"},
          "hand_calculation": {"omega_2"}, "copied_over_broken_chain": {"vx_A"}, "derived_typed": {"Alfa_A"}}


@pytest.fixture(scope="module")
def books(fourbar, values, tmp_path_factory) -> dict[str, Path]:
    """Every mistake in a book of its own, edited with openpyxl as a student would."""
    d = tmp_path_factory.mktemp("mistakes")
    out = {}
    for name, change in MISTAKES.items():
        wb = openpyxl.load_workbook(fourbar)
        ws = wb.worksheets[0]
        change(ws, rows_of(ws), values)
        out[name] = d / f"{name}.xlsx"
        wb.save(out[name])
    return out


def by_name(rep):
    return {r.name: r for r in rep.rows}


def causes(rep) -> set[str]:
    return {r.name for r in rep.causes}


@pytest.mark.parametrize("mistake", sorted(MISTAKES))
def test_the_causes_are_the_rows_at_fault(books, mistake):
    rep = validate(books[mistake])
    assert rep.error is None
    assert causes(rep) == CAUSES[mistake]
    for r in rep.rows:
        assert r.local in ("right", "wrong"), (r.name, r.status, r.local)
        assert not r.cause or r.local == "wrong"                 # right on its inputs: never a cause
        if r.status == "wrong" and not r.cause:                  # wrong only because of a cause above
            assert r.because_of and set(r.because_of) <= CAUSES[mistake], r
            # right on its inputs (omega_2 typed from the key is right, but not on its inputs)
            assert r.local == "right" or (mistake, r.name) == ("copied_over_broken_chain", "omega_2")
    # a typed number earns nothing even when right (issue 21): such a book is not "all correct"
    assert all_correct(rep) == (not CAUSES[mistake] and not rep.typed)


def test_rounded_typed_number_is_named_with_its_cell_and_digits(books, values, fourbar):
    rep = validate(books["rounded_omega"])
    rows = by_name(rep)
    om = rows["omega_2"]
    assert om.source == "typed" and om.status == "wrong" and om.wrong_cells == [OMEGA_COL - 4]
    assert om.got == -3.23 and om.expected == values["omega_2", OMEGA_COL]
    cell = f"{get_column_letter(OMEGA_COL)}{om.row}"
    m = re.fullmatch(rf"{cell} omega_2 typed -3\.23, 3 digits: downstream rows differ by up to (\S+)", om.note)
    assert m, om.note
    # the largest relative difference of the rows below omega_2, from the two books' values
    good, bad = evaluate(fourbar), evaluate(books["rounded_omega"])
    ws = openpyxl.load_workbook(fourbar).worksheets[0]
    below = [n for n, anc in row_ancestors(rep.variant_scene).items() if "omega_2" in anc and n in rows]
    worst = 0.0
    for n in below:
        r = rows_of(ws)[n]
        a = np.array([good.value(good.order[0], r, c) for c in POSITIONS], dtype=object)
        b = np.array([bad.value(bad.order[0], r, c) for c in POSITIONS], dtype=object)
        num = [i for i in range(13) if isinstance(a[i], float)]
        if num:
            scale = max(abs(a[i]) for i in num)
            worst = max(worst, max(abs(b[i] - a[i]) for i in num) / scale)
    assert 1e-5 < worst < 1e-2 and m.group(1) == magnitude(worst)
    # the four formulas the issue saw blamed: wrong, right on their inputs, not causes
    for n in ("f1_g1", "f2_g1", "vx_S2", "vy_S2"):
        assert rows[n].status == "wrong" and rows[n].local == "right" and not rows[n].cause
        assert rows[n].because_of == ["omega_2"] and rows[n].wrong_cells == [OMEGA_COL - 4]
    text = text_report(rep)
    first = next(line for line in text.splitlines() if "likely cause" in line)
    assert om.note in first and "wrong only because they depend on omega_2: f1_g1, f2_g1" in text


def test_sign_error_names_the_row_and_what_reads_it(books):
    rep = validate(books["sign_vx_A"])
    rows = by_name(rep)
    assert rows["vx_A"].status == "wrong" and rows["vx_A"].source == "formula" and not rows["vx_A"].note
    wrong = {r.name for r in rep.wrong}
    assert {"omega_2", "omega_3", "vx_B", "eps_2", "ay_A"} <= wrong and "ax_A" not in wrong
    assert all(rows[n].because_of == ["vx_A"] for n in wrong - {"vx_A"})


def test_typed_over_a_formula(books, values):
    """Decision: a number typed over a formula with every digit equals its formula: not a
    cause, not wrong (its source says typed); a wrong number typed is the cause, its note
    saying what its inputs give."""
    rep = validate(books["full_digits_over_formula"])
    om = by_name(rep)["omega_2"]
    assert om.source == "typed" and om.local == "right" and not om.cause and not om.note
    assert not rep.wrong and [r.name for r in rep.typed] == ["omega_2"] and not all_correct(rep)  # typed, not computed
    rep = validate(books["wrong_number_over_formula"])
    om = by_name(rep)["omega_3"]
    typed = round(1.1 * values["omega_3", OMEGA_COL], 3)
    assert om.cause and om.wrong_cells == [OMEGA_COL - 4]
    assert om.note.startswith(f"{get_column_letter(OMEGA_COL)}{om.row} omega_3 typed {typed_text(typed)}, "
                              f"{typed_digits(typed)} digits (its inputs give {values['omega_3', OMEGA_COL]:.6g}): "
                              "downstream rows differ by up to ")


def test_wrong_intermediate_formula(books):
    for mistake, row in (("wrong_F", "F_g1"), ("wrong_P", "P_g1")):
        rep = validate(books[mistake])
        rows = by_name(rep)
        assert rows[row].local == "wrong" and rows[row].cause
        assert {"phi_2", "phi_3", "omega_2", "x_B"} <= {r.name for r in rep.wrong}
        assert all(r.because_of == [row] for r in rep.wrong if r.name != row)


def test_two_mistakes_each_dependent_blamed_on_its_own_causes(books):
    rep = validate(books["two_mistakes"])
    rows = by_name(rep)
    alone = by_name(validate(books["rounded_omega"]))["omega_2"].note
    assert rows["omega_2"].note == alone and not rows["omega_3"].note     # omega_3's error not counted
    assert rows["f1_g1"].because_of == ["omega_2", "omega_3"]       # reads both
    assert rows["vx_S2"].because_of == ["omega_2"]                   # on the coupler: omega_2 only
    assert rows["vx_S3"].because_of == ["omega_3"]                   # on the rocker: omega_3 only
    assert rows["vx_S2"].wrong_cells == [OMEGA_COL - 4] and len(rows["vx_S3"].wrong_cells) > 6
    text = text_report(rep)
    lines = [line for line in text.splitlines() if "likely cause" in line]
    assert len(lines) == 2 and "omega_2 typed" in lines[0] and lines[1].startswith("  likely cause: omega_3")


def test_hand_calculation_from_rounded_numbers_is_right(books, values):
    """A typed number computed from an unrounded input is right within what the input's
    digits carry into it (without that propagation it would be off by ~0.03)."""
    rep = validate(books["hand_calculation"])
    f1 = by_name(rep)["f1_g1"]
    assert f1.source == "typed" and f1.status == "correct" and f1.local == "right" and not f1.cause
    assert causes(rep) == {"omega_2"}


def test_a_right_number_on_wrong_inputs_is_not_a_cause(books):
    rep = validate(books["copied_over_broken_chain"])
    om = by_name(rep)["omega_2"]
    assert om.source == "typed" and om.local == "wrong" and not om.cause
    assert om.status == "wrong" and OMEGA_COL - 4 not in om.wrong_cells        # only its formulas' cells
    assert om.because_of == ["vx_A"]


def test_a_derived_value_is_named(books):
    rep = validate(books["derived_typed"])
    rows = by_name(rep)
    a = rows["Alfa_A"]
    assert a.kind == "derived" and a.status == "wrong" and a.first_wrong is None and a.got == 0.15
    assert a.note.startswith(f"D{a.row} Alfa_A typed 0.15, 2 digits (its inputs give 0.14): downstream rows differ")
    assert rows["x_A"].because_of == ["Alfa_A"] and rows["x_A"].local == "right"
    assert "likely cause: Alfa_A" in text_report(rep)


def test_json_carries_local_and_note(books):
    rep = validate(books["rounded_omega"])
    import json
    d = json.loads(json_report([rep]))["reports"][0]
    om = next(r for r in d["rows"] if r["name"] == "omega_2")
    assert om["local"] == "wrong" and om["note"].startswith("L") and om["cause"]
    assert next(r for r in d["rows"] if r["name"] == "f1_g1")["local"] == "right"
    assert d["summary"]["causes"] == ["omega_2"]
    from sheetkin.course.report_html import html_page
    assert html.escape(om["note"]) in html_page([rep])        # the HTML details show the note too


def test_given_data_different_from_the_reference(fourbar):
    """Graded against another variant (as against the issued one, when the student changed
    L1): every row is right on the student's inputs, and the wrong ones are wrong because
    of L1, not of a row."""
    text = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    scene = sheetkin.parse_scene(text, "fourbar.toml")
    issued = dataclasses.replace(scene, crank=dataclasses.replace(scene.crank, length=0.15))
    ref = reference_book(issued)
    student = evaluate(fourbar)
    ws = openpyxl.load_workbook(fourbar).worksheets[0]
    names = {n: r for n, r in rows_of(ws).items() if r >= 5}
    rows_ = sheet_rows(scene).rows
    graded = [r.name for r in rows_ if r.kind in ("calc", "accepted", "guard") and r.name != "i"]
    local = judge(ref, student, student.order[0], names, graded)
    assert local.changed("L1") and not local.changed("L2")
    assert all(local.judgements[n].local == "right" for n in graded)
    reps = [RowReport(n, names[n], "wrong" if n in ("x_A", "omega_2") else "correct") for n in graded]
    name_causes(reps, local, row_ancestors(scene), {r.name for r in rows_ if r.kind == "input"},
                lambda n, c: RowReport(n, names[n], "correct"))
    assert not [r.name for r in reps if r.cause]
    assert {r.name: r.because_of for r in reps if r.status == "wrong"} == {"x_A": ["L1"], "omega_2": ["L1"]}


def test_number_helpers():
    assert [typed_digits(x) for x in (-2.54, 0.14, 3.0, 1200.0, 0.000123, 1.5e-07, 5.4347996430266345)] == \
        [3, 2, 1, 2, 3, 2, 17]
    assert typed_tolerance(-2.54) == pytest.approx(0.005) and typed_tolerance(3.0) == 0.5
    assert [magnitude(x) for x in (1.3e-4, 9.6e-4, 0.0, 0.25, 2.0, float("inf"))] == \
        ["1e-4", "1e-3", "0", "0.2", "2", "a non-number"]
    assert typed_text(3.0) == "3" and typed_text(-2.54) == "-2.54"


# ------------------------------------------------------------------ LibreOffice
def test_libreoffice_saved_books_give_the_same_causes(soffice, books, tmp_path):
    """The mistakes' books opened, recalculated and saved by LibreOffice (one soffice run):
    the same causes and the same notes."""
    saved = recalculate(list(books.values()), tmp_path)
    for name, path in books.items():
        ours, theirs = validate(path), validate(saved[path.resolve()])
        assert causes(theirs) == CAUSES[name], name
        assert [(r.name, r.note, r.because_of) for r in theirs.rows] == \
            [(r.name, r.note, r.because_of) for r in ours.rows], name


# ------------------------------------------------------------------ property
def _accepted_rows() -> list[tuple[str, str, int]]:
    """(bundled workbook, accepted row, its row) for every accepted row of every bundled book."""
    out = []
    for path in sorted(WORKBOOKS.glob("*.xlsx")):
        ws = openpyxl.load_workbook(path).worksheets[0]
        text = (WORKBOOKS / f"{path.stem}.toml").read_text(encoding="utf-8")
        kinds = {r.name: r.kind for r in sheet_rows(sheetkin.parse_scene(text, path.name)).rows}
        out += [(path.stem, n, r) for n, r in rows_of(ws).items() if kinds.get(n) == "accepted"]
    return out


ACCEPTED = _accepted_rows()


def _flipped(stem: str, row: int, dst: Path) -> Path:
    """The bundled workbook with every formula of one row sign-flipped, patched in the
    sheet's XML (fast: no openpyxl round trip)."""
    src = WORKBOOKS / f"{stem}.xlsx"
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "xl/worksheets/sheet1.xml":
                pattern = rb'(<c r="[A-Z]+%d"[^>]*>\s*<f>)([^<]*)(</f>)' % row
                data, n = re.subn(pattern, rb"\g<1>-(\g<2>)\g<3>", data)
                assert n > 0
            zout.writestr(item, data)
    return dst


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(pick=st.sampled_from(ACCEPTED))
def test_a_sign_flipped_accepted_row_is_the_only_cause(pick, tmp_path):
    stem, name, row = pick
    rep = validate(_flipped(stem, row, tmp_path / f"{stem}_{name}.xlsx"))
    assert rep.error is None
    flipped = by_name(rep)[name]
    if flipped.status == "wrong":          # (a row of zeros, or of 180 deg angles, flips to itself)
        assert causes(rep) == {name}, (stem, name, [(r.name, r.local) for r in rep.causes])
        assert all(r.because_of == [name] for r in rep.wrong if r.name != name)
    else:
        assert not rep.wrong and not rep.causes
