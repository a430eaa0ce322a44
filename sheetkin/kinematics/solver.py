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
from typing import cast

import numpy as np

from sheetkin.groups import kind_of
from sheetkin.groups.motion import (
    FRAME,
    Motion,
    Rotation,
    Slide,
    Values,
    carried_point,
    fixed,
)

from .scene import Crank, Group, Point, Scene


@dataclass
class Solution:
    phi1_deg: np.ndarray
    points: dict[str, Motion] = field(default_factory=dict)
    links: dict[int, Rotation] = field(default_factory=dict)
    slides: dict[str, Slide] = field(default_factory=dict)
    det: dict[int, Values] = field(default_factory=dict)          # group index -> toggle measure
    failed: dict[int, np.ndarray] = field(default_factory=dict)   # group index -> cannot assemble


def crank_motion(crank: Crank, pivot, phi, omega, eps) -> tuple[Motion, Rotation]:
    """Crank OA (lecture slide 6): x_t = -phi_t y, y_t = phi_t x, x_tt = -phi_tt y - phi_t y_t."""
    c, s = np.cos(phi), np.sin(phi)
    rx, ry = crank.length * c, crank.length * s
    vx, vy = -omega * ry, omega * rx
    # omega and eps stay scalars: the crank's rates are given, the same at every position
    return (Motion(pivot[0] + rx, pivot[1] + ry, vx, vy, -eps * ry - omega * vy, eps * rx + omega * vx),
            Rotation(c, s, omega, eps))


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
    known: dict[str, Motion] = {n: fixed(x, y) for n, (x, y) in scene.frame.items()}
    rot: dict[int, Rotation] = {0: FRAME}
    reached = np.ones(phi_deg.shape, dtype=bool)     # positions every earlier group assembled
    scale = crank.length
    with np.errstate(divide="ignore", invalid="ignore"):
        for kind, item in scene.plan:
            if kind == "crank":
                a, rot[1] = crank_motion(crank, scene.frame[crank.pivot], np.radians(phi_deg),
                                         omega, epsilon)
                known[crank.joint] = sol.points[crank.joint] = a
            elif kind == "point":
                p = cast(Point, item)
                known[p.name] = sol.points[p.name] = carried_point(
                    known[p.origin], rot[p.link], p.along, p.across)
            else:
                g = cast(Group, item)
                gm = kind_of(g).solve(g, known, rot, scale)
                for name, m in gm.joints.items():
                    known[name] = sol.points[name] = m
                rot.update(gm.links)
                sol.slides.update(gm.slides)
                fail = reached & ~(gm.disc > 0)     # 0: a dead point (groups.motion.DEAD_POINT)
                sol.failed[g.index] = fail
                sol.det[g.index] = gm.toggle
                reached &= ~fail
    rot.pop(0)
    sol.links = rot
    return sol
