"""Issue 31 on books made as students make them: typed into LibreOffice Calc through UNO
(tests/helpers/studentbooks.py) and saved by it. Cheats that read the given data and throw them
away earn nothing for their rows; honest habits keep 100; the last position left empty keeps
most of the grade. The cheap variants (openpyxl) are in test_behaviour.py."""
from __future__ import annotations

from pathlib import Path

import pytest
from helpers.studentbooks import Recipe, key_values, make_books, uno_available

from sheetkin.course import grades
from sheetkin.course.behaviour import row_share
from sheetkin.course.issued import KEY_FILE, Options, read_key, read_roster
from sheetkin.course.validator import validate

ROOT = Path(__file__).resolve().parents[2]
pytestmark = [pytest.mark.libreoffice,
              pytest.mark.skipif(not uno_available(), reason="LibreOffice with python3-uno is not installed")]


@pytest.fixture(scope="module")
def books(tmp_path_factory):
    from sheetkin.cli.commands import main
    d = tmp_path_factory.mktemp("uno31")
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "1", "--out", str(d), "--seed", "7"]) == 0
    ex, key = next(d.glob("*-01-exercise.xlsx")), next(d.glob("*-01-key.xlsx"))
    options = Options(read_roster(str(d / "roster.csv")), read_key(d / KEY_FILE))
    rows = Recipe(ex, key)._rows()
    values = key_values(key, ["phi_2", "omega_3"])

    def pasted(recipe: Recipe) -> Recipe:
        """A sheet Лист2 with the key's phi_2 and omega_3 at the same addresses."""
        recipe.ops.append(["insert_sheet", "Лист2", 1])
        recipe.ops.append(["values", "Лист2", [[rows[n], 5 + k, v] for n, vs in values.items()
                                               for k, v in enumerate(vs)]])
        return recipe

    def typed_plus(recipe: Recipe, name: str, tail: str) -> Recipe:
        for k, v in enumerate(values[name]):
            recipe.formula(name, f"={v!r}{tail}", col=5 + k)
        return recipe

    made = {
        "honest": Recipe(ex, key).honest(),
        "habits": Recipe(ex, key).honest().wrap("phi_2", "=IFERROR({f};\"не собирается\")")
        .wrap("omega_3", "=IFERROR({f};\"не собирается\")")
        .wrap("cos_2", f"=IFERROR(COS(PI()/180*{{{{c}}}}{rows['phi_2']});\"не собирается\")"),
        "times_zero": typed_plus(typed_plus(Recipe(ex, key).honest(), "phi_2", f"+0*$D${rows['L1']}"),
                                 "omega_3", f"+{{c}}${rows['phi_1']}*0"),
        "if_false": pasted(Recipe(ex, key).honest()).wrap("phi_2", "=IF(FALSE();{f};$Лист2.{{c}}{{r}})")
        .wrap("omega_3", "=IF(FALSE();{f};$Лист2.{{c}}{{r}})"),
        "index_row_column": pasted(Recipe(ex, key).honest())
        .formula("phi_2", "=INDEX($Лист2.$A$1:$Z$200;ROW();COLUMN())")
        .formula("omega_3", "=INDEX($Лист2.$A$1:$Z$200;ROW();COLUMN())"),
    }
    # the wrap templates name the cell's own column and row: filled in per cell
    for recipe in made.values():
        for op in recipe.ops:
            if op[0] == "formulas":
                op[2] = [[r, c, f.replace("{c}", _letter(c)).replace("{r}", str(r))] for r, c, f in op[2]]
    paths = {d / f"{name}.xlsx": recipe for name, recipe in made.items()}
    make_books(paths)
    return {p.stem: p for p in paths}, options
# (setFormula reads Calc's own A1 syntax for another sheet: $Лист2.E83, not Лист2!E83)


def _letter(c: int) -> str:
    from openpyxl.utils import get_column_letter
    return get_column_letter(c)


def _grade(path, options):
    rep = validate(path, options=options)
    assert rep.error is None, rep.error
    return rep, grades.score(rep)


@pytest.mark.parametrize("name", ["honest", "habits"])
def test_honest_books_score_100(books, name):
    paths, options = books
    rep, s = _grade(paths[name], options)
    assert s == 100.0, (grades.explain(rep), rep.notes)


@pytest.mark.parametrize("name", ["times_zero", "if_false", "index_row_column"])
def test_cheats_made_in_calc_earn_nothing(books, name):
    paths, options = books
    rep, s = _grade(paths[name], options)
    by = {r.name: r for r in rep.rows}
    for row in ("phi_2", "omega_3"):
        assert row_share(by[row], rep.positions, False) == 0, (name, by[row])
    assert s < 100
    others = [r for r in grades.graded_rows(rep) if r.name not in ("phi_2", "omega_3")]
    assert all(grades.row_verdict(r) == "correct" for r in others)
