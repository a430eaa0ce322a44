"""`sheetkin bench`: how fast and how exact each way of computing a scene's kinematics is.

Every method is timed per crank position and compared with a reference computed here with
mpmath at 50 digits, independently of the closed-form solver (issue #5):

  solver      the closed-form solver (the lecture's method, sheetkin.kinematics.solver);
  newton      Newton on the vector loop-closure equations (the seeds' Given-Find),
              warm-started from the previous position; rates from the Jacobian systems;
  fd          central differences of the solver's positions in the crank angle (what
              Mathcad's d/dphi does), for steps h = 1e-1 .. 1e-8 rad;
  evaluator   the workbook's formulas (sheetkin.sheet.workbook) through sheetkin.xlsx.evaluator;
  libreoffice the same workbook recalculated by LibreOffice Calc (when installed).

Errors are reported in three kinds, each the largest over positions and quantities of
|value - reference| / scale, where a quantity family's scale is max(1, the largest
|reference| of that family over all positions) (so small values are compared absolutely,
large ones relatively; the families are listed in FAMILIES):
  err_pos  x, y, s (m) and link angles phi_k (rad, the difference taken modulo 2 pi);
  err_vel  vx, vy, vs (m/s) and omega_k (rad/s);
  err_acc  ax, ay, as (m/s^2) and eps_k (rad/s^2).
A position where a method gives no number (NaN, a spreadsheet error) or jumps to the
other branch is a failure: the table's notes and a warning name the crank angles. So are
the positions a method's own check flags (the columns flagged and flagged_deg): the solver
near a toggle (its |det|), Newton converged where its Jacobian is nearly singular
(newton_singular, the same check as the stability study's), a finite-difference step whose
answer changes by more than SILENT_ERROR when the step is doubled (step_doubling, its
estimate in est_vel and est_acc; also the stability study's).

`sheetkin bench --stability --out DIR` (sheetkin.studies.stability): the solver, Newton and finite
differences walked towards where each group kind degenerates, against the same reference.
"""
from __future__ import annotations

import math
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any, cast

import mpmath
import numpy as np
import pandas as pd

from sheetkin.groups import kind_of
from sheetkin.groups.group import Group, slide_names
from sheetkin.kinematics.scene import Point, Scene, override_crank
from sheetkin.kinematics.solver import solve
from sheetkin.kinematics.table import TOGGLE_THRESHOLD, AssemblyError, assembly_gaps, failed_positions, solution_columns
from sheetkin.xlsx.libreoffice import soffice_path

FD_STEPS = tuple(10.0 ** -k for k in np.arange(1.0, 8.01, 0.5))     # rad, 1e-1 .. 1e-8
NEWTON_TOL = 1e-14          # step size (relative to 1 + |q|) at which Newton stops
NEWTON_MAX_ITER = 50
REPEATS = 5                 # timing: best of this many runs for the fast methods

# quantity head -> (error kind, family whose common scale it is measured against)
FAMILIES = {"x": ("pos", "m"), "y": ("pos", "m"), "s": ("pos", "m"), "phi": ("pos", "rad"),
            "vx": ("vel", "m/s"), "vy": ("vel", "m/s"), "vs": ("vel", "m/s"),
            "omega": ("vel", "rad/s"),
            "ax": ("acc", "m/s^2"), "ay": ("acc", "m/s^2"), "as": ("acc", "m/s^2"),
            "eps": ("acc", "rad/s^2")}
FAMILIES.update({"s2": FAMILIES["s"], "vs2": FAMILIES["vs"], "as2": FAMILIES["as"]})   # PRP's s2_N, vs2_N, as2_N
# flagged: how many positions the method's own checks flag (the solver's |det|, Newton's
# singular Jacobian, the finite differences' step doubling), flagged_deg: their crank angles;
# est_vel, est_acc: the finite differences' step-doubling estimate (empty for the others)
COLUMNS = ["method", "param", "seconds_per_position", "err_pos", "err_vel", "err_acc", "notes",
           "flagged", "flagged_deg", "est_vel", "est_acc"]
SILENT_ERROR = 1e-6         # a difference of h against 2h above this flags the finite
                            # differences; (stability) an "ok" answer off by more is silent
LOSE = "velocities and accelerations lose accuracy"


@dataclass
class MethodResult:
    """One method's values (name -> array over positions), its time and its failures."""
    method: str
    param: str
    seconds_per_position: float
    values: dict[str, np.ndarray]
    failures: dict[str, list[float]] = field(default_factory=dict)   # reason -> crank angles
    notes: str = ""
    flags: dict[str, list[float]] = field(default_factory=dict)      # warning -> crank angles
    # the method's own check per position (Newton: its smallest jacobian_sine; the finite
    # differences: the larger kind of their step-doubling estimate); None for the others
    measure: np.ndarray | None = None
    estimate: dict[str, np.ndarray] = field(default_factory=dict)   # fd: "vel", "acc" -> per position


def flag(res: MethodResult, what: str, why: str, phis, mask) -> None:
    """Record the warning `what at crank angles ... deg why` for the positions in `mask`
    (the key keeps {at} for the angles; the text before " at crank angles" is the note)."""
    at = [float(p) for p in np.asarray(phis, dtype=float)[np.asarray(mask, dtype=bool)]]
    if at:
        res.flags[f"{what} at crank angles {{at}} deg {why}".rstrip()] = at


def newton_singular(threshold: float) -> tuple[str, str]:
    """(what, why) of Newton's flag: it converged where its Jacobian is (near) singular."""
    return ("converged near a singular Jacobian",
            f"(|det J| / (|J col 1| |J col 2|) < {threshold:g}; RRR: |sin(psi - xi)|): "
            f"positions may be off, {LOSE}")


def unsure(estimate) -> np.ndarray:
    """Where the finite differences' step-doubling estimate flags them: above SILENT_ERROR,
    or no estimate (the doubled step gives no number)."""
    return ~(np.asarray(estimate, dtype=float) <= SILENT_ERROR)


def fd_unsure(limit: float = SILENT_ERROR) -> tuple[str, str]:
    """(what, why) of the finite differences' step-doubling flag (unsure)."""
    return (f"the answers at steps h and 2h differ by more than {limit:g}",
            "(step doubling: the step is too large or too small there, or too close to a "
            "singular position)")


def quantity_names(scene: Scene) -> list[str]:
    """The contract quantities the bench compares (magnitudes v_P, a_P are derived, left out)."""
    names = []
    for k in scene.links:
        names += [f"phi_{k}", f"omega_{k}", f"eps_{k}"]
    for p in scene.moving_joints + [p.name for p in scene.points]:
        names += [f"{q}_{p}" for q in ("x", "y", "vx", "vy", "ax", "ay")]
    for p in scene.sliders:
        names += list(slide_names(p))
    return names


# --------------------------------------------------------------------------- loop equations
# Written once for any number type: `lib` is MP (mpmath, 50 digits) or FLOAT (math +
# numpy). The reference and the Newton method share these equations; the closed-form solver
# shares nothing with them (different unknowns, no half-angle, no Cramer), which is what
# makes the reference independent of it.
def _mp_solve(m, b):
    return list(mpmath.lu_solve(mpmath.matrix(m), mpmath.matrix(b)))


MP = SimpleNamespace(cos=mpmath.cos, sin=mpmath.sin, pi=lambda: mpmath.pi, num=mpmath.mpf,
                     floor=mpmath.floor, solve=_mp_solve, finite=mpmath.isfinite,
                     sqrt=mpmath.sqrt, atan2=mpmath.atan2)
FLOAT = SimpleNamespace(cos=math.cos, sin=math.sin, pi=lambda: math.pi, num=float,
                        floor=math.floor, solve=lambda m, b: list(np.linalg.solve(m, b)),
                        finite=math.isfinite, sqrt=math.sqrt, atan2=math.atan2)


def _e(lib, a):
    return lib.cos(a), lib.sin(a)


def _ep(lib, a):
    """e(a) turned +90 deg: d e(a) / da."""
    return -lib.sin(a), lib.cos(a)


def _carried(lib, origin, link, along, across):
    """A point fixed on a link turning at (phi, w, eps): r = along e + across e_perp,
    v = v_O + w dr/dphi, a = a_O + eps dr/dphi - w^2 r."""
    (px, py), (vx, vy), (ax, ay) = origin
    phi, w, eps = link
    (c, s), (nc, ns) = _e(lib, phi), _ep(lib, phi)
    rx, ry = along * c + across * nc, along * s + across * ns
    dx, dy = along * nc - across * c, along * ns - across * s
    return ((px + rx, py + ry), (vx + w * dx, vy + w * dy),
            (ax + eps * dx - w * w * rx, ay + eps * dy - w * w * ry))


def _newton(lib, F, J, q, tol, max_iter):
    """Plain Newton from q; returns (q, converged). Converged: the last step was below
    tol * (1 + |q|) and the residual is small for the number type."""
    for _ in range(max_iter):
        dq = lib.solve(J(q), [-f for f in F(q)])
        q = [a + d for a, d in zip(q, dq, strict=False)]
        if not all(lib.finite(x) for x in q):
            return q, False
        if max(abs(d) for d in dq) <= tol * (1 + max(abs(x) for x in q)):
            return q, True
    return q, False


def jacobian_sine(J) -> float:
    """How far from singular a 2x2 Jacobian is, free of units: det J / (|col 1| |col 2|),
    the sine of the angle between its columns (RRR: sin(psi - xi), the coupler against the
    rocker; RRP: the coupler against the guide's normal; RPR: s / |J1 - J2|)."""
    (a, b), (c, d) = ([float(x) for x in row] for row in J)
    norm = math.hypot(a, c) * math.hypot(b, d)
    return (a * d - b * c) / norm if norm > 0 else 0.0


def loop_kinematics(lib, scene: Scene, phi_deg: float, guesses: dict[int, list], tol: float, max_iter: int,
          until: int | None = None):
    """Kinematics at one crank angle by the loop equations, placing the plan in order.

    guesses: group index -> starting q. Returns (values name -> number, q per group,
    problems: list of (group, "no convergence" | "branch jump"), the jacobian_sine of each
    group's Jacobian at its answer). With `until` = a group's index: stops before placing
    that group and returns (known, links) as its loop equations take them.
    """
    n = lib.num
    crank = scene.crank
    known = {name: ((n(x), n(y)), (n(0), n(0)), (n(0), n(0))) for name, (x, y) in scene.frame.items()}
    links = {1: (n(phi_deg) * lib.pi() / 180, n(crank.omega), n(crank.epsilon))}
    slides: dict = {}
    qs: dict[int, list] = {}
    problems: list[tuple[Group, str]] = []
    sines: dict[int, float] = {}
    for kind, item in scene.plan:
        if kind == "crank":
            known[crank.joint] = _carried(lib, known[crank.pivot], links[1], n(crank.length), n(0))
        elif kind == "point":
            p = cast(Point, item)
            known[p.name] = _carried(lib, known[p.origin], links[p.link], n(p.along), n(p.across))
        else:
            g = cast(Group, item)
            if g.index == until:
                return known, links
            km = kind_of(g)
            F, J, b_v, b_a, place = km.loop(lib, g, known, links)
            q, ok = _newton(lib, F, J, [n(x) for x in guesses[g.index]], tol, max_iter)
            if not ok:
                problems.append((g, "no convergence"))
                return None, qs, problems, sines
            Jq = J(q)
            sines[g.index] = jacobian_sine(Jq)
            qt = lib.solve(Jq, b_v(q))
            qtt = lib.solve(Jq, b_a(q, qt))
            joints, (la, lb), group_slides = place(q, qt, qtt)
            qs[g.index] = q
            known.update(joints)
            if not km.side_ok(lib, g, known, links, q, joints):
                problems.append((g, "branch jump"))
            links[g.links[0]], links[g.links[1]] = la, lb
            slides.update(group_slides)
    values = {}
    deg = 180 / lib.pi()
    for k in scene.links:
        phi, w, eps = links[k]
        a = phi * deg
        values[f"phi_{k}"], values[f"omega_{k}"], values[f"eps_{k}"] = a - 360 * lib.floor(a / 360), w, eps
    for name in scene.moving_joints + [p.name for p in scene.points]:
        (x, y), (vx, vy), (ax, ay) = known[name]
        values.update({f"x_{name}": x, f"y_{name}": y, f"vx_{name}": vx, f"vy_{name}": vy,
                       f"ax_{name}": ax, f"ay_{name}": ay})
    for tag, triple in slides.items():
        values.update(zip(slide_names(tag), triple, strict=False))
    return values, qs, problems, sines


def closed_form_unknowns(scene: Scene, phi_deg) -> list[dict[int, list[float]]]:
    """Each group's unknowns q from the closed-form solver, per position (starting points)."""
    sol = solve(scene, phi_deg)
    out: list[dict[int, list[float]]] = [{} for _ in np.atleast_1d(phi_deg)]
    for g in scene.groups:
        qa, qb = kind_of(g).unknowns(g, sol)
        for i, d in enumerate(out):
            d[g.index] = [float(qa[i]), float(qb[i])]
    return out


# --------------------------------------------------------------------------- the reference
def reference_mp(scene: Scene, phi_deg_list, dps: int = 50) -> dict[str, list]:
    """The contract quantities at each crank angle, by mpmath at `dps` digits.

    Each group's loop-closure equations are solved by Newton in mpmath, started from the
    float solver's answer (which only picks the root: 3-4 quadratic steps take it from 1e-16
    to 1e-50); rates from the differentiated equations by mpmath.lu_solve; points on links
    by the rigid-body formulas. Scene numbers enter as the exact values of their floats.
    Raises ArithmeticError if a group does not converge or lands on the other branch.
    """
    phis = [float(p) for p in phi_deg_list]
    starts = closed_form_unknowns(scene, phis)
    out: dict[str, list] = {name: [] for name in quantity_names(scene)}
    with mpmath.workdps(dps):
        tol = mpmath.mpf(10) ** (-(dps - 5))
        for phi, start in zip(phis, starts, strict=False):
            values, _, problems, _ = loop_kinematics(MP, scene, phi, start, tol, 60)
            if problems:
                g, why = problems[0]
                raise ArithmeticError(f"reference: {g.label}: {why} at crank angle {phi:g} deg")
            for name in out:
                out[name].append(+values[name])
    return out


# --------------------------------------------------------------------------- the methods
def best_time(fn, repeats: int = REPEATS):
    """fn() run `repeats` times: (its last result, the shortest wall time in seconds)."""
    best, result = math.inf, None
    for _ in range(repeats):
        t = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t)
    return result, best


def _nonfinite_mask(values: dict[str, np.ndarray], n: int) -> np.ndarray:
    bad = np.zeros(n, dtype=bool)
    for v in values.values():
        bad |= ~np.isfinite(np.asarray(v, dtype=float))
    return bad


def _nonfinite(values: dict[str, np.ndarray], phis) -> list[float]:
    return [float(p) for p in np.asarray(phis)[_nonfinite_mask(values, len(phis))]]


def method_solver(scene: Scene, phis) -> MethodResult:
    phis = np.asarray(phis, dtype=float)
    names = quantity_names(scene)
    sol, t = best_time(lambda: solve(scene, phis))
    cols = solution_columns(scene, sol)
    values = {n: cols[n] for n in names}
    res = MethodResult("solver", "", t / len(phis), values)
    fail = failed_positions(sol)
    if fail.any():
        res.failures["cannot assemble"] = [float(p) for p in phis[fail]]
    near = np.zeros(len(phis), dtype=bool)
    for det in sol.det.values():
        near |= ~(np.abs(det) >= TOGGLE_THRESHOLD)
    flag(res, "near a toggle", f"(|det| < {TOGGLE_THRESHOLD:g}): {LOSE}", phis, near & ~fail)
    return res


def method_newton(scene: Scene, phis, tol: float = NEWTON_TOL, max_iter: int = NEWTON_MAX_ITER,
                  threshold: float = TOGGLE_THRESHOLD) -> MethodResult:
    """Newton on the loop equations at each position in turn, started from the previous
    position's answer (the first from the closed-form solver's, as a user's sketch would
    give it to Mathcad's Find). Where it does not converge the position is NaN (and the
    next starts from the last converged answer); where it lands on the other branch the
    values are kept (they are what a Given-Find block would show) and reported.

    Its own check: `measure` is, per position, the jacobian_sine of the group whose
    Jacobian is nearest singular at Newton's answer (NaN where it did not converge); where
    |measure| < threshold the position is flagged (newton_singular): the answer may be off
    (the residual's valley is flat) and the rates, solved with that Jacobian, lose digits."""
    phis = [float(p) for p in phis]
    names = quantity_names(scene)
    first = closed_form_unknowns(scene, phis[:1])[0]

    def run():
        guess, rows, sines = dict(first), [], []
        problems: dict[str, list[float]] = {}
        for phi in phis:
            values, qs, probs, sine = loop_kinematics(FLOAT, scene, phi, guess, tol, max_iter)
            guess.update(qs)
            rows.append(values)
            sines.append(min(sine.values(), key=abs) if values and sine else np.nan)
            for g, why in probs:
                problems.setdefault(f"{why} ({g.label})", []).append(phi)
        return rows, problems, sines

    (rows, problems, sines), t = best_time(run, 3)
    values = {n: np.array([r[n] if r else np.nan for r in rows]) for n in names}
    measure = np.array(sines, dtype=float)
    res = MethodResult("newton", f"tol={tol:g}", t / len(phis), values, problems, measure=measure)
    flag(res, *newton_singular(threshold), phis, np.abs(measure) < threshold)
    return res


def _wrap_deg(d):
    return (d + 180.0) % 360.0 - 180.0


def fd_values(scene: Scene, phis, h: float) -> dict[str, np.ndarray]:
    """Central differences of the solver's positions in the crank angle at step h (rad):
    v = omega dx/dphi, a = omega^2 d2x/dphi2 + epsilon dx/dphi (x also a link angle or a
    slide). Positions are the solver's own."""
    phis = np.asarray(phis, dtype=float)
    w, eps = scene.crank.omega, scene.crank.epsilon
    hd = math.degrees(h)
    cols = solution_columns(scene, solve(scene, np.concatenate([phis - hd, phis, phis + hd])))
    values = {}
    for k in scene.links:
        lo, mid, hi = np.split(cols[f"phi_{k}"], 3)
        # link angles in degrees in [0, 360): differences taken modulo 360
        d1 = np.radians(_wrap_deg(hi - lo)) / (2 * h)
        d2 = np.radians(_wrap_deg(hi - mid) - _wrap_deg(mid - lo)) / (h * h)
        values[f"phi_{k}"], values[f"omega_{k}"], values[f"eps_{k}"] = mid, w * d1, w * w * d2 + eps * d1
    coords = [(f"x_{p}", f"vx_{p}", f"ax_{p}") for p in scene.moving_joints + [p.name for p in scene.points]]
    coords += [(f"y_{p}", f"vy_{p}", f"ay_{p}") for p in scene.moving_joints + [p.name for p in scene.points]]
    coords += [slide_names(p) for p in scene.sliders]
    for x, v, a in coords:
        lo, mid, hi = np.split(cols[x], 3)
        d1, d2 = (hi - lo) / (2 * h), (hi - 2 * mid + lo) / (h * h)
        values[x], values[v], values[a] = mid, w * d1, w * w * d2 + eps * d1
    return values


def step_doubling(at_h: dict[str, np.ndarray], at_2h: dict[str, np.ndarray],
                  each_position: bool = False) -> dict[str, np.ndarray]:
    """The finite differences' own error estimate: "vel", "acc" -> per position, the scaled
    difference (as in errors(), the answers at 2h standing for the reference) between the
    answers at steps h and 2h. With a second-order formula the truncation error at h is
    about a third of it; where round-off rules, about as large. NaN where either gives no
    number. each_position: each position scaled by its own values (positions that are
    separate cases), else by the family's largest over all of them (as the main table)."""
    per = scaled_differences(at_h, at_2h, each_position)
    bad = np.zeros(len(per["vel"]), dtype=bool)
    for d in (at_h, at_2h):
        bad |= _nonfinite_mask(d, len(bad))
    return {k: np.where(bad, np.nan, per[k]) for k in ("vel", "acc")}


def method_fd(scene: Scene, phis, steps=FD_STEPS) -> list[MethodResult]:
    """fd_values for each step h (timed), each with its step-doubling check (step_doubling
    against h doubled, not timed): `estimate` the estimate, `measure` its larger kind per
    position, flagged (fd_unsure) where that exceeds SILENT_ERROR."""
    phis = np.asarray(phis, dtype=float)
    out = []
    for h in steps:
        values, t = best_time(lambda h=h: fd_values(scene, phis, h))
        res = MethodResult("fd", f"h={h:.2g}", t / len(phis), values)
        bad = _nonfinite(values, phis)
        if bad:
            res.failures[f"a neighbour phi +- {math.degrees(h):.3g} deg cannot assemble"] = bad
        res.estimate = step_doubling(values, fd_values(scene, phis, 2 * h))
        res.measure = np.maximum(res.estimate["vel"], res.estimate["acc"])
        flag(res, *fd_unsure(), phis, unsure(res.measure) & ~_nonfinite_mask(values, len(phis)))
        out.append(res)
    return out


def _workbook_file(scene: Scene, scene_text: str | None, folder: Path) -> Path:
    from sheetkin.sheet.workbook import build_workbook  # openpyxl is needed only here
    path = folder / "bench.xlsx"
    build_workbook(scene, lang="en", scene_text=scene_text).save(path)
    return path


def _frame_values(df: pd.DataFrame, names, phis) -> dict[str, np.ndarray]:
    """name -> floats from a workbook's rows; text (a marker, a spreadsheet error) -> NaN."""
    out = {}
    for name in names:
        row = df.loc[name] if name in df.index else pd.Series([np.nan] * len(phis))
        if isinstance(row, pd.DataFrame):      # a name used twice: the accepted row comes first
            row = row.iloc[0]
        out[name] = pd.to_numeric(pd.Series(list(row)), errors="coerce").to_numpy(dtype=float)[:len(phis)]
    return out


def method_evaluator(scene: Scene, phis, workbook: Path) -> MethodResult:
    """The workbook's formulas through sheetkin.xlsx.evaluator; timed: reading and evaluating
    the file (not writing it), per position."""
    from sheetkin.xlsx.evaluator import evaluate, rows_frame
    df, t = best_time(lambda: rows_frame(evaluate(workbook)), 3)
    values = _frame_values(df, quantity_names(scene), phis)
    res = MethodResult("evaluator", "", t / len(phis), values)
    bad = _nonfinite(values, phis)
    if bad:
        res.failures["no number in the workbook"] = bad
    return res


def libreoffice_recalculate(book: Path, outdir: Path, timeout: float = 300) -> Path:
    """`book` recalculated by headless LibreOffice (sheetkin.xlsx.libreoffice: a private profile
    forces recalculation on load) and saved as outdir/<name>.xlsx."""
    from sheetkin.xlsx.libreoffice import recalculate
    return recalculate([book], outdir, timeout)[Path(book).resolve()]


def method_libreoffice(scene: Scene, phis, workbook: Path) -> MethodResult:
    """The workbook recalculated by LibreOffice (one run; the time includes soffice's
    start-up, most of it). LibreOffice stores 15 significant digits."""
    from openpyxl import load_workbook
    with tempfile.TemporaryDirectory(prefix="sheetkin-bench-lo-") as tmp:
        t = time.perf_counter()
        out = libreoffice_recalculate(workbook, Path(tmp))
        t = time.perf_counter() - t
        wb = load_workbook(out, data_only=True, read_only=True)
        try:
            ws = wb.worksheets[0]
            rows = {}
            for row in ws.iter_rows(min_row=5, values_only=True):
                if row and isinstance(row[0], str) and row[0] not in rows:
                    rows[row[0]] = list(row[4:4 + len(phis)])
        finally:
            wb.close()
    df = pd.DataFrame.from_dict(rows, orient="index")
    values = _frame_values(df, quantity_names(scene), phis)
    res = MethodResult("libreoffice", "", t / len(phis), values, notes="time includes soffice start-up")
    bad = _nonfinite(values, phis)
    if bad:
        res.failures["no number in the recalculated workbook"] = bad
    return res


# --------------------------------------------------------------------------- errors, table, chart
def scaled_differences(values: dict[str, np.ndarray], ref: dict, each_position: bool = False
                       ) -> dict[str, np.ndarray]:
    """"pos", "vel", "acc" -> per position, the largest |value - reference| / scale over the
    kind's quantities (see the module's docstring; NaN where none has a number). `ref` is
    the mpmath reference (each number split into two floats, hi + lo, so the difference is
    not limited by rounding it to a float) or floats. each_position: a family's scale is
    max(1, its largest |reference| at that position) instead of over all positions."""
    diffs: dict[str, Any] = {}
    scales: dict[str, Any] = {}   # a family -> its scale (one number, or one per position)
    for name, refs in ref.items():
        head = name.split("_", 1)[0]
        kind, family = FAMILIES[head]
        hi = np.array([float(r) for r in refs])
        d = np.asarray(values[name], dtype=float) - hi
        if any(isinstance(r, mpmath.mpf) for r in refs):
            d -= np.array([float(r - mpmath.mpf(h)) for r, h in zip(refs, hi, strict=False)])
        scales.setdefault(family, np.ones(len(hi)) if each_position else 1.0)
        if head == "phi":
            # degrees in [0, 360): the angle between, in radians; an angle's size says
            # nothing about its accuracy, so the scale stays 1
            d = np.radians(_wrap_deg(d))
        elif each_position:
            scales[family] = np.fmax(scales[family], np.abs(hi))
        else:
            scales[family] = max(scales[family], float(np.max(np.abs(hi), initial=0.0,
                                                              where=np.isfinite(hi))))
        diffs[name] = (kind, family, np.abs(d))
    n = len(next(iter(ref.values()), []))
    worst = {k: np.full(n, np.nan) for k in ("pos", "vel", "acc")}
    for kind, family, d in diffs.values():
        worst[kind] = np.fmax(worst[kind], d / scales[family])
    return worst


def errors(values: dict[str, np.ndarray], ref: dict[str, list]) -> dict[str, float]:
    """err_pos, err_vel, err_acc of `values` against the mpmath reference: the largest of
    scaled_differences over positions; positions where the method gave no number are left
    out (they are reported as failures)."""
    return {f"err_{k}": float(np.max(d, initial=0.0, where=np.isfinite(d)))
            for k, d in scaled_differences(values, ref).items()}


def _angles(phis) -> str:
    shown = ", ".join(f"{p:g}" for p in phis[:8])
    return shown + (f" ... ({len(phis)} positions)" if len(phis) > 8 else "")


def bench_scene(scene: Scene, positions: int | None, scene_text: str | None = None):
    """The scene (and its text, for the workbook) with `positions` crank positions over one
    revolution from phi0, in the crank's direction; the scene as it is for None."""
    text = scene_text if scene_text is not None else Path(scene.source).read_text(encoding="utf-8-sig")
    if positions is None:
        return scene, text
    step = math.copysign(360.0 / positions, scene.crank.step_deg or 1.0)
    text, scene = override_crank(text, scene.source, positions=positions, step_deg=step)
    return scene, text


def run_bench(scene: Scene, positions: int | None, out_dir, *, scene_text: str | None = None,
              libreoffice: bool = True, fd_steps=FD_STEPS):
    """Run every method, write out_dir/bench.csv and out_dir/bench.png.

    Returns (table, warnings): the table as a DataFrame with COLUMNS, the warnings as
    one-line texts naming the crank angles where a method fails or flags itself (the
    solver near a toggle, Newton at a singular Jacobian, a finite-difference step whose
    answer changes by more than SILENT_ERROR when the step is doubled; the rows of a method
    that say the same share one line). Raises AssemblyError if the scene cannot be
    assembled at some position (there is nothing to compare there).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    scene, text = bench_scene(scene, positions, scene_text)
    phis = np.asarray(scene.crank_angles_deg(), dtype=float)
    if failed_positions(solve(scene, phis)).any():
        raise AssemblyError("; ".join(map(str, assembly_gaps(scene, phis))) +
                            ": the bench needs every position assembled")
    ref = reference_mp(scene, phis)
    results = [method_solver(scene, phis), method_newton(scene, phis), *method_fd(scene, phis, fd_steps)]
    warnings = []
    with tempfile.TemporaryDirectory(prefix="sheetkin-bench-") as tmp:
        book = _workbook_file(scene, text, Path(tmp))
        results.append(method_evaluator(scene, phis, book))
        if libreoffice and soffice_path():
            try:
                results.append(method_libreoffice(scene, phis, book))
            except RuntimeError as e:
                warnings.append(f"libreoffice: skipped: {e}")
        elif libreoffice:
            warnings.append("libreoffice: skipped: LibreOffice (soffice) not found")
    rows: list = []
    said: dict[tuple[str, str], list] = {}   # (method, warning) -> the params (rows) it is said of
    for r in results:
        notes = [r.notes] if r.notes else []
        for why, at in r.failures.items():
            notes.append(f"{why} at {len(at)} of {len(phis)} positions")
            said.setdefault((r.method, f"{why} at crank angles {_angles(at)} deg"), []).append(r.param)
        for why, at in r.flags.items():
            notes.append(f"{why.partition(' at crank angles')[0]} at {len(at)} of {len(phis)} positions")
            said.setdefault((r.method, why.format(at=_angles(at))), []).append(r.param)
        flagged = {p for at in r.flags.values() for p in at}
        est = {f"est_{k}": float(np.nanmax(v)) if np.isfinite(v).any() else np.nan
               for k, v in r.estimate.items()}
        rows.append({"method": r.method, "param": r.param,
                     "seconds_per_position": r.seconds_per_position,
                     **errors(r.values, ref), "notes": "; ".join(notes), "flagged": len(flagged),
                     "flagged_deg": " ".join(f"{p:g}" for p in phis if p in flagged), **est})
    # one line for the rows of a method that say the same (the finite differences' steps)
    warnings += [f"{method} {', '.join(params)}".strip() + f": {text}"
                 for (method, text), params in said.items()]
    table = pd.DataFrame(rows, columns=COLUMNS)
    table.to_csv(out_dir / "bench.csv", index=False, float_format="%.3e", lineterminator="\n")
    plot(table, out_dir / "bench.png", f"{scene.title}: {len(phis)} positions")
    return table, warnings


FLOOR = 1e-18     # an error of exactly 0 is drawn here (a log axis has no 0)
MARKERS = {"solver": "o", "newton": "s", "evaluator": "^", "libreoffice": "D"}


def plot(table: pd.DataFrame, path, title: str = "") -> None:
    """Left: velocity (filled) and acceleration (hollow) error against time per position,
    log-log, one marker per method, the finite-difference steps joined by a line. Right:
    the finite-difference errors against the step h (the V: truncation against round-off)."""
    import matplotlib
    matplotlib.use("Agg")          # files only, no display
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
    fd = table[table["method"] == "fd"]
    for m, marker in MARKERS.items():
        row = table[table["method"] == m]
        if row.empty:
            continue
        t = row["seconds_per_position"]
        line = ax.loglog(t, np.maximum(row["err_vel"], FLOOR), marker, ms=9, label=f"{m} (velocity)")[0]
        ax.loglog(t, np.maximum(row["err_acc"], FLOOR), marker, ms=9, mfc="none",
                  color=line.get_color(), label=f"{m} (acceleration)")
    if not fd.empty:
        # the time does not depend on h: every step drawn at the median time, so the
        # steps form one column (timing noise would make a zigzag of them)
        t = np.full(len(fd), fd["seconds_per_position"].median())
        ax.loglog(t, np.maximum(fd["err_vel"], FLOOR), "_", ms=14, mew=2, color="gray",
                  label="fd, each step h = 1e-1..1e-8 (velocity)")
        ax.loglog(t, np.maximum(fd["err_acc"], FLOOR), "x", ms=6, color="gray", label="fd (acceleration)")
        h = fd["param"].str.slice(2).astype(float)
        bx.loglog(h, np.maximum(fd["err_pos"], FLOOR), ":", color="gray", label="positions")
        bx.loglog(h, np.maximum(fd["err_vel"], FLOOR), "o-", label="velocities")
        bx.loglog(h, np.maximum(fd["err_acc"], FLOOR), "s--", label="accelerations")
        bx.invert_xaxis()
    ax.set_xlabel("time per crank position, s")
    ax.set_ylabel("largest error (scaled, see bench.csv)")
    ax.set_title("error against time")
    ax.legend(fontsize=7)
    ax.grid(True, which="major", alpha=0.3)
    bx.set_xlabel("finite-difference step h, rad")
    bx.set_ylabel("largest error")
    bx.set_title("finite differences: truncation vs round-off")
    bx.legend(fontsize=8)
    bx.grid(True, which="major", alpha=0.3)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def format_bench(table: pd.DataFrame) -> str:
    """The table for a terminal."""
    lines = [f"{'method':<12}{'param':<12}{'s/position':>12}{'err_pos':>11}{'err_vel':>11}{'err_acc':>11}"
             f"{'est_vel':>11}{'est_acc':>11}  notes"]
    for r in table.itertuples(index=False):
        est = "".join(f"{v:>11.2e}" if np.isfinite(v) else f"{'':>11}" for v in (r.est_vel, r.est_acc))
        lines.append(f"{r.method:<12}{r.param:<12}{r.seconds_per_position:>12.3e}{r.err_pos:>11.2e}"
                     f"{r.err_vel:>11.2e}{r.err_acc:>11.2e}{est}  {r.notes}")
    return "\n".join(lines) + "\n"
