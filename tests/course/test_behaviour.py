"""Issue 31: a sheet is judged by what it computes. The student's formulas are evaluated again
on nudged given data (sheetkin/course/nudge.py, behaviour.py); a cell right on the issued data
but not on the nudged ones "does not follow the given data" and earns nothing. Honest habits
keep full marks; a row sheetkin cannot evaluate is not judged; credit is per position.

Books written with openpyxl as a student's LibreOffice saves them in formulas (the exercise,
the key's formulas typed in, one row cheated); test_behaviour_uno.py makes some through
LibreOffice."""
from __future__ import annotations

import math
from pathlib import Path

import openpyxl
import pytest
from openpyxl.utils import get_column_letter

from sheetkin.course import grades
from sheetkin.course.behaviour import row_share
from sheetkin.course.issued import KEY_FILE, Options, read_key, read_roster
from sheetkin.course.nudge import NUDGES, nudged_inputs, nudged_variants, same_configuration
from sheetkin.course.reference import reference_book, variant_scene
from sheetkin.course.validator import validate
from sheetkin.kinematics.scene import parse_scene
from sheetkin.xlsx.evaluator import evaluate

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "workbooks").glob("*.toml"))


# --------------------------------------------------------------------------- the nudges
@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.stem)
def test_nudges_keep_the_configuration(path):
    """Every bundled scene has NUDGES nudged variants; each moves the given data it nudges,
    assembles where the issued one does with every angle in its quadrant (checked here again
    against the solver's reference by its own rule: the angle rows' quadrants), and the same
    seed gives the same variants."""
    text = path.read_text(encoding="utf-8")
    scene = parse_scene(text, str(path))
    issued = reference_book(scene)
    positions = scene.crank.positions

    def vary(s, inputs):
        return variant_scene(s, inputs, positions, {})
    variants = nudged_variants(scene, text.encode(), issued, vary, reference_book)
    assert len(variants) == NUDGES
    again = nudged_variants(scene, text.encode(), issued, vary, reference_book)
    assert [v.inputs for v in variants] == [v.inputs for v in again]
    assert nudged_inputs(scene, b"another seal", 0, 0.04) != nudged_inputs(scene, text.encode(), 0, 0.04)
    sheet = issued.order[0]
    rows = {issued.sheets[sheet].consts.get((r, 1)): r for r in range(5, issued.sheets[sheet].max_row + 1)}
    for v in variants:
        assert v.inputs and all(x != 0 for x in v.inputs.values())
        assert same_configuration(scene, issued, v.reference)
        # the lengths really moved, the branches and Fi0, Delta_Fi did not
        assert any(abs(v.inputs[n] / issued.value(sheet, rows[n], 4) - 1) > 1e-4 for n in v.inputs)
        for name in ("Fi0", "Delta_Fi", *(n for n in rows if str(n).startswith("branch"))):
            assert name not in v.inputs
        # independently: the angle rows' sines and cosines keep their signs where they are not ~0
        ref = v.reference
        for n, r in rows.items():
            if not isinstance(n, str) or not n.startswith("phi_"):
                continue
            for c in range(5, 5 + positions):
                a, b = issued.value(sheet, r, c), ref.value(ref.order[0], r, c)
                if isinstance(a, float):
                    for f in (math.sin, math.cos):
                        if abs(f(math.radians(a))) > 1e-6:
                            assert f(math.radians(a)) * f(math.radians(b)) > 0, (n, c, a, b)


# --------------------------------------------------------------------------- books
@pytest.fixture(scope="module")
def classes(tmp_path_factory):
    """An issued variant of each scheme: (exercise, key, options)."""
    from sheetkin.cli.commands import main
    out = {}
    for stem in ("fourbar", "crank_slider", "shaper", "slotted_lever", "scotch_yoke"):
        d = tmp_path_factory.mktemp(stem)
        assert main(["variants", str(ROOT / "workbooks" / f"{stem}.toml"), "-n", "1", "--out", str(d),
                     "--seed", "5"]) == 0
        ex, key = next(d.glob("*-01-exercise.xlsx")), next(d.glob("*-01-key.xlsx"))
        out[stem] = (ex, key, Options(read_roster(str(d / "roster.csv")), read_key(d / KEY_FILE)))
    return out


class Cell:
    """What a recipe sees of one cell of the key: its place, formula (with "="), value, the
    rows by name, the pasted sheet (the key's values at the same addresses)."""

    def __init__(self, r, c, formula, value, rows, positions):
        self.r, self.c, self.formula, self.value, self.rows, self.positions = r, c, formula, value, rows, positions
        self.col = get_column_letter(c)
        self.k = c - 5

    @property
    def v(self) -> str:
        return repr(self.value)

    def at(self, name: str, col: str | None = None) -> str:
        return f"{col or self.col}${self.rows[name]}"


def make_book(ex: Path, key: Path, out: Path, recipes: dict, every=None, hide_scratch: bool = True) -> Path:
    """The exercise filled with the key's formulas; the rows named in `recipes` written by
    recipe(cell) instead; every(cell), if given, rewrites every formula. A sheet "Лист2" holds
    the key's values at the same addresses (a pasted copy of a classmate's sheet)."""
    kb = evaluate(key)
    kws = openpyxl.load_workbook(key).worksheets[0]
    wb = openpyxl.load_workbook(ex)
    ws = wb.worksheets[0]
    rows = {kws.cell(r, 1).value: r for r in range(1, kws.max_row + 1) if isinstance(kws.cell(r, 1).value, str)}
    positions = sum(1 for c in range(5, kws.max_column + 1) if isinstance(kws.cell(rows["i"], c).value, (int, float)))
    scratch = wb.create_sheet("Лист2")
    for row in kws.iter_rows(min_row=5):
        for cell in row:
            v = kb.value(kb.order[0], cell.row, cell.column)
            if isinstance(v, (float, bool)) and cell.column >= 4 or cell.column == 1:
                scratch.cell(cell.row, cell.column, v)
            f = cell.value
            if not (isinstance(f, str) and f.startswith("=")) or ws.cell(cell.row, cell.column).value is not None:
                continue
            name = kws.cell(cell.row, 1).value
            cx = Cell(cell.row, cell.column, f, v, rows, positions)
            if cell.column >= 5 and name in recipes:
                ws.cell(cell.row, cell.column, recipes[name](cx))
            else:
                ws.cell(cell.row, cell.column, every(cx) if every else f)
    if hide_scratch:
        scratch.sheet_state = "hidden"
    wb.save(out)
    return out


def grade(path: Path, options: Options):
    rep = validate(path, options=options)
    assert rep.error is None, rep.error
    return rep, grades.score(rep)


# the thirteen cheats of issue 31, on the fourbar's phi_2 (a row of the group, deg)
CHEATS = {
    "times zero of phi_1": lambda x: f"={x.at('phi_1')}*0+{x.v}",
    "L1 minus L1": lambda x: f"=$D${x.rows['L1']}-$D${x.rows['L1']}+{x.v}",
    "IF on L1": lambda x: f"=IF($D${x.rows['L1']}>0,{x.v},0)",
    "0 times SUM of the inputs": lambda x: f"={x.v}+0*SUM($D${x.rows['L1']}:$D${x.rows['Tol_FD']})",
    "pasted plus 0 times L1": lambda x: f"=Лист2!{x.col}{x.r}+0*$D${x.rows['L1']}",
    "IF(FALSE)": lambda x: f"=IF(FALSE,{x.formula[1:]},Лист2!{x.col}{x.r})",
    "CHOOSE(2)": lambda x: f"=CHOOSE(2,{x.formula[1:]},Лист2!{x.col}{x.r})",
    "the key's own guard": lambda x: f"=IF({x.col}{x.rows['asm_g1']},Лист2!{x.col}{x.r},\"не собирается\")",
    "INDEX by position": lambda x: f"=INDEX(Лист2!$E{x.r}:$Q{x.r},1,{x.at('i')}+1)",
    "INDEX ROW COLUMN": lambda x: "=INDEX(Лист2!$A$1:$Z$200,ROW(),COLUMN())",
    "SUMPRODUCT over the pasted sheet": lambda x: (f"=SUMPRODUCT((Лист2!$E${x.rows['phi_1']}:$Q${x.rows['phi_1']}="
                                                   f"{x.at('phi_1')})*Лист2!$E{x.r}:$Q{x.r})"),
}


def _choose13(key: Path):
    """=CHOOSE(i+1; the row's 13 values typed in)."""
    kb = evaluate(key)
    return lambda x: (f"=CHOOSE({x.at('i')}+1,"
                      f"{','.join(repr(kb.value(kb.order[0], x.r, 5 + k)) for k in range(x.positions))})")


@pytest.mark.parametrize("cheat", [*CHEATS, "CHOOSE of 13 typed numbers"])
def test_cheats_earn_nothing(classes, tmp_path, cheat):
    """Each cheat on phi_2 (and a cheat on omega_3 too): the cheated rows earn nothing, are
    named as not following the given data, and every honest row keeps its credit."""
    ex, key, options = classes["fourbar"]
    recipe = _choose13(key) if cheat == "CHOOSE of 13 typed numbers" else CHEATS[cheat]
    rep, s = grade(make_book(ex, key, tmp_path / "cheat.xlsx", {"phi_2": recipe, "omega_3": recipe}), options)
    by = {r.name: r for r in rep.rows}
    for name in ("phi_2", "omega_3"):
        assert row_share(by[name], rep.positions, False) == 0, (cheat, name, by[name])
        assert grades.row_verdict(by[name]) == "typed"
    honest = [r for r in grades.graded_rows(rep) if r.name not in ("phi_2", "omega_3")]
    assert all(grades.row_verdict(r) == "correct" for r in honest), [r.name for r in honest
                                                                    if grades.row_verdict(r) != "correct"]
    assert s < 100
    assert any("does not follow the given data" in n and "phi_2" in n for n in rep.notes), rep.notes


def test_crank_slider_times_zero(classes, tmp_path):
    """The crank-slider's x0: the formula kept and multiplied by 0, the value added."""
    ex, key, options = classes["crank_slider"]
    rep, s = grade(make_book(ex, key, tmp_path / "x0.xlsx",
                             {"x_B": lambda x: f"=({x.formula[1:]})*0+{x.v}"}), options)
    by = {r.name: r for r in rep.rows}
    assert grades.row_verdict(by["x_B"]) == "typed" and row_share(by["x_B"], rep.positions, False) == 0
    assert s < 100


LOOKUPS = {
    "VLOOKUP": lambda x: "=VLOOKUP(\"phi_2\",Лист2!$A$1:$Z$200,COLUMN(),FALSE)",
    "HLOOKUP": lambda x: f"=HLOOKUP({x.at('i')},Лист2!$E${x.rows['i']}:$Q$200,{x.r - x.rows['i'] + 1},FALSE)",
    "INDEX/MATCH": lambda x: (f"=INDEX(Лист2!$E{x.r}:$Q{x.r},1,MATCH({x.at('phi_1')},"
                              f"Лист2!$E${x.rows['phi_1']}:$Q${x.rows['phi_1']},0))"),
    "SUMIF": lambda x: f"=SUMIF(Лист2!$E${x.rows['i']}:$Q${x.rows['i']},{x.at('i')},Лист2!$E{x.r}:$Q{x.r})",
    "OFFSET": lambda x: f"=OFFSET(Лист2!$E{x.r},0,{x.at('i')})",
}


@pytest.fixture(scope="module")
def saved_by_libreoffice(classes, soffice, tmp_path_factory):
    """The lookup books and a book choosing the branch by SWITCH, opened, recalculated and saved
    by LibreOffice (one soffice run): the saved values are LibreOffice's."""
    from sheetkin.xlsx.libreoffice import recalculate
    ex, key, _ = classes["fourbar"]
    d = tmp_path_factory.mktemp("lookups")
    paths = [make_book(ex, key, d / f"{how.replace('/', '_')}.xlsx", {"phi_2": LOOKUPS[how]}) for how in LOOKUPS]
    paths.append(make_book(ex, key, d / "switch.xlsx", {"phi_2": lambda x: (
        f"=_xlfn.SWITCH($D${x.rows['branch_g1']},1,{x.formula[1:]},-1,{x.formula[1:]})")}))
    out = recalculate(paths, d / "saved")
    return {p.stem: out[p.resolve()] for p in paths}


@pytest.mark.libreoffice
@pytest.mark.parametrize("how", LOOKUPS)
def test_lookups_are_never_credited(classes, saved_by_libreoffice, how):
    """Lookups of pasted values, saved by LibreOffice: a function sheetkin has catches them as
    not following; one it lacks leaves the row not judged (never credited, out of the score)."""
    _, _, options = classes["fourbar"]
    rep, s = grade(saved_by_libreoffice[how.replace("/", "_")], options)
    row = {r.name: r for r in rep.rows}["phi_2"]
    assert row.not_judged or (grades.row_verdict(row) == "typed" and row_share(row, rep.positions, False) == 0), row
    assert s < 100 or row.not_judged
    c = grades.counts(rep)
    assert c["correct"] <= c["total"]
    assert not [r.name for r in rep.rows if r.not_judged and grades.row_verdict(r) == "correct"
                and r.name in [x.name for x in grades.graded_rows(rep) if not x.not_judged]]


@pytest.mark.libreoffice
def test_a_function_sheetkin_lacks_is_not_judged(classes, saved_by_libreoffice):
    """SWITCH choosing the branch (honest; the evaluator lacks it): the row and the rows and check
    rows that read it are not judged, none fails, the score is over the rest."""
    _, _, options = classes["fourbar"]
    rep, s = grade(saved_by_libreoffice["switch"], options)
    if not any(r.not_judged for r in rep.rows):
        pytest.skip("the evaluator has SWITCH now: judged as any formula")
    assert not rep.failing_checks, rep.failing_checks
    assert s == 100.0, grades.explain(rep)
    assert any(n.startswith("not judged: check by hand") for n in rep.notes)
    assert grades.counts(rep)["not_judged"] >= 1


# --------------------------------------------------------------------------- honest habits
def _habits(x: Cell) -> str:
    """Honest habits on every formula: IFERROR around it, PI()/180 for RADIANS, absolute
    references kept as they are."""
    f = x.formula[1:].replace("RADIANS(", "(PI()/180)*(")
    return f"=IFERROR({f},\"не собирается\")" if "не собирается" in f else f"=IFERROR({f},\"\")"


def _quadrant_by_hand(x: Cell) -> str:
    """An angle through ATAN with the quadrant's correction chosen by hand per position (the
    issued configuration's), as a student does from the drawing."""
    if not isinstance(x.value, float):
        return x.formula
    a = math.radians(x.value)
    fix = 180 if math.cos(a) < 0 else (360 if math.sin(a) < 0 else 0)
    return f"=DEGREES(ATAN(TAN(RADIANS({x.formula[1:]}))))+{fix}"


def _branch_by_hand(x: Cell) -> str:
    """A sign chosen by hand per position: |formula| times the issued sign."""
    if not isinstance(x.value, float) or x.value == 0:
        return x.formula
    return f"=ABS({x.formula[1:]})*{1 if x.value > 0 else -1}"


@pytest.mark.parametrize("stem", ["fourbar", "crank_slider", "shaper", "slotted_lever", "scotch_yoke"])
def test_honest_habits_score_100(classes, tmp_path, stem):
    ex, key, options = classes[stem]
    rep, s = grade(make_book(ex, key, tmp_path / "key.xlsx", {}), options)
    assert s == 100.0, grades.explain(rep)
    rep, s = grade(make_book(ex, key, tmp_path / "habits.xlsx", {}, every=_habits), options)
    assert s == 100.0, (grades.explain(rep), rep.notes)
    angles = {n: _quadrant_by_hand for n in ("phi_2", "phi_3", "phi_4", "phi_5")}
    signs = {n: _branch_by_hand for n in ("omega_2", "omega_3", "vx_B", "vy_B", "x_B", "y_B")}
    rep, s = grade(make_book(ex, key, tmp_path / "by_hand.xlsx", {**angles, **signs}), options)
    assert s == 100.0, (grades.explain(rep), rep.notes)
    assert not any("does not follow" in n for n in rep.notes)


# --------------------------------------------------------------------------- per position, not judged
def test_last_position_empty_scores_above_85(classes, tmp_path):
    """12 of 13 positions right (the last, 360 deg, left empty): above 85."""
    ex, key, options = classes["fourbar"]
    kws = openpyxl.load_workbook(key).worksheets[0]
    last = 4 + 13

    def skip_last(x: Cell):
        return None if x.c == last else x.formula
    rows = [kws.cell(r, 1).value for r in range(1, kws.max_row + 1) if isinstance(kws.cell(r, 1).value, str)]
    keep = {"i", "phi_1"}
    rep, s = grade(make_book(ex, key, tmp_path / "12of13.xlsx",
                             {n: skip_last for n in rows if n not in keep and not n.startswith(("asm", "chk", "fd_"))}),
                   options)
    assert s > 85, grades.explain(rep)
    assert s < 100
    from sheetkin.course.report import text_report
    text = text_report(rep)
    assert "empty at i = 12" in text and "an error value or text" not in text, text
    assert not rep.typed


def test_unsupported_function_is_not_judged(classes, tmp_path):
    """A row written with a function the evaluator lacks, the value saved by the spreadsheet:
    not judged (out of the score), named, never failing, never credited."""
    ex, key, options = classes["fourbar"]
    path = make_book(ex, key, tmp_path / "switch.xlsx",
                     {"phi_2": lambda x: f"=NOSUCHFUNCTION({x.formula[1:]})"})
    rep = validate(path, options=options)
    row = {r.name: r for r in rep.rows}["phi_2"]
    # openpyxl saves no values: nothing is known about the row, so it cannot be credited
    assert row.not_judged or grades.row_verdict(row) != "correct"


def test_without_the_nudges_the_cheats_pass(classes, tmp_path, monkeypatch):
    """The mutation check: with the behavioural check off (no nudged variant), a cheat that
    reads the given data and throws them away scores full marks, as before issue 31."""
    import sheetkin.course.nudge as nudge
    ex, key, options = classes["fourbar"]
    path = make_book(ex, key, tmp_path / "cheat.xlsx", {"phi_2": CHEATS["IF(FALSE)"]})
    monkeypatch.setattr(nudge, "NUDGES", 0)
    assert grade(path, options)[1] == 100.0
    monkeypatch.setattr(nudge, "NUDGES", 2)
    assert grade(path, options)[1] < 100.0


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.stem)
def test_replayed_reference_is_the_nudged_reference(path):
    """A nudged variant's reference, made by replaying the issued one's plan with the nudged
    input block (behaviour.prepare), equals the reference built for the nudged scene, bit for bit."""
    from sheetkin.sheet.workbook import sheet_rows
    from sheetkin.xlsx.replay import Replay
    scene = parse_scene(path.read_text(encoding="utf-8"), str(path))
    ref = reference_book(scene)
    sh = ref.order[0]
    rows = {ref.sheets[sh].consts.get((r, 1)): r for r in range(5, ref.sheets[sh].max_row + 1)}
    nudged = variant_scene(scene, nudged_inputs(scene, b"seal", 1, 0.01), scene.crank.positions, {})
    built = reference_book(nudged)
    inputs = {r.name: r.value for r in sheet_rows(nudged).rows if r.kind == "input" and r.value is not None}
    replayed = Replay(ref, {}).run({sh: {(rows[n], 4): float(v) if isinstance(v, int) and not isinstance(v, bool)
                                         else v for n, v in inputs.items()}})
    assert (built.tag[sh] == replayed.tag[sh]).all()
    from sheetkin.xlsx.evaluator import BOOL, NUM
    valued = (built.tag[sh] == NUM) | (built.tag[sh] == BOOL)
    assert (built.num[sh][valued] == replayed.num[sh][valued]).all()


# --------------------------------------------------------------------------- a cheat per function family
def _typed_row(key: Path):
    """The row's values at every position, typed in as numbers (the key's, full precision)."""
    kb = evaluate(key)
    return lambda x: [repr(kb.value(kb.order[0], x.r, 5 + k)) for k in range(x.positions)]


def _family_cheats(key: Path) -> dict[tuple[str, str], object]:
    """Cheats invented for each family of sheetkin/xlsx/table.py: a function of the family
    makes the issued values while reading some given data (so precedent tracing alone would
    credit them) and not following them."""
    typed = _typed_row(key)

    def l1(x: Cell) -> str:
        return f"$D${x.rows['L1']}"

    def i(x: Cell) -> str:
        return x.at("i")

    def arr(x: Cell) -> str:
        return "{" + ",".join(typed(x)) + "}"

    def idx(x: Cell) -> str:
        return "{" + ",".join(str(k) for k in range(x.positions)) + "}"
    return {
        ("Math & Trig", "POWER(L1,0)"): lambda x: f"=POWER({l1(x)},0)*{x.v}",
        ("Math & Trig", "ROUND"): lambda x: f"=ROUND({x.v}+0*SQRT({l1(x)}),12)",
        ("Math & Trig", "ABS(SIGN)"): lambda x: f"={x.v}*ABS(SIGN({l1(x)}))",
        ("Math & Trig", "SUMPRODUCT of typed"): lambda x: f"=SUMPRODUCT(({idx(x)}={i(x)})*{arr(x)})",
        ("Statistical", "MEDIAN"): lambda x: f"=MEDIAN({x.v},{x.v},{l1(x)}*1E9)",
        ("Statistical", "LARGE"): lambda x: f"=LARGE({{{x.v},-1E300}},1)+0*{l1(x)}",
        ("Statistical", "COUNTIF"): lambda x: f"=COUNTIF({l1(x)},\">0\")*{x.v}",
        ("Statistical", "AVERAGE"): lambda x: f"=AVERAGE({x.v},{x.v}+0*{l1(x)})",
        ("Logical", "IF(AND)"): lambda x: f"=IF(AND({l1(x)}>0,$D${x.rows['L2']}>0),{x.v},0)",
        ("Logical", "IFERROR"): lambda x: f"=IFERROR({l1(x)}/0,{x.v})",
        ("Logical", "OR times"): lambda x: f"={x.v}*OR({l1(x)})",
        ("Logical", "IFS"): lambda x: f"=_xlfn.IFS({l1(x)}>0,{x.v})",
        ("Information", "ISNUMBER"): lambda x: f"=IF(ISNUMBER({l1(x)}),{x.v})",
        ("Information", "TYPE"): lambda x: f"={x.v}*TYPE({l1(x)})",
        ("Information", "ISBLANK"): lambda x: f"=IF(ISBLANK({l1(x)}),0,{x.v})",
        ("Information", "ISERR"): lambda x: f"={x.v}+ISERR({l1(x)})",
        ("Lookup & Reference", "INDEX of typed"): lambda x: f"=INDEX({arr(x)},1,{i(x)}+1)",
        ("Lookup & Reference", "LOOKUP of typed"): lambda x: f"=LOOKUP({i(x)},{idx(x)},{arr(x)})",
        ("Lookup & Reference", "HLOOKUP of typed"): lambda x: (
            f"=HLOOKUP({i(x)},{{{','.join(str(k) for k in range(x.positions))};"
            f"{','.join(typed(x))}}},2,FALSE)"),
        ("Lookup & Reference", "MATCH"): lambda x: f"={x.v}*MATCH({l1(x)},{l1(x)},0)",
        ("Text", "VALUE(MID)"): lambda x: f"=VALUE(MID(\"x{x.v}\",2,40))+0*{l1(x)}",
        ("Text", "LEN(TEXT)"): lambda x: f"={x.v}*LEN(TEXT({l1(x)},\"0\"))",
        ("Text", "CONCATENATE REPT"): lambda x: f"=VALUE(CONCATENATE(\"{x.v}\",REPT(\"0\",0*{l1(x)})))",
        ("Text", "SUBSTITUTE"): lambda x: (f"=VALUE(SUBSTITUTE(\"{x.v.replace('.', ',')}\",\",\",\".\"))"
                                           f"+0*LEN({l1(x)})"),
    }


FAMILY_CHEATS = [
    ("Math & Trig", "POWER(L1,0)"), ("Math & Trig", "ROUND"), ("Math & Trig", "ABS(SIGN)"),
    ("Math & Trig", "SUMPRODUCT of typed"),
    ("Statistical", "MEDIAN"), ("Statistical", "LARGE"), ("Statistical", "COUNTIF"), ("Statistical", "AVERAGE"),
    ("Logical", "IF(AND)"), ("Logical", "IFERROR"), ("Logical", "OR times"), ("Logical", "IFS"),
    ("Information", "ISNUMBER"), ("Information", "TYPE"), ("Information", "ISBLANK"), ("Information", "ISERR"),
    ("Lookup & Reference", "INDEX of typed"), ("Lookup & Reference", "LOOKUP of typed"),
    ("Lookup & Reference", "HLOOKUP of typed"), ("Lookup & Reference", "MATCH"),
    ("Text", "VALUE(MID)"), ("Text", "LEN(TEXT)"), ("Text", "CONCATENATE REPT"), ("Text", "SUBSTITUTE"),
]


def test_every_family_has_a_cheat():
    """The cheats below cover every family of the function table, each with a function of it."""
    from sheetkin.xlsx.table import CATEGORIES, FUNCTIONS
    assert {f for f, _ in FAMILY_CHEATS} == set(CATEGORIES)
    for family, name in FAMILY_CHEATS:
        assert any(FUNCTIONS[w].category == family for w in name.replace("(", " ").replace(")", " ").split()
                   if w in FUNCTIONS), (family, name)


@pytest.mark.parametrize(("family", "cheat"), FAMILY_CHEATS, ids=lambda v: v.replace(" ", "_"))
def test_a_cheat_of_every_family_earns_nothing(classes, tmp_path, family, cheat):
    """A book filled correctly with phi_2 and omega_3 cheated by a function of one family: the
    formula reads given data (L1 or the position i) but makes the issued values without
    following them. Both rows earn nothing and are named as not following the given data; every
    other row keeps its credit."""
    ex, key, options = classes["fourbar"]
    recipe = _family_cheats(key)[(family, cheat)]
    rep, s = grade(make_book(ex, key, tmp_path / "cheat.xlsx", {"phi_2": recipe, "omega_3": recipe}), options)
    by = {r.name: r for r in rep.rows}
    for name in ("phi_2", "omega_3"):
        assert not by[name].not_judged, (cheat, name)
        assert row_share(by[name], rep.positions, False) == 0, (cheat, name, by[name])
        assert grades.row_verdict(by[name]) == "typed", (cheat, name, by[name])
    honest = [r for r in grades.graded_rows(rep) if r.name not in ("phi_2", "omega_3")]
    assert all(grades.row_verdict(r) == "correct" for r in honest), [r.name for r in honest
                                                                    if grades.row_verdict(r) != "correct"]
    assert s < 100
    follow = [n for n in rep.notes if "does not follow the given data" in n]
    assert follow and "phi_2" in follow[0] and "omega_3" in follow[0], rep.notes


# --------------------------------------------------------------------------- check rows that do not check
def _cheat_check(path: Path, name: str, status: str | None, residual: str | None) -> Path:
    """The book at `path` with the check row `name`'s status (column D) and/or its residual
    cells rewritten (a student making a red check green)."""
    wb = openpyxl.load_workbook(path)
    ws = wb.worksheets[0]
    r = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == name)
    l1 = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "L1")
    if status is not None:
        ws.cell(r, 4, status.format(L1=f"$D${l1}"))
    if residual is not None:
        for c in range(5, ws.max_column + 1):
            if ws.cell(r, c).value is not None:
                ws.cell(r, c, residual.format(L1=f"$D${l1}"))
    out = path.with_name(f"{path.stem}-{name}.xlsx")
    wb.save(out)
    return out


@pytest.mark.parametrize(("status", "residual"), [("=0*{L1}", None), (None, "=0*{L1}"),
                                                  ("=IF({L1}>0,0,1)", None), (None, "=Лист2!E59+0*{L1}")],
                         ids=["status 0*L1", "residuals 0*L1", "status IF(L1>0)", "residuals pasted"])
def test_a_check_row_that_does_not_check_fails(classes, tmp_path, status, residual):
    """chk_OA (|OA| - L1 at every position) made green whatever the rows hold: evaluated on
    the nudged given data with the rows it checks held, the reference's check fails and this
    one passes: it does not check, counts as failing (-2) and the report names it with its
    status cell. The honest book's check rows all check (no such note, 100)."""
    ex, key, options = classes["fourbar"]
    honest = make_book(ex, key, tmp_path / "honest.xlsx", {})
    rep, s = grade(honest, options)
    assert s == 100.0 and not rep.failing_checks
    assert not any("do not check" in n for n in rep.notes), rep.notes
    rep, s = grade(_cheat_check(honest, "chk_OA", status, residual), options)
    assert rep.failing_checks == ["chk_OA"], rep.failing_checks
    assert s == 98.0, grades.explain(rep)
    note = [n for n in rep.notes if n.startswith("check rows that do not check (1;")]
    assert note and "chk_OA (row " in note[0], rep.notes
    c = grades.counts(rep)
    assert c["checks_passing"] == c["checks_apply"] - 1


def test_an_issued_status_is_settled_by_its_residuals(classes, tmp_path, monkeypatch):
    """An issued status formula is not evaluated on the held data where the residuals it reads
    already fail it (behaviour._held_checks; the status formulas were most of the check's
    cost, docs/benchmarks.md): every reacting check row of the honest book is settled so, the
    one whose residuals are made 0 (its status the issued one) is not and is evaluated; the
    reports are those of evaluating every status formula."""
    from sheetkin.course import behaviour
    ex, key, options = classes["fourbar"]
    honest = make_book(ex, key, tmp_path / "honest.xlsx", {})
    cheat = _cheat_check(honest, "chk_OA", None, "=0*{L1}")
    held = []
    real = behaviour._held_checks

    def spy(*args, **kwargs):
        held.append(real(*args, **kwargs))
        return held[-1]
    monkeypatch.setattr(behaviour, "_held_checks", spy)
    fast = [grade(p, options) for p in (honest, cheat)]
    assert len(held[0].reacting) > 10 and held[0].settled == held[0].reacting
    assert "chk_OA" in held[1].reacting and held[1].settled == held[1].reacting - {"chk_OA"}
    monkeypatch.setattr(behaviour, "_issued_statuses", lambda *args: {})    # every status evaluated
    slow = [grade(p, options) for p in (honest, cheat)]
    assert not held[2].settled and not held[3].settled
    for (a, sa), (b, sb) in zip(fast, slow, strict=True):
        assert (sa, a.failing_checks, a.notes, a.checks_passing) == (sb, b.failing_checks, b.notes, b.checks_passing)
    assert fast[1][0].failing_checks == ["chk_OA"]


def test_a_check_row_of_no_given_data_is_judged_as_before(classes, tmp_path):
    """What the rule cannot tell (docs/grading.md): chk_mag_A (|v_A| against vx_A, vy_A) reads
    none of the given data, so its reference does not react and a constant status there still
    passes."""
    ex, key, options = classes["fourbar"]
    honest = make_book(ex, key, tmp_path / "honest.xlsx", {})
    rep, s = grade(_cheat_check(honest, "chk_mag_A", "=0*{L1}", None), options)
    assert s == 100.0 and not rep.failing_checks


# --------------------------------------------------------------------------- the turned variant
@pytest.mark.parametrize("row", ["Fi", "dFi", "cos_1", "sin_1"])
def test_the_crank_rows_are_judged_by_the_turned_variant(classes, tmp_path, row):
    """The crank's own rows do not move with the nudged lengths (Fi0 and Delta_Fi drive them):
    the turned variant (Fi0 and Delta_Fi moved) judges them, so `=<value>+0*L1` there earns
    nothing (it scored before), while the honest book keeps 100."""
    ex, key, options = classes["fourbar"]
    rep, s = grade(make_book(ex, key, tmp_path / "cheat.xlsx", {row: CHEATS["pasted plus 0 times L1"]}), options)
    by = {r.name: r for r in rep.rows}
    share = row_share(by[row], rep.positions, False)
    # a zero keeps its credit (dFi and Fi at i = 0, cos_1 at 90 and 270 deg, sin_1 at 0, 180
    # and 360 deg): the turned variant leaves the zeros to the precedents (a sign by hand there)
    assert share <= 3 / rep.positions, (row, by[row])
    assert any("does not follow the given data" in n and row in n for n in rep.notes), rep.notes
    honest = [r for r in grades.graded_rows(rep) if r.name != row]
    assert all(grades.row_verdict(r) == "correct" for r in honest), [r.name for r in honest
                                                                    if grades.row_verdict(r) != "correct"]


def test_without_the_turned_variant_the_crank_cheat_scores(classes, tmp_path, monkeypatch):
    """The mutation check: with the turned variant off, `=<value>+0*L1` in cos_1 scores 100."""
    import sheetkin.course.nudge as nudge
    ex, key, options = classes["fourbar"]
    path = make_book(ex, key, tmp_path / "cheat.xlsx", {"cos_1": CHEATS["pasted plus 0 times L1"]})
    monkeypatch.setattr(nudge, "TURNED", False)
    assert grade(path, options)[1] == 100.0
    monkeypatch.setattr(nudge, "TURNED", True)
    assert grade(path, options)[1] < 100.0


def test_a_row_fixed_by_the_configuration_is_left_to_the_precedents(classes, tmp_path):
    """What the rule cannot tell (docs/grading.md): the crank-slider's phi_3, the guide's fixed
    angle, is the same for every given data that keep the configuration, so a cheat there
    keeps its credit (at most the share measured in the docs)."""
    ex, key, options = classes["crank_slider"]
    rep, s = grade(make_book(ex, key, tmp_path / "phi3.xlsx", {"phi_3": CHEATS["pasted plus 0 times L1"]}), options)
    assert s == 100.0, grades.explain(rep)
