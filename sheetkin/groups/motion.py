"""Result types and small numpy kernels every group kind shares (a leaf: imports only numpy).

A point's motion, a link's rotation and a slider's slide, each as arrays over crank
positions (or scalars for the frame); Cramer's rule for the 2x2 systems of the lecture
(slides 19-21); a point carried by a turning link (slide 7, Euler form); a guide's line at
every position. `GroupMotion` is what every kind's `solve` returns.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# Arrays over crank positions, or one scalar where a value does not move (the frame,
# a fixed guide): numpy broadcasts either, so both are accepted wherever values are.
Values = np.ndarray | float


@dataclass
class Motion:
    """A point: coordinates, velocity and acceleration components (arrays or scalars)."""
    x: Values
    y: Values
    vx: Values
    vy: Values
    ax: Values
    ay: Values


@dataclass
class Rotation:
    """A link's direction as a unit vector (c, s) = (cos phi, sin phi) and its rates."""
    c: Values
    s: Values
    omega: Values
    eps: Values


@dataclass
class Slide:
    """A slider's travel along its guide (or slot) and its relative velocity/acceleration."""
    s: Values
    vs: Values
    as_: Values


@dataclass
class GroupMotion:
    """What a group kind's `solve` returns, the same for every kind.

    joints: the group's new joints by name (RRR, RRP: N; RPR: none);
    links:  both links' rotations {a: Rotation, b: Rotation};
    slides: slide tag -> Slide (see `slide_names`; RRP: {N}, RPR: {J1});
    disc:   > 0 where the group assembles; 0 at a dead point (at_dead_points_zero), < 0 or NaN
            where it cannot;
    toggle: the scale-invariant toggle measure (the Cramer determinant made free of units
            and size; near 0 at a dead position).
    """
    joints: dict[str, Motion]
    links: dict[int, Rotation]
    slides: dict[str, Slide] = field(default_factory=dict)
    disc: Values = 0.0
    toggle: Values = 1.0


def cramer(m11, m12, m21, m22, b1, b2, inv_det):
    """Solve [[m11, m12], [m21, m22]] @ [x, y] = [b1, b2] by determinants (lecture slide 20).

    x = det_x / det, y = det_y / det; the caller passes 1/det, shared by the velocity and
    the acceleration systems (same matrix).
    """
    return (b1 * m22 - b2 * m12) * inv_det, (m11 * b2 - m21 * b1) * inv_det


def inverse_det(m11, m12, m21, m22):
    det = m11 * m22 - m12 * m21
    return det, 1.0 / det


# A discriminant within DEAD_POINT of zero, relative to the size of its terms, is a dead point: the
# group does not assemble there (its Cramer determinant is 0 too, so no rate exists). The spreadsheets
# decide alike: LibreOffice snaps a near-cancelling difference to 0, Gnumeric works in long double,
# Excel "compensates" near zero (KB 78113), so the sign of a discriminant that is 0 in exact
# arithmetic is anyone's; the workbook's assembly test (rows.group_guard) has the same margin.
# docs/dead-points.md.
DEAD_POINT = 1e-12


def at_dead_points_zero(disc, size):
    """`disc` with every value closer than DEAD_POINT * `size` to zero set to 0 (a dead point:
    solver.solve counts only disc > 0 as assembled; the workbook's guard, disc >= DEAD_POINT *
    size, decides the same); NaN stays NaN."""
    with np.errstate(invalid="ignore"):
        return np.where(np.abs(disc) < DEAD_POINT * np.abs(size), 0.0, disc)


def sqrt_or_nan(d):
    """sqrt of a discriminant, NaN where the group cannot assemble (never a silent clip)."""
    return np.sqrt(np.where(d >= 0, d, np.nan))


def fixed(x, y) -> Motion:
    """A frame point: it does not move."""
    return Motion(x, y, 0.0, 0.0, 0.0, 0.0)


def carried_point(base: Motion, rot: Rotation, along: float, across: float) -> Motion:
    """A point fixed on a link, `along` its direction and `across` to the left of it.

    Euler form of the coupler's motion (lecture slide 7): v = v_P + omega x r,
    a = a_P + eps x r - omega^2 r.
    """
    if across:
        rx, ry = along * rot.c - across * rot.s, along * rot.s + across * rot.c
    else:   # the common case (a point on the line of the link's joints): 4 fewer operations
        rx, ry = along * rot.c, along * rot.s
    w, e = rot.omega, rot.eps
    w2 = w * w
    return Motion(base.x + rx, base.y + ry,
                  base.vx - w * ry, base.vy + w * rx,
                  base.ax - e * ry - w2 * rx, base.ay + e * rx - w2 * ry)


def turned(rot: Rotation, angle_deg: float) -> Rotation:
    """The direction phi_k + A of a line fixed on link k (a guide at angle A on the link):
    it turns with the link's omega and eps."""
    a = np.radians(angle_deg)
    ca, sa = np.cos(a), np.sin(a)
    return Rotation(rot.c * ca - rot.s * sa, rot.s * ca + rot.c * sa, rot.omega, rot.eps)


def guide_line(gd, known: dict, rot: dict) -> tuple[Motion, Rotation]:
    """A guide's (group.Guide) point P and direction u = e(phi_k + A), with the rates of
    the link k that carries it (the frame's: none); RRP and PRP place their blocks on it."""
    if not gd.moving:
        a = np.radians(gd.angle_deg)
        return fixed(*gd.point), Rotation(np.cos(a), np.sin(a), 0.0, 0.0)
    return known[gd.through], turned(rot.get(gd.link, FRAME), gd.angle_deg)


def guide_loop(lib, gd, known: dict, links: dict):
    """The same for the loop equations, in any number type `lib` (sheetkin.studies.bench's MP or
    FLOAT): the guide's point ((x, y), (vx, vy), (ax, ay)) and (angle, omega, eps)."""
    n = lib.num
    a = n(gd.angle_deg) * lib.pi() / 180
    if not gd.moving:
        z = (n(0), n(0))
        return ((n(gd.point[0]), n(gd.point[1])), z, z), (a, n(0), n(0))
    phi, w, eps = links[gd.link]
    return known[gd.through], (phi + a, w, eps)


FRAME = Rotation(1.0, 0.0, 0.0, 0.0)   # link 0: phi_0 = 0, at rest


def on_line(origin: Motion, u: Rotation, sl: Slide) -> Motion:
    """A point at distance s along a line through `origin` with direction u, the line
    itself moving with the link that carries it (relative motion, lecture slides 22-24):
    r = G + s u;  v = v_G + vs u + s omega n;
    a = a_G + as u + 2 vs omega n + s eps n - s omega^2 u  (n = u turned +90 deg)."""
    c, sn, w, e = u.c, u.s, u.omega, u.eps
    s, vs, as_ = sl.s, sl.vs, sl.as_
    tu = as_ - s * w * w                       # along u
    tn = 2.0 * vs * w + s * e                  # along n
    return Motion(origin.x + s * c, origin.y + s * sn,
                  origin.vx + vs * c - s * w * sn, origin.vy + vs * sn + s * w * c,
                  origin.ax + tu * c - tn * sn, origin.ay + tu * sn + tn * c)


# --------------------------------------------------------------------------- kinetostatics
@dataclass(frozen=True)
class Pair:
    """A kinematic pair whose reaction is computed: the force of link i on link j."""
    i: int
    j: int
    joint: str          # where the force acts (for a sliding pair: the slider's joint)
    sliding: bool = False

    @property
    def tag(self) -> str:
        return f"{self.i}_{self.j}"


@dataclass
class Loads:
    """Forces (x, y, fx, fy) and couples acting on one link, all arrays over positions."""
    forces: list[tuple[Values, Values, Values, Values]] = field(default_factory=list)
    couple: Values = 0.0

    def add(self, at: Motion, fx, fy):
        self.forces.append((at.x, at.y, fx, fy))

    def resultant(self):
        return sum(f[2] for f in self.forces) + 0.0, sum(f[3] for f in self.forces) + 0.0

    def moment(self, px, py):
        """Moment about (px, py), counterclockwise positive."""
        return self.couple + sum((x - px) * fy - (y - py) * fx for x, y, fx, fy in self.forces)


def resultants(loads: dict, a: int, b: int):
    """The resultant loads (x, y) on a group's links a and b, and their sum."""
    fa, fb = loads[a].resultant(), loads[b].resultant()
    return fa, fb, (fa[0] + fb[0], fa[1] + fb[1])


def hinge(loads: dict, owner: int, link: int, at: Motion, r) -> tuple[str, tuple]:
    """The revolute pair at `at` through which link `owner` acts on `link` with the force r:
    the owner takes -r there (action and reaction). Returns its tag and (Rx, Ry, no couple)."""
    loads[owner].add(at, -r[0], -r[1])
    return f"{owner}_{link}", (r[0], r[1], None)


def cross(dx, dy, fx, fy):
    return dx * fy - dy * fx
