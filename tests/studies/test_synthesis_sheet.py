"""The synthesis sheet (`sheetkin synth crank-rocker ... --workbook OUT.xlsx`, and in a scene's
own workbook when the scene has a [synthesis] table, issue #6 part 1): its live formulas,
recalculated by LibreOffice, give what synthesize_crank_rocker gives, also after an input cell
is edited and for K_w = 1; the four equations' residuals pass, and in a scene's workbook the
rows comparing the solution with the kinematics sheet's input block; the chart is there."""
from __future__ import annotations

import math
import re
import zipfile

import openpyxl
import pytest
from helpers.libreoffice import is_error, read_values, recalculate
from openpyxl.utils import get_column_letter

from sheetkin.cli.commands import main
from sheetkin.course.grades import all_correct
from sheetkin.studies.synthesis import SynthesisError, synthesize_crank_rocker
from sheetkin.studies.synthesis_sheet import SYNTH_SHEET_TITLES, build_synthesis_workbook

SEED = dict(kw=1.2, l3=0.6, yd=-0.1, gamma1_deg=60.0, gamma2_deg=105.0)
KW1 = dict(kw=1.0, l3=0.6, yd=-1.0, gamma1_deg=0.0, gamma2_deg=45.0)    # theta = 0
UNKNOWNS = ("l1", "l2", "phi1H_deg", "X_D")


def _rows(ws):
    """{name in column A: row number}."""
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1)
            if isinstance(ws.cell(r, 1).value, str)}


def _close(a, b, rel=1e-9):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


def _synth_args(data):
    return ["synth", "crank-rocker", "--kw", repr(data["kw"]), "--l3", repr(data["l3"]),
            "--yd", repr(data["yd"]), "--gamma1-deg", repr(data["gamma1_deg"]),
            "--gamma2-deg", repr(data["gamma2_deg"])]


@pytest.fixture(scope="module")
def recalculated(tmp_path_factory, soffice):
    """Seed 002's sheet, the same with K_w edited to 1.4, one with K_w = 2 (no solution), the
    K_w = 1 sheet; the scenes' workbooks with the synthesis sheet (`synth -o`, then `workbook`)
    of seed 002 (English) and of K_w = 1 (Russian); all recalculated in one soffice run.
    Returns the seed's path, the synthesis sheet's rows, {key: {sheet: {cell: value}}}, and
    {key: (the generated workbook, LibreOffice's recalculated copy)}."""
    d = tmp_path_factory.mktemp("synth_sheet")
    seed = d / "seed.xlsx"
    assert main(_synth_args(SEED) + ["--workbook", str(seed), "--lang", "en"]) == 0
    paths = {"seed": seed}
    for key, kw in (("edited", 1.4), ("none", 2.0)):
        wb = openpyxl.load_workbook(seed)
        ws = wb.active
        ws.cell(_rows(ws)["K_w"], 4).value = kw
        paths[key] = d / f"{key}.xlsx"
        wb.save(paths[key])
    paths["kw1"] = d / "kw1.xlsx"
    assert main(_synth_args(KW1) + ["--workbook", str(paths["kw1"]), "--lang", "en"]) == 0
    for key, data, lang in (("scene", SEED, "en"), ("scene_kw1", KW1, "ru")):
        toml = d / f"{key}.toml"
        assert main(_synth_args(data) + ["-o", str(toml)]) == 0
        assert main(["workbook", str(toml), "--lang", lang, "--synthesis"]) == 0
        paths[key] = toml.with_suffix(".xlsx")
    out = recalculate(list(paths.values()), d / "out")
    rows = _rows(openpyxl.load_workbook(seed).active)
    values = {}
    for key, p in paths.items():
        names = openpyxl.load_workbook(p).sheetnames
        values[key] = {name: read_values(out[p.resolve()], name) for name in names}
    return seed, rows, values, {k: (p, out[p.resolve()]) for k, p in paths.items()}


def _check_solution(values, rows, data, passed="all checks pass"):
    m = synthesize_crank_rocker(**data)
    for name in UNKNOWNS:
        got = values[f"D{rows[name]}"]
        assert not is_error(got) and _close(got, getattr(m, name)), (name, got, getattr(m, name))
    assert _close(values[f"D{rows['theta_deg']}"], m.theta_deg)
    for i in range(1, 5):
        assert abs(values[f"D{rows[f'res_{i}']}"]) <= 1e-9
    assert values["D3"] == passed
    # the dead positions' points, as in the seed
    phi, th = math.radians(m.phi1H_deg), math.radians(m.theta_deg)
    expected = {"X_H": [0, m.l1 * math.cos(phi), (m.l1 + m.l2) * math.cos(phi), m.X_D],
                "Y_H": [0, m.l1 * math.sin(phi), (m.l1 + m.l2) * math.sin(phi), m.yd],
                "X_K": [0, -m.l1 * math.cos(phi + th), (m.l2 - m.l1) * math.cos(phi + th), m.X_D],
                "Y_K": [0, -m.l1 * math.sin(phi + th), (m.l2 - m.l1) * math.sin(phi + th), m.yd]}
    for name, want in expected.items():
        got = [values.get(f"{c}{rows[name]}", 0.0) for c in "DEFG"]
        assert all(abs(g - w) <= 1e-9 for g, w in zip(got, want, strict=False)), (name, got, want)
    # the arc: 31 points from gamma1 to gamma2, at distance l3 from D
    xs = [values[f"{get_column_letter(4 + k)}{rows['X_arc']}"] for k in range(31)]
    ys = [values[f"{get_column_letter(4 + k)}{rows['Y_arc']}"] for k in range(31)]
    assert f"{get_column_letter(4 + 31)}{rows['X_arc']}" not in values
    assert len(xs) == len(ys) == 31
    for x, y in zip(xs, ys, strict=False):
        assert abs(math.hypot(x - m.X_D, y - m.yd) - m.l3) <= 1e-12
    assert abs(xs[0] - (m.X_D + m.l3 * math.cos(math.radians(data["gamma1_deg"])))) <= 1e-12


def _synthesis_values(values, key, lang="en"):
    return values[key][SYNTH_SHEET_TITLES[lang]]


def test_seed_002_sheet_matches_python(recalculated):
    _, rows, values, _ = recalculated
    _check_solution(_synthesis_values(values, "seed"), rows, SEED)
    # seed 002's printed results
    v = _synthesis_values(values, "seed")
    assert round(v[f"D{rows['theta_deg']}"], 2) == 16.36 and round(v[f"D{rows['l1']}"], 3) == 0.185
    assert round(v[f"D{rows['l2']}"], 2) == 0.97 and round(v[f"D{rows['phi1H_deg']}"], 1) == 21.3
    assert round(v[f"D{rows['X_D']}"], 3) == 0.777


def test_edited_input_is_followed(recalculated):
    _, rows, values, _ = recalculated
    _check_solution(_synthesis_values(values, "edited"), rows, dict(SEED, kw=1.4))


def test_kw_1_is_solved(recalculated):
    """theta = 0: the 2x2 system of the old sheet was singular there; the normal equations
    are not. The closed form's K_w = 1 mechanism is checked through the solver in
    test_synthesis.py."""
    _, rows, values, _ = recalculated
    assert synthesize_crank_rocker(**KW1).theta_deg == 0.0
    v = _synthesis_values(values, "kw1")
    assert v[f"D{rows['theta']}"] == 0 and v[f"D{rows['root']}"] in (1, 2)
    _check_solution(v, rows, KW1)


def test_no_solution_shows_and_fails(recalculated):
    _, rows, values, _ = recalculated
    with pytest.raises(SynthesisError):
        synthesize_crank_rocker(**dict(SEED, kw=2.0))
    v = _synthesis_values(values, "none")
    assert v[f"D{rows['root']}"] == 0
    assert v[f"D{rows['l1']}"] == "no solution"
    assert v["D3"] == "checks fail"


@pytest.mark.parametrize("key, data, lang", [("scene", SEED, "en"), ("scene_kw1", KW1, "ru")])
def test_scenes_workbook_has_the_synthesis_sheet(recalculated, key, data, lang):
    """`synth -o scene.toml` then `workbook scene.toml`: the kinematics sheet first, its checks
    passing; the synthesis sheet before the hidden scene sheet, solving the scene's [synthesis]
    data as the separate sheet does, and its rows comparing the solution with the kinematics
    sheet's input block (L1, L2, L3, D - O, the branch) pass: the scene is the mechanism."""
    _, _, values, paths = recalculated
    wb = openpyxl.load_workbook(paths[key][0])
    kin, charts = {"en": ("Kinematics", "Charts"), "ru": ("Кинематика", "Графики")}[lang]
    title = SYNTH_SHEET_TITLES[lang]
    assert wb.sheetnames == [kin, charts, "plotted", "paths", title, "scene"]      # the charts: data, fine paths
    assert wb["scene"].sheet_state == "hidden" and wb[title].sheet_state == "visible"
    rows = _rows(wb[title])
    v = values[key][title]
    _check_solution(v, rows, data, passed="all checks pass" if lang == "en" else "все проверки выполнены")
    m = synthesize_crank_rocker(**data)
    assert v[f"D{rows['branch']}"] == m.branch
    kin_rows = [n for n in rows if n.startswith("kin_")]
    assert len(kin_rows) == 6
    for name in kin_rows:
        assert abs(v[f"D{rows[name]}"]) <= 1e-9, (name, v[f"D{rows[name]}"])
        assert f"'{kin}'!$D$" in wb[title].cell(rows[name], 4).value
    assert values[key][kin]["D3"].startswith("all checks pass" if lang == "en" else "все проверки выполнены")
    # the kinematics sheet computes that mechanism: its rocker starts at gamma1 (phi_3, E)
    krows = _rows(wb[kin])
    assert math.remainder(values[key][kin][f"E{krows['phi_3']}"] - data["gamma1_deg"], 360) == \
        pytest.approx(0, abs=1e-9)
    assert _close(values[key][kin][f"D{krows['L1']}"], m.l1, 1e-14)    # 15 digits saved


@pytest.mark.parametrize("key", ["scene", "scene_kw1"])
def test_scenes_workbook_validates_after_libreoffice(recalculated, key, capsys):
    """The workbook LibreOffice saved (cached values everywhere) still validates: every row
    correct, no failing check, no cell whose formula disagrees with its saved value (the
    K_w = 1 rocker starts at gamma1 = 0: LibreOffice saves that angle as 0 where the
    evaluator gives 359.99999999999994, the same angle on an angle row)."""
    from sheetkin.course.validator import validate
    out = recalculated[3][key][1]
    report = validate(out)
    assert all_correct(report) and not report.failing_checks, report
    assert not report.cache_mismatch, report.cache_mismatch
    assert len(report.rows) > 30 and all(r.status == "correct" for r in report.rows)
    assert main(["validate", str(out), "--lang", "en"]) == 0
    assert "all correct" in capsys.readouterr().out


def test_chart_has_three_series(recalculated):
    seed, _, _, _ = recalculated
    with zipfile.ZipFile(seed) as z:
        xml = z.read("xl/charts/chart1.xml").decode()
    assert len(re.findall(r"<(?:c:)?ser>", xml)) == 3
    assert len(re.findall(r"<(?:c:)?scatterChart>", xml)) == 1


def test_sheet_layout_without_libreoffice():
    wb = build_synthesis_workbook(**SEED, lang="ru")
    ws = wb.active
    assert wb.sheetnames == [SYNTH_SHEET_TITLES["ru"]]
    rows = _rows(ws)
    for name in ("K_w", "l3", "Y_D", "gamma1_deg", "gamma2_deg", "Tol"):
        assert isinstance(ws.cell(rows[name], 4).value, float)
        assert ws.cell(rows[name], 4).fill.fgColor.rgb.endswith("FFF2CC")
    assert ws.cell(rows["theta"], 4).value == f"=PI()*($D${rows['K_w']}-1)/($D${rows['K_w']}+1)"
    for name in UNKNOWNS:
        assert str(ws.cell(rows[name], 4).value).startswith("=IF(")
    with pytest.raises(ValueError):
        build_synthesis_workbook(**SEED, lang="de")


def test_sheet_agrees_with_python_on_random_data(tmp_path):
    """The sheet's formulas, evaluated headlessly (sheetkin's evaluator agrees with
    LibreOffice, tests/xlsx/test_evaluator.py), against synthesize_crank_rocker on random data, a
    third of them with K_w = 1: the same solution to 1e-9, or "no solution" where the closed
    form refuses."""
    import random

    from sheetkin.xlsx.evaluator import evaluate
    rnd = random.Random(2)
    solved = refused = solved_kw1 = 0
    for i in range(36):
        g1 = round(rnd.uniform(-60, 200), 1)
        data = dict(kw=1.0 if i % 3 == 0 else round(rnd.uniform(1, 2.5), 3),
                    l3=round(rnd.uniform(0.2, 1.5), 3), yd=round(rnd.uniform(-1.5, 1.0), 3),
                    gamma1_deg=g1, gamma2_deg=round(g1 + rnd.uniform(5, 170), 1))
        path = tmp_path / f"{i}.xlsx"
        build_synthesis_workbook(**data, lang="en").save(path)
        book = evaluate(path)
        s = book.order[0]
        rows = {book.value(s, r, 1): r for r in range(1, book.sheets[s].max_row + 1)}
        got = {n: book.value(s, rows[n], 4) for n in UNKNOWNS}
        try:
            m = synthesize_crank_rocker(**data)
        except SynthesisError:
            assert got["l1"] == "no solution" and book.value(s, 3, 4) == "checks fail", data
            refused += 1
            continue
        solved += 1
        solved_kw1 += data["kw"] == 1.0
        for n in UNKNOWNS:
            assert isinstance(got[n], float) and _close(got[n], getattr(m, n)), (data, n, got)
        assert book.value(s, 3, 4) == "all checks pass", data
    assert solved >= 5 and refused >= 5 and solved_kw1 >= 3


@pytest.mark.parametrize("lang", ["ru", "uk", "en"])
def test_sheet_in_each_language(tmp_path, lang, capsys):
    """Issue 22: the synthesis sheet in Russian, Ukrainian (new) and English: every row's
    description, the units (м, град, рад in ru and uk), the chart's axes, the verdict and the
    "no solution" marker in its language; the formulas the same in every language, so the
    headless evaluator gives the same solution."""
    from sheetkin.xlsx.evaluator import evaluate
    path = tmp_path / f"{lang}.xlsx"
    assert main(_synth_args(SEED) + ["--workbook", str(path), "--lang", lang]) == 0
    capsys.readouterr()
    ws = openpyxl.load_workbook(path)[SYNTH_SHEET_TITLES[lang]]
    texts = " ".join(str(c.value) for row in ws.iter_rows(max_col=5) for c in row   # descriptions, titles
                     if isinstance(c.value, str) and not c.value.startswith("=") and (c.column > 1 or " " in c.value))
    units = {ws.cell(r, 2).value for r in range(5, ws.max_row + 1)} - {None, ""}
    cyrillic = lang != "en"
    assert units == ({"м", "град", "рад", "м²"} if cyrillic else {"m", "deg", "rad", "m²"}), units
    with zipfile.ZipFile(path) as z:
        chart = z.read("xl/charts/chart1.xml").decode()
    assert ("x, м" in chart) == cyrillic and ("x, m" in chart) == (not cyrillic)
    # words of a language: in uk no Russian-only letters, in ru and uk no English words
    # (formulas' names, the seed's name and the functions apart)
    words = set(re.findall(r"[A-Za-z]{3,}", re.sub(r"\w*_\w*|\b\w*\d\w*\b", " ", texts)))
    english = words - {"theta", "sin", "cos", "ctg", "psi", "beta", "delta", "acos", "atan", "sqrt", "phi",
                       "den", "seed", "gamma", "branch", "Grashof"}
    assert bool(english) == (not cyrillic), sorted(english)
    if lang == "uk":
        assert not re.search("[ыэъёЫЭЪЁ]", texts) and "Розв'язок" in texts and "Вихідні дані" in texts
    book = evaluate(path)
    s = book.order[0]
    rows = {book.value(s, r, 1): r for r in range(1, book.sheets[s].max_row + 1)}
    m = synthesize_crank_rocker(**SEED)
    for n in UNKNOWNS:
        assert _close(book.value(s, rows[n], 4), getattr(m, n)), n
    verdict = {"ru": "все проверки выполнены", "uk": "усі перевірки виконано", "en": "all checks pass"}[lang]
    assert book.value(s, 3, 4) == verdict
    # no solution (K_w = 2): the marker in the book's language
    none = tmp_path / f"none-{lang}.xlsx"
    build_synthesis_workbook(**{**SEED, "kw": 2.0}, lang=lang).save(none)
    book = evaluate(none)
    marker = {"ru": "нет решения", "uk": "немає розв'язку", "en": "no solution"}[lang]
    assert book.value(book.order[0], rows["l1"], 4) == marker


def test_scene_workbook_with_synthesis_in_ukrainian(tmp_path, capsys):
    """`workbook --lang uk` of a scene with a [synthesis] table: once refused, now both
    sheets in Ukrainian."""
    toml = tmp_path / "s.toml"
    assert main(_synth_args(SEED) + ["-o", str(toml)]) == 0
    assert main(["workbook", str(toml), "--lang", "uk", "--synthesis"]) == 0
    capsys.readouterr()
    wb = openpyxl.load_workbook(toml.with_suffix(".xlsx"))
    assert SYNTH_SHEET_TITLES["uk"] in wb.sheetnames
    ws = wb[SYNTH_SHEET_TITLES["uk"]]
    rows = _rows(ws)
    assert ws.cell(rows["kin_l2"], 3).value == "довжина шатуна (аркуш кінематики) - l2"
    assert str(ws.cell(rows["kin_l2"], 4).value).startswith("=")
