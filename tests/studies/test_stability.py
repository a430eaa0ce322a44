"""`sheetkin bench --stability` (issue #5, items 2-3; issue #12: a family for every kind):
each method walked towards a toggle, a change point, just past the edge of a non-assembling
interval, the edge of an RPR's range and two lines turning parallel (PRP, RPP), 1e-2 ..
1e-10 rad away.

What is pinned here is what the methods actually do there (measured against the mpmath
reference), and that every failure is reported: no method shows unflagged numbers that are
wrong. Fast: one run of the study (about 5 s), no LibreOffice.
"""
from __future__ import annotations

import csv
import math
import re

import mpmath
import numpy as np
import pytest

from sheetkin.cli.commands import main
from sheetkin.groups.rrr import FOURBAR as _STABILITY_SCENE
from sheetkin.kinematics.caps import SceneError
from sheetkin.kinematics.scene import override_crank
from sheetkin.kinematics.table import TOGGLE_THRESHOLD, AssemblyError, compute
from sheetkin.studies.bench import SILENT_ERROR, method_solver
from sheetkin.studies.stability import (
    FAMILY_TITLES,
    STABILITY_DISTANCES,
    edge_mp,
    family,
    family_cases,
    reference_near_singular,
    stability_scene,
    stability_study,
)

D = list(STABILITY_DISTANCES)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    table, warnings, edges = stability_study(out)
    return table, warnings, edges, out


def _rrr_mp(scene, phi):
    """(crank joint A, its frame point O1, L2, L3) of a one-dyad scene in mpmath at the crank
    angle phi (radians, an mpf): the closed form below is this test's, not the package's."""
    c, g = scene.crank, scene.groups[0]
    ox, oy = (mpmath.mpf(v) for v in scene.frame[c.pivot])
    ax, ay = ox + mpmath.mpf(c.length) * mpmath.cos(phi), oy + mpmath.mpf(c.length) * mpmath.sin(phi)
    jx, jy = (mpmath.mpf(v) for v in scene.frame[g.joints[2]])
    return (ax, ay), (jx, jy), mpmath.mpf(g.lengths[0]), mpmath.mpf(g.lengths[1])


def rows(table, fam, method):
    t = table[(table["family"] == fam) & (table["method"] == method)]
    assert list(t["d"]) == D
    return t


def warning(warnings, start):
    hits = [w for w in warnings if w.startswith(start)]
    assert len(hits) == 1, (start, warnings)
    return hits[0]


def named_distances(text):
    """The distances d named in a warning's list of crank angles."""
    return [float(x) for x in re.findall(r"\(d=([0-9.e+-]+)\)", text)]


# --------------------------------------------------------------------------- the cases
def test_scenes_are_exact_binary_fractions():
    """The change point is a change point in floats too: s + l = p + q exactly."""
    cp = stability_scene("change-point")
    assert cp.crank.length + cp.frame["O1"][0] == sum(cp.groups[0].lengths) == 0.625
    tg = stability_scene("toggle")
    assert tg.crank.length + tg.frame["O1"][0] > sum(tg.groups[0].lengths)   # non-Grashof


def test_edge_angle_is_the_discriminant_root():
    scene = stability_scene("toggle")
    with mpmath.workdps(50):
        edge = edge_mp(scene, family("toggle"))
        exact = mpmath.acos(mpmath.mpf(-0.3125))     # (r^2 + d^2 - (L2 + L3)^2) / (2 r d)
        assert abs(edge - exact) < mpmath.mpf(10) ** -45


def test_reference_agrees_with_differentiating_the_closed_form():
    """The reference's velocity and acceleration at 1e-6 rad from the toggle equal the
    derivatives (mpmath.diff, 60 digits) of B's closed-form position."""
    scene = stability_scene("toggle")
    with mpmath.workdps(60):
        phi = float(mpmath.degrees(edge_mp(scene, family("toggle")) - mpmath.mpf("1e-6")))
        ref = reference_near_singular(scene, family("toggle"), [phi])

        def xb(t_deg):
            (ax, ay), (jx, jy), l2, l3 = _rrr_mp(scene, t_deg * mpmath.pi / 180)
            px, py = jx - ax, jy - ay
            dist = mpmath.sqrt(px * px + py * py)
            a = (dist * dist + l2 * l2 - l3 * l3) / (2 * dist)
            return ax + a * px / dist - mpmath.sqrt(l2 * l2 - a * a) * py / dist

        k = 180 / mpmath.pi * scene.crank.omega        # d/dt = omega d/dphi, phi in degrees
        vx = mpmath.diff(xb, mpmath.mpf(phi)) * k
        ax_ = mpmath.diff(xb, mpmath.mpf(phi), 2) * k * k
        assert abs(vx / ref["vx_B"][0] - 1) < mpmath.mpf(10) ** -40
        assert abs(ax_ / ref["ax_B"][0] - 1) < mpmath.mpf(10) ** -40
        assert abs(ref["ax_B"][0]) > 1e8          # it is near the toggle: huge accelerations


# --------------------------------------------------------------------------- the solver
def test_solver_towards_a_toggle_flags_and_loses_digits_like_1_over_d(study):
    table, warnings, _, _ = study
    t = rows(table, "toggle", "solver")
    det = t["det"].abs().to_numpy()
    # flagged exactly where |det| < threshold; det ~ sqrt(d) (a square-root toggle)
    assert list(t["status"]) == ["ok"] * 3 + ["flagged"] * 6
    assert ((det < TOGGLE_THRESHOLD) == (t["status"] == "flagged")).all()
    assert det[4] / det[6] == pytest.approx(10, rel=0.01)
    # the velocity error, relative, grows like eps / d but stays finite and usable
    err = t["err_vel"].to_numpy()
    assert np.isfinite(t[["err_pos", "err_vel", "err_acc"]].to_numpy()).all()
    assert (err * np.array(D) < 1e-15).all() and (err * np.array(D) > 1e-19).all()
    assert err[-1] > 1e4 * err[0] and err[-1] < 1e-6
    w = warning(warnings, "solver (toggle): near a toggle at crank angles ")
    assert named_distances(w) == D[3:]
    assert w.endswith("deg (|det| < 0.01): velocities and accelerations lose accuracy")


def test_solver_just_outside_the_edge_refuses_naming_the_interval(study):
    table, warnings, edges, _ = study
    edge = float(edges["gap-edge"])
    assert list(rows(table, "gap-edge", "solver")["status"]) == ["refused"] * len(D)
    scene = stability_scene("toggle")
    for d in D:
        with pytest.raises(AssemblyError) as e:
            compute(scene, at=[edge + math.degrees(d)])
        start, end = map(float, re.search(r"crank angles ([0-9.]+)\.\.([0-9.]+) deg", str(e.value)).groups())
        assert start == pytest.approx(edge, abs=0.01) and end == pytest.approx(360 - edge, abs=0.01)
    # just inside it computes, flagged as near a toggle from 1e-5 rad on
    df = compute(scene, at=[edge - math.degrees(d) for d in D])
    assert list(df["near_toggle"]) == [""] * 3 + ["1"] * 6
    marked = compute(scene, at=[edge - 1e-6, edge + 1e-6], allow_gaps=True)
    assert list(marked["assembled"]) == [True, False]
    assert named_distances(warning(warnings, "solver (gap-edge): cannot assemble")) == D


def test_solver_at_a_change_point_keeps_its_branch_and_says_when_it_has_no_rates(study):
    table, warnings, edges, _ = study
    assert float(edges["change-point"]) == 180.0
    t = rows(table, "change-point", "solver")
    # det ~ d: flagged from the first distance on; from 1e-6 rad on the discriminant (a double
    # root, ~d^2) is within 1e-12 of its terms: a dead point, where the group does not assemble
    # in sheetkin and in every spreadsheet alike (docs/dead-points.md)
    assert set(t["status"]) == {"flagged", "refused"}
    assert list(t[t["status"] == "refused"]["d"]) == [1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    w = warning(warnings, "solver (change-point): cannot assemble")
    assert named_distances(w) == [1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    # positions stay good (error ~ eps / d at worst) ...
    assert (t["err_pos"].dropna() < 1e-8).all()
    # ... the accelerations are lost (flagged): 1e-2 rad away already at 2.6e-8
    acc = t["err_acc"].to_numpy()
    assert acc[0] < 1e-6 and acc[3] > 0.1
    # no silent branch flip: B never on the other side of A -> O1 than branch = +1
    scene = stability_scene("change-point")
    df = compute(scene, at=list(t["phi_deg"]), allow_gaps=True)
    df = df[df["assembled"]]
    assert len(df) == 4
    cross = ((0.5 - df["x_A"]) * (df["y_B"] - df["y_A"]) - (0.0 - df["y_A"]) * (df["x_B"] - df["x_A"]))
    assert (cross > 0).all()
    assert (df["near_toggle"] == "1").all()


# --------------------------------------------------------------------------- Newton
def test_newton_towards_a_toggle_converges_then_stops_and_says_so(study):
    table, warnings, _, _ = study
    t = rows(table, "toggle", "newton")
    assert list(t["status"]) == ["ok"] * 3 + ["flagged"] * 4 + ["diverged"] * 2
    assert (t["err_vel"].iloc[:7] < 1e-8).all() and t["err_vel"].iloc[6] > 100 * t["err_vel"].iloc[0]
    assert t[["err_pos", "err_vel", "err_acc"]].iloc[7:].isna().all().all()
    w = warning(warnings, "newton (toggle): no convergence at crank angles ")
    assert named_distances(w) == [1e-9, 1e-10]
    assert "108.209956807 (d=1e-09)" in w


def test_newton_past_the_edge_diverges_and_says_so(study):
    table, warnings, _, _ = study
    assert list(rows(table, "gap-edge", "newton")["status"]) == ["diverged"] * len(D)
    assert named_distances(warning(warnings, "newton (gap-edge): no convergence")) == D


def test_newton_at_a_change_point_stalls_in_the_flat_valley_flagged(study):
    """Newton's step test passes (the residual is round-off in a valley ~d wide), so it
    'converges', but its answer stops following the crank near 1e-8 rad: positions off by
    ~1e-8, velocities by their own size. Its own |sin(psi - xi)| flags all of it."""
    table, warnings, _, _ = study
    t = rows(table, "change-point", "newton")
    assert list(t["status"]) == ["flagged"] * len(D)
    assert t["err_pos"].iloc[-1] > 1e-9 and t["err_vel"].iloc[-1] > 0.1
    assert t["err_vel"].iloc[0] < 1e-10
    w = warning(warnings, "newton (change-point): converged near a singular Jacobian")
    assert named_distances(w) == D


# --------------------------------------------------------------------------- differences
def test_finite_differences_lose_digits_and_are_reported(study):
    table, warnings, _, _ = study
    t = rows(table, "toggle", "fd")
    # a neighbour phi +- 3e-4 rad falls in the gap from 1e-4 rad on: no number
    assert list(t["status"]) == ["unsure"] * 2 + ["refused"] * 7
    acc = t["err_acc"].to_numpy()
    assert acc[1] > 10 * acc[0] > 1e-3          # 1e-2 -> 1e-3 rad: another digit lost
    assert t["det"].iloc[1] > t["det"].iloc[0] > SILENT_ERROR    # its step-doubling estimate
    w = warning(warnings, "fd (toggle): the answers at steps h and 2h differ")
    assert named_distances(w) == [1e-2, 1e-3]
    # towards the change point the acceleration error grows decade by decade, to no digit
    c = rows(table, "change-point", "fd")
    acc = c["err_acc"].to_numpy()
    assert (acc[1:] >= 0.5 * acc[:-1]).all() and acc[-1] > 1e4 * acc[0]
    assert (c["err_vel"].iloc[4:] > 0.1).all()
    assert set(c["status"]) == {"flagged"}


def test_no_method_is_silently_wrong(study):
    table, warnings, _, _ = study
    assert not table["silent"].any()
    assert not [w for w in warnings if "SILENT" in w]
    # and the check can fire: an unflagged wrong answer would be counted
    ok = table[table["status"] == "ok"]
    assert (ok[["err_pos", "err_vel", "err_acc"]].max(axis=1) <= SILENT_ERROR).all()


def test_other_kinds_edges_are_exact(study):
    """The RRP families' edges, found by mpmath on the groups' discriminants, against
    geometry written out here: the crank-slider's coupler (0.2) stands across its guide
    (y = 0.05) when 0.05 - 0.25 sin(phi) = 0.2; the second rocker O2 D (0.3) stands across
    the line O1 B of the four-bar's rocker, B from the mpmath reference."""
    from sheetkin.kinematics.scene import parse_scene
    from sheetkin.studies.bench import reference_mp
    _, _, edges, _ = study
    with mpmath.workdps(50):
        edge, _, _ = family_cases(family("slider-toggle"), D)
        # the scene's numbers are the floats 0.05, 0.2, 0.25, taken exactly
        exact = mpmath.pi + mpmath.asin((mpmath.mpf(0.2) - mpmath.mpf(0.05)) / mpmath.mpf(0.25))
        assert abs(edge - exact) < mpmath.mpf(10) ** -40
    scene = stability_scene("slotted-toggle")
    fourbar = parse_scene(_STABILITY_SCENE.format(title="x", frame=0.0, crank=0.14, coupler=0.5, rocker=0.34,
                                                  branch=-1).replace("O1 = [0.0, 0.0]", "O1 = [0.0, -0.53]"))
    ref = reference_mp(fourbar, [float(edges["slotted-toggle"])], dps=30)
    bx, by = float(ref["x_B"][0]), float(ref["y_B"][0])
    (ox, oy), (qx, qy) = scene.frame["O1"], scene.frame["O2"]
    h = abs((bx - ox) * (qy - oy) - (by - oy) * (qx - ox)) / math.hypot(bx - ox, by - oy)
    assert h == pytest.approx(0.3, abs=1e-12)
    for fam in ("slider-toggle", "slotted-toggle"):
        solver = rows(study[0], fam, "solver")
        # the solver keeps its answers to the end, flagged once |det| < the threshold
        assert set(solver["status"]) <= {"ok", "flagged"} and solver["status"].iloc[-1] == "flagged"


# --------------------------------------------------------------------------- every kind
def test_every_kind_has_a_family_on_its_own_group():
    """Each kind module declares at least one family (its STABILITY), and each family's
    failing group is of that kind: the study reaches every kind through the registry."""
    from sheetkin.groups import KINDS
    names = [f.name for kind in KINDS.values() for f in kind.STABILITY]
    assert len(names) == len(set(names)) == len(FAMILY_TITLES)
    for kind in KINDS.values():
        assert kind.STABILITY
        for f in kind.STABILITY:
            scene = stability_scene(f.name)
            assert next(g for g in scene.groups if g.index == f.group).type == kind.KIND


def test_new_kinds_edges_are_exact(study):
    """The edges found by mpmath on the kinds' own functions, against geometry written out
    here. RPR: |A - C| = e, 0.0625 + 0.25 + 0.25 cos(phi) = 0.375^2, cos(phi) = -0.6875.
    PRP: the crank-slider's coupler (sin eta = -0.25 sin(phi) / 0.5) at the fixed guide's
    20 deg. RPP: the slot at the guide's 30 deg."""
    _, _, edges, _ = study
    with mpmath.workdps(50):
        kulisa, _, _ = family_cases(family("kulisa-edge"), D)
        assert abs(kulisa - mpmath.acos(mpmath.mpf("-0.6875"))) < mpmath.mpf(10) ** -40
        lines, _, _ = family_cases(family("parallel-lines"), D)
        exact = mpmath.pi + mpmath.asin(2 * mpmath.sin(mpmath.radians(20)))
        assert abs(lines - exact) < mpmath.mpf(10) ** -40
    assert edges["parallel-slot"] == 30


def test_new_kinds_toggle_measure_vanishes_at_the_edge(study):
    """The solver's and Newton's toggle measures go to 0 at the singular position: like
    sqrt(d) at the RPR's range edge (s / L1), like d where two lines turn parallel (PRP:
    sin(theta - eta), RPP: sin(alpha - gamma))."""
    table = study[0]
    det = rows(table, "kulisa-edge", "solver")["det"].abs().to_numpy()
    assert det[2] / det[4] == pytest.approx(10, rel=0.01) and det[-1] < 2e-5
    for fam, last in (("parallel-lines", 9), ("parallel-slot", 7)):
        det = rows(table, fam, "solver")["det"].abs().to_numpy()[:last]
        assert det[:-1] / det[1:] == pytest.approx(np.full(last - 1, 10.0), rel=0.01)
        newton = rows(table, fam, "newton")
        ok = newton["status"].isin(["ok", "flagged"]).to_numpy()[:last]
        assert newton["det"].abs().to_numpy()[:last][ok] == pytest.approx(det[ok], rel=1e-6)


def test_new_kinds_closed_form_loses_at_most_eps_over_d(study):
    """The closed form's error, relative to the quantities' size, stays at round-off far
    from the failure and grows no faster than eps / d towards it (the rates too: N and K
    running off, their speeds grow like 1/d^2 and still keep that relative accuracy)."""
    table = study[0]
    for fam in ("kulisa-edge", "parallel-lines", "parallel-slot"):
        t = rows(table, fam, "solver")
        got = t[t["status"] != "refused"]
        d = got["d"].to_numpy()
        err = got[["err_pos", "err_vel", "err_acc"]].max(axis=1).to_numpy()
        assert np.isfinite(err).all() and err[0] < 1e-13, fam
        assert (err * d < 1e-15).all(), (fam, err * d)
        # Newton, where it gives a number, is no better: the same conditioning
        n = rows(table, fam, "newton")
        n = n[n["status"].isin(["ok", "flagged"])]
        assert (n[["err_pos", "err_vel", "err_acc"]].max(axis=1) * n["d"] < 1e-14).all(), fam
    # the RPR behaves as the four-bar's toggle: flagged from 1e-5 rad on
    assert list(rows(table, "kulisa-edge", "solver")["status"]) == ["ok"] * 3 + ["flagged"] * 6
    # two lines nearly parallel: flagged from the first distance (|det| = 0.39 d)
    assert set(rows(table, "parallel-lines", "solver")["status"]) == {"flagged"}


def test_prp_crossing_point_runs_off_like_1_over_d(study):
    """N = L goes to infinity as the coupler's line turns parallel to the fixed guide: |s_L| d
    tends to a constant (the solver, away from the last distances' round-off)."""
    t = rows(study[0], "parallel-lines", "solver")
    scene = stability_scene("parallel-lines")
    s = compute(scene, at=list(t["phi_deg"]))["s_L"].abs().to_numpy()
    k = s * t["distance"].to_numpy()
    assert s[-1] > 1e9
    assert k[3:] == pytest.approx(np.full(len(k) - 3, k[-1]), rel=1e-3)


def test_newtons_no_convergence_where_lines_turn_parallel_is_its_step_test():
    """The Scotch yoke's equations are linear: Newton's answer is right after one step, but
    its step test (NEWTON_TOL of |q|) cannot be met once the condition number is ~1/d: at
    1e-4 and 1e-6 rad it reports no convergence; with a test of 1e-10 the same iterations
    stop, on the solver's answer."""
    from sheetkin.studies.bench import FLOAT, NEWTON_MAX_ITER, NEWTON_TOL, closed_form_unknowns, loop_kinematics
    _, _, cases = family_cases(family("parallel-slot"), [1e-4, 1e-6])
    for scene, phi, _, _ in cases:
        start = closed_form_unknowns(scene, [phi])[0]
        assert loop_kinematics(FLOAT, scene, phi, dict(start), NEWTON_TOL, NEWTON_MAX_ITER)[2][0][1] == "no convergence"
        values, _, problems, _ = loop_kinematics(FLOAT, scene, phi, dict(start), 1e-10, NEWTON_MAX_ITER)
        assert not problems
        df = compute(scene, at=[phi])
        for name in ("x_K", "s_K", "vs_K", "as_A"):
            assert values[name] == pytest.approx(df[name].iloc[0], rel=1e-9), name


def test_scotch_yoke_family_varies_the_slot_and_the_parser_refuses_it_at_last(study):
    """RPP's toggle measure does not depend on the crank angle: the family varies
    slot_angle_deg at one crank angle, and within 1e-9 rad of the guide the scene is
    refused (by every method: there is no scene), said with the slot angles."""
    table, warnings, _, out = study
    t = table[table["family"] == "parallel-slot"]
    assert set(t["varies"]) == {"slot_angle_deg"} and set(t["phi_deg"]) == {100.0}
    solver = rows(table, "parallel-slot", "solver")
    assert solver["value_deg"].to_numpy() == pytest.approx(30 - np.degrees(D), abs=1e-12)
    assert list(solver["status"]) == ["flagged"] * 7 + ["refused"] * 2
    for method in ("newton", "fd"):
        assert list(rows(table, "parallel-slot", method)["status"])[7:] == ["refused"] * 2
    w = warning(warnings, "solver (parallel-slot): cannot assemble at slot_angle_deg ")
    assert named_distances(w) == [1e-9, 1e-10] and w.endswith("deg (refused)")
    with pytest.raises(SceneError, match="slot_angle_deg.*runs along the guide"):
        stability_scene("parallel-slot", float(solver["value_deg"].iloc[-1]))
    crank = table[table["family"] == "toggle"]
    assert set(crank["varies"]) == {"crank angle"} and (crank["value_deg"] == crank["phi_deg"]).all()


# --------------------------------------------------------------------------- files, CLI
def test_csv_and_png_written(study):
    table, _, _, out = study
    with open(out / "stability.csv", newline="") as f:
        got = list(csv.DictReader(f))
    assert len(got) == len(FAMILY_TITLES) * 3 * len(D) == len(table)
    assert list(got[0]) == ["family", "d", "distance", "phi_deg", "method", "param", "status", "err_pos",
                            "err_vel", "err_acc", "det", "silent", "varies", "value_deg", "seconds"]
    # the float angle's distance from the edge is the nominal one to 1e-6 of it
    for r in got:
        assert float(r["distance"]) == pytest.approx(float(r["d"]), rel=1e-5)
    png = (out / "stability.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 30_000


def test_cli_stability(tmp_path, capsys, monkeypatch):
    # the command runs the study's own function: one family is enough here (the study
    # fixture runs them all)
    toggle = family("toggle")
    monkeypatch.setattr("sheetkin.studies.stability.families", lambda: [toggle])
    assert main(["bench", "--stability", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert out.split()[:4] == ["family", "d", "method", "status"]
    assert ("sheetkin: warning: solver (toggle): near a toggle at crank angles "
            "108.209383906 (d=1e-05)") in err
    assert (tmp_path / "stability.csv").is_file() and (tmp_path / "stability.png").is_file()
    assert main(["bench", "--out", str(tmp_path)]) == 2
    assert "a SCENE.toml is needed" in capsys.readouterr().err


def test_main_bench_warns_about_the_solvers_near_toggle_positions(tmp_path, capsys):
    text = _STABILITY_SCENE.format(title="t", frame=0.5, crank=0.25, coupler=0.375, rocker=0.25,
                                   branch=1)
    text, scene = override_crank(text, "t.toml", phi0_deg=108.2099, step_deg=-30.0, positions=2)
    r = method_solver(scene, scene.crank_angles_deg())
    assert list(r.flags.values()) == [[108.2099]] and not r.failures
    path = tmp_path / "t.toml"
    path.write_text(text)
    assert main(["bench", str(path), "--out", str(tmp_path / "o"), "--no-libreoffice"]) == 0
    err = capsys.readouterr().err
    assert ("sheetkin: warning: solver: near a toggle at crank angles 108.21 deg (|det| < 0.01): "
            "velocities and accelerations lose accuracy") in err
