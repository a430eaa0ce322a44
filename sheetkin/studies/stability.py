"""`sheetkin bench --stability --out DIR`: each method walked towards where a group kind
degenerates, at distances d = 1e-2 .. 1e-10 rad (issue #5, items 2-3; issue #12: every kind).

The families are the kinds' own (each kind module's STABILITY, sheetkin.groups.group.Family): a
scene, the group that fails and the function whose root is its singular position; this
module runs them all without knowing their kinds:
  RRR   toggle        non-Grashof four-bar: coupler and rocker stretched in line at the edge
                      of the crank's range (approached from inside);
        change-point  s + l = p + q: at 180 deg all links in line, the two branches meet;
        gap-edge      the toggle seen from the far side, where no real position exists
                      (the right answer is a refusal);
  RRP   slider-toggle, slotted-toggle   the coupler standing across its (fixed or moving)
                      guide at the edge of the range;
  RPR   kulisa-edge   an offset slot the crank cannot always reach: s -> 0 at the edge;
  PRP   parallel-lines  the coupler's line turning parallel to the fixed guide: no edge,
                      N runs off to infinity;
  RPP   parallel-slot the Scotch yoke's slot turned towards its guide's direction: nothing
                      depends on the crank angle, so the slot's angle is varied instead.
Each distance is compared with the bench's mpmath reference (sheetkin.studies.bench.reference_mp's
loop equations) with _REF_EXTRA_DPS guard digits; the singular angle itself is found by
mpmath's root finder on the family's function, through the groups before it.
"""
from __future__ import annotations

import math
from pathlib import Path

import mpmath
import numpy as np
import pandas as pd

from sheetkin.groups import families
from sheetkin.groups.group import Family
from sheetkin.kinematics.caps import SceneError
from sheetkin.kinematics.scene import Scene, parse_scene
from sheetkin.kinematics.solver import solve
from sheetkin.kinematics.table import TOGGLE_THRESHOLD, assembly_gaps, failed_positions, solution_columns

from .bench import (
    FAMILIES,
    FLOAT,
    FLOOR,
    LOSE,
    MP,
    NEWTON_MAX_ITER,
    NEWTON_TOL,
    SILENT_ERROR,
    best_time,
    closed_form_unknowns,
    errors,
    fd_unsure,
    fd_values,
    loop_kinematics,
    newton_singular,
    quantity_names,
    step_doubling,
    unsure,
)

STABILITY_DISTANCES = tuple(10.0 ** -k for k in range(2, 11))     # rad, 1e-2 .. 1e-10
STABILITY_FD_STEPS = {"vel": 1e-5, "acc": 3e-4}     # the main bench's best steps (rad)
STABILITY_FAR = 0.5         # rad: where Newton's walk towards the edge starts
_REF_EXTRA_DPS = 30         # the reference's guard digits: the singular point costs up to 20
# det: the toggle measure the method's status is judged by (solver: its |det|, newton:
# the jacobian_sine of its own answer; fd: not a determinant but its step-doubling
# estimate); varies: "crank angle" or the scene key the family varies, value_deg its value
STABILITY_COLUMNS = ["family", "d", "distance", "phi_deg", "method", "param", "status",
                     "err_pos", "err_vel", "err_acc", "det", "silent", "varies", "value_deg", "seconds"]
STABILITY_REPEATS = 3       # seconds: the best of this many runs at each distance
FAMILY_TITLES = {f.name: f.title for f in families()}
CRANK = "crank angle"


def family(name: str) -> Family:
    for f in families():
        if f.name == name:
            return f
    raise ValueError(f"unknown stability family {name!r}")


def stability_scene(name: str, value_deg: float | None = None) -> Scene:
    """The family's scene; for a family that varies a scene key, with that key at
    `value_deg` (default: STABILITY_FAR rad below its singular value). Raises SceneError
    where the parser refuses that value."""
    f = family(name)
    text = f.scene
    if f.vary is not None:
        if value_deg is None:
            value_deg = f.edge - math.degrees(STABILITY_FAR)
        text = text.replace("{value}", repr(float(value_deg)))
    return parse_scene(text, f"<stability {name}>")


def _group(scene: Scene, index: int):
    return next(g for g in scene.groups if g.index == index)


def _edge_function_mp(scene: Scene, f: Family, phi, guesses):
    """The family's function (f.edge) of its group at the crank angle phi (radians, mpf),
    the groups before it placed by Newton on their loop equations in mpmath."""
    tol = mpmath.mpf(10) ** (-(mpmath.mp.dps - 5))
    known, links = loop_kinematics(MP, scene, phi * 180 / mpmath.pi, guesses, tol, 60, until=f.group)
    return f.edge(MP, _group(scene, f.group), known, links)


def edge_mp(scene: Scene, f: Family, dps: int = 50):
    """The singular crank angle or scene value (radians, mpf): f.edge's root by mpmath's
    root finder, started at f.near_deg or at the start of the first crank interval where
    the float solver cannot assemble (a simple root: the edge of a range, two lines turning
    parallel); or f.edge itself where the family gives it exactly."""
    if not callable(f.edge):
        return mpmath.radians(mpmath.mpf(f.edge))
    near = f.near_deg
    if near is None:
        # a gap narrower than 1e-3 deg is a dead point the range only touches (the discriminant's
        # band about a double root, docs/dead-points.md), not the edge of a range
        near = next(g.start_deg for g in assembly_gaps(scene, np.arange(0.0, 360.0, 1.0))
                    if g.end_deg - g.start_deg > 1e-3)
    guesses = closed_form_unknowns(scene, [near - 0.5])[0]
    with mpmath.workdps(dps + 10):
        root = mpmath.findroot(lambda t: _edge_function_mp(scene, f, t, guesses), mpmath.radians(near),
                               tol=mpmath.mpf(10) ** (-dps - 5))
    return +root


def _case(f: Family, base: Scene, angle):
    """(scene or None where the parser refuses it, crank angle deg, varied value deg) at
    `angle` (radians, mpf) of the family's varied quantity."""
    value = float(mpmath.degrees(angle))
    if f.vary is None:
        return base, value, value
    try:
        scene = stability_scene(f.name, value)
    except SceneError:
        scene = None
    return scene, float(base.crank_angles_deg()[0]), value


def family_cases(f: Family, distances):
    """The singular position (mpf, rad), the family's scene and its cases at the distances:
    (scene or None, crank angle deg, value deg, the distance the float value really is
    from the singular one, rad: its rounding to a double is ~1e-16, 1e-6 of the smallest d)."""
    with mpmath.workdps(60):
        base = stability_scene(f.name)
        edge = edge_mp(base, f)
        cases = []
        for d in distances:
            scene, phi, value = _case(f, base, edge + f.side * d)
            cases.append((scene, phi, value, float(abs(edge - mpmath.radians(mpmath.mpf(value))))))
    return edge, base, cases


def reference_by_continuation(scene: Scene, phi_deg_list, edge, dps: int = 50) -> dict[str, list]:
    """reference_mp for crank angles approaching `edge` (rad, mpf) from below, in order of
    decreasing distance: Newton in mpmath walked towards the edge by steps that halve the
    distance, each started from the last answer (the other branch stays twice as far as
    the step), from the float solver's answer 0.05 rad away; _REF_EXTRA_DPS guard digits."""
    out: dict[str, list] = {name: [] for name in quantity_names(scene)}
    with mpmath.workdps(dps + _REF_EXTRA_DPS):
        tol = mpmath.mpf(10) ** (-(dps + 5))
        d = mpmath.mpf("0.05")
        guesses = closed_form_unknowns(scene, [float(mpmath.degrees(edge - d))])[0]
        for phi in phi_deg_list:
            target = edge - mpmath.radians(mpmath.mpf(float(phi)))
            while True:
                d = max(d / 2, target)
                values, qs, problems, _ = loop_kinematics(MP, scene, mpmath.degrees(edge - d), guesses, tol, 60)
                if problems:
                    raise ArithmeticError(f"reference: {problems[0][0].label}: {problems[0][1]} "
                                          f"at {float(d)!r} rad from the edge")
                guesses = qs
                if d == target:
                    break
            for name in out:
                out[name].append(+values[name])
    return out


def reference_near_singular(scene: Scene, f: Family, phi_deg_list, dps: int = 50) -> dict[str, list]:
    """reference_mp started independently of the float solver (which may give NaN or the
    wrong digits there) and of the last answer (where the branches meet a walk cannot tell
    them apart): the family's closed form in mpmath (f.start) at each crank angle, then
    Newton on the loop equations, with _REF_EXTRA_DPS guard digits because the Jacobian's
    conditioning near the singular point costs up to 20 of them. A position with no real
    solution gives None for every quantity."""
    g = _group(scene, f.group)
    out: dict[str, list] = {name: [] for name in quantity_names(scene)}
    with mpmath.workdps(dps + _REF_EXTRA_DPS):
        tol = mpmath.mpf(10) ** (-(dps + 5))
        for phi in phi_deg_list:
            guesses = closed_form_unknowns(scene, [float(phi)])[0]      # the groups before (float), f.group's replaced
            known, links = loop_kinematics(MP, scene, float(phi), guesses, tol, 60, until=g.index)
            q = f.start(MP, g, known, links)
            if q is None:
                for name in out:
                    out[name].append(None)
                continue
            guesses[g.index] = q
            values, _, problems, _ = loop_kinematics(MP, scene, float(phi), guesses, tol, 60)
            if problems:
                raise ArithmeticError(f"reference: {problems[0][0].label}: {problems[0][1]} "
                                      f"at crank angle {float(phi)!r} deg")
            for name in out:
                out[name].append(+values[name])
    return out


def _reference_at(scene: Scene, phi: float, dps: int = 50) -> dict:
    """bench.reference_mp at one crank angle, with _REF_EXTRA_DPS guard digits (its own
    tolerance, 1e-45 at 50 digits, is out of reach where the Jacobian's condition number
    is 1e8 and more)."""
    with mpmath.workdps(dps + _REF_EXTRA_DPS):
        start = closed_form_unknowns(scene, [phi])[0]
        values, _, problems, _ = loop_kinematics(MP, scene, phi, start, mpmath.mpf(10) ** (-(dps + 5)), 60)
    if problems:
        raise ArithmeticError(f"reference: {problems[0][0].label}: {problems[0][1]} at crank angle {phi!r} deg")
    return {n: +values[n] for n in quantity_names(scene)}


def _reference(f: Family, base: Scene, edge, cases, dps: int = 50) -> list[dict | None]:
    """The reference per case (None where no position exists or the scene is refused)."""
    names = quantity_names(base)
    if f.vary is not None:
        return [None if scene is None else _reference_at(scene, phi, dps) for scene, phi, _, _ in cases]
    phis = [phi for _, phi, _, _ in cases]
    ref = (reference_near_singular(base, f, phis, dps) if f.start is not None
           else reference_by_continuation(base, phis, edge, dps))
    return [None if ref[names[0]][i] is None else {n: ref[n][i] for n in names} for i in range(len(cases))]


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


def _finite(values: dict) -> bool:
    return all(np.isfinite(np.asarray(v, dtype=float)).all() for v in values.values())


def newton_walk(walk, threshold: float):
    """Newton on the loop equations at each (scene, crank angle) of `walk` in turn, each
    started from the last answer (the first from the closed-form solver's), as
    bench.method_newton: (values or None, status, jacobian_sine, seconds) per point. Status:
    refused (no scene), diverged, branch jump, nan, flagged (|jacobian_sine| < threshold:
    newton_singular) or ok."""
    guess, out = None, []
    for scene, phi in walk:
        if scene is None:
            out.append((None, "refused", np.nan, np.nan))
            continue
        if guess is None:
            guess = dict(closed_form_unknowns(scene, [phi])[0])
        (values, qs, problems, sines), t = best_time(
            lambda scene=scene, phi=phi, guess=guess: loop_kinematics(FLOAT, scene, phi, dict(guess), NEWTON_TOL,
                                                            NEWTON_MAX_ITER),
            STABILITY_REPEATS)
        guess.update(qs)
        sine = min(sines.values(), key=abs) if values and sines else np.nan
        if problems:
            status = "diverged" if any(why == "no convergence" for _, why in problems) else "branch jump"
        elif not _finite(values):
            status = "nan"
        elif abs(sine) < threshold:
            status = "flagged"
        else:
            status = "ok"
        out.append((values, status, sine, t))
    return out


def _stability_family(f: Family, distances, threshold: float):
    edge, base, cases = family_cases(f, distances)
    ref = _reference(f, base, edge, cases)
    names = quantity_names(base)
    varies = CRANK if f.vary is None else f.vary
    rows = []

    def add(i, method, param, status, values, det=np.nan, seconds=np.nan):
        exists = ref[i] is not None
        if not exists or values is None or status in ("refused", "diverged", "nan"):
            err = {"err_pos": np.nan, "err_vel": np.nan, "err_acc": np.nan}
        else:
            err = errors({n: np.atleast_1d(np.asarray(values[n], dtype=float)) for n in names},
                         {n: [ref[i][n]] for n in names})
        # a silent failure: numbers shown with no flag, either where no position exists
        # or off by more than SILENT_ERROR
        silent = status == "ok" and (not exists or max(err.values()) > SILENT_ERROR)
        _, phi, value, dist = cases[i]
        rows.append({"family": f.name, "d": distances[i], "distance": dist, "phi_deg": phi,
                     "method": method, "param": param, "status": status, **err,
                     "det": det, "silent": bool(silent), "varies": varies, "value_deg": value,
                     "seconds": seconds})

    # Newton walks from STABILITY_FAR rad away towards (and, from beyond, past) the edge,
    # each position warm-started from the last converged one
    with mpmath.workdps(60):
        far = _case(f, base, edge - STABILITY_FAR)[:2]
        inside = [_case(f, base, edge - d)[:2] for d in distances]
    here = [c[:2] for c in cases]
    if f.side > 0:
        walk = [far] + [p for pair in zip(inside, here, strict=False) for p in pair]
        pick = list(range(2, len(walk), 2))
    else:
        walk = [far] + here
        pick = list(range(1, len(walk)))
    newton = newton_walk(walk, threshold)
    for i, (scene, phi, _, _) in enumerate(cases):
        # the solver, position by position (it has no memory)
        if scene is None:
            for method in ("solver", "newton", "fd"):
                add(i, method, "", "refused", None)
            continue
        (sv, sfail, sdet), t = best_time(lambda scene=scene, phi=phi: _solver_at(scene, [phi]), STABILITY_REPEATS)
        st = ("refused" if sfail[0] else "nan" if not _finite(sv) else
              "flagged" if sdet[0] < threshold else "ok")
        add(i, "solver", "", st, sv, sdet[0], t)
        # Newton's own toggle measure (jacobian_sine) and flag, as the main bench's
        values, st, sine, t = newton[pick[i]]
        add(i, "newton", f"from {STABILITY_FAR:g} rad", st, values, sine, t)
        # finite differences cannot tell by themselves; the bench can, from the solver's
        # toggle measure and from the step doubled (fd_estimate)
        fv, t = best_time(lambda scene=scene, phi=phi: _fd_at(scene, [phi]), STABILITY_REPEATS)
        fest = fd_estimate(scene, [phi])
        st = ("refused" if not _finite(fv) else "flagged" if sdet[0] < threshold else
              "unsure" if unsure(fest)[0] else "ok")
        add(i, "fd", "h=1e-05/3e-04", st, fv, fest[0], t)
    return rows, edge


def stability_warnings(table: pd.DataFrame, threshold: float = 1e-2) -> list[str]:
    """One line per family, method and kind of trouble, naming the crank angles (or the
    varied scene key's values) and how far each is from the singular one."""
    out = []
    # status -> method -> (what happened, why / what it means), the angles go between
    say = {"flagged": {"solver": ("near a toggle", f"(|det| < {threshold:g}): {LOSE}"),
                       "newton": newton_singular(threshold),
                       "fd": ("near a toggle", f"(the solver's |det| < {threshold:g}): the "
                                               "differences lose digits")},
           "unsure": {"fd": fd_unsure()},
           "refused": {"solver": ("cannot assemble", "(refused)"),
                       "newton": ("cannot assemble", "(the scene is refused)"),
                       "fd": ("no number", "(a neighbour phi +- h cannot assemble)")},
           "diverged": {"newton": ("no convergence", "(no number)")},
           "branch jump": {"newton": ("landed on the other branch", "")},
           "nan": {"solver": ("no velocities or accelerations", "(NaN: det = 0 in floats)"),
                   "newton": ("no number", "(NaN)"), "fd": ("no number", "(NaN)")}}
    for (fam, method), grp in table.groupby(["family", "method"], sort=False):
        varies = grp["varies"].iloc[0]
        where = "crank angles" if varies == CRANK else varies

        def listed(hit):
            return ", ".join(f"{p:.12g} (d={d:.0e})" for p, d in zip(hit["value_deg"], hit["d"], strict=False))
        for status, text in say.items():
            hit = grp[grp["status"] == status]
            if text.get(method) and len(hit):
                what, why = text[method]
                if status == "refused" and method == "fd" and varies != CRANK:
                    why = "(the scene is refused)"
                out.append(f"{method} ({fam}): {what} at {where} {listed(hit)} deg {why}".rstrip())
        hit = grp[grp["silent"]]
        if len(hit):
            out.append(f"{method} ({fam}): SILENT: numbers with no flag but wrong by more than "
                       f"{SILENT_ERROR:g} (or where no position exists) at {where} {listed(hit)} deg")
    return out


def stability_study(out_dir, distances=STABILITY_DISTANCES, threshold: float | None = None, only=None):
    """Run the families (FAMILY_TITLES, or the names in `only`), write out_dir/stability.csv
    and out_dir/stability.png.

    Returns (table, warnings, edges): a DataFrame with STABILITY_COLUMNS (err_* NaN where
    the method gave no number or no position exists; `silent` True where a method printed
    unflagged numbers that are wrong), the warning lines, and each family's singular crank
    angle (or varied value) in degrees (mpf).
    """
    threshold = TOGGLE_THRESHOLD if threshold is None else threshold
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows, edges = [], {}
    for f in families():
        if only is not None and f.name not in only:
            continue
        r, edge = _stability_family(f, list(distances), threshold)
        rows += r
        edges[f.name] = mpmath.degrees(edge)
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

    fams = list(dict.fromkeys(table["family"]))
    ncols = min(3, len(fams))
    nrows = -(-len(fams) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(6 * ncols, 6 * nrows), sharey=True, squeeze=False)
    for ax in axes.flat[len(fams):]:
        ax.set_visible(False)
    axes = axes.flat[:len(fams)]
    clip = 1e8          # errors above are drawn here (wrong in every digit anyway)
    levels = {"solver": 1e10, "newton": 1e12, "fd": 1e14}    # rows of "no number" crosses
    for ax, fam in zip(axes, fams, strict=False):
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
        ax.set_title(FAMILY_TITLES.get(fam, fam), fontsize=9)
        varies = t["varies"].iloc[0]
        ax.set_xlabel(f"distance d from the singular {'crank angle' if varies == CRANK else varies}, rad")
        ax.invert_xaxis()
        ax.grid(True, which="major", alpha=0.3)
    first = axes[0]
    first.set_ylabel(f"error against mpmath (scaled; >= {clip:.0e} drawn at the line)")
    fig.legend(*first.get_legend_handles_labels(), fontsize=8, ncol=9, loc="lower center")
    fig.suptitle("stability: error against distance to the singular position; hollow marker: "
                 "the method flagged it; x on top: no number (the status says why)", fontsize=10)
    fig.tight_layout(rect=(0, 0.06 / nrows, 1, 1 - 0.03 / nrows))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def format_stability(table: pd.DataFrame) -> str:
    """The study's table for a terminal."""
    w = max([len("family")] + [len(f) for f in table["family"]]) + 2
    lines = [f"{'family':<{w}}{'d':>8}  {'method':<8}{'status':<12}{'err_pos':>10}{'err_vel':>10}"
             f"{'err_acc':>10}{'|det|':>10}{'s/pos':>10}"]
    for r in table.itertuples(index=False):
        e = [f"{v:10.1e}" if np.isfinite(v) else f"{'-':>10}" for v in (r.err_pos, r.err_vel, r.err_acc)]
        det = f"{abs(r.det):10.1e}" if np.isfinite(r.det) else f"{'':>10}"
        sec = f"{r.seconds:10.1e}" if np.isfinite(r.seconds) else f"{'':>10}"
        lines.append(f"{r.family:<{w}}{r.d:>8.0e}  {r.method:<8}{r.status + ('!' if r.silent else ''):<12}"
                     f"{''.join(e)}{det}{sec}")
    return "\n".join(lines) + "\n"
