"""Issue 32's "done when", through the grader: a correct book that computes with SWITCH, IFS,
VLOOKUP of a computed table, MDETERM (Cramer's rule, the 2x2 determinant of the velocity
system from cells) or ACOT scores 100; the same book with one formula wrong names that row.

The books are typed into LibreOffice Calc through UNO and saved by it, as students make them
(tests/helpers/studentbooks.py): Calc writes the functions newer than Excel 2007 as Excel
stores them (`_xlfn.SWITCH(...)`, `_xlfn.IFS(...)`, `_xlfn.ACOT(...)`), so the test reads the
same files Excel would write. Each kind of book is checked to hold its function, so a recipe
that silently typed something else cannot pass."""
from __future__ import annotations

import zipfile
from dataclasses import replace
from pathlib import Path

import pytest
from helpers.clirun import run
from helpers.studentbooks import Recipe, key_values, make_books, uno_available

from sheetkin.course import grades
from sheetkin.course.issued import KEY_FILE, Options, read_key, read_roster
from sheetkin.course.validator import validate
from sheetkin.xlsx.table import SUPPORTED

ROOT = Path(__file__).resolve().parents[2]
pytestmark = [pytest.mark.libreoffice,
              pytest.mark.skipif(not uno_available(), reason="LibreOffice with python3-uno is not installed")]

MAIN = "Кинематика"


def _recipes(ex: Path, key: Path) -> dict[str, tuple[Recipe, str, str]]:
    """{book: (recipe, the function's name as stored in the file, the row it computes)}; a
    book whose name ends in "_wrong" has that row's formula wrong in one way a student errs."""
    rows = Recipe(ex, key)._rows()
    r = {n: rows[n] for n in ("phi_1", "i", "L2", "L3", "branch_g1", "Delta_g1", "sin_2", "cos_2", "sin_3",
                              "cos_3", "psi_p_g1", "psi_m_g1", "xi_p_g1", "xi_m_g1", "asm_g1", "P_g1", "Q_g1",
                              "F_g1", "D_g1", "phi_2")}
    positions = Recipe(ex, key)._positions()

    def switch(wrong: bool) -> Recipe:
        # the branch chosen by SWITCH on the given branch sign (the wrong book swaps them)
        plus, minus = "{c}" + str(r["psi_p_g1"]), "{c}" + str(r["psi_m_g1"])
        a, b = (minus, plus) if wrong else (plus, minus)
        return Recipe(ex, key).honest().formula(
            "phi_2", f"=IF({{c}}{r['asm_g1']};MOD(DEGREES(SWITCH($D${r['branch_g1']};1;{a};{b}));360);"
                     "\"не собирается\")")

    def ifs(wrong: bool) -> Recipe:
        xi_p, xi_m = "{c}" + str(r["xi_p_g1"]), "{c}" + str(r["xi_m_g1"])
        other = xi_p if wrong else xi_m      # the wrong book takes the same branch both ways
        return Recipe(ex, key).honest().formula(
            "phi_3", f"=IF({{c}}{r['asm_g1']};MOD(DEGREES(IFS($D${r['branch_g1']}=1;{xi_p};"
                     f"$D${r['branch_g1']}=-1;{other}));360);\"не собирается\")")

    def vlookup(wrong: bool) -> Recipe:
        # a helper sheet "Таблица": position i and cos of phi_2 computed from the main sheet,
        # one position a row (transposed); cos_2 looked up by i
        recipe = Recipe(ex, key).honest()
        recipe.ops.append(["insert_sheet", "Таблица", 1])
        cells = []
        for k in range(positions):
            col = _letter(5 + k)
            cells.append([k + 1, 1, f"=$'{MAIN}'.{col}{r['i']}"])
            cells.append([k + 1, 2, f"=COS(RADIANS($'{MAIN}'.{col}{r['phi_2']}))"])
        recipe.ops.append(["formulas", "Таблица", cells])
        column = 2 if not wrong else 1
        return recipe.formula("cos_2", f"=IF({{c}}{r['asm_g1']};VLOOKUP({{c}}{r['i']};$Таблица.$A$1:$B${positions};"
                                       f"{column};0);\"не собирается\")")

    def mdeterm(wrong: bool) -> Recipe:
        # Cramer's rule as in the lecture: the velocity system's matrix
        # [[-L2 sin2, L3 sin3], [L2 cos2, -L3 cos3]] written in a helper sheet "Крамер", two
        # rows a position, and its determinant by MDETERM
        recipe = Recipe(ex, key).honest()
        recipe.ops.append(["insert_sheet", "Крамер", 1])
        cells = []
        for k in range(positions):
            col, top = _letter(5 + k), 2 * k + 1
            m = f"$'{MAIN}'."
            cells += [[top, 1, f"=-{m}$D${r['L2']}*{m}{col}{r['sin_2']}"],
                      [top, 2, f"={m}$D${r['L3']}*{m}{col}{r['sin_3']}"],
                      [top + 1, 1, f"={m}$D${r['L2']}*{m}{col}{r['cos_2']}"],
                      [top + 1, 2, f"=-{m}$D${r['L3']}*{m}{col}{r['cos_3' if not wrong else 'sin_3']}"]]
        recipe.ops.append(["formulas", "Крамер", cells])
        for k in range(positions):
            top = 2 * k + 1
            recipe.formula("Delta_g1", f"=IF({{c}}{r['asm_g1']};MDETERM($Крамер.$A${top}:$B${top + 1});"
                                       "\"не собирается\")", col=5 + k)
        return recipe

    def acot(wrong: bool) -> Recipe:
        # the half-angle solution with ACOT for the issued branch (-1): the key's
        # psi = 2 ATAN2(P + F; Q - sqrt D) is 2 acot((P + F)/(Q - sqrt D)) up to a turn, which
        # MOD(...; 360) takes away (the wrong book takes the other branch's + sqrt D)
        sign = "+" if wrong else "-"
        return Recipe(ex, key).honest().formula(
            "phi_2", f"=IF({{c}}{r['asm_g1']};MOD(DEGREES(2*ACOT(({{c}}{r['P_g1']}+{{c}}{r['F_g1']})/"
                     f"({{c}}{r['Q_g1']}{sign}SQRT({{c}}{r['D_g1']}))));360);\"не собирается\")")

    def bitand(wrong: bool) -> Recipe:
        # a function sheetkin's table lacks (LibreOffice and Excel 2013 have it): cos_2 times
        # BITAND(3;1) = 1; the wrong book takes the sine
        trig = "SIN" if wrong else "COS"
        return Recipe(ex, key).honest().formula(
            "cos_2", f"=IF({{c}}{r['asm_g1']};BITAND(3;1)*{trig}(RADIANS({{c}}{r['phi_2']}));\"не собирается\")")

    def bitand_cheat() -> Recipe:
        # cos_2 typed as the key's numbers, each disguised as work by a function sheetkin lacks
        # (BITAND(3;1) = 1): right on the issued data, the same numbers on any other
        recipe = Recipe(ex, key).honest()
        for k, v in enumerate(key_values(key, ["cos_2"])["cos_2"]):
            recipe.formula("cos_2", f"=IF({{c}}{r['asm_g1']};BITAND(3;1)*{v!r};\"не собирается\")", col=5 + k)
        return recipe

    def index_range(wrong: bool) -> Recipe:
        # a range ending in a function (phi_2's cell to INDEX of it: the cell itself), which
        # sheetkin computes since issue 32 (it was a formula its parser did not read)
        trig = "SIN" if wrong else "COS"
        return Recipe(ex, key).honest().formula(
            "cos_2", f"=IF({{c}}{r['asm_g1']};{trig}(RADIANS(SUM({{c}}{r['phi_2']}:INDEX({{c}}{r['phi_2']}:"
                     f"{{c}}{r['cos_2'] - 1};1))));\"не собирается\")")

    out = {}
    for name, make, stored, row in (("index_range", index_range, ":INDEX(", "cos_2"),
                                    ("bitand", bitand, "_xlfn.BITAND(", "cos_2"),
                                    ("switch", switch, "_xlfn.SWITCH(", "phi_2"), ("ifs", ifs, "_xlfn.IFS(", "phi_3"),
                                    ("vlookup", vlookup, "VLOOKUP(", "cos_2"),
                                    ("mdeterm", mdeterm, "MDETERM(", "Delta_g1"),
                                    ("acot", acot, "_xlfn.ACOT(", "phi_2")):
        out[name] = (make(False), stored, row)
        out[name + "_wrong"] = (make(True), stored, row)
    out["bitand_cheat"] = (bitand_cheat(), "_xlfn.BITAND(", "cos_2")
    return out


def _letter(c: int) -> str:
    from openpyxl.utils import get_column_letter
    return get_column_letter(c)


@pytest.fixture(scope="module")
def books(tmp_path_factory):
    from sheetkin.cli.commands import main
    d = tmp_path_factory.mktemp("functions32")
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "1", "--out", str(d), "--seed", "7"]) == 0
    ex, key = next(d.glob("*-01-exercise.xlsx")), next(d.glob("*-01-key.xlsx"))
    options = Options(read_roster(str(d / "roster.csv")), read_key(d / KEY_FILE))
    made = _recipes(ex, key)
    paths = {d / f"{name}.xlsx": recipe for name, (recipe, _, _) in made.items()}
    make_books(paths)
    return {name: (d / f"{name}.xlsx", stored, row) for name, (_, stored, row) in made.items()}, options, d


def _sheet_xml(path: Path) -> str:
    with zipfile.ZipFile(path) as z:
        return "".join(z.read(n).decode("utf-8") for n in z.namelist() if n.startswith("xl/worksheets/sheet"))


FUNCTIONS = ["switch", "ifs", "vlookup", "mdeterm", "acot", "index_range"]


@pytest.mark.parametrize("name", FUNCTIONS)
def test_a_correct_book_using_the_function_scores_100(books, name):
    made, options, _ = books
    path, stored, row = made[name]
    assert stored in _sheet_xml(path), f"{name}: the saved book does not call {stored}"
    rep = validate(path, options=options)
    assert rep.error is None, rep.error
    assert grades.score(rep) == 100, grades.explain(rep)
    assert next(r for r in rep.rows if r.name == row).status == "correct"
    assert not any(r.not_judged for r in rep.rows)          # computed here, not left to the teacher


@pytest.mark.parametrize("name", FUNCTIONS)
def test_the_same_book_with_one_wrong_formula_names_that_row(books, name):
    made, options, _ = books
    path, stored, row = made[name + "_wrong"]
    assert stored in _sheet_xml(path)
    rep = validate(path, options=options)
    assert rep.error is None, rep.error
    assert grades.score(rep) < 100
    wrong = [r.name for r in rep.rows if r.status == "wrong"]
    assert wrong and wrong[0] == row, wrong


def test_sheetkin_validate_grades_the_switch_book_100(books, capsys, tmp_path):
    made, _, d = books
    grades_csv = tmp_path / "grades.csv"
    code, out, err = run(capsys, "validate", made["switch"][0], "--key", d / KEY_FILE,
                         "--roster", d / "roster.csv", "--grades", grades_csv)
    assert code == 0, out + err
    assert ",100" in grades_csv.read_text("utf-8-sig"), grades_csv.read_text("utf-8-sig")


@pytest.mark.parametrize("name", ["bitand"])
def test_what_sheetkin_cannot_compute_is_computed_by_libreoffice(books, name):
    """Issue 31 item 2: the cells sheetkin cannot compute (a function its table lacks, a
    formula it cannot read) take LibreOffice's recalculation and are judged: the right book
    scores 100, the wrong one names its row."""
    assert "BITAND" not in SUPPORTED          # else this test no longer tests the fallback
    made, options, _ = books
    path, stored, row = made[name]
    assert stored in _sheet_xml(path)
    rep = validate(path, options=options)
    assert grades.score(rep) == 100, grades.explain(rep)
    assert not any(r.not_judged for r in rep.rows)
    rep = validate(made[name + "_wrong"][0], options=options)
    wrong = [r.name for r in rep.rows if r.status == "wrong"]
    assert wrong and wrong[0] == row, wrong
    assert grades.score(rep) < 100


def test_libreoffice_computes_the_nudged_copies_too(books):
    """Issue 31 item 2, the nudged copies: cos_2 through BITAND (a function sheetkin lacks) is
    computed by LibreOffice on the nudged given data as on the issued ones. The honest book
    follows them (100, no note); its cheated twin, the key's numbers typed times BITAND(3;1),
    is right on the issued data and "does not follow the given data" at every position of
    cos_2, which earns nothing."""
    made, options, _ = books
    rep = validate(made["bitand"][0], options=options)
    cos_2 = next(r for r in rep.rows if r.name == "cos_2")
    assert cos_2.status == "correct" and not cos_2.not_following and not cos_2.not_judged
    assert not any("does not follow" in n for n in rep.notes), rep.notes
    assert grades.score(rep) == 100, grades.explain(rep)
    path, stored, row = made["bitand_cheat"]
    assert stored in _sheet_xml(path)
    rep = validate(path, options=options)
    cos_2 = next(r for r in rep.rows if r.name == row)
    assert cos_2.status == "correct" and not cos_2.not_judged          # right on the issued data
    assert cos_2.not_following, grades.explain(rep)
    assert set(cos_2.typed_cells) >= set(cos_2.not_following)
    assert any("does not follow the given data" in n and "cos_2" in n and "BITAND" in n for n in rep.notes), rep.notes
    assert grades.score(rep) < 100, grades.explain(rep)


def test_without_libreoffice_what_reads_it_is_not_judged(books):
    """--no-libreoffice: the rows reading the unknown function are "not judged: check by
    hand", out of the denominator; none is wrong, so the right and the wrong book alike score
    on the rest (the teacher checks cos_2 and what reads it by hand)."""
    made, options, _ = books
    off = replace(options, libreoffice=False)
    for name in ("bitand", "bitand_wrong", "bitand_cheat"):
        rep = validate(made[name][0], options=off)
        unjudged = [r.name for r in rep.rows if r.not_judged]
        assert unjudged and unjudged[0] == "cos_2", unjudged
        assert not [r.name for r in rep.rows if r.status == "wrong" and not r.not_judged]
        assert any("not judged: check by hand" in n for n in rep.notes)
        assert grades.score(rep) == 100, grades.explain(rep)
