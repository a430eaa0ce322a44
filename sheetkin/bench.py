"""`sheetkin bench`: how fast and how exact each way of computing a scene's kinematics is.

Every method is timed per crank position and compared with a reference computed here with
mpmath at 50 digits, independently of the closed-form solver (issue #5):

  solver      the closed-form solver (the lecture's method, sheetkin.solver);
  newton      Newton on the vector loop-closure equations (the seeds' Given-Find),
              warm-started from the previous position; rates from the Jacobian systems;
  fd          central differences of the solver's positions in the crank angle (what
              Mathcad's d/dphi does), for steps h = 1e-1 .. 1e-8 rad;
  evaluator   the workbook's formulas (sheetkin.workbook) through sheetkin.evaluator;
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

`sheetkin bench --stability --out DIR` (stability_study): the solver, Newton and finite
differences walked towards a toggle, a change point and past the edge of a non-assembling
interval, 1e-2 .. 1e-10 rad away, against the reference; see the section at the end.
"""
from __future__ import annotations

import math
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import mpmath
import numpy as np
import pandas as pd

from .compute import TOGGLE_THRESHOLD, AssemblyError, assembly_gaps, failed_positions, solution_columns
from .libreoffice import soffice_path
from .scene import Scene, override_crank, parse_scene
from .groups import kind_of
from .group import slide_names
from .solver import solve

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
                     floor=mpmath.floor, solve=_mp_solve, finite=mpmath.isfinite)
FLOAT = SimpleNamespace(cos=math.cos, sin=math.sin, pi=lambda: math.pi, num=float,
                        floor=math.floor, solve=lambda m, b: list(np.linalg.solve(m, b)),
                        finite=math.isfinite)


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
        q = [a + d for a, d in zip(q, dq)]
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


def _walk(lib, scene: Scene, phi_deg: float, guesses: dict[int, list], tol: float, max_iter: int,
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
    slides, qs, problems, sines = {}, {}, [], {}
    for kind, item in scene.plan:
        if kind == "crank":
            known[crank.joint] = _carried(lib, known[crank.pivot], links[1], n(crank.length), n(0))
        elif kind == "point":
            known[item.name] = _carried(lib, known[item.origin], links[item.link],
                                        n(item.along), n(item.across))
        else:
            g = item
            if g.index == until:
                return known, links
            kind = kind_of(g)
            F, J, b_v, b_a, place = kind.loop(lib, g, known, links)
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
            if not kind.side_ok(lib, g, known, links, q, joints):
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
        values.update(zip(slide_names(tag), triple))
    return values, qs, problems, sines


def _unknowns(scene: Scene, phi_deg) -> list[dict[int, list[float]]]:
    """Each group's unknowns q from the closed-form solver, per position (starting points)."""
    sol = solve(scene, phi_deg)
    out = [{} for _ in np.atleast_1d(phi_deg)]
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
    starts = _unknowns(scene, phis)
    out = {name: [] for name in quantity_names(scene)}
    with mpmath.workdps(dps):
        tol = mpmath.mpf(10) ** (-(dps - 5))
        for phi, start in zip(phis, starts):
            values, _, problems, _ = _walk(MP, scene, phi, start, tol, 60)
            if problems:
                g, why = problems[0]
                raise ArithmeticError(f"reference: {g.label}: {why} at crank angle {phi:g} deg")
            for name in out:
                out[name].append(+values[name])
    return out


# --------------------------------------------------------------------------- the methods
def _best_time(fn, repeats: int = REPEATS):
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
    sol, t = _best_time(lambda: solve(scene, phis))
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
    first = _unknowns(scene, phis[:1])[0]

    def run():
        guess, rows, problems, sines = dict(first), [], {}, []
        for phi in phis:
            values, qs, probs, sine = _walk(FLOAT, scene, phi, guess, tol, max_iter)
            guess.update(qs)
            rows.append(values)
            sines.append(min(sine.values(), key=abs) if values and sine else np.nan)
            for g, why in probs:
                problems.setdefault(f"{why} ({g.label})", []).append(phi)
        return rows, problems, sines

    (rows, problems, sines), t = _best_time(run, 3)
    values = {n: np.array([r[n] if r else np.nan for r in rows]) for n in names}
    res = MethodResult("newton", f"tol={tol:g}", t / len(phis), values, problems,
                       measure=np.array(sines, dtype=float))
    flag(res, *newton_singular(threshold), phis, np.abs(res.measure) < threshold)
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
        values, t = _best_time(lambda: fd_values(scene, phis, h))
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
    from .workbook import build_workbook      # openpyxl is needed only here
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
    """The workbook's formulas through sheetkin.evaluator; timed: reading and evaluating
    the file (not writing it), per position."""
    from .evaluator import evaluate, rows_frame
    df, t = _best_time(lambda: rows_frame(evaluate(workbook)), 3)
    values = _frame_values(df, quantity_names(scene), phis)
    res = MethodResult("evaluator", "", t / len(phis), values)
    bad = _nonfinite(values, phis)
    if bad:
        res.failures["no number in the workbook"] = bad
    return res


def libreoffice_recalculate(book: Path, outdir: Path, timeout: float = 300) -> Path:
    """`book` recalculated by headless LibreOffice (sheetkin.libreoffice: a private profile
    forces recalculation on load) and saved as outdir/<name>.xlsx."""
    from .libreoffice import recalculate
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
    diffs, scales = {}, {}
    for name, refs in ref.items():
        head = name.split("_", 1)[0]
        kind, family = FAMILIES[head]
        hi = np.array([float(r) for r in refs])
        d = np.asarray(values[name], dtype=float) - hi
        if any(isinstance(r, mpmath.mpf) for r in refs):
            d -= np.array([float(r - mpmath.mpf(h)) for r, h in zip(refs, hi)])
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
    rows, said = [], {}         # (method, warning) -> the params (rows) it is said of
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


# --------------------------------------------------------------------------- stability study
# Issue #5, items 2-3: each method walked towards a place where the kinematics degenerate,
# at distances d = 1e-2 .. 1e-10 rad of crank angle. Three four-bars (RRR), every length a
# binary fraction, so the float scene IS the mechanism studied (0.45 + 0.25 != 0.7 in
# binary would move a change point by ~1e-8 rad, or open a gap there):
#   toggle        non-Grashof (s + l = 0.75 > p + q = 0.625): the crank cannot turn fully;
#                 at the edge of its range coupler and rocker are stretched in line, the
#                 dyad's toggle (discriminant P^2 + Q^2 - F^2 -> 0, sin(psi - xi) -> 0);
#                 approached from the assembling side, phi = phi_edge - d.
#   change-point  Grashof sum equal (s + l = 0.625 = p + q): at phi = 180 deg all four
#                 links are in line and the two branches of the dyad meet (the
#                 discriminant touches 0 from above); phi = 180 deg - d.
#   gap-edge      the toggle family seen from the far side: phi = phi_edge + d, where no
#                 real position exists; the right answer is a refusal.
STABILITY_DISTANCES = tuple(10.0 ** -k for k in range(2, 11))     # rad, 1e-2 .. 1e-10
STABILITY_FD_STEPS = {"vel": 1e-5, "acc": 3e-4}     # the main bench's best steps (rad)
STABILITY_FAR = 0.5         # rad: where Newton's walk towards the edge starts
_REF_EXTRA_DPS = 30         # the reference's guard digits: the singular point costs up to 20
# det: the toggle measure the method's status is judged by (solver: its |det|, newton:
# |sin(psi - xi)| of its own answer; fd: not a determinant but its step-doubling estimate)
STABILITY_COLUMNS = ["family", "d", "distance", "phi_deg", "method", "param", "status",
                     "err_pos", "err_vel", "err_acc", "det", "silent"]
FAMILY_TITLES = {"toggle": "towards a toggle (non-Grashof crank, edge of its range)",
                 "change-point": "towards a change point (s + l = p + q, links in line)",
                 "gap-edge": "just outside the edge of a non-assembling interval",
                 "slider-toggle": "RRP: towards the coupler standing across its guide (edge of the range)",
                 "slotted-toggle": "RRP on a moving guide (two rockers, slotted pair): rocker across the kulisa"}
# families of the group kinds other than the four-bar's RRR: the scene, and the group whose
# range ends in a toggle (approached from inside, as the "toggle" family)
_KIND_FAMILIES = {
    "slider-toggle": ("""\
title = "Crank-slider with a short coupler: it stands across the guide at the edge of its range"
[frame]
O = [0.0, 0.0]
[crank]
pivot = "O"
joint = "A"
length = 0.25
positions = 1
omega = 10.0
[[group]]
type = "RRP"
links = [2, 3]
joints = ["A", "B"]
length = 0.2
guide = { through = [0.0, 0.05], angle_deg = 0.0 }
branch = 1
""", 1),
    "slotted-toggle": ("""\
title = "Two rockers with a slotted pair: rocker O2 D stands across the kulisa O1 B at the edge"
[frame]
O  = [0.0, 0.0]
O1 = [0.0, -0.53]
O2 = [-0.45, -0.2]
[crank]
pivot = "O"
joint = "A"
length = 0.14
positions = 1
omega = 20.0
[[group]]
type    = "RRR"
links   = [2, 3]
joints  = ["A", "B", "O1"]
lengths = [0.5, 0.34]
branch  = -1
[[group]]
type   = "RRP"
links  = [4, 5]
joints = ["O2", "D"]
length = 0.3
guide  = { through = "O1", angle_deg = 0.0, link = 3 }
branch = -1
""", 2),
}

_STABILITY_SCENE = """\
title = "{title}"
author = "sheetkin stability study"

[frame]
O  = [0.0, 0.0]
O1 = [{frame!r}, 0.0]

[crank]
pivot = "O"
joint = "A"
length = {crank!r}
phi0_deg = 0.0
step_deg = 30.0
positions = 1
omega = 10.0
epsilon = 0.0

[[group]]
type = "RRR"
links = [2, 3]
joints = ["A", "B", "O1"]
lengths = [{coupler!r}, {rocker!r}]
branch = {branch}
"""


def stability_scene(family: str) -> Scene:
    """The four-bar of a stability family ("toggle" and "gap-edge" share theirs), or the
    scene of a family of another group kind."""
    if family in _KIND_FAMILIES:
        return parse_scene(_KIND_FAMILIES[family][0], f"<stability {family}>")
    if family in ("toggle", "gap-edge"):
        kw = dict(title="Non-Grashof four-bar: the crank's range ends in a toggle",
                  frame=0.5, crank=0.25, coupler=0.375, rocker=0.25, branch=1)
    elif family == "change-point":
        kw = dict(title="Change-point four-bar: s + l = p + q",
                  frame=0.5, crank=0.125, coupler=0.375, rocker=0.25, branch=1)
    else:
        raise ValueError(f"unknown stability family {family!r}")
    return parse_scene(_STABILITY_SCENE.format(**kw), f"<stability {family}>")


def _rrr_mp(scene: Scene, phi):
    """(crank joint A, its frame point O1, L2, L3) of the one-dyad scene, in mpmath, at the
    crank angle phi (radians, an mpf)."""
    c, g = scene.crank, scene.groups[0]
    ox, oy = (mpmath.mpf(v) for v in scene.frame[c.pivot])
    ax, ay = ox + mpmath.mpf(c.length) * mpmath.cos(phi), oy + mpmath.mpf(c.length) * mpmath.sin(phi)
    jx, jy = (mpmath.mpf(v) for v in scene.frame[g.joints[2]])
    return (ax, ay), (jx, jy), mpmath.mpf(g.lengths[0]), mpmath.mpf(g.lengths[1])


def _discriminant_mp(scene: Scene, phi):
    """The dyad's discriminant P^2 + Q^2 - F^2 at crank angle phi (rad), exactly as the
    lecture writes it, in mpmath."""
    (ax, ay), (jx, jy), l2, l3 = _rrr_mp(scene, phi)
    p, q = jx - ax, jy - ay
    f = (p * p + q * q + l2 * l2 - l3 * l3) / (2 * l2)
    return p * p + q * q - f * f


def edge_angle_mp(scene: Scene, near_deg: float, dps: int = 50):
    """The crank angle (radians, mpf) near `near_deg` where the dyad's discriminant is 0:
    mpmath's root finder on P^2 + Q^2 - F^2 (a simple root at a toggle that ends the range).
    """
    with mpmath.workdps(dps + 10):
        root = mpmath.findroot(lambda t: _discriminant_mp(scene, t), mpmath.radians(near_deg),
                               tol=mpmath.mpf(10) ** (-dps - 5))
    return +root


def _group_discriminant_mp(scene: Scene, index: int, phi, guesses):
    """Group `index`'s discriminant at the crank angle phi (radians, mpf), the groups before
    it placed by Newton on their loop equations in mpmath (kind.discriminant)."""
    g = next(g for g in scene.groups if g.index == index)
    tol = mpmath.mpf(10) ** (-(mpmath.mp.dps - 5))
    known, links = _walk(MP, scene, phi * 180 / mpmath.pi, guesses, tol, 60, until=index)
    return kind_of(g).discriminant(MP, g, known, links)


def _kind_edge_mp(scene: Scene, index: int, dps: int = 50):
    """The crank angle (radians, mpf) where group `index`'s range ends (its discriminant's
    root at the start of the first non-assembling interval the float solver finds)."""
    from .compute import assembly_gaps
    gaps = assembly_gaps(scene, np.arange(0.0, 360.0, 1.0))
    near = gaps[0].start_deg
    guesses = _unknowns(scene, [near - 0.5])[0]
    with mpmath.workdps(dps + 10):
        root = mpmath.findroot(lambda t: _group_discriminant_mp(scene, index, t, guesses),
                               mpmath.radians(near), tol=mpmath.mpf(10) ** (-dps - 5))
    return +root


def reference_by_continuation(scene: Scene, phi_deg_list, edge, dps: int = 50) -> dict[str, list]:
    """reference_mp for crank angles approaching `edge` (rad, mpf) from below, in order of
    decreasing distance: Newton in mpmath walked towards the edge by steps that halve the
    distance, each started from the last answer (the other branch stays twice as far as
    the step), from the float solver's answer 0.05 rad away; _REF_EXTRA_DPS guard digits."""
    out = {name: [] for name in quantity_names(scene)}
    with mpmath.workdps(dps + _REF_EXTRA_DPS):
        tol = mpmath.mpf(10) ** (-(dps + 5))
        d = mpmath.mpf("0.05")
        guesses = _unknowns(scene, [float(mpmath.degrees(edge - d))])[0]
        for phi in phi_deg_list:
            target = edge - mpmath.radians(mpmath.mpf(float(phi)))
            while True:
                d = max(d / 2, target)
                values, qs, problems, _ = _walk(MP, scene, mpmath.degrees(edge - d), guesses, tol, 60)
                if problems:
                    raise ArithmeticError(f"reference: {problems[0][0].label}: {problems[0][1]} "
                                          f"at {float(d)!r} rad from the edge")
                guesses = qs
                if d == target:
                    break
            for name in out:
                out[name].append(+values[name])
    return out


def _family_angles(family: str, scene: Scene, distances):
    """The exact singular angle (mpf, rad) and the float crank angles (deg) at the distances."""
    with mpmath.workdps(60):
        if family in _KIND_FAMILIES:
            edge = _kind_edge_mp(scene, _KIND_FAMILIES[family][1])
        elif family == "change-point":
            edge = +mpmath.pi                      # all links in line: crank pointing away from O1
        else:
            # the closed form only gives the start: cos phi = (r^2 + d^2 - (L2 + L3)^2) / (2 r d)
            c, g = scene.crank, scene.groups[0]
            r, fr = c.length, scene.frame[g.joints[2]][0]
            near = math.degrees(math.acos((r * r + fr * fr - sum(g.lengths) ** 2) / (2 * r * fr)))
            edge = edge_angle_mp(scene, near)
        sign = 1 if family == "gap-edge" else -1
        phis = [float(mpmath.degrees(edge + sign * d)) for d in distances]
        # the distance the float angle really is from the edge (the rounding of phi to a
        # float double is ~1e-16 rad: 1e-6 of the smallest d)
        dist = [float(abs(edge - mpmath.radians(mpmath.mpf(p)))) for p in phis]
    return edge, phis, dist


def reference_near_singular(scene: Scene, phi_deg_list, dps: int = 50) -> dict[str, list]:
    """reference_mp for the one-dyad stability scenes, started independently of the float
    solver (which may give NaN or the wrong digits there): the circles' intersection in
    mpmath, then Newton on the loop equations, with _REF_EXTRA_DPS guard digits because the
    Jacobian's conditioning near the singular point costs up to 20 of them. A position with
    no real solution gives None for every quantity."""
    g = scene.groups[0]
    out = {name: [] for name in quantity_names(scene)}
    work = dps + _REF_EXTRA_DPS
    with mpmath.workdps(work):
        tol = mpmath.mpf(10) ** (-(dps + 5))
        for phi in phi_deg_list:
            t = mpmath.mpf(float(phi)) * mpmath.pi / 180
            (ax, ay), (jx, jy), l2, l3 = _rrr_mp(scene, t)
            px, py = jx - ax, jy - ay
            dd = px * px + py * py
            a = (dd + l2 * l2 - l3 * l3) / (2 * mpmath.sqrt(dd))    # along A -> O1
            h2 = l2 * l2 - a * a
            if h2 < 0:
                for name in out:
                    out[name].append(None)
                continue
            h = mpmath.sqrt(h2) * g.branch                           # left of A -> O1: +
            ux, uy = px / mpmath.sqrt(dd), py / mpmath.sqrt(dd)
            bx, by = ax + a * ux - h * uy, ay + a * uy + h * ux
            start = {g.index: [mpmath.atan2(by - ay, bx - ax), mpmath.atan2(by - jy, bx - jx)]}
            values, _, problems, _ = _walk(MP, scene, float(phi), start, tol, 60)
            if problems:
                raise ArithmeticError(f"reference: {problems[0][0].label}: {problems[0][1]} "
                                      f"at crank angle {float(phi)!r} deg")
            for name in out:
                out[name].append(+values[name])
    return out


def _at(values: dict, i: int) -> dict:
    return {n: np.asarray(v, dtype=float)[i:i + 1] for n, v in values.items()}


def _solver_at(scene: Scene, phis):
    sol = solve(scene, np.asarray(phis, dtype=float))
    cols = solution_columns(scene, sol)
    det = np.min(np.abs(np.vstack(list(sol.det.values()))), axis=0)
    return {n: cols[n] for n in quantity_names(scene)}, failed_positions(sol), det


def _fd_at(scene: Scene, phis, factor: float = 1.0) -> dict[str, np.ndarray]:
    """Finite differences at the main bench's best steps (times `factor`): positions and
    velocities from h_vel, accelerations from h_acc."""
    v = fd_values(scene, phis, STABILITY_FD_STEPS["vel"] * factor)
    a = fd_values(scene, phis, STABILITY_FD_STEPS["acc"] * factor)
    return {n: (a[n] if FAMILIES[n.split("_", 1)[0]][0] == "acc" else v[n]) for n in v}


def fd_estimate(scene: Scene, phis) -> np.ndarray:
    """The finite differences' step_doubling estimate, per position (each scaled by its own
    values: each position is a case of its own), the larger of velocities' and
    accelerations'. NaN where either step gives no number."""
    est = step_doubling(_fd_at(scene, phis), _fd_at(scene, phis, 2.0), each_position=True)
    return np.maximum(est["vel"], est["acc"])


def _stability_family(family: str, distances, threshold: float):
    scene = stability_scene(family)
    edge, phis, dist = _family_angles(family, scene, distances)
    ref = (reference_by_continuation(scene, phis, edge) if family in _KIND_FAMILIES
           else reference_near_singular(scene, phis))
    far = float(mpmath.degrees(edge - STABILITY_FAR))
    rows = []

    def add(i, method, param, status, values, det=np.nan):
        if ref[next(iter(ref))][i] is None:
            err = {"err_pos": np.nan, "err_vel": np.nan, "err_acc": np.nan}
        elif status in ("refused", "diverged", "nan"):
            err = {"err_pos": np.nan, "err_vel": np.nan, "err_acc": np.nan}
        else:
            err = errors(_at(values, i), {n: r[i:i + 1] for n, r in ref.items()})
        exists = ref[next(iter(ref))][i] is not None
        # a silent failure: numbers shown with no flag, either where no position exists
        # or off by more than SILENT_ERROR
        silent = status == "ok" and (not exists or max(err.values()) > SILENT_ERROR)
        rows.append({"family": family, "d": distances[i], "distance": dist[i], "phi_deg": phis[i],
                     "method": method, "param": param, "status": status, **err,
                     "det": det, "silent": bool(silent)})

    # the solver, position by position (it has no memory)
    sv, sfail, sdet = _solver_at(scene, phis)
    nan_s = np.zeros(len(phis), dtype=bool)
    for v in sv.values():
        nan_s |= ~np.isfinite(v)
    # Newton walks from STABILITY_FAR rad away towards (and, for gap-edge, past) the edge,
    # each position warm-started from the last converged one
    if family == "gap-edge":
        inside = [float(mpmath.degrees(edge - d)) for d in distances]
        walk = [far] + [p for pair in zip(inside, phis) for p in pair]
        pick = list(range(2, len(walk), 2))
    else:
        walk = [far] + list(phis)
        pick = list(range(1, len(walk)))
    nr = method_newton(scene, walk, threshold=threshold)
    singular = {p for at in nr.flags.values() for p in at}
    why_at = {}
    for why, at in nr.failures.items():
        for p in at:
            why_at.setdefault(p, "diverged" if why.startswith("no convergence") else "branch jump")
    nv = {n: np.asarray(v)[pick] for n, v in nr.values.items()}
    # Newton's own toggle measure (jacobian_sine: here sin(psi - xi)) and flag, as the
    # main bench's
    ndet = nr.measure[pick]
    fv = _fd_at(scene, phis)
    fest = fd_estimate(scene, phis)
    fd_unsure_at = unsure(fest)
    for i, phi in enumerate(phis):
        st = ("refused" if sfail[i] else "nan" if nan_s[i] else
              "flagged" if abs(sdet[i]) < threshold else "ok")
        add(i, "solver", "", st, sv, sdet[i])
        st = why_at.get(walk[pick[i]], "ok")
        if st == "ok" and not all(np.isfinite(v[i]) for v in nv.values()):
            st = "nan"
        elif st == "ok" and walk[pick[i]] in singular:
            st = "flagged"
        add(i, "newton", f"from {STABILITY_FAR:g} rad", st, nv, ndet[i])
        fd_ok = all(np.isfinite(v[i]) for v in fv.values())
        # finite differences cannot tell by themselves; the bench can, from the solver's
        # toggle measure and from the step doubled (fd_estimate)
        st = ("refused" if not fd_ok else "flagged" if abs(sdet[i]) < threshold else
              "unsure" if fd_unsure_at[i] else "ok")
        add(i, "fd", "h=1e-05/3e-04", st, fv, fest[i])
    return rows, edge


def stability_warnings(table: pd.DataFrame, threshold: float = 1e-2) -> list[str]:
    """One line per family, method and kind of trouble, naming the crank angles (and how
    far each is from the singular angle)."""
    out = []
    # status -> method -> (what happened, why / what it means), the angles go between
    say = {"flagged": {"solver": ("near a toggle", f"(|det| < {threshold:g}): {LOSE}"),
                       "newton": newton_singular(threshold),
                       "fd": ("near a toggle", f"(the solver's |det| < {threshold:g}): the "
                                               "differences lose digits")},
           "unsure": {"fd": fd_unsure()},
           "refused": {"solver": ("cannot assemble", "(refused)"),
                       "fd": ("no number", "(a neighbour phi +- h cannot assemble)")},
           "diverged": {"newton": ("no convergence", "(no number)")},
           "branch jump": {"newton": ("landed on the other branch", "")},
           "nan": {"solver": ("no velocities or accelerations", "(NaN: det = 0 in floats)"),
                   "newton": ("no number", "(NaN)"), "fd": ("no number", "(NaN)")}}
    for (family, method), grp in table.groupby(["family", "method"], sort=False):
        for status, text in say.items():
            hit = grp[grp["status"] == status]
            if text.get(method) and len(hit):
                at = ", ".join(f"{p:.12g} (d={d:.0e})" for p, d in zip(hit["phi_deg"], hit["d"]))
                what, why = text[method]
                out.append(f"{method} ({family}): {what} at crank angles {at} deg {why}".rstrip())
        hit = grp[grp["silent"]]
        if len(hit):
            at = ", ".join(f"{p:.12g} (d={d:.0e})" for p, d in zip(hit["phi_deg"], hit["d"]))
            out.append(f"{method} ({family}): SILENT: numbers with no flag but wrong by more than "
                       f"{SILENT_ERROR:g} (or where no position exists) at crank angles {at} deg")
    return out


def stability_study(out_dir, distances=STABILITY_DISTANCES, threshold: float | None = None):
    """Run the families (FAMILY_TITLES), write out_dir/stability.csv and out_dir/stability.png.

    Returns (table, warnings, edges): a DataFrame with STABILITY_COLUMNS (err_* NaN where
    the method gave no number or no position exists; `silent` True where a method printed
    unflagged numbers that are wrong), the warning lines, and each family's singular crank
    angle in degrees (mpf).
    """
    from .compute import TOGGLE_THRESHOLD
    threshold = TOGGLE_THRESHOLD if threshold is None else threshold
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows, edges = [], {}
    for family in FAMILY_TITLES:
        r, edge = _stability_family(family, list(distances), threshold)
        rows += r
        edges[family] = mpmath.degrees(edge)
    table = pd.DataFrame(rows, columns=STABILITY_COLUMNS)
    table.to_csv(out_dir / "stability.csv", index=False, float_format="%.6e", lineterminator="\n")
    plot_stability(table, out_dir / "stability.png")
    return table, stability_warnings(table, threshold), edges


_METHOD_COLOURS = {"solver": "C0", "newton": "C3", "fd": "C2"}
_KIND_STYLES = {"err_pos": ("-", "o"), "err_vel": ("--", "s"), "err_acc": (":", "^")}


def plot_stability(table: pd.DataFrame, path) -> None:
    """One panel per family (three a row): each method's error against the distance d, log-log,
    one line per method and quantity; a hollow marker where the method flagged the
    position; where it gave no number, a cross at the top with its status."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fams = list(FAMILY_TITLES)
    ncols = min(3, len(fams))
    nrows = -(-len(fams) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(6 * ncols, 6 * nrows), sharey=True, squeeze=False)
    for ax in axes.flat[len(fams):]:
        ax.set_visible(False)
    axes = axes.flat[:len(fams)]
    clip = 1e8          # errors above are drawn here (wrong in every digit anyway)
    levels = {"solver": 1e10, "newton": 1e12, "fd": 1e14}    # rows of "no number" crosses
    for ax, fam in zip(axes, fams):
        t = table[table["family"] == fam]
        for m, colour in _METHOD_COLOURS.items():
            tm = t[t["method"] == m]
            for kind, (ls, mk) in _KIND_STYLES.items():
                y = np.clip(tm[kind].to_numpy(dtype=float), FLOOR, clip)
                ax.loglog(tm["d"], y, ls, color=colour, lw=1.2,
                          label=f"{m} {kind[4:]}" if fam == fams[0] else None)
                fl = (tm["status"] != "ok").to_numpy()
                ax.loglog(tm["d"][fl], y[fl], mk, color=colour, mfc="none", ms=6)
                ax.loglog(tm["d"][~fl], y[~fl], mk, color=colour, ms=4)
            bad = tm[tm[["err_pos", "err_vel", "err_acc"]].isna().all(axis=1)]
            if len(bad):
                ax.loglog(bad["d"], np.full(len(bad), levels[m]), "x", color=colour, ms=8)
                ax.annotate(f"{m}: {', '.join(sorted(set(bad['status'])))}",
                            (bad["d"].max(), levels[m]), fontsize=8, color=colour,
                            xytext=(0, 6), textcoords="offset points")
        ax.axhline(clip, color="gray", lw=0.5)
        ax.set_ylim(FLOOR / 10, 1e16)
        ax.set_title(FAMILY_TITLES[fam], fontsize=9)
        ax.set_xlabel("distance d from the singular crank angle, rad")
        ax.invert_xaxis()
        ax.grid(True, which="major", alpha=0.3)
    first = axes[0]
    first.set_ylabel(f"error against mpmath (scaled; >= {clip:.0e} drawn at the line)")
    fig.legend(*first.get_legend_handles_labels(), fontsize=8, ncol=9, loc="lower center")
    fig.suptitle("stability: error against distance to the singular position; hollow marker: "
                 "the method flagged it; x on top: no number (the status says why)", fontsize=10)
    fig.tight_layout(rect=(0, 0.06 / nrows, 1, 1))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def format_stability(table: pd.DataFrame) -> str:
    """The study's table for a terminal."""
    lines = [f"{'family':<13}{'d':>8}  {'method':<8}{'status':<12}{'err_pos':>10}{'err_vel':>10}"
             f"{'err_acc':>10}{'|det|':>10}"]
    for r in table.itertuples(index=False):
        e = [f"{v:10.1e}" if np.isfinite(v) else f"{'-':>10}" for v in (r.err_pos, r.err_vel, r.err_acc)]
        det = f"{abs(r.det):10.1e}" if np.isfinite(r.det) else f"{'':>10}"
        lines.append(f"{r.family:<13}{r.d:>8.0e}  {r.method:<8}{r.status + ('!' if r.silent else ''):<12}"
                     f"{''.join(e)}{det}")
    return "\n".join(lines) + "\n"
