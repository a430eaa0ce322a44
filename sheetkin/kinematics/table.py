"""The reference kinematics of a scene as a table: contract names, units, gaps, toggles.

`compute(scene)` returns a pandas DataFrame, one row per crank position, columns named as
in docs/scene-format.md ("Output names"), followed by sheetkin's own extra columns:
  assembled       False where some group cannot assemble (only with allow_gaps=True)
  det_g<i>        group i's normalised Jacobian determinant (toggle measure)
  near_toggle     the groups (e.g. "1" or "1,2") whose |det| is below the threshold, else ""
and, with analogs=True, the velocity/acceleration analogs (d/dphi, d2/dphi2): vqx_A,
vq_A, aqx_A, omegaq_2, epsq_2, vqs_B, ... (seed 000's v_qAx, omega_q2, ...); with
dynamics=True, the energy and force analysis (sheetkin.kinematics.dynamics: T_k, U_k, ..., M_bal).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sheetkin.errors import InputError
from sheetkin.groups.group import slide_names

from .dynamics import dynamics as solve_dynamics
from .dynamics import dynamics_names
from .scene import AssemblyError, Scene, as_scene
from .solver import Solution, solve

TOGGLE_THRESHOLD = 1e-2
_SCAN_STEP_DEG = 0.005      # grid of the revolution scanned for non-assembly intervals
# Positions per chunk: a chunk's temporaries (128 KB each) stay in the core's 2 MB L2
# cache; fresh 8 MB temporaries at 1e6 positions cost more in cache misses and page faults
# than the arithmetic, and much smaller chunks pay numpy's per-call overhead. Measured on
# this 2-core machine (benchmarks/solver.py, four-bar, 1e6): 16384 to 65536 fastest.
CHUNK = 16384


class NumericOverflow(InputError):
    """A result is not a finite number where the mechanism assembles and is not at a toggle
    (the scene's numbers, within the scene caps, still overflow): one line, never `inf`."""


class TooLarge(InputError):
    """The table would not fit in this machine's available memory (fewer positions, or
    streamed output, mend it)."""


@dataclass(frozen=True)
class Gap:
    """A range of crank angles where a group cannot assemble: `compute(scene, allow_gaps=True)`
    lists them in `df.attrs["gaps"]`; str() says it in one line."""

    group: str                # label of the first group that cannot assemble
    start_deg: float          # crank-angle interval, in [0, 360), may wrap past 360
    end_deg: float

    def __str__(self):
        return f"{self.group} cannot assemble for crank angles {self.start_deg:.2f}..{self.end_deg:.2f} deg"


def column_names(scene: Scene) -> list[str]:
    """The output columns named in the scene format (docs: scene-format), in order."""
    cols = ["phi_1"]
    for k in scene.links:
        cols += [f"phi_{k}", f"omega_{k}", f"eps_{k}"]
    for p in scene.moving_joints + [p.name for p in scene.points]:
        cols += [f"{q}_{p}" for q in ("x", "y", "vx", "vy", "v", "ax", "ay", "a")]
    for p in scene.sliders:
        cols += list(slide_names(p))
    return cols


_UNITS = {"phi": "deg", "omega": "rad/s", "eps": "rad/s^2", "x": "m", "y": "m",
          "vx": "m/s", "vy": "m/s", "v": "m/s", "ax": "m/s^2", "ay": "m/s^2", "a": "m/s^2",
          "s": "m", "vs": "m/s", "as": "m/s^2",
          "omegaq": "1", "epsq": "1", "vqx": "m", "vqy": "m", "vq": "m", "aqx": "m", "aqy": "m",
          "aq": "m", "vqs": "m", "aqs": "m", "det": "1"}


_UNITS.update({"T": "J", "U": "J", "Fix": "N", "Fiy": "N", "Mi": "N m", "Rx": "N", "Ry": "N",
               "R": "N", "M": "N m"})
_WHOLE_UNITS = {"T_t": "W", "U_t": "W", "P_ext": "W", "P_bal": "W", "balance": "W",
                "M_bal": "N m"}


def unit(column: str) -> str:
    # s2_N, vs2_N, as2_N (a group's second slide) have the units of s, vs, as
    return _WHOLE_UNITS.get(column) or _UNITS.get(column.split("_", 1)[0].rstrip("0123456789"), "")


def analog_name(column: str) -> str:
    """vx_A -> vqx_A, v_A -> vq_A, omega_2 -> omegaq_2, eps_2 -> epsq_2, as_B -> aqs_B."""
    head, subject = column.split("_", 1)
    head = head + "q" if head in ("omega", "eps", "v", "a") else head[0] + "q" + head[1:]
    return f"{head}_{subject}"


def solution_columns(scene: Scene, sol: Solution, out: dict | None = None) -> dict[str, np.ndarray]:
    """The contract's columns of a Solution (angles in degrees, in [0, 360)).

    With `out` (name -> preallocated 1-D array) every column is written in place, with no
    temporaries: at a million positions the copies cost as much as the kinematics.
    """
    n = len(sol.phi1_deg)
    out = {name: np.empty(n) for name in column_names(scene)} if out is None else out

    def put(name, value):
        np.copyto(out[name], value)

    put("phi_1", sol.phi1_deg)
    for k in scene.links:
        r, dst = sol.links[k], out[f"phi_{k}"]
        np.arctan2(r.s, r.c, out=dst, casting="unsafe")
        np.multiply(dst, 180.0 / np.pi, out=dst)
        # (-180, 180] -> [0, 360); masked adds cost a tenth of np.mod. An angle a hair below
        # 0 rounds to 360.0 after the add: fold it back. +0.0 turns -0.0 into 0.
        np.add(dst, 360.0, out=dst, where=dst < 0.0)
        np.subtract(dst, 360.0, out=dst, where=dst >= 360.0)
        dst += 0.0
        put(f"omega_{k}", r.omega)
        put(f"eps_{k}", r.eps)
    for name in scene.moving_joints + [p.name for p in scene.points]:
        m = sol.points[name]
        for q, value in (("x", m.x), ("y", m.y), ("vx", m.vx), ("vy", m.vy), ("ax", m.ax), ("ay", m.ay)):
            put(f"{q}_{name}", value)
        _norm(m.vx, m.vy, out[f"v_{name}"])
        _norm(m.ax, m.ay, out[f"a_{name}"])
    for tag in scene.sliders:
        sl = sol.slides[tag]
        for name, value in zip(slide_names(tag), (sl.s, sl.vs, sl.as_), strict=False):
            put(name, value)
    return out


def _norm(x, y, out):
    """|(x, y)| into out; kinematic magnitudes never approach overflow, so no hypot."""
    np.multiply(x, x, out=out)
    out += y * y
    np.sqrt(out, out=out)


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
    for s_idx, e_idx, a, z in zip(starts, ends, start, end, strict=False):
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


ANALOG_HEADS = ("omega", "eps", "vx", "vy", "v", "ax", "ay", "a", "vs", "as")
_MALLOC_TUNED = False


def _keep_temporaries_in_heap():
    """Once per process, on glibc: a chunk's 128 KB temporaries sit at glibc's mmap
    threshold, so by default each one is mmap'd, faulted in page by page, and unmapped
    when freed; raising the mmap and trim thresholds keeps them in the heap for reuse
    (4.7x faster at 1e4 positions, benchmarks/scale.py). The cost: up to 256 MB of freed
    memory stays with the process. SHEETKIN_NO_MALLOPT=1 leaves malloc alone."""
    global _MALLOC_TUNED
    if _MALLOC_TUNED or os.environ.get("SHEETKIN_NO_MALLOPT"):
        return
    _MALLOC_TUNED = True
    try:
        import ctypes
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(-3, 64 << 20)        # M_MMAP_THRESHOLD
        libc.mallopt(-1, 256 << 20)       # M_TRIM_THRESHOLD
    except (OSError, AttributeError):      # not glibc: nothing to tune
        pass


def table_names(scene: Scene, analogs: bool = False, dynamics: bool = False) -> list[str]:
    """Rows of solve_table: the contract's columns, [their analogs], [the dynamics], then
    det_g<i>."""
    names = column_names(scene)
    if analogs:
        names += [analog_name(n) for n in names if n.split("_", 1)[0] in ANALOG_HEADS]
    if dynamics:
        names += dynamics_names(scene)
    return names + [f"det_g{g.index}" for g in scene.groups]


def available_memory() -> int | None:
    """Bytes this process may still allocate (Linux MemAvailable), None if unknown."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def check_table_fits(scene: Scene, n: int, n_columns: int) -> None:
    """Refuse (TooLarge, one line) a table of n positions x n_columns float64 that would
    not fit in the memory available now: better than an allocation that the kernel kills
    halfway (Linux overcommits, so np.empty itself seldom fails)."""
    need = 8 * n * n_columns
    have = available_memory()
    if have is not None and need > 0.9 * have:
        raise TooLarge(f"{scene.source}: {n:,} positions x {n_columns} columns need {need / 1e9:.1f} GB "
                       f"in memory, {have / 1e9:.1f} GB are available; compute fewer positions at a "
                       "time (e.g. split the crank angles with --at or phi0_deg/positions)")


def _finite_positions(block: np.ndarray) -> np.ndarray:
    """Per position (column of the chunk), True if every value in it is finite."""
    return np.isfinite(block).all(axis=0)


def solve_table(scene: Scene, phi_deg, *, analogs: bool = False, dynamics: bool = False,
                threads: int | None = None, finite: np.ndarray | None = None):
    """Solve in cache-sized chunks (on `threads` threads) into one preallocated table.

    Returns (names, table, failed): table[j] is the column names[j] (see table_names);
    failed[i - 1] marks where group i cannot assemble. The analogs are the same solve
    with omega = 1, epsilon = 0 (d/dphi and d2/dphi2). With `finite` (a bool array, one
    per position), each chunk marks there whether all its values are finite while they
    are still in cache. numpy's floating-point warnings are off: NaN marks a group that
    cannot assemble, inf a toggle, both reported by the callers in their own words.
    """
    _keep_temporaries_in_heap()
    phi = np.asarray(phi_deg, dtype=float).reshape(-1)
    n = phi.size
    names = table_names(scene, analogs, dynamics)
    check_table_fits(scene, n, len(names))
    table = np.empty((len(names), n))
    failed = np.zeros((len(scene.groups), n), dtype=bool)
    row_of = {name: j for j, name in enumerate(names)}
    contract = column_names(scene)
    analog_of = {analog_name(c): c for c in contract if c.split("_", 1)[0] in ANALOG_HEADS}

    def run(start: int, stop: int):
        with np.errstate(all="ignore"):     # per thread: numpy's error state is thread-local
            _run(start, stop)

    def _run(start: int, stop: int):
        for a in range(start, stop, CHUNK):
            b = min(a + CHUNK, stop)
            sol = solve(scene, phi[a:b])
            solution_columns(scene, sol, {c: table[row_of[c], a:b] for c in contract})
            for g in scene.groups:
                np.copyto(table[row_of[f"det_g{g.index}"], a:b], sol.det[g.index])
            for i, f in sol.failed.items():
                failed[i - 1, a:b] = f
            if dynamics:
                for name, value in solve_dynamics(scene, sol).items():
                    np.copyto(table[row_of[name], a:b], value)
            if analogs:
                q = solution_columns(scene, solve(scene, phi[a:b], omega=1.0, epsilon=0.0))
                for name, base in analog_of.items():
                    np.copyto(table[row_of[name], a:b], q[base])
            if finite is not None:
                finite[a:b] = _finite_positions(table[:, a:b])

    threads = threads or min(2, os.cpu_count() or 1)
    if threads > 1 and n > 4 * CHUNK:
        # one contiguous share per thread; numpy releases the GIL inside ufuncs, so the
        # shares run in parallel
        from concurrent.futures import ThreadPoolExecutor
        bounds = np.linspace(0, n // CHUNK, threads + 1).astype(int) * CHUNK
        bounds[-1] = n
        with ThreadPoolExecutor(threads) as pool:
            list(pool.map(run, bounds[:-1], bounds[1:]))
    else:
        run(0, n)
    return names, table, failed


def compute(scene: Scene | str | Path, at=None, *, analogs: bool = False, allow_gaps: bool = False,
            toggle_threshold: float = TOGGLE_THRESHOLD, dynamics: bool = False):
    """Positions, velocities and accelerations of every link and point, one row per position.

    `scene` is a Scene or a path to a scene file; `at` (degrees) replaces the scene's crank
    positions. Raises AssemblyError naming the crank-angle intervals where a group cannot
    assemble, unless allow_gaps, which keeps those rows (NaN, `assembled` False).
    Columns: the contract's, [analogs], [dynamics], [assembled], det_g<i>..., near_toggle.
    With dynamics, a scene needs [[mass]] or [[force]] tables (ValueError otherwise).
    """
    scene = as_scene(scene)          # a Scene, a path or the scene's text
    if dynamics and not scene.has_dynamics:
        raise ValueError(f"{scene.source}: no [[mass]] or [[force]] tables, so there is nothing for "
                         "the dynamics to compute (masses, forces, gravity: see `sheetkin docs dynamics`)")
    c = scene.crank
    # refused before anything is allocated (touching 1e8 fresh angles alone takes seconds)
    check_table_fits(scene, c.positions if at is None else np.size(at),
                     len(table_names(scene, analogs, dynamics)))
    # the scene's angles as crank_angles_deg() gives them (the same float operations), without
    # a Python list: 1e8 positions would be 3 GB of float objects
    phi = (c.phi0_deg + np.arange(c.positions, dtype=float) * c.step_deg if at is None else
           np.asarray(at, dtype=float).reshape(-1))
    finite = np.ones(phi.size, dtype=bool)
    names, table, failed = solve_table(scene, phi, analogs=analogs, dynamics=dynamics, finite=finite)
    fail = failed.any(axis=0)
    n_det = len(scene.groups)
    if not finite.all():
        _undefined_at_toggles(scene, names, table, phi, ~finite & ~fail, toggle_threshold)
        _undefined_at_gaps(table, ~finite & fail)
    if fail.any() and not allow_gaps:
        gaps = assembly_gaps(scene, phi)
        raise AssemblyError("; ".join(map(str, gaps)) +
                            f" ({int(fail.sum())} of {fail.size} positions; use allow_gaps=True to keep the rest)")
    import pandas as pd  # only here: the command line's path (sheetkin.views.output) needs no pandas
    # the table's rows become the frame's columns without a copy (one float block)
    df = pd.DataFrame(table.T, columns=names, copy=False)
    if fail.any():
        df.insert(len(names) - n_det, "assembled", ~fail)
    df["near_toggle"] = _near_toggle(table[len(names) - n_det:].T, fail, toggle_threshold)
    df.attrs["title"] = scene.title
    return df


def _undefined_at_toggles(scene: Scene, names: list[str], table: np.ndarray, phi: np.ndarray,
                          where: np.ndarray, threshold: float) -> None:
    """Non-finite values at assembled positions (`where`): at a toggle (some group's |det|
    below the threshold, flagged as near_toggle and warned about) the rates are undefined
    and become NaN (an empty CSV cell, JSON null), never `inf`; anywhere else they are an
    overflow, NumericOverflow naming the first column and crank angle."""
    cols = np.flatnonzero(where)
    dets = table[len(names) - len(scene.groups):][:, cols]
    at_toggle = (~(np.abs(dets) >= threshold)).any(axis=0)
    block = table[:, cols]
    if not at_toggle.all():
        k = int(np.flatnonzero(~at_toggle)[0])
        j = int(np.flatnonzero(~np.isfinite(block[:, k]))[0])
        raise NumericOverflow(f"{scene.source}: {names[j]} = {block[j, k]} at crank angle {phi[cols[k]]:g} "
                              "deg: the result overflows double precision (the mechanism's numbers "
                              "are too large or too small for each other)")
    block[~np.isfinite(block)] = np.nan
    table[:, cols] = block


def _undefined_at_gaps(table: np.ndarray, where: np.ndarray) -> None:
    """Non-finite values at positions that do not assemble (`where`) become NaN, never `inf`:
    at a dead point (a discriminant within DEAD_POINT of its terms, which does not assemble)
    the positions are computed from a zero discriminant and the rates divide by a zero
    determinant."""
    cols = np.flatnonzero(where)
    block = table[:, cols]
    block[~np.isfinite(block)] = np.nan
    table[:, cols] = block


def _near_toggle(dets: np.ndarray, fail: np.ndarray, threshold: float):
    """The near_toggle column as a pandas Categorical (see near_toggle_codes)."""
    import pandas as pd
    codes, labels = near_toggle_codes(dets, fail, threshold)
    return pd.Categorical.from_codes(codes, categories=labels)


def near_toggle_codes(dets: np.ndarray, fail: np.ndarray, threshold: float) -> tuple[np.ndarray, list[str]]:
    """(codes, labels): labels[codes[i]] is "1", "1,2", ... naming the groups whose |det| is
    below threshold at position i, "" where none is. dets is (positions, groups).

    Built from a bitmask of flagged groups: a million positions need a few distinct
    strings, not a million Python objects.
    """
    flags = ~(np.abs(dets) >= threshold) & ~fail[:, None]
    mask = (flags.astype(np.int64) << np.arange(flags.shape[1])).sum(axis=1)
    if mask.size and mask.max() < 1 << 16:     # the usual case: find the masks present without sorting
        present = np.flatnonzero(np.bincount(mask))
        lookup = np.zeros(present[-1] + 1, dtype=np.int64)
        lookup[present] = np.arange(present.size)
        codes = lookup[mask]
    else:
        present, codes = np.unique(mask, return_inverse=True)
    labels = [",".join(str(i + 1) for i in range(flags.shape[1]) if m >> i & 1) for m in present]
    return codes.reshape(-1), labels


# --------------------------------------------------------------------------- blocks, for the command line
# Positions per block of the command line's output: 16 Ki positions x 40 columns is 5 MB of
# numbers and about 20 MB of text slots in flight, whatever the total (1e7 positions stream
# in about 100-150 MB; benchmarks/cli.py measures it). Larger blocks save nothing: the
# formatting works in chunks of 8192 numbers anyway.
BLOCK = 16384


@dataclass(frozen=True)
class AngleRange:
    """The crank angles first + i * step / scale, i < count (scale = 10^decimals: the angles
    are exact decimal multiples, so --range 0:360:0.1 gives 0.3, not 0.30000000000000004)."""
    first: int
    step: int
    scale: int
    count: int

    def __len__(self):
        return self.count

    def take(self, a: int, b: int) -> np.ndarray:
        return (self.first + self.step * np.arange(a, b, dtype=np.float64)) / self.scale


def _angles(phi, a: int, b: int) -> np.ndarray:
    return phi.take(a, b) if isinstance(phi, AngleRange) else phi[a:b]


@dataclass
class Block:
    """Positions start..start+n of a computation: table[j] is the column names[j] (see
    table_names), fail marks the positions where some group cannot assemble, near_toggle's
    labels[codes[i]] names the groups near a toggle."""
    start: int
    table: np.ndarray
    fail: np.ndarray
    codes: np.ndarray
    labels: list[str]

    @property
    def phi(self) -> np.ndarray:
        return self.table[0]


def failing(scene: Scene, phi, block: int = BLOCK) -> np.ndarray:
    """Where some group cannot assemble, for every position (positions only, no rates: a
    first pass that decides the output's columns and refuses before anything is written)."""
    n = len(phi)
    fail = np.zeros(n, dtype=bool)
    for a in range(0, n, block):
        fail[a:a + block] = failed_positions(solve(scene, _angles(phi, a, min(a + block, n))))
    return fail


def compute_blocks(scene: Scene, phi, *, analogs: bool = False, dynamics: bool = False,
                   toggle_threshold: float = TOGGLE_THRESHOLD, block: int = BLOCK):
    """compute() without pandas and in blocks of `block` positions, for writing as they come:
    yields Block objects over the angles `phi` (an array or an AngleRange). Assembly is not
    checked here (see failing); failing positions come back as NaN with fail set. Values
    that are not finite at a toggle become NaN; anywhere else they raise NumericOverflow
    (on stdout the blocks before it are already written)."""
    n = len(phi)
    n_det = len(scene.groups)
    for a in range(0, n, block):
        b = min(a + block, n)
        angles = _angles(phi, a, b)
        finite = np.ones(b - a, dtype=bool)
        names, table, failed = solve_table(scene, angles, analogs=analogs, dynamics=dynamics, finite=finite)
        fail = failed.any(axis=0)
        if not finite.all():         # as compute(): NaN at a toggle, NumericOverflow elsewhere
            _undefined_at_toggles(scene, names, table, angles, ~finite & ~fail, toggle_threshold)
            _undefined_at_gaps(table, ~finite & fail)
        codes, labels = near_toggle_codes(table[len(names) - n_det:].T, fail, toggle_threshold)
        yield Block(a, table, fail, codes, labels)
