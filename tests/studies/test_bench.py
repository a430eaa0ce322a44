"""`sheetkin bench` (issue #5): the mpmath reference, the methods' errors, the files, the CLI.

Fast (no LibreOffice): the bundled four-bar at its 13 positions, plus small variants.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import mpmath
import numpy as np
import pytest

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.kinematics.scene import override_crank, parse_scene
from sheetkin.kinematics.table import TOGGLE_THRESHOLD, AssemblyError, solution_columns
from sheetkin.studies.bench import (
    COLUMNS,
    SILENT_ERROR,
    _workbook_file,
    bench_scene,
    errors,
    method_evaluator,
    method_fd,
    method_newton,
    method_solver,
    quantity_names,
    reference_mp,
    run_bench,
    scaled_differences,
)

ROOT = Path(__file__).resolve().parents[2]
FOURBAR_TOML = ROOT / "workbooks" / "fourbar.toml"
FOURBAR_TEXT = FOURBAR_TOML.read_text(encoding="utf-8")


def _subst(text, old, new):
    assert text.count(old) == 1
    return text.replace(old, new)


def _fourbar(lengths, positions, step):
    """The bundled four-bar with other dyad lengths and crank positions."""
    t = _subst(FOURBAR_TEXT, "lengths = [0.5, 0.34]", f"lengths = {lengths}")
    t = _subst(t, "positions = 13", f"positions = {positions}")
    return _subst(t, "step_deg  = 30.0", f"step_deg = {step}")


# coupler + rocker = 0.6705, just over the largest |A O1| = 0.67 (crank at 90 deg): a
# near-toggle at 90 deg where both branches almost meet
NEAR_TOGGLE = _fourbar("[0.3305, 0.34]", 4, 90.0)
# coupler + rocker = 0.67 exactly: the toggle itself at 90 deg
AT_TOGGLE = _fourbar("[0.33, 0.34]", 4, 90.0)
# coupler + rocker = 0.670001: 89 .. 91 deg in steps of 0.25 deg, the middle ones so near the
# toggle that the transmission angle's sine is below TOGGLE_THRESHOLD, the outer ones not
CLOSE_TO_TOGGLE = override_crank(_fourbar("[0.330001, 0.34]", 13, 30.0), "close.toml",
                                 phi0_deg=89.0, step_deg=0.25, positions=9)[0]
FD_FLAG = "the answers at steps h and 2h differ by more than"


@pytest.fixture(scope="module")
def fourbar():
    scene = sheetkin.load_scene(FOURBAR_TOML)
    phis = np.array(scene.crank_angles_deg())
    return scene, phis, reference_mp(scene, phis)


def _slotted_lever_with_offset():
    t = (ROOT / "workbooks" / "slotted_lever.toml").read_text(encoding="utf-8")
    return parse_scene(_subst(t, 'joints = ["A", "O3"]', 'joints = ["A", "O3"]\noffset = 0.3'))


@pytest.mark.parametrize("scene", [
    pytest.param(lambda: sheetkin.load_scene(FOURBAR_TOML), id="RRR"),
    pytest.param(lambda: sheetkin.load_scene(ROOT / "workbooks" / "shaper.toml"), id="RPR+RRP"),
    pytest.param(lambda: sheetkin.load_scene(ROOT / "workbooks" / "crank_slider.toml"), id="RRP"),
    pytest.param(_slotted_lever_with_offset, id="RPR-offset")])
def test_reference_agrees_with_solver(scene):
    scene = scene()
    phis = scene.crank_angles_deg()
    ref = reference_mp(scene, phis)
    assert set(ref) == set(quantity_names(scene))
    cols = solution_columns(scene, sheetkin.solve(scene, phis))
    for name, values in ref.items():
        got, want = cols[name], np.array([float(v) for v in values])
        diff = (got - want + 180.0) % 360.0 - 180.0 if name.startswith("phi_") else got - want
        scale = max(1.0, float(np.max(np.abs(want))))
        assert np.max(np.abs(diff)) <= 1e-12 * scale, name


def test_reference_carries_50_digits(fourbar):
    """The reference is not a float result in disguise: the coupler's length |A B| and the
    rocker's |B O1| hold to ~45 digits."""
    scene, phis, ref = fourbar
    with mpmath.workdps(50):
        for i in range(len(phis)):
            ab = mpmath.hypot(ref["x_B"][i] - ref["x_A"][i], ref["y_B"][i] - ref["y_A"][i])
            bo = mpmath.hypot(ref["x_B"][i], ref["y_B"][i] - mpmath.mpf(-0.53))
            assert abs(ab - mpmath.mpf(0.5)) < mpmath.mpf(10) ** -44
            assert abs(bo - mpmath.mpf(0.34)) < mpmath.mpf(10) ** -44


def test_errors_measure_the_difference(fourbar):
    scene, phis, ref = fourbar
    exact = {n: np.array([float(v) for v in vs]) for n, vs in ref.items()}
    assert max(errors(exact, ref).values()) < 1e-15
    off = dict(exact, x_B=exact["x_B"] + 1e-6)
    assert errors(off, ref)["err_pos"] == pytest.approx(1e-6, rel=1e-6)
    # velocities are measured relative to the largest speed (|v| up to ~3 m/s here)
    big = max(abs(float(v)) for n in ref if n.startswith(("vx_", "vy_")) for v in ref[n])
    off = dict(exact, vy_S3=exact["vy_S3"] + 1e-6)
    assert errors(off, ref)["err_vel"] == pytest.approx(1e-6 / big, rel=1e-6)
    # an angle just below 360 is just below 0: the error is the small difference, not 2 pi
    i = int(np.argmin(exact["phi_2"]))
    off = dict(exact, phi_2=exact["phi_2"].copy())
    off["phi_2"][i] = exact["phi_2"][i] + 360.0 - 1e-9
    assert errors(off, ref)["err_pos"] == pytest.approx(math.radians(1e-9), rel=1e-3)


def test_solver_and_newton_are_exact(fourbar):
    scene, phis, ref = fourbar
    for r in (method_solver(scene, phis), method_newton(scene, phis)):
        assert not r.failures, r.method
        assert r.seconds_per_position > 0
        assert max(errors(r.values, ref).values()) < 1e-12, r.method


def test_finite_differences_show_the_v(fourbar):
    """Too large a step: truncation error; too small: round-off; the best is in between."""
    scene, phis, ref = fourbar
    results = method_fd(scene, phis)
    assert [r.param for r in results][0] == "h=0.1" and results[-1].param == "h=1e-08"
    for kind in ("err_vel", "err_acc"):
        err = np.array([errors(r.values, ref)[kind] for r in results])
        best = int(np.argmin(err))
        assert 0 < best < len(err) - 1, kind
        assert err[0] > 100 * err[best] and err[-1] > 100 * err[best], (kind, err)
    # positions are the solver's own at every step
    assert all(errors(r.values, ref)["err_pos"] < 1e-12 for r in results)


def test_evaluator_is_exact(fourbar, tmp_path):
    scene, phis, ref = fourbar
    scene, text = bench_scene(scene, None)
    book = _workbook_file(scene, text, tmp_path)
    r = method_evaluator(scene, phis, book)
    assert not r.failures
    assert max(errors(r.values, ref).values()) < 1e-10


def test_run_bench_writes_table_and_chart(tmp_path):
    scene = sheetkin.load_scene(FOURBAR_TOML)
    table, warnings = run_bench(scene, None, tmp_path, libreoffice=False)
    # a normal scene: only the finite-difference steps too large or too small are flagged
    assert warnings and all(w.startswith("fd h=") and FD_FLAG in w for w in warnings)
    assert (table[table["method"] != "fd"]["flagged"] == 0).all()
    assert list(table["method"].unique()) == ["solver", "newton", "fd", "evaluator"]
    with open(tmp_path / "bench.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    # the old columns first, unchanged (readers of the old file keep working)
    assert list(rows[0])[:7] == ["method", "param", "seconds_per_position", "err_pos", "err_vel",
                                 "err_acc", "notes"]
    assert list(rows[0]) == COLUMNS
    assert len(rows) == len(table) and sum(r["method"] == "fd" for r in rows) == 15
    for r in rows:
        assert int(r["flagged"]) == len(r["flagged_deg"].split())
        assert (r["est_vel"] != "") == (r["method"] == "fd")
    png = (tmp_path / "bench.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000


def test_cli_bench(tmp_path, capsys):
    assert main(["bench", str(FOURBAR_TOML), "--out", str(tmp_path), "--positions", "8",
                 "--no-libreoffice"]) == 0
    out, err = capsys.readouterr()
    assert out.splitlines()[0].split()[:3] == ["method", "param", "s/position"]
    assert "evaluator" in out
    # the only warnings: finite-difference steps flagged by their step doubling, one line
    # for the steps flagged at the same positions
    warned = [line for line in err.splitlines() if "warning" in line]
    assert warned and all(w.startswith("sheetkin: warning: fd h=") and FD_FLAG in w for w in warned)
    assert len(warned) < sum(line.startswith("fd") and FD_FLAG in line for line in out.splitlines())
    assert (tmp_path / "bench.csv").is_file() and (tmp_path / "bench.png").is_file()
    with open(tmp_path / "bench.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert float(rows[0]["err_vel"]) < 1e-12


def test_positions_cover_one_revolution():
    scene, text = bench_scene(sheetkin.load_scene(ROOT / "workbooks" / "shaper.toml"), 8)
    assert scene.crank_angles_deg() == pytest.approx([248.2617 - 45.0 * i for i in range(8)])
    assert "positions = 8" in text


def test_newton_jumps_branch_near_a_toggle(tmp_path, capsys):
    """Warm-started 90 deg apart past a near-toggle at 90 deg, Newton lands on the other
    branch at 180 and stays there at 270: the bench says so, and its error shows it."""
    scene = parse_scene(NEAR_TOGGLE, "near_toggle.toml")
    r = method_newton(scene, scene.crank_angles_deg())
    assert r.failures == {"branch jump (group 1 (RRR A-B-O1))": [180.0, 270.0]}
    path = tmp_path / "near_toggle.toml"
    path.write_text(NEAR_TOGGLE)
    assert main(["bench", str(path), "--out", str(tmp_path / "out"), "--no-libreoffice"]) == 0
    out, err = capsys.readouterr()
    assert ("sheetkin: warning: newton tol=1e-14: branch jump (group 1 (RRR A-B-O1)) "
            "at crank angles 180, 270 deg") in err
    newton = next(line for line in out.splitlines() if line.startswith("newton"))
    assert "branch jump" in newton and float(newton.split()[3]) > 0.1   # err_pos
    # with small steps it follows the branch
    scene24, _ = bench_scene(scene, 24, NEAR_TOGGLE)
    assert not method_newton(scene24, scene24.crank_angles_deg()).failures


def test_newton_does_not_converge_after_the_toggle():
    """Started from the toggle itself (90 deg, where J is singular), the step to 180 deg
    does not converge: that position is NaN and named."""
    scene = parse_scene(AT_TOGGLE, "at_toggle.toml")
    r = method_newton(scene, scene.crank_angles_deg())
    assert r.failures == {"no convergence (group 1 (RRR A-B-O1))": [180.0]}
    assert np.isnan(r.values["x_B"][2]) and np.isfinite(r.values["x_B"][[0, 1, 3]]).all()


def test_bench_refuses_a_scene_that_cannot_assemble(tmp_path, capsys):
    path = tmp_path / "short.toml"
    path.write_text(_fourbar("[0.25, 0.34]", 13, 30.0))
    with pytest.raises(AssemblyError):
        run_bench(sheetkin.load_scene(path), None, tmp_path, libreoffice=False)
    assert main(["bench", str(path), "--out", str(tmp_path / "out"), "--no-libreoffice"]) == 3
    assert capsys.readouterr().err.startswith("sheetkin: error: ")


# --------------------------------------------------------------------------- the methods' own checks
def _sine_from_reference(ref):
    """sin(psi - xi), coupler against rocker, of the four-bar from the mpmath reference:
    the toggle measure computed without the bench's Jacobian."""
    return np.array([float(mpmath.sin(mpmath.radians(a - b)))
                     for a, b in zip(ref["phi_2"], ref["phi_3"], strict=False)])


def test_newton_flags_its_singular_jacobian_in_the_main_table(tmp_path, capsys):
    """Near a toggle Newton still converges, but its Jacobian is nearly singular: the main
    table counts and names those positions and a warning names the crank angles, exactly
    where the reference's |sin(psi - xi)| is below the threshold."""
    scene = parse_scene(CLOSE_TO_TOGGLE, "close.toml")
    phis = scene.crank_angles_deg()
    sine = _sine_from_reference(reference_mp(scene, phis))
    expected = [p for p, s in zip(phis, sine, strict=False) if abs(s) < TOGGLE_THRESHOLD]
    assert 0 < len(expected) < len(phis)          # the scene has both kinds of position
    r = method_newton(scene, phis)
    assert not r.failures
    assert r.measure == pytest.approx(sine, abs=1e-9)
    assert list(r.flags.values()) == [expected]
    path = tmp_path / "close.toml"
    path.write_text(CLOSE_TO_TOGGLE)
    assert main(["bench", str(path), "--out", str(tmp_path / "out"), "--no-libreoffice"]) == 0
    out, err = capsys.readouterr()
    at = ", ".join(f"{p:g}" for p in expected)
    assert (f"sheetkin: warning: newton tol=1e-14: converged near a singular Jacobian at crank "
            f"angles {at} deg") in err
    newton = next(line for line in out.splitlines() if line.startswith("newton"))
    assert f"converged near a singular Jacobian at {len(expected)} of {len(phis)} positions" in newton
    with open(tmp_path / "out" / "bench.csv", newline="") as f:
        rows = {row["method"]: row for row in csv.DictReader(f)}
    assert int(rows["newton"]["flagged"]) == len(expected)
    assert [float(p) for p in rows["newton"]["flagged_deg"].split()] == expected
    # the solver's own |det| flags the same positions
    assert [float(p) for p in rows["solver"]["flagged_deg"].split()] == expected


@pytest.mark.parametrize("name", ["fourbar", "crank_slider", "shaper"])
def test_newton_flags_nothing_on_a_normal_scene(name):
    """Far from toggles nothing is flagged; Newton's measure (its Jacobian's columns) is
    the solver's toggle measure (its Cramer determinant) for RRR and RRP groups."""
    scene = sheetkin.load_scene(ROOT / "workbooks" / f"{name}.toml")
    phis = scene.crank_angles_deg()
    r = method_newton(scene, phis)
    assert not r.flags and not r.failures and not method_solver(scene, phis).flags
    assert (np.abs(r.measure) > TOGGLE_THRESHOLD).all()
    if len(scene.groups) == 1 and scene.groups[0].type in ("RRR", "RRP"):
        det = sheetkin.solve(scene, phis).det[scene.groups[0].index]
        assert r.measure == pytest.approx(det, abs=1e-12)


def test_fd_step_doubling_estimates_the_true_error(fourbar):
    """The step-doubling estimate (h against 2h, no reference used) against the true error
    (against mpmath): three times it where truncation rules (error ~ h^2: the difference of
    h and 2h is 4 - 1 = 3 errors), within a small factor where round-off rules, for every
    step whose answer has any digits left."""
    scene, phis, ref = fourbar
    checked = 0
    for r in method_fd(scene, phis):
        err = scaled_differences(r.values, ref)
        for kind in ("vel", "acc"):
            true, est = float(np.max(err[kind])), float(np.max(r.estimate[kind]))
            assert np.isfinite(est) and est > 0
            if float(r.param[2:]) >= 1e-3:             # truncation: the ratio is 3
                assert est / true == pytest.approx(3, rel=0.05), (r.param, kind)
            if true < 1e-2:
                assert 0.3 < est / true < 5, (r.param, kind, est, true)
                checked += 1
    assert checked >= 25


def test_fd_step_doubling_flags_agree_with_the_reference(fourbar, tmp_path):
    """The FD rows the check leaves unflagged are right to 1e-6; those wrong by 10 times
    more are flagged at every position."""
    scene, phis, _ = fourbar
    table, _ = run_bench(scene, None, tmp_path, libreoffice=False)
    fd = table[table["method"] == "fd"]
    worst = fd[["err_vel", "err_acc"]].max(axis=1)
    assert (worst[fd["flagged"] == 0] <= SILENT_ERROR).all()
    assert (fd["flagged"][worst > 10 * SILENT_ERROR] == len(phis)).all()
    assert (fd["flagged"] == 0).any() and (worst > 10 * SILENT_ERROR).any()
    # the estimate the row shows is the check's: above the threshold where flagged
    est = fd[["est_vel", "est_acc"]].max(axis=1)
    assert ((est > SILENT_ERROR) == (fd["flagged"] > 0)).all()
