"""Reference solver: closed-form positions, exact velocities and accelerations (numpy, no I/O).

Every quantity is an array over crank positions; no Python loop runs over positions.
Each Assur group is solved the way the lecture (seed 003) does it: the position in closed
form from its kinematic constraints, then the time derivative of those constraints, a 2x2
linear system in the group's two unknown rates, solved by Cramer's rule (slides 19-21);
differentiating once more gives the same matrix with a new right-hand side for the
accelerations. The matrix's determinant, divided by the group's lengths, is the toggle
measure (for RRR the sine of the transmission angle).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .scene import Crank, Group, Point, Scene


@dataclass
class Motion:
    """A point: coordinates, velocity and acceleration components (arrays or scalars)."""
    x: np.ndarray
    y: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    ax: np.ndarray
    ay: np.ndarray


@dataclass
class Rotation:
    """A link's direction as a unit vector (c, s) = (cos phi, sin phi) and its rates."""
    c: np.ndarray
    s: np.ndarray
    omega: np.ndarray
    eps: np.ndarray


@dataclass
class Slide:
    """A slider's travel along its guide (or slot) and its relative velocity/acceleration."""
    s: np.ndarray
    vs: np.ndarray
    as_: np.ndarray


@dataclass
class Solution:
    phi1_deg: np.ndarray
    points: dict[str, Motion] = field(default_factory=dict)
    links: dict[int, Rotation] = field(default_factory=dict)
    slides: dict[str, Slide] = field(default_factory=dict)
    det: dict[int, np.ndarray] = field(default_factory=dict)      # group index -> toggle measure
    failed: dict[int, np.ndarray] = field(default_factory=dict)   # group index -> cannot assemble


def cramer(m11, m12, m21, m22, b1, b2, inv_det):
    """Solve [[m11, m12], [m21, m22]] @ [x, y] = [b1, b2] by determinants (lecture slide 20).

    x = det_x / det, y = det_y / det; the caller passes 1/det, shared by the velocity and
    the acceleration systems (same matrix).
    """
    return (b1 * m22 - b2 * m12) * inv_det, (m11 * b2 - m21 * b1) * inv_det


def inverse_det(m11, m12, m21, m22):
    det = m11 * m22 - m12 * m21
    return det, 1.0 / det


def crank_motion(crank: Crank, pivot, phi, omega, eps) -> tuple[Motion, Rotation]:
    """Crank OA (lecture slide 6): x_t = -phi_t y, y_t = phi_t x, x_tt = -phi_tt y - phi_t y_t."""
    c, s = np.cos(phi), np.sin(phi)
    rx, ry = crank.length * c, crank.length * s
    vx, vy = -omega * ry, omega * rx
    # omega and eps stay scalars: the crank's rates are given, the same at every position
    return (Motion(pivot[0] + rx, pivot[1] + ry, vx, vy, -eps * ry - omega * vy, eps * rx + omega * vx),
            Rotation(c, s, omega, eps))


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


def _sqrt_or_nan(d):
    """sqrt of the discriminant, NaN where the group cannot assemble (never a silent clip)."""
    return np.sqrt(np.where(d >= 0, d, np.nan))


def solve_rrr(j1: Motion, j2: Motion, l2: float, l3: float, branch: int):
    """Dyad RRR: J1 - N - J2, with |J1 N| = L2, |N J2| = L3 (lecture slides 16-21).

    Constraint (a): J1 + L2 e(psi) = J2 + L3 e(xi). With P = xJ2 - xJ1, Q = yJ2 - yJ1:
    P cos psi + Q sin psi = F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2), and
    tg(psi/2) = (Q +- sqrt(P^2 + Q^2 - F^2)) / (P + F). The sign +1 puts N to the left
    of the directed line J1 -> J2. The same root is also (F - P) / (Q -+ sqrt(..)) (the
    product of the two roots is (F - P)/(P + F)); we take whichever form has no
    cancellation, so the half-angle never degenerates to 0/0.
    Returns N, rotations of the links J1->N (psi) and J2->N (xi), the discriminant and
    the toggle measure sin(psi - xi).
    """
    p, q = j2.x - j1.x, j2.y - j1.y
    f = (p * p + q * q + l2 * l2 - l3 * l3) / (2.0 * l2)
    disc = p * p + q * q - f * f
    root = branch * _sqrt_or_nan(disc)
    num1, den1 = q + root, p + f          # the lecture's form
    num2, den2 = f - p, q - root          # the same root, rationalised
    first = num1 * num1 + den1 * den1 >= num2 * num2 + den2 * den2
    num, den = np.where(first, num1, num2), np.where(first, den1, den2)
    # sin and cos from tg(psi/2) = num/den (lecture: sin = 2t/(1+t^2), cos = (1-t^2)/(1+t^2))
    h = num * num + den * den
    c2, s2 = (den * den - num * num) / h, 2.0 * num * den / h
    # cos xi = (L2 cos psi - P) / L3, sin xi = (L2 sin psi - Q) / L3 (system (a))
    c3, s3 = (l2 * c2 - p) / l3, (l2 * s2 - q) / l3
    # velocities, system (b): -L2 sin psi psi_t + L3 sin xi xi_t = vx_J2 - vx_J1, ...
    m11, m12, m21, m22 = -l2 * s2, l3 * s3, l2 * c2, -l3 * c3
    det, inv = inverse_det(m11, m12, m21, m22)
    w2, w3 = cramer(m11, m12, m21, m22, j2.vx - j1.vx, j2.vy - j1.vy, inv)
    # accelerations: same matrix; right side gains the centripetal terms (lecture f1, f2)
    b1 = j2.ax - j1.ax + l2 * w2 * w2 * c2 - l3 * w3 * w3 * c3
    b2 = j2.ay - j1.ay + l2 * w2 * w2 * s2 - l3 * w3 * w3 * s3
    e2, e3 = cramer(m11, m12, m21, m22, b1, b2, inv)
    rot2, rot3 = Rotation(c2, s2, w2, e2), Rotation(c3, s3, w3, e3)
    return carried_point(j1, rot2, l2, 0.0), rot2, rot3, disc, det / (l2 * l3)


def solve_rrp(j1: Motion, length: float, through, angle_deg: float, branch: int):
    """Dyad RRP: coupler J1 - N, slider N on the fixed straight guide through G at angle gamma.

    As the lecture's crank-slider and "angle between the coupler and the fixed guide"
    (slides 13-15, 29): h, the signed distance of J1 from the guide, gives the coupler's
    angle to the guide, sin(mu) = h / L; N lies sqrt(L^2 - h^2) ahead (+1) or behind (-1)
    the foot of the perpendicular from J1. Unknown rates: the coupler's omega and the
    slide's velocity, from N = J1 + L e(phi) = G + s u.
    """
    gam = np.radians(angle_deg)
    ux, uy = np.cos(gam), np.sin(gam)
    dx, dy = j1.x - through[0], j1.y - through[1]
    along = dx * ux + dy * uy
    h = -dx * uy + dy * ux                     # left of the guide is positive
    disc = length * length - h * h
    ahead = branch * _sqrt_or_nan(disc)
    s = along + ahead
    c2, s2 = (ahead * ux + h * uy) / length, (ahead * uy - h * ux) / length
    # velocities: L omega e_perp(phi) - vs u = -v_J1
    m11, m12, m21, m22 = -length * s2, -ux, length * c2, -uy
    det, inv = inverse_det(m11, m12, m21, m22)
    w2, vs = cramer(m11, m12, m21, m22, -j1.vx, -j1.vy, inv)
    e2, as_ = cramer(m11, m12, m21, m22, -j1.ax + length * w2 * w2 * c2,
                     -j1.ay + length * w2 * w2 * s2, inv)
    rot2 = Rotation(c2, s2, w2, e2)
    joint = Motion(through[0] + s * ux, through[1] + s * uy, vs * ux, vs * uy, as_ * ux, as_ * uy)
    zero = np.zeros_like(s)
    rot3 = Rotation(ux + zero, uy + zero, zero, zero)
    return joint, rot2, rot3, Slide(s, vs, as_), disc, det / length


def solve_rpr(j1: Motion, j2: Motion, offset: float, scale: float):
    """Slotted lever (kulisa) turning about J2, its block hinged at J1 (slides 22-24).

    The slot line passes at distance `offset` from J2: J1 - J2 = s u + e n, u = e(theta),
    n = u rotated +90 deg; s = sqrt(|J1 - J2|^2 - e^2) (the seeds' L_TEK, S_AB, l31).
    Unknown rates theta_t and s_t; the Coriolis term 2 s_t theta_t appears in the
    acceleration's right side. Toggle measure: s / scale (the determinant is -s).
    """
    e = offset
    dx, dy = j1.x - j2.x, j1.y - j2.y
    r2 = dx * dx + dy * dy
    disc = np.where(r2 > 0, r2 - e * e, -1.0)   # J1 on J2 with no offset: slot undefined
    s = _sqrt_or_nan(disc)
    c, sn = (s * dx + e * dy) / r2, (s * dy - e * dx) / r2
    col1x, col1y = -s * sn - e * c, s * c - e * sn      # d/dtheta of (s u + e n)
    det, inv = inverse_det(col1x, c, col1y, sn)
    w, vs = cramer(col1x, c, col1y, sn, j1.vx - j2.vx, j1.vy - j2.vy, inv)
    # bias: 2 s_t theta_t n - s theta_t^2 u - e theta_t^2 n
    bn, bu = 2.0 * vs * w - e * w * w, -s * w * w
    bx, by = bu * c - bn * sn, bu * sn + bn * c
    eps, as_ = cramer(col1x, c, col1y, sn, j1.ax - j2.ax - bx, j1.ay - j2.ay - by, inv)
    rot = Rotation(c, sn, w, eps)
    return rot, Slide(s, vs, as_), disc, -det / scale


def solve(scene: Scene, phi_deg, omega: float | None = None, epsilon: float | None = None) -> Solution:
    """Kinematics of every link and point at the crank angles `phi_deg` (degrees).

    `omega`, `epsilon` override the crank's; omega=1, epsilon=0 gives the analogs
    (d/dphi and d2/dphi2, seed 000's v_q, a_q).
    """
    phi_deg = np.atleast_1d(np.asarray(phi_deg, dtype=float))
    crank = scene.crank
    omega = crank.omega if omega is None else omega
    epsilon = crank.epsilon if epsilon is None else epsilon
    sol = Solution(phi_deg)
    known: dict[str, Motion] = {n: Motion(x, y, 0.0, 0.0, 0.0, 0.0) for n, (x, y) in scene.frame.items()}
    rot: dict[int, Rotation] = {}
    reached = np.ones(phi_deg.shape, dtype=bool)     # positions every earlier group assembled
    scale = crank.length
    with np.errstate(divide="ignore", invalid="ignore"):
        for kind, item in scene.plan:
            if kind == "crank":
                a, rot[1] = crank_motion(crank, scene.frame[crank.pivot], np.radians(phi_deg),
                                         omega, epsilon)
                known[crank.joint] = sol.points[crank.joint] = a
            elif kind == "point":
                p: Point = item
                known[p.name] = sol.points[p.name] = carried_point(
                    known[p.origin], rot[p.link], p.along, p.across)
            else:
                g: Group = item
                la, lb = g.links
                if g.type == "RRR":
                    j, rot[la], rot[lb], disc, det = solve_rrr(
                        known[g.joints[0]], known[g.joints[2]], *g.lengths, g.branch)
                    known[g.joints[1]] = sol.points[g.joints[1]] = j
                elif g.type == "RRP":
                    j, rot[la], rot[lb], sol.slides[g.slider], disc, det = solve_rrp(
                        known[g.joints[0]], g.lengths[0], g.guide_point, g.guide_angle_deg, g.branch)
                    known[g.joints[1]] = sol.points[g.joints[1]] = j
                else:
                    rot[lb], sol.slides[g.slider], disc, det = solve_rpr(
                        known[g.joints[0]], known[g.joints[1]], g.offset, scale)
                    rot[la] = rot[lb]
                fail = reached & ~(disc >= 0)
                sol.failed[g.index] = fail
                sol.det[g.index] = det
                reached &= ~fail
    sol.links = rot
    return sol
