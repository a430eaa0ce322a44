"""A computed cell computes only when its formula reaches the book's given data through
formulas (sheetkin.xlsx.precedents): the key's values pasted on a scratch sheet, far right of
the table or behind a defined name, then read by "=Лист2!C7", are typed, not computed. Honest
books keep full marks: a scratch sheet of real formulas, helper cells, PI() and 180 in
formulas, a row that reads only the position i, a derived value typed as a number.
Books written with openpyxl; tests/course/test_pasted_numbers_and_copies_uno.py has the same through LibreOffice."""
from __future__ import annotations

from pathlib import Path

import openpyxl
import pytest
from openpyxl.utils import get_column_letter
from openpyxl.workbook.defined_name import DefinedName

from sheetkin.course import grades
from sheetkin.course.grades import all_correct
from sheetkin.course.issued import KEY_FILE, Options, read_key, read_roster
from sheetkin.course.validator import validate
from sheetkin.xlsx.evaluator import evaluate

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def issued(tmp_path_factory):
    d = tmp_path_factory.mktemp("pasted")
    from sheetkin.cli.commands import main
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "1", "--out", str(d), "--seed", "3"]) == 0
    ex, key = next(d.glob("*-01-exercise.xlsx")), next(d.glob("*-01-key.xlsx"))
    return d, ex, key, Options(read_roster(str(d / "roster.csv")), read_key(d / KEY_FILE))


def _filled(ex: Path, key: Path, out: Path, how) -> Path:
    """The exercise with every cell the key computes filled by how(ws, sheet2, r, c, formula,
    value) (it writes the cell); row numbers by name in `rows`."""
    kb = evaluate(key)
    kws = openpyxl.load_workbook(key).worksheets[0]
    wb = openpyxl.load_workbook(ex)
    ws = wb.worksheets[0]
    scratch = wb.create_sheet("Лист2")
    for row in kws.iter_rows(min_row=36):
        for cell in row:
            f = cell.value
            if isinstance(f, str) and f.startswith("=") and ws.cell(cell.row, cell.column).value is None:
                how(ws, scratch, cell.row, cell.column, f, kb.value(kb.order[0], cell.row, cell.column))
    wb.save(out)
    return out


def _rows(ws) -> dict[str, int]:
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if isinstance(ws.cell(r, 1).value, str)}


def _grade(path: Path, options) -> tuple:
    rep = validate(path, options=options)
    assert rep.error is None, rep.error
    return rep, grades.score(rep)


def test_pasted_numbers_read_by_formulas_are_typed(issued, tmp_path):
    d, ex, key, options = issued
    at: dict[str, int] = {"n": 0}

    def scratch(ws, sc, r, c, f, v):          # every number on Лист2, read by "=Лист2!C7"
        if c >= 5 and isinstance(v, float):
            at["n"] += 1
            sc.cell(at["n"], 3, v)
            ws.cell(r, c, f"=Лист2!C{at['n']}")
        else:
            ws.cell(r, c, f)

    def far(ws, sc, r, c, f, v):              # the numbers 40 columns right of the table
        if c >= 5 and isinstance(v, float):
            ws.cell(r, c + 40, v)
            ws.cell(r, c, f"={get_column_letter(c + 40)}{r}*1")
        else:
            ws.cell(r, c, f)

    for name, how in (("scratch", scratch), ("far", far)):
        rep, s = _grade(_filled(ex, key, tmp_path / f"{name}.xlsx", how), options)
        assert s <= grades.NO_FORMULA_CAP and not all_correct(rep), name
        assert grades.verdict(rep) == "typed, not computed"
        # every row of positions is typed; the derived values of column D hold their formulas
        positions = [r for r in grades.graded_rows(rep) if r.kind != "derived"]
        assert {r.name for r in rep.typed} == {r.name for r in positions} and all(r.reads_typed for r in rep.typed)
        assert all(r.status == "correct" and not r.is_typed for r in grades.graded_rows(rep) if r.kind == "derived")


def test_a_named_range_of_pasted_numbers_and_a_partial_paste(issued, tmp_path):
    """Half the rows read numbers pasted behind a defined name (implicit intersection of a
    row range); the other half compute: only the pasted rows are typed."""
    d, ex, key, options = issued
    ws0 = openpyxl.load_workbook(ex).worksheets[0]
    rows = _rows(ws0)
    pasted = {"x_A", "y_A", "vx_A"}
    by_row = {rows[n]: n for n in pasted}

    def half(ws, sc, r, c, f, v):
        if r in by_row and c >= 5:
            sc.cell(r, c, v)
            ws.cell(r, c, f"=SIN(1)*0+p_{by_row[r]}")
        else:
            ws.cell(r, c, f)
    path = _filled(ex, key, tmp_path / "named.xlsx", half)
    wb = openpyxl.load_workbook(path)
    last = get_column_letter(4 + 13)
    for n in pasted:
        wb.defined_names[f"p_{n}"] = DefinedName(f"p_{n}", attr_text=f"Лист2!$E${rows[n]}:${last}${rows[n]}")
    wb.save(path)
    rep, s = _grade(path, options)
    assert {r.name for r in rep.typed} == pasted
    assert all(r.reads_typed == list(range(1, 14)) for r in rep.typed)
    assert 0 < s < 100 and not all_correct(rep)
    rest = [r for r in grades.graded_rows(rep) if r.name not in pasted]
    assert rest and all(r.status == "correct" and not r.typed_cells for r in rest)


def test_honest_habits_keep_full_marks(issued, tmp_path):
    """A scratch sheet of real formulas (Fi read from Лист2, computed there from phi_1),
    a helper cell right of the table, PI() and 180 in formulas score 100. Delta_Fi_rad typed
    as a number costs that row only: dFi, which reads it and i (the position is given data),
    still computes."""
    d, ex, key, options = issued
    rows = _rows(openpyxl.load_workbook(ex).worksheets[0])

    def honest(ws, sc, r, c, f, v):
        col = get_column_letter(c)
        if r == rows["Fi"] and c >= 5:            # on the scratch sheet, as real formulas
            sc.cell(1, c, f"='{ws.title}'!{col}{rows['phi_1']}*PI()/180")
            ws.cell(r, c, f"=Лист2!{col}1")
        elif r == rows["cos_1"] and c >= 5:       # through a helper cell right of the table
            ws.cell(r, c + 30, f"=COS({col}{rows['Fi']})")
            ws.cell(r, c, f"={get_column_letter(c + 30)}{r}")
        elif r == rows["Delta_Fi_rad"] and c == 4:
            ws.cell(r, c, v)                      # typed: a number, where a formula was asked
        elif r == rows["dFi"] and c >= 5:
            ws.cell(r, c, f"={col}{rows['i']}*$D${rows['Delta_Fi']}/180*PI()")
        else:
            ws.cell(r, c, f)
    rep, s = _grade(_filled(ex, key, tmp_path / "honest.xlsx", honest), options)
    assert [r.name for r in rep.typed] == ["Delta_Fi_rad"], [(r.name, r.typed_cells) for r in rep.typed]
    total = len(grades.graded_rows(rep))
    assert s == pytest.approx(round(90 * (total - 1) / total + 10, 1)) and not all_correct(rep)
    rows_ = {r.name: r for r in rep.rows}
    assert rows_["dFi"].status == "correct" and not rows_["dFi"].is_typed

    def dfi_on_i(ws, sc, r, c, f, v):              # the same, Delta_Fi_rad computed: full marks
        if r == rows["dFi"] and c >= 5:
            ws.cell(r, c, f"={get_column_letter(c)}{rows['i']}*$D${rows['Delta_Fi']}/180*PI()")
        else:
            honest(ws, sc, r, c, f, v) if r != rows["Delta_Fi_rad"] else ws.cell(r, c, f)
    rep, s = _grade(_filled(ex, key, tmp_path / "honest2.xlsx", dfi_on_i), options)
    assert not rep.typed and s == 100.0 and all_correct(rep)


def test_derived_values_of_column_d_are_graded(issued, tmp_path):
    """Delta_Fi_rad, Alfa_A, Betta_A (column D, the student computes them) are graded as
    computed rows: a formula right, a wrong formula wrong, a number typed or read from a
    pasted number typed (it earns nothing), a blank one missing."""
    d, ex, key, options = issued
    rows = _rows(openpyxl.load_workbook(ex).worksheets[0])

    def derived(ws, sc, r, c, f, v):
        if r == rows["Delta_Fi_rad"] and c == 4:
            ws.cell(r, c, v)                                  # typed
        elif r == rows["Alfa_A"] and c == 4:
            sc["Z1"] = v
            ws.cell(r, c, "=Лист2!Z1")                        # reads a pasted number
        elif r == rows["Betta_A"] and c == 4:
            ws.cell(r, c, f + "+1")                           # wrong
        else:
            ws.cell(r, c, f)
    rep, s = _grade(_filled(ex, key, tmp_path / "derived.xlsx", derived), options)
    by = {r.name: r for r in rep.rows}
    assert by["Delta_Fi_rad"].is_typed and by["Delta_Fi_rad"].status == "correct"
    assert by["Alfa_A"].is_typed and by["Alfa_A"].reads_typed
    assert by["Betta_A"].status == "wrong" and by["Betta_A"].got == pytest.approx(by["Betta_A"].expected + 1)
    c = grades.counts(rep)
    assert c["typed"] == 2 and by["Betta_A"].kind == "derived" and not all_correct(rep)
    assert grades.row_verdict(by["Betta_A"]) == "wrong"

    def blank(ws, sc, r, c, f, v):
        if not (r == rows["Alfa_A"] and c == 4):
            ws.cell(r, c, f)
    rep, s = _grade(_filled(ex, key, tmp_path / "blank.xlsx", blank), options)
    assert {r.name: r.status for r in rep.rows}["Alfa_A"] == "empty" and grades.counts(rep)["missing"] == 1


def test_check_of_an_angle_taken_mod_a_full_turn_passes(issued, tmp_path):
    """Fi taken MOD 2*PI(): Fi is right modulo a full turn, and so is chk_Fi. The sheet's
    check takes its residual modulo the turn (status 0); in a book issued before it did (its
    residual -2 pi at 360 deg, the sheet's own status 1) the validator judges the check
    modulo the turn too, as the rows are. A residual that is not a whole turn still fails."""
    d, ex, key, options = issued
    rows = _rows(openpyxl.load_workbook(ex).worksheets[0])
    fi, i, chk = rows["Fi"], rows["i"], rows["chk_Fi"]

    def mod(ws, sc, r, c, f, v, shift=""):
        ws.cell(r, c, f"=MOD({f[1:]},2*PI()){shift}" if r == fi and c >= 5 else f)
    path = _filled(ex, key, tmp_path / "mod.xlsx", mod)
    sheet = openpyxl.load_workbook(path).worksheets[0].title
    assert evaluate(path).value(sheet, chk, 4) == 0                     # the sheet's own status: passes
    rep, s = _grade(path, options)
    assert "chk_Fi" not in rep.failing_checks and s == 100.0 and all_correct(rep)

    wb = openpyxl.load_workbook(path)                                  # the check as issued before
    for c in range(5, 18):
        col = get_column_letter(c)
        wb.worksheets[0].cell(chk, c, f"={col}{fi}-(RADIANS($D${rows['Fi0']})+{col}{i}*$D${rows['Delta_Fi_rad']})")
    wb.save(tmp_path / "old.xlsx")
    assert evaluate(tmp_path / "old.xlsx").value(sheet, chk, 4) == 1
    rep, s = _grade(tmp_path / "old.xlsx", options)
    assert "chk_Fi" not in rep.failing_checks and s == 100.0 and all_correct(rep)

    def off(ws, sc, r, c, f, v):
        mod(ws, sc, r, c, f, v, shift="+0.001")
    rep, s = _grade(_filled(ex, key, tmp_path / "off.xlsx", off), options)
    assert "chk_Fi" in rep.failing_checks and s < 100.0
