"""PRP (ПВП): two blocks hinged together at N, each sliding on its own guide.

The lecture's "slider on the coupler with a fixed guide" (seed 003, "КУЛИСНАЯ ПАРА С
ПОЛЗУШКОЙ НА ШАТУНЕ И ФИКСИРОВАННОЙ НАПРАВЛЯЮЩЕЙ", equations (1)-(7)): N is the point L
where two straight lines cross, line (1) y = m + x tg(theta) (the fixed guide) and line (2)
y = n + x tg(eta) (the coupler AB, tg(eta) by (4), n by (3a)); x_L, y_L by (7).
A guide may sit on the frame or on a moving link k (a kulisa): it passes through a point P
of link k and its direction is phi_k + A.

Constraint (the vector form of (5a), (5b)):  N = P_a + s1 u_a = P_b + s2 u_b,
two unknowns s1 = s_N (along guides[0]) and s2 = s2_N (along guides[1]); the 2x2 matrix
[u_a, -u_b] has the determinant -sin(theta_b - theta_a), so Cramer's rule gives s1, s2 and,
differentiated once and twice in time, the relative velocities and accelerations:
    u_a vs1 - u_b vs2 = v_Pb - v_Pa - s1 w_a n_a + s2 w_b n_b,
    u_a as1 - u_b as2 = a_Pb - a_Pa - (2 vs1 w_a + s1 e_a) n_a + s1 w_a^2 u_a
                                    + (2 vs2 w_b + s2 e_b) n_b - s2 w_b^2 u_b,
with n = u turned +90 deg and (w, e) the rates of the link carrying the guide (2 vs w n is
the Coriolis term). Toggle measure: sin(theta_b - theta_a), the sine of the angle between
the two lines: free of position and size; zero when the guides are parallel (no N).

The functions below take and return plain numbers or numpy arrays (vectorised over crank
positions); `through` is a point with x, y, vx, vy, ax, ay and `guide` a direction with
c, s, omega, eps (the solver's Motion and Rotation).
"""
from __future__ import annotations

import numpy as np

from ..solver import Motion, Rotation, Slide, cramer, inverse_det

KIND = "PRP"
LECTURE = "ПВП"


# --------------------------------------------------------------------------- geometry
def guide_direction(carrier: Rotation, angle_rad: float) -> Rotation:
    """A guide fixed on a link that turns as `carrier`: direction phi_k + A, same rates."""
    ca, sa = np.cos(angle_rad), np.sin(angle_rad)
    return Rotation(carrier.c * ca - carrier.s * sa, carrier.s * ca + carrier.c * sa,
                    carrier.omega, carrier.eps)


def frame_direction(angle_rad: float) -> Rotation:
    """A guide on the frame: the absolute angle A, no rates."""
    return Rotation(np.cos(angle_rad), np.sin(angle_rad), 0.0, 0.0)


def toggle(ga: Rotation, gb: Rotation):
    """sin(theta_b - theta_a): the sine of the angle between the two guides (scale-free)."""
    return ga.c * gb.s - ga.s * gb.c


def intersection(pa: Motion, ga: Rotation, pb: Motion, gb: Rotation):
    """s1, s2 with P_a + s1 u_a = P_b + s2 u_b (Cramer's rule); inf/NaN for parallel guides."""
    m11, m12, m21, m22 = ga.c, -gb.c, ga.s, -gb.s
    _, inv = inverse_det(m11, m12, m21, m22)
    return cramer(m11, m12, m21, m22, pb.x - pa.x, pb.y - pa.y, inv)


def solve_prp(pa: Motion, ga: Rotation, pb: Motion, gb: Rotation):
    """N, the two slides (s_N along guide a, s2_N along guide b), the discriminant
    (negative where the guides are parallel) and the toggle measure sin(theta_b - theta_a)."""
    m11, m12, m21, m22 = ga.c, -gb.c, ga.s, -gb.s
    det, inv = inverse_det(m11, m12, m21, m22)
    s1, s2 = cramer(m11, m12, m21, m22, pb.x - pa.x, pb.y - pa.y, inv)
    nax, nay, nbx, nby = -ga.s, ga.c, -gb.s, gb.c
    wa, ea, wb, eb = ga.omega, ga.eps, gb.omega, gb.eps
    # velocities: the guides' turning moves the crossing point along the other line
    b1 = pb.vx - pa.vx - s1 * wa * nax + s2 * wb * nbx
    b2 = pb.vy - pa.vy - s1 * wa * nay + s2 * wb * nby
    vs1, vs2 = cramer(m11, m12, m21, m22, b1, b2, inv)
    # accelerations: same matrix; Coriolis 2 vs w n, tangential s e n, centripetal -s w^2 u
    ta, tb = 2.0 * vs1 * wa + s1 * ea, 2.0 * vs2 * wb + s2 * eb
    ra, rb = s1 * wa * wa, s2 * wb * wb
    b1 = pb.ax - pa.ax - ta * nax + ra * ga.c + tb * nbx - rb * gb.c
    b2 = pb.ay - pa.ay - ta * nay + ra * ga.s + tb * nby - rb * gb.s
    as1, as2 = cramer(m11, m12, m21, m22, b1, b2, inv)
    joint = Motion(pa.x + s1 * ga.c, pa.y + s1 * ga.s,
                   pa.vx + vs1 * ga.c + s1 * wa * nax, pa.vy + vs1 * ga.s + s1 * wa * nay,
                   pa.ax + as1 * ga.c + ta * nax - ra * ga.c, pa.ay + as1 * ga.s + ta * nay - ra * ga.s)
    sine = -det + np.zeros(np.shape(s1))
    disc = np.where(sine != 0, sine * sine, -1.0)
    return joint, Slide(s1, vs1, as1), Slide(s2, vs2, as2), disc, sine


# --------------------------------------------------------------------------- the lecture's form
def lecture_intersection(xa, ya, eta, m_cos, theta):
    """x_L, y_L by the lecture's (3a), (7), multiplied through by cos(theta) cos(eta).

    The lecture writes line (2) through A as y = n + x tg(eta) with n = y_A - x_A tg(eta)
    (3a), line (1) as y = m + x tg(theta), and x_L = (n - m)/(tg theta - tg eta),
    y_L = (n tg theta - m tg eta)/(tg theta - tg eta) (7). A vertical line makes tg
    infinite; with n' = n cos(eta) = y_A cos(eta) - x_A sin(eta) and m' = m cos(theta)
    (the lines' signed distances from the origin) the same formulas read
        x_L = (n' cos theta - m' cos eta) / sin(theta - eta),
        y_L = (n' sin theta - m' sin eta) / sin(theta - eta),
    finite for every pair of non-parallel lines. Returns (n', x_L, y_L).
    """
    n_cos = ya * np.cos(eta) - xa * np.sin(eta)
    d = np.sin(theta - eta)
    return n_cos, (n_cos * np.cos(theta) - m_cos * np.cos(eta)) / d, \
        (n_cos * np.sin(theta) - m_cos * np.sin(eta)) / d


# --------------------------------------------------------------------------- kinetostatics
def reactions(fa, fb, ma_n, mb_n, ga: Rotation, gb: Rotation):
    """The group's pair forces from its links' loads (pure arithmetic over arrays).

    fa, fb: resultant loads (x, y) on blocks a and b; ma_n, mb_n: their moments about N.
    Guide k_a acts on block a with Qa n_a through N and a couple Ca; guide k_b on block b
    with Qb n_b and Cb; block b on block a with X at N. Block a: Qa n_a + X + Fa = 0,
    Ca + Ma(N) = 0; block b: Qb n_b - X + Fb = 0, Cb + Mb(N) = 0. The sum gives
    Qa n_a + Qb n_b = -(Fa + Fb): Cramer with the determinant sin(theta_b - theta_a),
    zero (no answer) exactly where the kinematics has its toggle.
    Returns (Qa n_a, Ca), (Qb n_b, Cb), X: forces as (x, y) pairs.
    """
    nax, nay, nbx, nby = -ga.s, ga.c, -gb.s, gb.c
    _, inv = inverse_det(nax, nbx, nay, nby)
    qa, qb = cramer(nax, nbx, nay, nby, -(fa[0] + fb[0]), -(fa[1] + fb[1]), inv)
    xx, xy = -qa * nax - fa[0], -qa * nay - fa[1]
    return ((qa * nax, qa * nay), -ma_n), ((qb * nbx, qb * nby), -mb_n), (xx, xy)


# --------------------------------------------------------------------------- loop equations
def loop(lib, pa, guide_a, pb, guide_b):
    """The loop-closure equation F(q) = P_a + s1 u_a - P_b - s2 u_b = 0 in q = (s1, s2),
    for any number type `lib` (mpmath or float, sheetkin.bench). pa, pb: ((x, y), (vx, vy),
    (ax, ay)); guide_*: (theta, omega, eps) of the guide's direction.
    Returns F, J, b_v, b_a, place as bench's loops do; place gives N, the two links'
    (theta, omega, eps) and the two slides (s, vs, as)."""
    (p1, v1, a1), (p2, v2, a2) = pa, pb
    (ta, wa, ea), (tb, wb, eb) = guide_a, guide_b
    ua, ub = (lib.cos(ta), lib.sin(ta)), (lib.cos(tb), lib.sin(tb))
    na, nb = (-ua[1], ua[0]), (-ub[1], ub[0])

    def F(q):
        return [p1[i] + q[0] * ua[i] - p2[i] - q[1] * ub[i] for i in (0, 1)]

    def J(q):
        return [[ua[0], -ub[0]], [ua[1], -ub[1]]]

    def b_v(q):
        return [v2[i] - v1[i] - q[0] * wa * na[i] + q[1] * wb * nb[i] for i in (0, 1)]

    def b_a(q, qt):
        return [a2[i] - a1[i] - (2 * qt[0] * wa + q[0] * ea) * na[i] + q[0] * wa * wa * ua[i]
                + (2 * qt[1] * wb + q[1] * eb) * nb[i] - q[1] * wb * wb * ub[i] for i in (0, 1)]

    def place(q, qt, qtt):
        pos = tuple(p1[i] + q[0] * ua[i] for i in (0, 1))
        vel = tuple(v1[i] + qt[0] * ua[i] + q[0] * wa * na[i] for i in (0, 1))
        acc = tuple(a1[i] + qtt[0] * ua[i] + (2 * qt[0] * wa + q[0] * ea) * na[i]
                    - q[0] * wa * wa * ua[i] for i in (0, 1))
        slides = ((q[0], qt[0], qtt[0]), (q[1], qt[1], qtt[1]))
        return (pos, vel, acc), (guide_a, guide_b), slides
    return F, J, b_v, b_a, place
