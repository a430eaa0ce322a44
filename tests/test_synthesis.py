"""`sheetkin synth crank-rocker` and sheetkin.synthesis (seed 002, issue #6 part 1).

The synthesized mechanism is checked through the solver, independently of the synthesis
formulas: its rocker angle phi_3 over a revolution has its extremes at gamma1 and gamma2, at
crank angles (found by bisection on omega_3 = 0) whose ratio of working stroke to return is K_w.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import fsolve

import sheetkin
from sheetkin.cli import main
from sheetkin.synthesis import SynthesisError, _check, overlap_angle_deg, synthesize_crank_rocker

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
