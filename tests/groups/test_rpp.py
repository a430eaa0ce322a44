"""RPP (block on J1 in the slot of a kulisa that moves straight, the Scotch yoke): the
closed form against independent checks: J1 back from K + s_J1 u_s, 8th-order finite
differences in time, a 50-digit mpmath solution, and the kinetostatics' power balance."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sheetkin.groups import rpp
from sheetkin.groups.motion import Motion

D1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
D2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])


def j1_path(lib, t, c):
    """J1 on a crank: centre (x0, y0), radius r, phase p + w t + e t^2 / 2."""
    x0, y0, r, p, w, e = c
    a, at, att = p + w * t + e * t * t / 2, w + e * t, e
    ca, sa = lib.cos(a), lib.sin(a)
    return ((x0 + r * ca, y0 + r * sa), (-r * at * sa, r * at * ca),
            (-r * att * sa - r * at * at * ca, r * att * ca - r * at * at * sa))


def as_motion(t, c):
    p, v, a = j1_path(math, t, c)
    return Motion(p[0], p[1], v[0], v[1], a[0], a[1])


crank = st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(0.01, 1), st.floats(0, 6.3),
                  st.floats(-20, 20), st.floats(-50, 50))
yoke = st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(-3.2, 3.2), st.floats(-3.2, 3.2))


def usable(y):
    return abs(math.sin(y[3] - y[2])) > 0.2


@settings(max_examples=200, deadline=None)
@given(crank, yoke)
def test_rpp_block_lies_on_the_slot_through_k_and_k_on_the_guide(c, y):
    if not usable(y):
        return
    j1 = as_motion(0.0, c)
    k, sk, sj, disc, sine, slot = rpp.solve_rpp(j1, y[:2], y[2], y[3])
    assert abs(k.x + sj.s * slot.c - j1.x) + abs(k.y + sj.s * slot.s - j1.y) < 1e-12 * (1 + abs(sj.s))
    assert abs(-(k.x - y[0]) * math.sin(y[2]) + (k.y - y[1]) * math.cos(y[2])) < 1e-12 * (1 + abs(sk.s))
    residual = abs(k.vx + sj.vs * slot.c - j1.vx) + abs(k.vy + sj.vs * slot.s - j1.vy)
    assert residual < 1e-11 * (1 + abs(j1.vx) + abs(j1.vy))
    assert disc > 0 and sine == pytest.approx(math.sin(y[3] - y[2]), abs=1e-15)


@settings(max_examples=100, deadline=None)
@given(crank, yoke)
def test_rpp_rates_equal_eighth_order_differences_of_positions(c, y):
    if not usable(y):
        return
    h = 1e-3
    sols = [rpp.solve_rpp(as_motion(t, c), y[:2], y[2], y[3]) for t in h * np.arange(-4, 5)]
    k, sk, sj = sols[4][:3]
    for get, v, a in ((lambda r: r[0].x, k.vx, k.ax), (lambda r: r[0].y, k.vy, k.ay),
                      (lambda r: r[1].s, sk.vs, sk.as_), (lambda r: r[2].s, sj.vs, sj.as_)):
        f = np.array([get(r) for r in sols])
        scale = 1 + abs(v) + abs(a) + np.abs(f).max()
        assert D1 @ f / h == pytest.approx(v, abs=1e-7 * scale)
        assert D2 @ f / h ** 2 == pytest.approx(a, abs=1e-3 * scale)


@pytest.mark.parametrize("c, y", [((0.0, 0.0, 0.1, 0.3, 10.0, 5.0), (0.3, 0.0, 0.0, math.pi / 2)),
                                  ((0.2, -0.1, 0.5, 2.0, -3.0, 0.0), (1.0, 1.0, 0.4, 2.0))])
def test_rpp_agrees_with_a_50_digit_mpmath_solution(c, y):
    """mpmath: J1 - G projected on the dual basis (lu_solve), rates by mpmath.diff."""
    with mpmath.workdps(50):
        mc, my = [mpmath.mpf(v) for v in c], [mpmath.mpf(v) for v in y]

        def pos(t):
            p = j1_path(mpmath, t, mc)[0]
            m = mpmath.matrix([[mpmath.cos(my[2]), mpmath.cos(my[3])], [mpmath.sin(my[2]), mpmath.sin(my[3])]])
            x = mpmath.lu_solve(m, mpmath.matrix([p[0] - my[0], p[1] - my[1]]))
            return [x[0], x[1]]
        t0 = mpmath.mpf("0.05")
        ref = [[float(mpmath.diff(lambda t, i=i: pos(t)[i], t0, d)) for i in (0, 1)] for d in (0, 1, 2)]
    _, sk, sj, *_ = rpp.solve_rpp(as_motion(0.05, c), y[:2], y[2], y[3])
    got = [[sk.s, sj.s], [sk.vs, sj.vs], [sk.as_, sj.as_]]
    for d in range(3):
        assert np.allclose(got[d], ref[d], rtol=0, atol=1e-11 * (1 + max(map(abs, ref[d]))))


@settings(max_examples=100, deadline=None)
@given(crank, yoke, st.tuples(*[st.floats(-10, 10)] * 6))
def test_rpp_kinetostatics_balances_power(c, y, loads):
    """Loads on the block (at J1) and the yoke (at K): their power equals the power the pin
    at J1 takes from the block's driver (the yoke's guide is fixed, its couple does no work)."""
    if not usable(y):
        return
    j1 = as_motion(0.0, c)
    k, sk, sj, *_ = rpp.solve_rpp(j1, y[:2], y[2], y[3])
    fax, fay, fbx, fby, ma, mb = loads
    r1, (p, cc), (q, cq) = rpp.reaction_forces((fax, fay), (fbx, fby), ma, mb, (j1.x - k.x, j1.y - k.y), y[2], y[3])
    scale = 1 + sum(map(abs, loads))
    # the yoke's equilibrium: -P n_s + Q n_g + Fb = 0 and the moments about K
    assert abs(-p[0] + q[0] + fbx) + abs(-p[1] + q[1] + fby) < 1e-9 * scale * (1 + abs(1 / math.sin(y[3] - y[2])))
    mom = (j1.x - k.x) * (-p[1]) - (j1.y - k.y) * (-p[0]) - cc + cq + mb
    assert abs(mom) < 1e-9 * scale * (1 + abs(sj.s)) * (1 + abs(1 / math.sin(y[3] - y[2])))
    # power: nothing turns; the loads move with J1 (block) and K (yoke)
    p_loads = fax * j1.vx + fay * j1.vy + fbx * k.vx + fby * k.vy
    p_pin = -(r1[0] * j1.vx + r1[1] * j1.vy)     # what the group passes back to the crank
    assert p_loads == pytest.approx(p_pin,
                                    abs=1e-9 * scale * (1 + abs(j1.vx) + abs(j1.vy)) / abs(math.sin(y[3] - y[2])))


def test_rpp_toggle_measure_is_constant_and_free_of_size():
    a = rpp.solve_rpp(as_motion(0.0, (0, 0, 0.1, 0.3, 10, 0)), (0.3, 0.0), 0.2, 1.7)[4]
    b = rpp.solve_rpp(as_motion(0.0, (5, 5, 3.0, 1.0, 10, 0)), (9.0, -4.0), 0.2, 1.7)[4]
    assert a == pytest.approx(b, abs=1e-15) == pytest.approx(math.sin(1.5), abs=1e-15)


def test_rpp_loop_equations_hold_at_the_closed_form_answer():
    from sheetkin.studies.bench import FLOAT
    c, y = (0.2, -0.1, 0.5, 2.0, -3.0, 1.0), (1.0, 1.0, 0.4, 2.0)
    k, sk, sj, *_ = rpp.solve_rpp(as_motion(0.0, c), y[:2], y[2], y[3])
    F, J, b_v, b_a, place = rpp.loop_lines(FLOAT, j1_path(math, 0.0, c), y[:2], y[2], y[3])
    q, qt, qtt = [sk.s, sj.s], [sk.vs, sj.vs], [sk.as_, sj.as_]
    assert max(map(abs, F(q))) < 1e-14
    assert np.allclose(np.array(J(q)) @ qt, b_v(q), atol=1e-12)
    assert np.allclose(np.array(J(q)) @ qtt, b_a(q, qt), atol=1e-10)
    joint, _, _ = place(q, qt, qtt)
    assert np.allclose(sum(joint, ()), [k.x, k.y, k.vx, k.vy, k.ax, k.ay], atol=1e-12)
