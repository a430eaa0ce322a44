"""The synthesis sheet (`sheetkin synth crank-rocker ... --workbook OUT.xlsx`, issue #6 part 1):
its live formulas, recalculated by LibreOffice, give what synthesize_crank_rocker gives, also
after an input cell is edited; the four equations' residuals pass; the chart is there."""
from __future__ import annotations

import math
import re
import zipfile

import openpyxl
from openpyxl.utils import get_column_letter
import pytest

from libreoffice import is_error, read_values, recalculate
from sheetkin.cli import main
from sheetkin.synthesis import (SYNTH_SHEET_TITLES, SynthesisError, build_synthesis_workbook,
                                synthesize_crank_rocker)

SEED = dict(kw=1.2, l3=0.6, yd=-0.1, gamma1_deg=60.0, gamma2_deg=105.0)
UNKNOWNS = ("l1", "l2", "phi1H_deg", "X_D")


def _rows(ws):
    """{name in column A: row number}."""
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1)
            if isinstance(ws.cell(r, 1).value, str)}


def _close(a, b, rel=1e-9):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


@pytest.fixture(scope="module")
def recalculated(tmp_path_factory, soffice):
    """Seed 002's sheet, the same with K_w edited to 1.4, and one with K_w = 2 (no solution),
    recalculated in one soffice run."""
    d = tmp_path_factory.mktemp("synth_sheet")
    seed = d / "seed.xlsx"
    assert main(["synth", "crank-rocker", "--kw", "1.2", "--l3", "0.6", "--yd", "-0.1",
                 "--gamma1-deg", "60", "--gamma2-deg", "105", "--workbook", str(seed),
                 "--lang", "en"]) == 0
    paths = {"seed": seed}
    for key, kw in (("edited", 1.4), ("none", 2.0)):
        wb = openpyxl.load_workbook(seed)
        ws = wb.active
        ws.cell(_rows(ws)["K_w"], 4).value = kw
        paths[key] = d / f"{key}.xlsx"
        wb.save(paths[key])
    out = recalculate(list(paths.values()), d / "out")
    rows = _rows(openpyxl.load_workbook(seed).active)
    return seed, rows, {k: read_values(out[p.resolve()]) for k, p in paths.items()}


def _check_solution(values, rows, data):
    m = synthesize_crank_rocker(**data)
    for name in UNKNOWNS:
        got = values[f"D{rows[name]}"]
        assert not is_error(got) and _close(got, getattr(m, name)), (name, got, getattr(m, name))
    assert _close(values[f"D{rows['theta_deg']}"], m.theta_deg)
    for i in range(1, 5):
        assert abs(values[f"D{rows[f'res_{i}']}"]) <= 1e-9
    assert values["D3"] == "all checks pass"
    # the dead positions' points, as in the seed
    phi, th = math.radians(m.phi1H_deg), math.radians(m.theta_deg)
    expected = {"X_H": [0, m.l1 * math.cos(phi), (m.l1 + m.l2) * math.cos(phi), m.X_D],
                "Y_H": [0, m.l1 * math.sin(phi), (m.l1 + m.l2) * math.sin(phi), m.yd],
                "X_K": [0, -m.l1 * math.cos(phi + th), (m.l2 - m.l1) * math.cos(phi + th), m.X_D],
                "Y_K": [0, -m.l1 * math.sin(phi + th), (m.l2 - m.l1) * math.sin(phi + th), m.yd]}
    for name, want in expected.items():
        got = [values.get(f"{c}{rows[name]}", 0.0) for c in "DEFG"]
        assert all(abs(g - w) <= 1e-9 for g, w in zip(got, want)), (name, got, want)
    # the arc: 31 points from gamma1 to gamma2, at distance l3 from D
    xs = [values[f"{get_column_letter(4 + k)}{rows['X_arc']}"] for k in range(31)]
    ys = [values[f"{get_column_letter(4 + k)}{rows['Y_arc']}"] for k in range(31)]
    assert f"{get_column_letter(4 + 31)}{rows['X_arc']}" not in values
    assert len(xs) == len(ys) == 31
    for x, y in zip(xs, ys):
        assert abs(math.hypot(x - m.X_D, y - m.yd) - m.l3) <= 1e-12
    assert abs(xs[0] - (m.X_D + m.l3 * math.cos(math.radians(data["gamma1_deg"])))) <= 1e-12


def test_seed_002_sheet_matches_python(recalculated):
    _, rows, values = recalculated
    _check_solution(values["seed"], rows, SEED)


def test_edited_input_is_followed(recalculated):
    _, rows, values = recalculated
    _check_solution(values["edited"], rows, dict(SEED, kw=1.4))


def test_no_solution_shows_and_fails(recalculated):
    _, rows, values = recalculated
    with pytest.raises(SynthesisError):
        synthesize_crank_rocker(**dict(SEED, kw=2.0))
    v = values["none"]
    assert v[f"D{rows['root']}"] == 0
    assert v[f"D{rows['l1']}"] == "no solution"
    assert v["D3"] == "checks fail"


def test_chart_has_three_series(recalculated):
    seed, _, _ = recalculated
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
