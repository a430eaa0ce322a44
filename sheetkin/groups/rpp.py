"""RPP (ВПП): a block hinged at J1 sliding in the slot of a link b that moves straight.

The lecture's "kulisa that moves straight" (seed 003: "Кулисы бывают вращающиеся,
качающиеся, прямолинейно движущиеся"), the Scotch yoke: the block a turns about J1 and
slides in a straight slot of link b; b does not turn and slides along its own guide on the
frame (through G, direction gamma). The slot's direction alpha is absolute (b translates).
K is the point of b where the slot line through J1 crosses b's guide: a point of b, so its
motion is b's motion.

Constraint:  J1 = G + s_K u_g + s_J1 u_s,  u_g = e(gamma), u_s = e(alpha),
two unknowns s_K (K along the guide from G) and s_J1 (J1 along the slot from K). The matrix
[u_g, u_s] is constant, with the determinant sin(alpha - gamma): the rates follow from
v_J1 and a_J1 by the same Cramer's rule (no Coriolis term: nothing turns). Toggle measure:
sin(alpha - gamma), the sine of the angle between slot and guide: free of position and
size, constant over the cycle, zero when the slot is parallel to the guide (no K).
"""
from __future__ import annotations

import numpy as np

from ..solver import Motion, Rotation, Slide, cramer, inverse_det

KIND = "RPP"
LECTURE = "ВПП"


# --------------------------------------------------------------------------- geometry
def toggle(gamma_rad: float, alpha_rad: float) -> float:
    """sin(alpha - gamma): the sine of the angle between the slot and b's guide."""
    return float(np.sin(alpha_rad - gamma_rad))


def solve_rpp(j1: Motion, through, gamma_rad: float, alpha_rad: float):
    """K (on b's guide), the slides s_K and s_J1, the discriminant (negative where the slot
    is parallel to the guide), the toggle measure and the common direction of links a, b."""
    gx, gy, sx, sy = np.cos(gamma_rad), np.sin(gamma_rad), np.cos(alpha_rad), np.sin(alpha_rad)
    det, inv = inverse_det(gx, sx, gy, sy)
    sk, sj = cramer(gx, sx, gy, sy, j1.x - through[0], j1.y - through[1], inv)
    vk, vj = cramer(gx, sx, gy, sy, j1.vx, j1.vy, inv)
    ak, aj = cramer(gx, sx, gy, sy, j1.ax, j1.ay, inv)
    joint = Motion(through[0] + sk * gx, through[1] + sk * gy, vk * gx, vk * gy, ak * gx, ak * gy)
    zero = 0.0 * sk
    slot = Rotation(sx + zero, sy + zero, zero, zero)
    disc = zero + (1.0 if det != 0 else -1.0)
    return joint, Slide(sk, vk, ak), Slide(sj, vj, aj), disc, det + zero, slot


# --------------------------------------------------------------------------- kinetostatics
def reactions(fa, fb, ma_j1, mb_k, j1_minus_k, gamma_rad: float, alpha_rad: float):
    """The group's pair forces from its links' loads (pure arithmetic over arrays).

    fa, fb: resultant loads (x, y) on block a and yoke b; ma_j1: a's moment about J1; mb_k:
    b's moment about K. The yoke acts on the block with P n_s through J1 and a couple C, the
    frame on the yoke with Q n_g through K and a couple Cq; R1 is the force on the block at
    J1. Block: R1 + P n_s + Fa = 0, C + Ma(J1) = 0. Yoke: -P n_s + Q n_g + Fb = 0,
    (J1 - K) x (-P n_s) - C + Cq + Mb(K) = 0. Forces on b: P n_s - Q n_g = Fb (Cramer, the
    determinant sin(gamma - alpha) up to sign).
    Returns R1, (P n_s, C) the yoke on the block, (Q n_g, Cq) the frame on the yoke.
    """
    nsx, nsy = -np.sin(alpha_rad), np.cos(alpha_rad)
    ngx, ngy = -np.sin(gamma_rad), np.cos(gamma_rad)
    _, inv = inverse_det(nsx, -ngx, nsy, -ngy)
    p, q = cramer(nsx, -ngx, nsy, -ngy, fb[0], fb[1], inv)
    c = -ma_j1
    dx, dy = j1_minus_k
    cq = c - mb_k + dx * p * nsy - dy * p * nsx
    r1 = (-p * nsx - fa[0], -p * nsy - fa[1])
    return r1, ((p * nsx, p * nsy), c), ((q * ngx, q * ngy), cq)


# --------------------------------------------------------------------------- loop equations
def loop(lib, j1, through, gamma, alpha):
    """F(q) = G + s_K u_g + s_J1 u_s - J1 = 0 in q = (s_K, s_J1), for any number type
    `lib` (sheetkin.bench). j1: ((x, y), (vx, vy), (ax, ay)); through: (x, y) on the frame;
    gamma, alpha: angles in radians of lib's type. place gives K, the links'
    (alpha, 0, 0) twice and the slides (s_K, ...), (s_J1, ...)."""
    p1, v1, a1 = j1
    ug, us = (lib.cos(gamma), lib.sin(gamma)), (lib.cos(alpha), lib.sin(alpha))

    def F(q):
        return [through[i] + q[0] * ug[i] + q[1] * us[i] - p1[i] for i in (0, 1)]

    def J(q):
        return [[ug[0], us[0]], [ug[1], us[1]]]

    def b_v(q):
        return [v1[0], v1[1]]

    def b_a(q, qt):
        return [a1[0], a1[1]]

    def place(q, qt, qtt):
        k = (tuple(through[i] + q[0] * ug[i] for i in (0, 1)), (qt[0] * ug[0], qt[0] * ug[1]),
             (qtt[0] * ug[0], qtt[0] * ug[1]))
        still = (alpha, lib.num(0), lib.num(0))
        return k, (still, still), ((q[0], qt[0], qtt[0]), (q[1], qt[1], qtt[1]))
    return F, J, b_v, b_a, place
