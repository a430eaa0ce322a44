"""`sheetkin synth crank-rocker` and sheetkin.studies.synthesis (seed 002, issue #6 part 1).

The synthesized mechanism is checked through the solver, independently of the synthesis
formulas: its rocker angle phi_3 over a revolution has its extremes at gamma1 and gamma2, at
crank angles (found by bisection on omega_3 = 0) whose ratio of working stroke to return is K_w.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import fsolve

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.studies.synthesis import SynthesisError, _check, overlap_angle_deg, synthesize_crank_rocker

SEED = dict(kw=1.2, l3=0.6, yd=-0.1, gamma1_deg=60.0, gamma2_deg=105.0)
SEED_ARGS = ["synth", "crank-rocker", "--kw", "1.2", "--l3", "0.6", "--yd", "-0.1",
             "--gamma1-deg", "60", "--gamma2-deg", "105"]


def _residuals(m):
    th, g1, g2 = map(math.radians, (m.theta_deg, m.gamma1_deg, m.gamma2_deg))
    phi = math.radians(m.phi1H_deg)
    return [(m.l1 + m.l2) * math.cos(phi) - m.X_D - m.l3 * math.cos(g1),
            (m.l1 + m.l2) * math.sin(phi) - m.yd - m.l3 * math.sin(g1),
            (m.l2 - m.l1) * math.cos(phi + th) - m.X_D - m.l3 * math.cos(g2),
            (m.l2 - m.l1) * math.sin(phi + th) - m.yd - m.l3 * math.sin(g2)]


def test_seed_002_printed_results():
    m = synthesize_crank_rocker(**SEED)
    assert round(overlap_angle_deg(1.2), 2) == 16.36 and round(m.theta_deg, 2) == 16.36
    assert round(m.l1, 3) == 0.185
    assert round(m.l2, 2) == 0.97
    assert round(m.phi1H_deg, 1) == 21.3
    assert round(m.X_D, 3) == 0.777
    assert max(map(abs, _residuals(m))) < 1e-14


def test_matches_newton_from_the_seeds_initial_guess():
    """Mathcad's Given/Find from l1 = 0.2, l2 = 0.5, phi1H = 30 deg, X_D = 0.5 (scipy here)."""
    th, g1, g2, l3, yd = math.radians(overlap_angle_deg(1.2)), math.radians(60), math.radians(105), 0.6, -0.1

    def f(x):
        l1, l2, phi, xd = x
        return [(l1 + l2) * math.cos(phi) - xd - l3 * math.cos(g1),
                (l1 + l2) * math.sin(phi) - yd - l3 * math.sin(g1),
                (l2 - l1) * math.cos(phi + th) - xd - l3 * math.cos(g2),
                (l2 - l1) * math.sin(phi + th) - yd - l3 * math.sin(g2)]
    x = fsolve(f, [0.2, 0.5, math.radians(30), 0.5], xtol=1e-12)
    m = synthesize_crank_rocker(**SEED)
    assert np.allclose(x, [m.l1, m.l2, math.radians(m.phi1H_deg), m.X_D], rtol=0, atol=1e-10)


def _rocker_extremes(scene):
    """Crank angles (deg, in [phi0, phi0 + 360)) where omega_3 changes sign, refined by
    bisection through the solver, with phi_3 there."""
    phi0 = scene.crank.phi0_deg
    grid = phi0 + 0.5 + np.arange(3600) * 0.1            # avoid landing exactly on an extreme
    df = sheetkin.compute(scene, at=grid)
    w = df["omega_3"].to_numpy()
    idx = np.nonzero(np.sign(w[:-1]) != np.sign(w[1:]))[0]
    lo, hi = list(grid[idx]), list(grid[idx + 1])
    if np.sign(w[-1]) != np.sign(w[0]):                   # an extreme between the ends
        lo.append(grid[-1])
        hi.append(grid[0] + 360.0)
    lo, hi = np.array(lo), np.array(hi)
    s_lo = np.sign(sheetkin.compute(scene, at=lo)["omega_3"].to_numpy())
    for _ in range(60):
        mid = (lo + hi) / 2
        s = np.sign(sheetkin.compute(scene, at=mid)["omega_3"].to_numpy())
        same = s == s_lo
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    at = (lo + hi) / 2
    return at, sheetkin.compute(scene, at=at)["phi_3"].to_numpy()


@pytest.mark.parametrize("data", [
    SEED,
    dict(kw=1.5, l3=0.6, yd=-0.1, gamma1_deg=60.0, gamma2_deg=105.0),
    dict(kw=1.0, l3=0.6, yd=-1.0, gamma1_deg=0.0, gamma2_deg=45.0),     # phi1H = 292.5 deg
    dict(kw=2.0, l3=0.6, yd=-0.5, gamma1_deg=30.0, gamma2_deg=75.0),
    dict(kw=1.4, l3=1.0, yd=-0.3, gamma1_deg=40.0, gamma2_deg=100.0),
])
def test_synthesized_mechanism_through_the_solver(data):
    m = synthesize_crank_rocker(**data)
    scene = sheetkin.parse_scene(m.scene_toml(), "synth.toml")
    df = sheetkin.compute(scene)                          # the scene's 13 positions assemble
    g1 = data["gamma1_deg"]
    assert math.remainder(df["phi_3"].iloc[0] - g1, 360.0) == pytest.approx(0, abs=1e-9)
    at, phi3 = _rocker_extremes(scene)
    phi3 = g1 + np.array([math.remainder(p - g1, 360.0) for p in phi3])   # phi_3 is in [0, 360)
    assert len(at) == 2
    order = np.argsort(phi3)
    (c_min, c_max), (p_min, p_max) = at[order], phi3[order]
    assert p_min == pytest.approx(data["gamma1_deg"], abs=1e-9)
    assert p_max == pytest.approx(data["gamma2_deg"], abs=1e-9)
    work = (c_max - c_min) % 360.0                        # crank turning counterclockwise
    ret = 360.0 - work
    assert work / ret == pytest.approx(data["kw"], abs=1e-9)
    # the extremes are the dead positions: phi1H and phi1H + 180 + theta
    assert math.remainder(c_min - m.phi1H_deg, 360.0) == pytest.approx(0, abs=1e-9)
    assert math.remainder(c_max - m.phi1H_deg - 180.0 - m.theta_deg, 360.0) == pytest.approx(0, abs=1e-9)


def test_cli_table_and_json(capsys):
    assert main(SEED_ARGS) == 0
    out = capsys.readouterr().out
    names = [line.split()[0] for line in out.splitlines()]
    assert names == ["l1", "l2", "phi1H_deg", "X_D"]
    assert main(SEED_ARGS + ["--format", "json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert list(res) == ["l1", "l2", "phi1H_deg", "X_D"]
    assert round(res["l1"], 3) == 0.185 and round(res["l2"], 2) == 0.97
    assert round(res["phi1H_deg"], 1) == 21.3 and round(res["X_D"], 3) == 0.777


def test_cli_writes_a_scene_for_compute_and_workbook(tmp_path, capsys):
    out = tmp_path / "scene.toml"
    assert main(SEED_ARGS + ["-o", str(out)]) == 0
    capsys.readouterr()
    scene = sheetkin.load_scene(out)
    m = synthesize_crank_rocker(**SEED)
    assert scene.frame["O"] == (0.0, 0.0) and scene.frame["D"] == (m.X_D, -0.1)
    assert scene.crank.length == m.l1 and scene.crank.phi0_deg == m.phi1H_deg
    assert scene.groups[0].lengths == (m.l2, 0.6)
    assert main(["compute", str(out), "--format", "csv"]) == 0
    assert capsys.readouterr().out.startswith("phi_1,")
    pytest.importorskip("openpyxl")
    assert main(["workbook", str(out)]) == 0
    assert (tmp_path / "scene.xlsx").exists()


@pytest.mark.parametrize("args, words", [
    (["--kw", "0.9"], "K_w = 0.9 < 1"),
    (["--gamma2-deg", "60"], "gamma2 = 60 deg <= gamma1 = 60 deg"),
    (["--gamma1-deg", "105", "--gamma2-deg", "60"], "gamma2 = 60 deg <= gamma1 = 105 deg"),
    (["--gamma2-deg", "250"], ">= 180 deg"),
    (["--kw", "1", "--yd", "-1", "--gamma1-deg", "30", "--gamma2-deg", "180"], "l1 = "),
    (["--kw", "1.2", "--yd", "-0.1", "--gamma1-deg", "90", "--gamma2-deg", "180"], "l2 = "),
    (["--kw", "1.2", "--yd", "-1", "--gamma1-deg", "0", "--gamma2-deg", "10"], "no solution"),
    (["--kw", "1.2", "--yd", "-1", "--gamma1-deg", "200", "--gamma2-deg", "290"], "branches"),
    (["--kw", "1", "--yd", "0", "--gamma1-deg", "30", "--gamma2-deg", "180"], "Grashof"),
])
def test_cli_refusals_are_one_line_exit_2(args, words, capsys):
    argv = list(SEED_ARGS)
    for i in range(0, len(args), 2):
        k = argv.index(args[i])
        argv[k + 1] = args[i + 1]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("sheetkin: error: ") and err.count("\n") == 1
    assert words in err


def test_specific_refusal_messages():
    with pytest.raises(SynthesisError, match=r"l1 = .* <= 0"):
        synthesize_crank_rocker(1.0, 0.6, -1.0, 30.0, 180.0)
    with pytest.raises(SynthesisError, match=r"l2 = .* <= l1 = .*cannot rotate fully"):
        synthesize_crank_rocker(1.2, 0.6, -0.1, 90.0, 180.0)
    with pytest.raises(SynthesisError, match="K_w"):
        synthesize_crank_rocker(0.5, 0.6, -0.1, 60.0, 105.0)


def test_grashof_and_shortest_link_checks():
    """Both dead positions existing with 0 < l1 < l2 already implies a Grashof crank-rocker,
    so these guards are exercised directly."""
    # l1 = 0.5, l2 = 0.7, l3 = 0.6, frame |OD| = 0.3: the frame is shorter than the crank
    with pytest.raises(SynthesisError, match="crank is not the shortest link"):
        _check(1.2, 0.6, 0.0, 60.0, 105.0, 16.0, 1.2, 0.2, 0.3, 0.5)
    # l1 = 0.2, l2 = 0.5, l3 = 0.6, |OD| = 1.0: s + l = 1.2 > p + q = 1.1
    with pytest.raises(SynthesisError, match=r"Grashof's condition violated: s \+ l = 1.2 > p \+ q = 1.1"):
        _check(1.2, 0.6, 0.0, 60.0, 105.0, 16.0, 0.7, 0.3, 1.0, 0.5)


def test_bad_option_values_exit_2(capsys):
    argv = list(SEED_ARGS)
    argv[argv.index("--l3") + 1] = "-0.6"
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    assert main(SEED_ARGS + ["--omega", "-5"]) == 2
    assert "--omega" in capsys.readouterr().err


# --------------------------------------------------------------------------- the [synthesis] table
def _seed_scene(tmp_path, capsys, name="scene.toml", args=SEED_ARGS):
    out = tmp_path / name
    assert main(args + ["-o", str(out)]) == 0
    capsys.readouterr()
    return out


def _line_of(text, prefix):
    """1-based number of the only line starting with `prefix`."""
    found = [no for no, line in enumerate(text.splitlines(), 1) if line.startswith(prefix)]
    assert len(found) == 1, (prefix, found)
    return found[0]


def test_synth_writes_the_synthesis_table(tmp_path, capsys):
    import tomllib

    from sheetkin.studies.synthesis import parse_synthesis
    out = _seed_scene(tmp_path, capsys)
    text = out.read_text(encoding="utf-8")
    table = tomllib.loads(text)["synthesis"]
    assert table == SEED and all(type(v) is float for v in table.values())
    assert parse_synthesis(text, str(out)) == SEED
    # the scene itself still loads, and a scene without the table has no synthesis data
    sheetkin.load_scene(out)
    start = _line_of(text, "[synthesis]")
    lines = text.splitlines()
    without = "\n".join(lines[:start - 1] + lines[start + len(SEED):]) + "\n"
    assert "[synthesis]" not in without and "gamma1_deg" not in without
    assert parse_synthesis(without, "x.toml") is None
    assert sheetkin.parse_scene(without, "x.toml") == sheetkin.parse_scene(text, "x.toml")


def _workbook_error(path, capsys, *extra):
    assert main(["workbook", str(path), *extra]) == 2
    captured = capsys.readouterr()
    err = captured.err
    assert err.startswith("sheetkin: error: ") and err.count("\n") == 1, err
    assert not path.with_suffix(".xlsx").exists()
    return err


@pytest.mark.parametrize("old, new, key, words", [
    ("kw = 1.2", "kw = 0.9", "kw", "K_w = 0.9 < 1"),
    ("kw = 1.2", 'kw = "1.2"', "kw", "expected a number, got a string '1.2'"),
    ("kw = 1.2", "kw = nan", "kw", "expected a finite number, got nan"),
    ("l3 = 0.6", "l3 = -0.6", "l3", "the rocker length must be positive"),
    ("yd = -0.1", "yd = [0.1]", "yd", "expected a number, got an array"),
    ("gamma2_deg = 105.0", "gamma2_deg = 50.0", "gamma2_deg", "gamma2 = 50 deg <= gamma1 = 60 deg"),
    ("gamma2_deg = 105.0", "gamma2_deg = 250.0", "gamma2_deg", ">= 180 deg"),
    ("yd = -0.1", "yd = -0.1\nk_w = 1.3", "k_w", "unknown key; expected one of: kw, l3, yd, "
                                                   "gamma1_deg, gamma2_deg"),
])
def test_bad_synthesis_values_are_one_line_errors(tmp_path, capsys, old, new, key, words):
    out = _seed_scene(tmp_path, capsys)
    text = out.read_text(encoding="utf-8")
    assert text.count(old + "\n") == 1
    out.write_text(text.replace(old + "\n", new + "\n"), encoding="utf-8")
    no = _line_of(out.read_text(encoding="utf-8"), f"{key} =")
    err = _workbook_error(out, capsys)
    assert err.startswith(f"sheetkin: error: {out}:{no}: [synthesis] key '{key}': "), err
    assert words in err


def test_missing_key_and_no_solution_point_at_the_table(tmp_path, capsys):
    out = _seed_scene(tmp_path, capsys)
    text = out.read_text(encoding="utf-8")
    header = _line_of(text, "[synthesis]")
    out.write_text(text.replace("l3 = 0.6\n", ""), encoding="utf-8")
    err = _workbook_error(out, capsys)
    assert err.startswith(f"sheetkin: error: {out}:{header}: [synthesis] key 'l3': missing; "
                          "expected a number"), err
    # K_w = 2 with the seed's other data: no crank-rocker (the closed form says why)
    with pytest.raises(SynthesisError) as e:
        synthesize_crank_rocker(**dict(SEED, kw=2.0))
    out.write_text(text.replace("kw = 1.2\n", "kw = 2.0\n"), encoding="utf-8")
    err = _workbook_error(out, capsys)
    assert err == (f"sheetkin: error: {out}:{header}: [synthesis]: no crank-rocker for these "
                   f"data: {e.value}\n")


def test_synthesis_table_of_the_wrong_kind(tmp_path, capsys):
    from sheetkin.kinematics.scene import SceneError
    from sheetkin.studies.synthesis import parse_synthesis
    out = _seed_scene(tmp_path, capsys)
    text = out.read_text(encoding="utf-8")
    header = _line_of(text, "[synthesis]")
    block = "".join(text.splitlines(keepends=True)[header - 1:header + len(SEED)])
    # an inline table: errors point at its line
    inline = text.replace(block, 'synthesis = {kw = 1.2, l3 = 0.6, yd = -0.1, gamma1_deg = 60, '
                                 'gamma2_deg = "105"}\n')
    with pytest.raises(SceneError, match=rf"^x.toml:{header}: \[synthesis\] key "
                                         r"'synthesis.gamma2_deg': expected a number"):
        parse_synthesis(inline, "x.toml")
    assert parse_synthesis(inline.replace('"105"', "105"), "x.toml") == SEED
    with pytest.raises(SceneError, match=rf"^x.toml:{header}: scene key 'synthesis': expected a "
                                         r"\[synthesis\] table, got an integer"):
        parse_synthesis(text.replace(block, "synthesis = 5\n"), "x.toml")
    # the data of a crank-rocker in a scene that is not one (its first group is an RRP)
    slider = (Path(__file__).resolve().parents[2] / "workbooks" / "crank_slider.toml").read_text(encoding="utf-8")
    with pytest.raises(SceneError, match=r"^s.toml:\d+: \[synthesis\]: .*first group is not an "
                                         r"RRR dyad from the crank's joint"):
        parse_synthesis(slider + "\n" + block, "s.toml")


def test_workbook_synthesis_option(tmp_path, capsys):
    """--synthesis requires the table; without the option a scene without it gets no sheet."""
    import openpyxl

    from sheetkin.studies.synthesis_sheet import SYNTH_SHEET_TITLES
    out = _seed_scene(tmp_path, capsys)
    text = out.read_text(encoding="utf-8")
    plain = tmp_path / "plain.toml"
    header = _line_of(text, "[synthesis]")
    lines = text.splitlines()
    plain.write_text("\n".join(lines[:header - 1] + lines[header + len(SEED):]) + "\n",
                     encoding="utf-8")
    err = _workbook_error(plain, capsys, "--synthesis")
    assert err == (f"sheetkin: error: {plain}: --synthesis: the scene has no [synthesis] table "
                   "(the data of `sheetkin synth crank-rocker`, which writes it with -o)\n")
    assert main(["workbook", str(plain)]) == 0
    assert "synthesis sheet" not in capsys.readouterr().err
    assert openpyxl.load_workbook(plain.with_suffix(".xlsx")).sheetnames == ["Кинематика", "Графики", "plotted",
                                                                            "paths", "scene"]
    assert main(["workbook", str(out), "--synthesis"]) == 0
    assert "synthesis sheet" in capsys.readouterr().err
    wb = openpyxl.load_workbook(out.with_suffix(".xlsx"))
    assert wb.sheetnames == ["Кинематика", "Графики", "plotted", "paths", SYNTH_SHEET_TITLES["ru"], "scene"]
    assert wb["scene"].sheet_state == "hidden" and wb.active.title == "Кинематика"


def test_scene_workbook_check_evaluate_validate(tmp_path, capsys):
    """--check (the fingerprint covers the synthesis sheet), evaluate and validate on a
    scene's workbook with the synthesis sheet; the sheet evaluated headlessly gives the closed
    form, and its rows comparing it with the kinematics sheet pass."""
    from sheetkin.sheet.workbook import SCENE_SHEET, embedded_scene_text
    from sheetkin.studies.synthesis_sheet import SYNTH_SHEET_TITLES
    from sheetkin.xlsx.cells import read_book
    from sheetkin.xlsx.evaluator import evaluate
    out = _seed_scene(tmp_path, capsys)
    book = out.with_suffix(".xlsx")
    assert main(["workbook", str(out), "--lang", "en"]) == 0
    assert main(["workbook", str(out), "--lang", "en", "--check"]) == 0
    assert "up to date" in capsys.readouterr().out
    assert main(["workbook", str(out), "--check"]) == 1          # ru: other descriptions
    assert "stale" in capsys.readouterr().out
    text = out.read_text(encoding="utf-8")
    assert embedded_scene_text(read_book(book).sheets[SCENE_SHEET]) == text
    # the synthesis sheet is in the fingerprint: other [synthesis] data make the book stale
    m2 = synthesize_crank_rocker(**dict(SEED, kw=1.3))
    out.write_text(text.replace("kw = 1.2\n", "kw = 1.3\n"), encoding="utf-8")
    assert main(["workbook", str(out), "--lang", "en", "--check"]) == 1
    assert "stale" in capsys.readouterr().out
    out.write_text(text, encoding="utf-8")
    assert main(["evaluate", str(book), "--format", "csv"]) == 0
    assert capsys.readouterr().out.startswith("name,1,2,")
    assert main(["validate", str(book)]) == 0
    report = capsys.readouterr().out
    assert "0 wrong, 0 missing or empty" in report and "all correct" in report
    b = evaluate(book)
    s = SYNTH_SHEET_TITLES["en"]
    assert b.order[0] == "Kinematics" and s in b.order and not b.problems
    rows = {b.value(s, r, 1): r for r in range(1, b.sheets[s].max_row + 1)}
    m = synthesize_crank_rocker(**SEED)
    for name in ("l1", "l2", "phi1H_deg", "X_D", "branch"):
        assert b.value(s, rows[name], 4) == pytest.approx(getattr(m, name), rel=1e-12, abs=1e-12)
    assert m2.l1 != pytest.approx(m.l1, rel=1e-3)
    kin = [n for n in rows if isinstance(n, str) and n.startswith("kin_")]
    assert kin == ["kin_l1", "kin_l2", "kin_l3", "kin_X_D", "kin_Y_D", "kin_branch"]
    for n in kin + ["res_1", "res_2", "res_3", "res_4"]:
        assert abs(b.value(s, rows[n], 4)) <= 1e-12, n
    assert b.value(s, 3, 4) == "all checks pass"
    assert b.value("Kinematics", 3, 4).startswith("all checks pass")


def test_a_scene_unlike_its_synthesis_data_is_warned_and_checked(tmp_path, capsys):
    from sheetkin.xlsx.evaluator import evaluate
    out = _seed_scene(tmp_path, capsys)
    m = synthesize_crank_rocker(**SEED)
    text = out.read_text(encoding="utf-8")
    out.write_text(text.replace(f"length = {m.l1!r}\n", "length = 0.19\n"), encoding="utf-8")
    assert main(["workbook", str(out), "--lang", "en"]) == 0
    err = capsys.readouterr().err
    warning = [line for line in err.splitlines() if line.startswith("sheetkin: warning:")]
    assert len(warning) == 1 and f"L1 = 0.19 but the synthesis gives l1 = {m.l1:.9g}" in warning[0]
    b = evaluate(out.with_suffix(".xlsx"))
    rows = {b.value("Synthesis", r, 1): r for r in range(1, b.sheets["Synthesis"].max_row + 1)}
    assert b.value("Synthesis", rows["kin_l1"], 4) == pytest.approx(0.19 - m.l1, abs=1e-12)
    assert abs(b.value("Synthesis", rows["kin_l2"], 4)) <= 1e-12
    assert b.value("Synthesis", 3, 4) == "checks fail"


def test_kw_1_closed_form_and_the_seeds_data():
    """K_w = 1 (theta = 0): the dead positions' crank lines coincide, so O lies on the line
    B1 B2, with B2 between O and B1 (|OB1| = l1 + l2 > |OB2| = l2 - l1). With Y_D = -0.1 and
    gamma 60 -> 105 that line puts B1 nearer O than B2: no crank (l1 < 0), as the closed form
    says; with Y_D = -1, gamma 0 -> 45 it is a crank-rocker."""
    def collinear(l3, yd, g1, g2):
        g1, g2 = math.radians(g1), math.radians(g2)
        ux, uy = math.cos(g1) - math.cos(g2), math.sin(g1) - math.sin(g2)     # (B1 - B2)/l3
        # O = (0, 0) on the line through B1 = (xd + l3 cos g1, yd + l3 sin g1), direction u
        b1y = yd + l3 * math.sin(g1)
        xd = b1y * ux / uy - l3 * math.cos(g1)
        b1 = (xd + l3 * math.cos(g1), b1y)
        b2 = (xd + l3 * math.cos(g2), yd + l3 * math.sin(g2))
        return xd, math.hypot(*b1), math.hypot(*b2), b1[0] * b2[0] + b1[1] * b2[1] > 0
    xd, r1, r2, same_side = collinear(0.6, -0.1, 60.0, 105.0)
    assert same_side and r1 < r2
    with pytest.raises(SynthesisError, match=rf"l1 = {(r1 - r2) / 2:.5g} <= 0"):
        synthesize_crank_rocker(1.0, 0.6, -0.1, 60.0, 105.0)
    xd, r1, r2, same_side = collinear(0.6, -1.0, 0.0, 45.0)
    m = synthesize_crank_rocker(1.0, 0.6, -1.0, 0.0, 45.0)
    assert same_side and r1 > r2 and m.theta_deg == 0.0
    assert (m.l1, m.l2, m.X_D) == pytest.approx(((r1 - r2) / 2, (r1 + r2) / 2, xd), abs=1e-12)


@pytest.mark.parametrize("lang, word", [(None, "Кривошипно-коромысловый"), ("uk", "Кривошипно-коромисловий"),
                                        ("en", "Crank-rocker")])
def test_synthesized_scene_is_titled_in_the_books_language(tmp_path, capsys, lang, word):
    """The scene `synth -o` writes becomes a book's title: in the book's language (Russian by
    default, like the books), and naming no source document by its number."""
    out = tmp_path / "cr.toml"
    extra = ["--lang", lang] if lang else []
    assert main(["synth", "crank-rocker", "--kw", "1.4", "--l3", "0.3", "--yd", "-0.2", "--gamma1", "10",
                 "--gamma2", "70", "-o", str(out), *extra]) == 0
    text = out.read_text(encoding="utf-8")
    assert sheetkin.parse_scene(text).title.startswith(word) and "seed" not in text
