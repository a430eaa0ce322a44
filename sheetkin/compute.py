"""The reference kinematics of a scene as a table: contract names, units, gaps, toggles.

`compute(scene)` returns a pandas DataFrame, one row per crank position, columns named as
in shared/spec/scene.md ("Output names"), followed by sheetkin's own extra columns:
  assembled       False where some group cannot assemble (only with allow_gaps=True)
  det_g<i>        group i's normalised Jacobian determinant (toggle measure)
  near_toggle     the groups (e.g. "1" or "1,2") whose |det| is below the threshold, else ""
and, with analogs=True, the velocity/acceleration analogs (d/dphi, d2/dphi2): vqx_A,
vq_A, aqx_A, omegaq_2, epsq_2, vqs_B, ... (seed 000's v_qAx, omega_q2, ...).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from .scene import Scene, load_scene
from .solver import Solution, solve

TOGGLE_THRESHOLD = 1e-2
_SCAN_STEP_DEG = 0.005      # grid of the revolution scanned for non-assembly intervals


class AssemblyError(ValueError):
    """The mechanism cannot be assembled at some requested crank positions."""


@dataclass(frozen=True)
class Gap:
    group: str                # label of the first group that cannot assemble
    start_deg: float          # crank-angle interval, in [0, 360), may wrap past 360
    end_deg: float

    def __str__(self):
        return f"{self.group} cannot assemble for crank angles {self.start_deg:.2f}..{self.end_deg:.2f} deg"


def column_names(scene: Scene) -> list[str]:
    """The contract's output columns, in order."""
    cols = ["phi_1"]
    for k in scene.links:
        cols += [f"phi_{k}", f"omega_{k}", f"eps_{k}"]
    for p in scene.moving_joints + [p.name for p in scene.points]:
        cols += [f"{q}_{p}" for q in ("x", "y", "vx", "vy", "v", "ax", "ay", "a")]
    for p in scene.sliders:
        cols += [f"s_{p}", f"vs_{p}", f"as_{p}"]
    return cols


_UNITS = {"phi": "deg", "omega": "rad/s", "eps": "rad/s^2", "x": "m", "y": "m",
          "vx": "m/s", "vy": "m/s", "v": "m/s", "ax": "m/s^2", "ay": "m/s^2", "a": "m/s^2",
          "s": "m", "vs": "m/s", "as": "m/s^2",
          "omegaq": "1", "epsq": "1", "vqx": "m", "vqy": "m", "vq": "m", "aqx": "m", "aqy": "m",
          "aq": "m", "vqs": "m", "aqs": "m", "det": "1"}


def unit(column: str) -> str:
    return _UNITS.get(column.split("_", 1)[0], "")


def analog_name(column: str) -> str:
    """vx_A -> vqx_A, v_A -> vq_A, omega_2 -> omegaq_2, eps_2 -> epsq_2, as_B -> aqs_B."""
    head, subject = column.split("_", 1)
    head = head + "q" if head in ("omega", "eps", "v", "a") else head[0] + "q" + head[1:]
    return f"{head}_{subject}"


def solution_columns(scene: Scene, sol: Solution) -> dict[str, np.ndarray]:
    """Flatten a Solution into the contract's columns (angles in degrees, [0, 360))."""
    out = {"phi_1": sol.phi1_deg}
    for k in scene.links:
        r = sol.links[k]
        out[f"phi_{k}"] = np.degrees(np.arctan2(r.s, r.c)) % 360.0
        out[f"omega_{k}"], out[f"eps_{k}"] = r.omega, r.eps
    for name in scene.moving_joints + [p.name for p in scene.points]:
        m = sol.points[name]
        out[f"x_{name}"], out[f"y_{name}"] = m.x, m.y
        out[f"vx_{name}"], out[f"vy_{name}"], out[f"v_{name}"] = m.vx, m.vy, np.hypot(m.vx, m.vy)
        out[f"ax_{name}"], out[f"ay_{name}"], out[f"a_{name}"] = m.ax, m.ay, np.hypot(m.ax, m.ay)
    for name in scene.sliders:
        sl = sol.slides[name]
        out[f"s_{name}"], out[f"vs_{name}"], out[f"as_{name}"] = sl.s, sl.vs, sl.as_
    n = len(sol.phi1_deg)
    # a quantity that does not vary (e.g. a slider's guide angle) comes back as a scalar
    return {k: np.broadcast_to(np.asarray(v, dtype=float), (n,)) for k, v in out.items()}


def failed_positions(sol: Solution) -> np.ndarray:
    fail = np.zeros(sol.phi1_deg.shape, dtype=bool)
    for f in sol.failed.values():
        fail |= f
    return fail


def assembly_gaps(scene: Scene, phi_deg) -> list[Gap]:
    """The crank-angle intervals (to 1e-6 deg) containing the given positions that fail.

    The revolution is scanned on a fine grid together with the failing positions
    themselves (so a narrow interval around one of them is never missed); each interval's
    ends are then found by bisection between a failing and an assembling angle.
    """
    phi_deg = np.asarray(phi_deg, dtype=float)
    fail_at = failed_positions(solve(scene, phi_deg))
    if not fail_at.any():
        return []
    grid = np.unique(np.concatenate([np.arange(0.0, 360.0, _SCAN_STEP_DEG),
                                     phi_deg[fail_at] % 360.0]))
    sol = solve(scene, grid)
    culprit = np.zeros(grid.shape, dtype=int)
    for i, f in sol.failed.items():
        culprit[f & (culprit == 0)] = i
    bad = culprit > 0
    if bad.all():
        g = scene.groups[int(culprit[0]) - 1].label
        return [Gap(g, 0.0, 360.0)]
    # runs of failing grid points, rotated so that the array starts on an assembling angle
    shift = int(np.argmin(bad))
    order = np.roll(np.arange(grid.size), -shift)
    b = bad[order]
    starts = np.flatnonzero(b & ~np.roll(b, 1))
    ends = np.flatnonzero(b & ~np.roll(b, -1))
    lo_ok, lo_bad = grid[order[starts - 1]], grid[order[starts]]
    hi_bad, hi_ok = grid[order[ends]], grid[order[(ends + 1) % grid.size]]
    start = _bisect(scene, lo_ok, lo_bad)
    end = _bisect(scene, hi_ok, hi_bad)
    wanted = phi_deg[fail_at] % 360.0
    gaps = []
    for s_idx, e_idx, a, z in zip(starts, ends, start, end):
        members = grid[order[s_idx:e_idx + 1]]
        if np.isin(wanted, members).any():
            gaps.append(Gap(scene.groups[int(culprit[order[s_idx]]) - 1].label, a % 360.0, z % 360.0))
    return gaps


def _bisect(scene: Scene, ok, bad, iterations: int = 40):
    """Move each (assembling, failing) pair of angles together until they are 1e-6 deg apart."""
    ok, bad = np.array(ok, dtype=float), np.array(bad, dtype=float)
    bad = np.where(bad < ok - 180.0, bad + 360.0, np.where(bad > ok + 180.0, bad - 360.0, bad))
    for _ in range(iterations):
        mid = 0.5 * (ok + bad)
        f = failed_positions(solve(scene, mid))
        bad, ok = np.where(f, mid, bad), np.where(f, ok, mid)
        if np.max(np.abs(bad - ok), initial=0.0) < 1e-7:
            break
    return 0.5 * (ok + bad)


def compute(scene: Scene | str | Path, at=None, *, analogs: bool = False, allow_gaps: bool = False,
            toggle_threshold: float = TOGGLE_THRESHOLD) -> pd.DataFrame:
    """Positions, velocities and accelerations of every link and point, one row per position.

    `scene` is a Scene or a path to a scene file; `at` (degrees) replaces the scene's crank
    positions. Raises AssemblyError naming the crank-angle intervals where a group cannot
    assemble, unless allow_gaps, which keeps those rows (NaN, `assembled` False).
    """
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    phi = np.asarray(scene.crank_angles_deg() if at is None else at, dtype=float).reshape(-1)
    sol = solve(scene, phi)
    fail = failed_positions(sol)
    if fail.any() and not allow_gaps:
        gaps = assembly_gaps(scene, phi)
        raise AssemblyError("; ".join(map(str, gaps)) +
                            f" ({int(fail.sum())} of {fail.size} positions; use --allow-gaps to keep the rest)")
    cols = solution_columns(scene, sol)
    if analogs:
        sol_q = solve(scene, phi, omega=1.0, epsilon=0.0)
        cols_q = solution_columns(scene, sol_q)
        for name in column_names(scene):
            head = name.split("_", 1)[0]
            if head in ("omega", "eps", "vx", "vy", "v", "ax", "ay", "a", "vs", "as"):
                cols[analog_name(name)] = cols_q[name]
    if fail.any():
        cols["assembled"] = ~fail
    near = np.full(phi.shape, "", dtype=object)
    for i, det in sol.det.items():
        det = np.broadcast_to(det, phi.shape)
        cols[f"det_g{i}"] = det
        flag = ~fail & ~(np.abs(det) >= toggle_threshold)
        near[flag] = [f"{s},{i}" if s else str(i) for s in near[flag]]
    cols["near_toggle"] = near
    df = pd.DataFrame(cols)
    df.attrs["title"] = scene.title
    return df
