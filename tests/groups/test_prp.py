"""PRP (two blocks hinged at N, each on its own guide): the closed form and its rates
against independent checks: N on both lines, 8th-order finite differences in time, a
50-digit mpmath solution (lu_solve for positions, mpmath.diff for rates), the Cramer
residuals, the lecture's form (7), and the kinetostatics' power balance."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sheetkin.groups import prp
from sheetkin.groups.motion import Motion, Rotation

# 8th-order central differences: weights for f' and f'' on offsets -4..4
D1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
D2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])


def trajectory(lib, t, c):
    """A guide's through point circling (radius r, rate w, phase p, centre x0, y0) and its
    direction theta0 + om t + ep t^2 / 2: position, velocity, acceleration exactly."""
    x0, y0, r, w, p, th0, om, ep = c
    a = w * t + p
    pt = ((x0 + r * lib.cos(a), y0 + r * lib.sin(a)), (-r * w * lib.sin(a), r * w * lib.cos(a)),
          (-r * w * w * lib.cos(a), -r * w * w * lib.sin(a)))
    return pt, (th0 + om * t + ep * t * t / 2, om + ep * t, ep)


def as_float(t, c):
    (p, v, a), (th, om, ep) = trajectory(math, t, c)
    return Motion(p[0], p[1], v[0], v[1], a[0], a[1]), Rotation(math.cos(th), math.sin(th), om, ep)


guide = st.tuples(*[st.floats(-2, 2)] * 2, st.floats(0, 1), st.floats(-3, 3), st.floats(0, 6.3),
                  st.floats(0, 6.3), st.floats(-3, 3), st.floats(-5, 5))


def crossing(ca, cb, t=0.0):
    pa, ga = as_float(t, ca)
    pb, gb = as_float(t, cb)
    return prp.solve_prp(pa, ga, pb, gb), (pa, ga, pb, gb)


def far_from_parallel(ca, cb, t=0.0):
    return abs(math.sin(ca[5] + ca[6] * t + ca[7] * t * t / 2 - cb[5] - cb[6] * t - cb[7] * t * t / 2)) > 0.2


@settings(max_examples=200, deadline=None)
@given(guide, guide)
def test_prp_joint_lies_on_both_guides(ca, cb):
    if not far_from_parallel(ca, cb):
        return
    (n, sa, sb, disc, sine), (pa, ga, pb, gb) = crossing(ca, cb)
    for p, g, s in ((pa, ga, sa), (pb, gb, sb)):
        scale = 1 + abs(s.s)
        # N - P is along u (cross product 0) and its projection is the slide
        assert abs((n.x - p.x) * g.s - (n.y - p.y) * g.c) < 1e-12 * scale
        assert abs((n.x - p.x) * g.c + (n.y - p.y) * g.s - s.s) < 1e-12 * scale
    assert disc > 0
    assert sine == pytest.approx(math.sin(math.atan2(gb.s, gb.c) - math.atan2(ga.s, ga.c)), abs=1e-12)


@settings(max_examples=100, deadline=None)
@given(guide, guide)
def test_prp_rates_equal_eighth_order_differences_of_positions(ca, cb):
    if not far_from_parallel(ca, cb):
        return
    h = 1e-3
    ts = h * np.arange(-4, 5)
    if not all(far_from_parallel(ca, cb, t) for t in ts):
        return
    sols = [crossing(ca, cb, t)[0] for t in ts]
    (n, sa, sb, _, _) = sols[4]
    for get, v, a in ((lambda r: r[0].x, n.vx, n.ax), (lambda r: r[0].y, n.vy, n.ay),
                      (lambda r: r[1].s, sa.vs, sa.as_), (lambda r: r[2].s, sb.vs, sb.as_)):
        f = np.array([get(r) for r in sols])
        scale = 1 + abs(v) + abs(a) + np.abs(f).max()
        assert D1 @ f / h == pytest.approx(v, abs=1e-7 * scale)
        assert D2 @ f / h ** 2 == pytest.approx(a, abs=2e-4 * scale)


def mp_solution(ca, cb, t):
    """N and the slides by mpmath at 50 digits: lu_solve of the two line equations in
    normal form (not Cramer), the rates by mpmath.diff of those positions."""
    with mpmath.workdps(50):
        mca, mcb = [mpmath.mpf(x) for x in ca], [mpmath.mpf(x) for x in cb]

        def positions(tt):
            (pa, _, _), (ta, _, _) = trajectory(mpmath, tt, mca)
            (pb, _, _), (tb, _, _) = trajectory(mpmath, tt, mcb)
            # n . X = n . P for each line, n the line's normal
            m = mpmath.matrix([[-mpmath.sin(ta), mpmath.cos(ta)], [-mpmath.sin(tb), mpmath.cos(tb)]])
            rhs = mpmath.matrix([-mpmath.sin(ta) * pa[0] + mpmath.cos(ta) * pa[1],
                                 -mpmath.sin(tb) * pb[0] + mpmath.cos(tb) * pb[1]])
            x = mpmath.lu_solve(m, rhs)
            s1 = (x[0] - pa[0]) * mpmath.cos(ta) + (x[1] - pa[1]) * mpmath.sin(ta)
            s2 = (x[0] - pb[0]) * mpmath.cos(tb) + (x[1] - pb[1]) * mpmath.sin(tb)
            return [x[0], x[1], s1, s2]

        t = mpmath.mpf(t)
        return [[float(mpmath.diff(lambda tt, i=i: positions(tt)[i], t, k)) for i in range(4)]
                for k in (0, 1, 2)]


@pytest.mark.parametrize("ca, cb", [
    ((0.1, -0.2, 0.3, 2.0, 0.4, 0.3, 1.5, -2.0), (0.5, 0.7, 0.2, -1.0, 1.0, 1.9, -0.5, 3.0)),
    # a vertical guide: the lecture's tg would be infinite
    ((0.0, 0.0, 0.14, 20.0, 0.0, 0.0, 2.0, 0.0), (0.4, 0.0, 0.0, 0.0, 0.0, math.pi / 2, 0.0, 0.0)),
    ((1.0, 1.0, 0.5, 3.0, 2.0, 2.5, 0.0, 1.0), (-1.0, 0.5, 0.5, -2.0, 0.0, 0.1, 4.0, 0.0)),
])
def test_prp_agrees_with_a_50_digit_mpmath_solution(ca, cb):
    (n, sa, sb, _, _), _ = crossing(ca, cb, 0.1)
    ref = mp_solution(ca, cb, 0.1)
    got = [[n.x, n.y, sa.s, sb.s], [n.vx, n.vy, sa.vs, sb.vs], [n.ax, n.ay, sa.as_, sb.as_]]
    for k in range(3):
        scale = 1 + max(abs(v) for v in ref[k])
        assert np.allclose(got[k], ref[k], rtol=0, atol=1e-11 * scale), (k, got[k], ref[k])


@settings(max_examples=100, deadline=None)
@given(guide, guide)
def test_prp_cramer_residuals_vanish_from_both_sides(ca, cb):
    """N's velocity and acceleration (built from guide a's side) equal those from guide b's
    side, P_b + s2 u_b differentiated: the Cramer solution satisfies both equations."""
    if not far_from_parallel(ca, cb):
        return
    (n, sa, sb, _, _), (pa, ga, pb, gb) = crossing(ca, cb)
    nbx, nby = -gb.s, gb.c
    vx = pb.vx + sb.vs * gb.c + sb.s * gb.omega * nbx
    vy = pb.vy + sb.vs * gb.s + sb.s * gb.omega * nby
    t = 2 * sb.vs * gb.omega + sb.s * gb.eps
    r = sb.s * gb.omega ** 2
    ax = pb.ax + sb.as_ * gb.c + t * nbx - r * gb.c
    ay = pb.ay + sb.as_ * gb.s + t * nby - r * gb.s
    scale = 1 + abs(n.vx) + abs(n.vy) + abs(n.ax) + abs(n.ay)
    assert abs(vx - n.vx) + abs(vy - n.vy) < 1e-11 * scale
    assert abs(ax - n.ax) + abs(ay - n.ay) < 1e-10 * scale


@settings(max_examples=100, deadline=None)
@given(guide, guide)
def test_prp_lecture_form_seven_gives_the_same_crossing(ca, cb):
    if not far_from_parallel(ca, cb):
        return
    (n, _, _, _, _), (pa, ga, pb, gb) = crossing(ca, cb)
    # line (2) is guide a (the coupler, through A = P_a), line (1) guide b (m' = m cos theta)
    eta, theta = math.atan2(ga.s, ga.c), math.atan2(gb.s, gb.c)
    m_cos = pb.y * math.cos(theta) - pb.x * math.sin(theta)
    _, xl, yl = prp.lecture_intersection(pa.x, pa.y, eta, m_cos, theta)
    scale = 1 + abs(n.x) + abs(n.y)
    assert abs(xl - n.x) + abs(yl - n.y) < 1e-11 * scale


def test_prp_toggle_measure_is_free_of_position_and_size():
    ca = (0.1, -0.2, 0.3, 2.0, 0.4, 0.3, 1.5, -2.0)
    cb = (0.5, 0.7, 0.2, -1.0, 1.0, 1.9, -0.5, 3.0)
    (_, _, _, _, base), _ = crossing(ca, cb)
    for k, dx, dy in ((3.0, 0.0, 0.0), (0.01, 5.0, -7.0)):
        moved = [(k * c[0] + dx, k * c[1] + dy, k * c[2]) + tuple(c[3:]) for c in (ca, cb)]
        (_, _, _, _, sine), _ = crossing(*moved)
        assert sine == pytest.approx(base, abs=1e-14)


def test_prp_parallel_guides_cannot_assemble():
    z = np.zeros(1)
    pa, ga = Motion(z, z, z, z, z, z), Rotation(z + 1.0, z, z, z)
    pb, gb = Motion(z, z + 1, z, z, z, z), Rotation(z - 1.0, z, z, z)
    with np.errstate(divide="ignore", invalid="ignore"):
        *_, disc, sine = prp.solve_prp(pa, ga, pb, gb)
    assert disc[0] < 0 and sine[0] == 0


@settings(max_examples=100, deadline=None)
@given(guide, guide, st.tuples(*[st.floats(-10, 10)] * 6))
def test_prp_kinetostatics_balances_power_through_ideal_sliding_pairs(ca, cb, loads):
    """With the reactions, the loads' power on the two blocks equals the power the group
    passes to the links carrying the guides (no work in the ideal sliding pairs)."""
    if not far_from_parallel(ca, cb):
        return
    (n, sa, sb, _, _), (pa, ga, pb, gb) = crossing(ca, cb)
    fax, fay, fbx, fby, ma, mb = loads
    (qa, ca_), (qb, cb_), x = prp.reaction_forces((fax, fay), (fbx, fby), ma, mb, ga, gb)
    # equilibrium of each block (forces): Qa n_a + X + Fa = 0, Qb n_b - X + Fb = 0
    assert abs(qa[0] + x[0] + fax) + abs(qa[1] + x[1] + fay) < 1e-9 * (1 + sum(map(abs, loads)))
    assert abs(qb[0] - x[0] + fbx) + abs(qb[1] - x[1] + fby) < 1e-9 * (1 + sum(map(abs, loads)))
    # power: loads on the blocks (moving with N and turning with their guides) ...
    p_loads = fax * n.vx + fay * n.vy + ma * ga.omega + fbx * n.vx + fby * n.vy + mb * gb.omega
    # ... and the reactions on the carriers at the carriers' points coincident with N
    p_carriers = 0.0
    for p, g, (q, c) in ((pa, ga, (qa, ca_)), (pb, gb, (qb, cb_))):
        vcx, vcy = p.vx - g.omega * (n.y - p.y), p.vy + g.omega * (n.x - p.x)
        p_carriers += -(q[0] * vcx + q[1] * vcy) - c * g.omega
    scale = (1 + sum(map(abs, loads))) * (1 + abs(n.vx) + abs(n.vy) + abs(ga.omega) + abs(gb.omega))
    assert p_loads == pytest.approx(p_carriers, abs=1e-9 * scale)


def test_prp_loop_equations_hold_at_the_closed_form_answer():
    from sheetkin.studies.bench import FLOAT
    ca = (0.1, -0.2, 0.3, 2.0, 0.4, 0.3, 1.5, -2.0)
    cb = (0.5, 0.7, 0.2, -1.0, 1.0, 1.9, -0.5, 3.0)
    (n, sa, sb, _, _), _ = crossing(ca, cb)
    F, J, b_v, b_a, place = prp.loop_lines(FLOAT, *trajectory(math, 0.0, ca), *trajectory(math, 0.0, cb))
    q, qt, qtt = [sa.s, sb.s], [sa.vs, sb.vs], [sa.as_, sb.as_]
    assert max(map(abs, F(q))) < 1e-14
    assert np.allclose(np.array(J(q)) @ qt, b_v(q), atol=1e-12)
    assert np.allclose(np.array(J(q)) @ qtt, b_a(q, qt), atol=1e-10)
    joint, _, _ = place(q, qt, qtt)
    assert np.allclose(sum(joint, ()), [n.x, n.y, n.vx, n.vy, n.ax, n.ay], atol=1e-12)
