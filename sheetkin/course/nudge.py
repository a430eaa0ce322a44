"""Nudged given data (issue 31): other variants of a book's scheme, near its own, on which the
student's formulas are evaluated again (sheetkin/course/behaviour.py).

A nudged variant keeps everything that fixes the mechanism's configuration and changes what a
formula must read: lengths, offsets, point positions, masses, forces and the crank's speed are
scaled by a factor near 1 (each its own, reproducible from the book's sealed scene text); the
branches, angles of guides, Fi0, Delta_Fi, the tolerances and every zero stay as issued (a
zero is a configuration: an axis through the origin, a guide without offset).

A nudge is kept only when the nudged mechanism is the same configuration at every position:
it assembles where the issued one does (its "assembles" rows are the same), every computed
angle (unit deg or rad) stays in its quadrant, and every number of the reference stays a
number. So an honest formula that is right only for the issued configuration (a branch sign
chosen by hand, ATAN with a fixed quadrant correction) stays right on the nudged data. The
check is made on the reference workbook of the nudged variant, whose values equal the
solver's (tests/sheet). A nudge that fails is halved, down to MIN_SCALE; below that the
variant is dropped (a book with no nudged variant is judged as before, by its precedents).

The turned variant (turned_variant) moves Fi0 and Delta_Fi instead, for the cells the others
leave unmoved (the crank's own rows): the positions move, so only the assembly is kept.
"""
from __future__ import annotations

import hashlib
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from sheetkin.kinematics.scene import Scene
from sheetkin.sheet.workbook import FIRST_COL
from sheetkin.xlsx.evaluator import NUM, Book

from .caches import scene_rows

NUDGES = 2               # nudged variants per book
TURNED = True           # and the turned variant (Fi0, Delta_Fi moved), for the cells the others do not move
START_SCALE = 0.04       # the largest relative change of a given value
MIN_SCALE = 0.0025       # below this a nudge tells too little: the variant is dropped
# the units of given values that a formula must read and that do not fix the configuration
NUDGED_UNITS = frozenset({"m", "rad/s", "rad/s^2", "kg", "kg m^2", "N", "N m", "m/s^2"})
_FIXED = frozenset({"Fi0", "Delta_Fi", "Tol", "Tol_FD"})
_QUADRANT_SLACK = 1e-7   # an angle this close to a quadrant's edge (in degrees) may sit on it
# the turned variant (turned_variant): the crank's start moved by up to TURN_SHIFT degrees and
# its step scaled by 1 +- up to TURN_STEP, each halved down to 1/TURN_HALVINGS... if needed
TURN_SHIFT = 0.5
TURN_STEP = 0.01
TURN_TRIES = 5


@dataclass(frozen=True)
class Nudged:
    """One nudged variant: its given data (input name -> value), scene and reference."""
    inputs: dict
    scene: Scene
    reference: Book
    scale: float
    turned: bool = False     # the turned variant: judges only the cells the others do not move


def nudged_inputs(scene: Scene, seed: bytes, which: int, scale: float) -> dict[str, float]:
    """The given data of nudged variant `which`: each nudged value times 1 + scale * u, u in
    +-[0.5, 1] drawn from the seed (the same book always gets the same variants)."""
    rng = np.random.default_rng(int.from_bytes(hashlib.sha256(seed + b"\0%d" % which).digest()[:8], "big"))
    out = {}
    for r in scene_rows(scene):
        if r.kind != "input" or r.name in _FIXED or r.unit not in NUDGED_UNITS:
            continue
        v = r.value
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v == 0 or not math.isfinite(v):
            continue
        u = rng.uniform(0.5, 1.0) * (1 if rng.random() < 0.5 else -1)
        out[r.name] = float(v) * (1.0 + scale * u)
    return out


def same_configuration(scene: Scene, issued: Book, nudged: Book, quadrants: bool = True) -> bool:
    """Whether the nudged reference is the issued configuration at every position: the same
    guards, every angle in its quadrant (unless not `quadrants`), numbers where the issued
    has numbers."""
    sheet_i, sheet_n = issued.order[0], nudged.order[0]
    where = {issued.sheets[sheet_i].consts.get((r, 1)): r for r in range(5, issued.sheets[sheet_i].max_row + 1)}
    positions = scene.crank.positions
    ni, ti, nn, tn = issued.num[sheet_i], issued.tag[sheet_i], nudged.num[sheet_n], nudged.tag[sheet_n]
    for row in scene_rows(scene):
        if row.kind not in ("calc", "accepted", "guard", "derived") or row.name not in where:
            continue
        r = where[row.name]
        cols = slice(4, 5) if row.kind == "derived" else slice(FIRST_COL, FIRST_COL + positions)
        a_tag, b_tag = ti[r, cols], tn[r, cols]
        if not np.array_equal(a_tag, b_tag):
            return False                     # a marker became a number, a number an error ...
        if row.kind == "guard":
            if not np.array_equal(ni[r, cols], nn[r, cols]):
                return False                 # assembles elsewhere, or not at all
            continue
        numbers = a_tag == NUM
        a, b = ni[r, cols][numbers], nn[r, cols][numbers]
        if not np.isfinite(b).all():
            return False
        if quadrants and row.unit in ("deg", "rad"):
            turn = 360.0 if row.unit == "deg" else 2 * math.pi
            if not all(_same_quadrant(float(x), float(y), turn) for x, y in zip(a, b, strict=True)):
                return False
    return True


def _same_quadrant(a: float, b: float, turn: float) -> bool:
    q = turn / 4
    slack = _QUADRANT_SLACK * turn / 360.0
    a, b = a % turn, b % turn
    edge = round(a / q) * q
    if abs(a - edge) <= slack:                     # on an edge: stays on it
        d = abs(b - edge % turn)
        return min(d, turn - d) <= max(slack, 1e-6 * q)
    return math.floor(a / q) == math.floor(b / q)


def nudged_variants(scene: Scene, seed: bytes, issued: Book,
                    vary: Callable[[Scene, dict], Scene], reference: Callable[[Scene], Book],
                    count: int = NUDGES) -> list[Nudged]:
    """Up to `count` nudged variants of the scene (see the module's docstring); vary(scene,
    inputs) is the scene with those given data, reference(scene) its evaluated reference."""
    out: list[Nudged] = []
    for which in range(count):
        scale = START_SCALE
        while scale >= MIN_SCALE:
            inputs = nudged_inputs(scene, seed, which, scale)
            if not inputs:
                return out
            s = vary(scene, inputs)
            ref = reference(s)
            if same_configuration(scene, issued, ref):
                out.append(Nudged(inputs, s, ref, scale))
                break
            scale /= 2
    return out


def turned_inputs(scene: Scene, seed: bytes, scale: float) -> dict[str, float]:
    """The given data of the turned variant: Fi0 moved by scale * TURN_SHIFT * u degrees and
    Delta_Fi scaled by 1 + scale * TURN_STEP * u' (u, u' in +-[0.5, 1] from the seed)."""
    rng = np.random.default_rng(int.from_bytes(hashlib.sha256(seed + b"\0turned").digest()[:8], "big"))
    out = {}
    for r in scene_rows(scene):
        if r.kind != "input" or r.name not in ("Fi0", "Delta_Fi"):
            continue
        v = r.value
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            continue
        u = rng.uniform(0.5, 1.0) * (1 if rng.random() < 0.5 else -1)
        out[r.name] = float(v) + scale * TURN_SHIFT * u if r.name == "Fi0" else float(v) * (1 + scale * TURN_STEP * u)
    return out


def turned_variant(scene: Scene, seed: bytes, issued: Book, vary: Callable[[Scene, dict], Scene],
                   reference: Callable[[Scene], Book]) -> Nudged | None:
    """The turned variant (issue 31): the crank's start Fi0 and step Delta_Fi moved a little,
    every other given datum as issued. It moves what the nudged lengths do not: the crank's
    own rows (Fi, dFi, cos_1, sin_1, phi_1 and Delta_Fi_rad), the zeros of a quadrant's edge
    (x_A at 90 deg) ... The positions move, so the angles may leave a quadrant's edge: it is
    kept when the mechanism assembles where the issued one does, numbers where the issued has
    numbers (no quadrant kept), and it judges only the cells the nudged lengths leave
    unmoved (sheetkin/course/behaviour.py), not a formula's quadrant or branch chosen by hand."""
    scale = 1.0
    for _ in range(TURN_TRIES):
        inputs = turned_inputs(scene, seed, scale)
        if not inputs:
            return None
        s = vary(scene, inputs)
        ref = reference(s)
        if same_configuration(scene, issued, ref, quadrants=False):
            return Nudged(inputs, s, ref, scale, turned=True)
        scale /= 2
    return None
