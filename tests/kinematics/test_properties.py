"""Property-based tests of sheetkin's kinematics over random assemblable mechanisms.

Every kind and chains of kinds (test_every_kind_and_chain_of_kinds): tests/helpers/strategies.py
draws random assemblable instances of each of the five kinds (RRR, RRP, RPR, PRP, RPP), of
four-bars extended by guides on moving links and kulisas about moving axes, and of chains of
two or three groups of any kinds; each goes through tests/helpers/kinds.py's checks: kept
distances, points on their lines and loop closure written out from the contract, the
kinds' loop equations and Cramer residuals, the 30-digit mpmath solution, and 8th-order
finite differences of the positions.

In more depth, three families of one-dyad mechanisms (tests/helpers/strategies.py) are fed through
the public API (`parse_scene`, `compute`):

  * crank + RRR dyad (four-bar), built from a prescribed transmission-angle range so that it
    assembles over the whole revolution and stays away from toggle;
  * crank + RRP dyad (crank-slider) on an offset, inclined guide, the coupler long enough
    that it assembles everywhere;
  * crank + RPR dyad (slotted lever), with and without a slot offset.

For each, at random crank angles we check
  (a) the geometry the scene asks for (hinge distances, slider on its guide, slot offset,
      branch side, points at their along/across places, output names and order),
  (b) the vector loop-closure equation with the reported angles and slides,
  (c) velocities and accelerations against 8th-order central finite differences of the
      solver's own positions (resp. velocities) in the crank angle,
  (d) the analog identities v = vq*omega, a = aq*omega^2 + vq*epsilon,
  (e) an independent Newton solve of the loop equations (numpy only, started off the
      solver's answer), whose rates come from the differentiated loop equations.
Plus two example tests: the crank's epsilon is honoured exactly, and a near-toggle
crank-rocker is flagged in `near_toggle`.

Tolerances are relative to a length scale of the mechanism (its largest length or
coordinate) or, for rates, to that scale times omega (or omega^2 + |epsilon|), whichever is
larger than the quantity itself.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from helpers.kinds import check_derivatives, check_geometry, check_loop, check_reference
from helpers.strategies import (
    KINDS,
    MECHANISMS,
    STRATEGIES,
    Mechanism,
    angle_diff,
    contract_columns,
    cross,
    e,
    e_perp,
    signs,
)
from hypothesis import given, note, settings
from hypothesis import strategies as st

import sheetkin

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"

# database=None: no .hypothesis/ directory is written next to the sources.
PROPERTY = settings(max_examples=75, deadline=None, database=None)

POSITION_TOL = 1e-12      # (a), (b): relative to the mechanism's size
FD_TOL = 1e-7             # (c): finite differences are good to ~1e-11; this leaves room
ANALOG_TOL = 1e-10        # (d): the identities hold to rounding
NEWTON_POS_TOL = 1e-10    # (e) positions
NEWTON_RATE_TOL = 1e-9    # (e) velocities and accelerations


# --------------------------------------------------------------------------- assertions
def assert_abs(got, expected, atol, what):
    """max |got - expected| <= atol."""
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    err = float(np.max(np.abs(got - expected), initial=0.0))
    assert np.all(np.isfinite(got)), f"{what}: non-finite value {got}"
    assert err <= atol, f"{what}: off by {err:.3e} (allowed {atol:.3e}); got {got}, expected {expected}"


def assert_close(got, expected, rel, char_scale, what):
    """max |got - expected| <= rel * max(char_scale, max |expected|)."""
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    scale = max(char_scale, float(np.max(np.abs(expected), initial=0.0)))
    err = float(np.max(np.abs(got - expected), initial=0.0))
    assert np.all(np.isfinite(got)), f"{what}: non-finite value {got}"
    assert err <= rel * scale, (f"{what}: off by {err:.3e} = {err / scale:.3e} of its scale "
                                f"{scale:.3e} (allowed {rel:g}); got {got}, expected {expected}")


def draw_mechanism(data, kind) -> Mechanism:
    m = data.draw(MECHANISMS[kind], label="mechanism")
    note(f"scene:\n{m.toml}\ncrank angles: {m.angles}")
    return m


# --------------------------------------------------------------------------- (a) + (b)
def row_vectors(df, i, name):
    r = df.iloc[i]
    return np.array([r[f"x_{name}"], r[f"y_{name}"]])


def link_angle(df, i, k):
    return math.radians(df.iloc[i][f"phi_{k}"])


@pytest.mark.parametrize("kind", KINDS)
@PROPERTY
@given(data=st.data())
def test_geometry_and_loop_closure(kind, data):
    """(a) + (b): the reported configuration is the one the scene describes."""
    m = draw_mechanism(data, kind)
    df = sheetkin.compute(m.scene(), at=m.angles)
    tol = POSITION_TOL * m.size

    # output names in the spec's order (extra columns may follow)
    cols = contract_columns(m)
    assert list(df.columns[:len(cols)]) == cols
    assert len(df) == len(m.angles)
    assert_close(df["phi_1"], m.angles, 1e-15, 360.0, "phi_1 echoes the requested angles")
    for k in (2, 3):
        # the spec: [0, 360) (test_link_angle_just_below_zero_reads_0 pins the edge)
        assert ((df[f"phi_{k}"] >= 0.0) & (df[f"phi_{k}"] < 360.0)).all(), f"phi_{k} outside [0, 360)"

    O = m.frame["O"]
    for i, phi1_deg in enumerate(m.angles):
        phi1, phi2, phi3 = math.radians(phi1_deg), link_angle(df, i, 2), link_angle(df, i, 3)
        A = row_vectors(df, i, "A")
        assert_abs(np.linalg.norm(A - O), m.L1, tol, "|A - O| = L1")
        assert_abs(A, O + m.L1 * e(phi1), tol, "A = O + L1 e(phi_1)")
        g = m.group
        if m.kind == "RRR":
            O1, B = m.frame["O1"], row_vectors(df, i, "B")
            assert_abs(np.linalg.norm(B - A), g["L2"], tol, "|B - A| = L2")
            assert_abs(np.linalg.norm(B - O1), g["L3"], tol, "|B - O1| = L3")
            assert_abs(B, A + g["L2"] * e(phi2), tol, "phi_2 is the direction A -> B")
            assert_abs(B, O1 + g["L3"] * e(phi3), tol, "phi_3 is the direction O1 -> B")
            loop = O + m.L1 * e(phi1) + g["L2"] * e(phi2) - g["L3"] * e(phi3) - O1
            assert_abs(loop, [0.0, 0.0], tol, "loop O + L1 e1 + L2 e2 - L3 e3 - O1 = 0")
            # branch +1: B to the left of the directed line A -> O1
            assert np.sign(cross(O1 - A, B - A)) == g["branch"], "B on the wrong side of A -> O1"
        elif m.kind == "RRP":
            G, gam = g["G"], math.radians(g["gamma_deg"])
            u, N, s = e(gam), row_vectors(df, i, "B"), df.iloc[i]["s_B"]
            assert_abs(np.linalg.norm(N - A), g["L"], tol, "|N - A| = L")
            assert_abs(cross(u, N - G), 0.0, tol, "N on the guide line")
            assert_abs(s, np.dot(N - G, u), tol, "s_N = (N - G) . u")
            assert_abs(N, A + g["L"] * e(phi2), tol, "phi_2 is the direction A -> N")
            assert_abs(angle_diff(phi3, gam), 0.0, 1e-13, "phi_3 is the guide angle")
            assert_abs([df.iloc[i]["omega_3"], df.iloc[i]["eps_3"]], [0.0, 0.0], 0.0,
                         "the slider does not turn")
            loop = O + m.L1 * e(phi1) + g["L"] * e(phi2) - G - s * u
            assert_abs(loop, [0.0, 0.0], tol, "loop A + L e2 - G - s u = 0")
            # branch +1: N ahead of the foot of the perpendicular from A (in the guide's direction)
            assert np.sign(np.dot(N - A, u)) == g["branch"], "N on the wrong side of the foot"
        else:
            O1, e_off, s = m.frame["O1"], g["offset"], df.iloc[i]["s_A"]
            u, n = e(phi3), e_perp(phi3)
            assert_abs(angle_diff(phi2, phi3), 0.0, 1e-13, "block and lever turn together")
            # J1 lies on the slot line; that line passes `offset` from J2. The spec gives no
            # sign convention; the loop below uses J1 - J2 = s u + offset n (n = u + 90 deg).
            assert_abs(abs(cross(u, A - O1)), abs(e_off), tol, "slot line is `offset` from O1")
            assert_abs(s, np.dot(A - O1, u), tol, "s_A is the along-slot coordinate")
            assert s > 0, "s_A is a distance from J2 along the slot (J2 -> J1)"
            loop = O + m.L1 * e(phi1) - O1 - s * u - e_off * n
            assert_abs(loop, [0.0, 0.0], tol, "loop A - O1 - s u - offset n = 0")

        for p in m.points:
            phi = link_angle(df, i, p.link)
            origin = m.frame["O1"] if p.origin == "O1" else row_vectors(df, i, p.origin)
            assert_abs(row_vectors(df, i, p.name),
                       origin + p.along * e(phi) + p.across * e_perp(phi), tol,
                         f"{p.name} at along/across from {p.origin} on link {p.link}")

    # magnitudes, relative to the mechanism's velocity / acceleration scale (a 1e-183 m/s
    # velocity may legitimately come out as 0 if the norm is taken without hypot)
    for name in ["A"] + m.new_joints + [p.name for p in m.points]:
        assert_close(df[f"v_{name}"], np.hypot(df[f"vx_{name}"], df[f"vy_{name}"]), 1e-14,
                     m.size * m.omega_scale, f"v_{name} = |(vx, vy)|")
        assert_close(df[f"a_{name}"], np.hypot(df[f"ax_{name}"], df[f"ay_{name}"]), 1e-14,
                     m.size * m.eps_scale, f"a_{name} = |(ax, ay)|")


# --------------------------------------------------------------------------- (c)
# 8th-order central difference of the first derivative, offsets -4..4 steps; with a step of
# 1e-3 rad the truncation error is ~h^8 (negligible) and rounding ~1e-16 / h ~ 1e-13.
FD8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
FD_STEP = 1e-3
RATE_OF = {"x": "vx", "y": "vy", "phi": "omega", "s": "vs"}
ACCEL_OF = {"vx": "ax", "vy": "ay", "omega": "eps", "vs": "as"}


def stencil(angles_deg):
    offsets = np.degrees(FD_STEP * np.arange(-4, 5))
    return (np.asarray(angles_deg, dtype=float)[:, None] + offsets[None, :]).ravel()


def d_dphi(df, column, n):
    """d column / d phi_1 at each stencil centre (phi_1 in radians)."""
    values = df[column].to_numpy().reshape(n, 9)
    if column.startswith("phi_"):
        values = np.unwrap(np.radians(values), axis=1)   # 359.99 -> 360.01 is a small step
    return values @ FD8 / FD_STEP


@pytest.mark.parametrize("kind", KINDS)
@PROPERTY
@given(data=st.data())
def test_rates_match_finite_differences(kind, data):
    """(c): v = X'(phi_1) omega and a = X''(phi_1) omega^2 + X'(phi_1) epsilon, with X' from
    the solver's positions and X'' omega from its velocities (dv/dphi_1 = X'' omega)."""
    m = draw_mechanism(data, kind)
    n = len(m.angles)
    df = sheetkin.compute(m.scene(), at=stencil(m.angles))
    centre = df.iloc[4::9]
    w, eps = m.omega, m.epsilon
    checked = 0
    for col in contract_columns(m):
        head, subject = col.split("_", 1)
        if head not in RATE_OF or col == "phi_1":
            continue
        angular = head == "phi"
        length = 1.0 if angular else m.size
        vel_col = f"{RATE_OF[head]}_{subject}"
        acc_col = f"{ACCEL_OF[RATE_OF[head]]}_{subject}"
        dx = d_dphi(df, col, n)
        assert_close(centre[vel_col], dx * w, FD_TOL, length * abs(w), f"{vel_col} vs d{col}/dt")
        dv = d_dphi(df, vel_col, n)
        assert_close(centre[acc_col], dv * w + dx * eps, FD_TOL, length * m.eps_scale,
                     f"{acc_col} vs d{vel_col}/dt")
        checked += 1
    # x, y of A, B (if any), P2, P3; phi_2, phi_3; the slide (if any)
    assert checked == 2 * (1 + len(m.new_joints) + len(m.points)) + 2 + len(m.sliders)


# --------------------------------------------------------------------------- (d)
ANALOG_OF = {"vx": "vqx", "vy": "vqy", "v": "vq", "ax": "aqx", "ay": "aqy", "a": "aq",
             "omega": "omegaq", "eps": "epsq", "vs": "vqs", "as": "aqs"}
FIRST_ORDER_OF = {"ax": "vx", "ay": "vy", "eps": "omega", "as": "vs"}


@pytest.mark.parametrize("kind", KINDS)
@PROPERTY
@given(data=st.data())
def test_analog_identities(kind, data):
    """(d): the analogs are d/dphi and d2/dphi2: v = vq omega, a = aq omega^2 + vq epsilon."""
    m = draw_mechanism(data, kind)
    df = sheetkin.compute(m.scene(), at=m.angles, analogs=True)
    w, eps = m.omega, m.epsilon
    for col in contract_columns(m):
        head, subject = col.split("_", 1)
        if head not in ANALOG_OF:
            continue
        q = lambda h, subject=subject: df[f"{ANALOG_OF[h]}_{subject}"].to_numpy()      # noqa: E731
        length = 1.0 if head in ("omega", "eps") else m.size
        if head in ("vx", "vy", "omega", "vs"):
            assert_close(df[col], q(head) * w, ANALOG_TOL, length * abs(w), f"{col} = {ANALOG_OF[head]} omega")
        elif head in FIRST_ORDER_OF:
            first = FIRST_ORDER_OF[head]
            assert_close(df[col], q(head) * w * w + q(first) * eps, ANALOG_TOL, length * m.eps_scale,
                         f"{col} = {ANALOG_OF[head]} omega^2 + {ANALOG_OF[first]} epsilon")
        elif head == "v":       # magnitudes: |vq omega| = vq |omega|
            assert_close(df[col], q("v") * abs(w), ANALOG_TOL, length * abs(w), f"{col} = vq |omega|")
            assert_close(q("v"), np.hypot(q("vx"), q("vy")), 1e-14, length, f"vq_{subject} magnitude")
        else:                   # "a"
            assert_close(q("a"), np.hypot(q("ax"), q("ay")), 1e-14, length, f"aq_{subject} magnitude")


# --------------------------------------------------------------------------- (e)
def newton(residual, jacobian, q0, size):
    """Plain Newton iteration on a 2x2 system; asserts that it converged."""
    q = np.array(q0, dtype=float)
    for _ in range(40):
        q = q + np.linalg.solve(jacobian(q), -residual(q))
    res = np.linalg.norm(residual(q))
    assert np.isfinite(res) and res <= 1e-13 * size, f"Newton did not converge: |F| = {res:.3e}"
    return q


def carried(origin, phi, w, eps, along, across):
    """A point fixed on a rigid link turning at (phi, w, eps): r = along e + across e_perp,
    dr/dt = w dr/dphi, d2r/dt2 = eps dr/dphi - w^2 r."""
    pos, vel, acc = origin
    r = along * e(phi) + across * e_perp(phi)
    dr = along * e_perp(phi) - across * e(phi)
    return pos + r, vel + w * dr, acc + eps * dr - w * w * r


def reference(m: Mechanism, phi1_deg: float, guess) -> dict:
    """Independent kinematics at one crank angle.

    Positions: Newton on the vector loop equation F(q, phi_1) = 0 (two scalar equations,
    two unknowns q), as the seeds' Mathcad Given-Find blocks do. Rates: differentiating
    F = 0 in time gives J qdot = -F_t and J qddot = -(terms quadratic in the rates), J = dF/dq.
    Returns {"links": {k: (phi, omega, eps)}, "points": {name: (pos, vel, acc)},
    "slides": {name: (s, vs, as)}}.
    """
    phi1, w, eps = math.radians(phi1_deg), m.omega, m.epsilon
    O, L1, g = m.frame["O"], m.L1, m.group
    A = O + L1 * e(phi1)
    vA = L1 * w * e_perp(phi1)
    aA = L1 * (eps * e_perp(phi1) - w * w * e(phi1))
    points = {"A": (A, vA, aA), "O1": (m.frame.get("O1"), np.zeros(2), np.zeros(2))}
    slides = {}

    if m.kind == "RRR":
        # F = A + L2 e(phi2) - L3 e(phi3) - O1, q = (phi2, phi3)
        L2, L3, O1 = g["L2"], g["L3"], m.frame["O1"]
        F = lambda q: A + L2 * e(q[0]) - L3 * e(q[1]) - O1                       # noqa: E731
        J = lambda q: np.column_stack([L2 * e_perp(q[0]), -L3 * e_perp(q[1])])   # noqa: E731
        p2, p3 = newton(F, J, guess, m.size)
        Jq = J((p2, p3))
        w2, w3 = np.linalg.solve(Jq, -vA)
        # d2F/dt2 = aA + L2 (eps2 e_perp2 - w2^2 e2) - L3 (eps3 e_perp3 - w3^2 e3)
        e2, e3 = np.linalg.solve(Jq, -(aA - L2 * w2 * w2 * e(p2) + L3 * w3 * w3 * e(p3)))
        links = {2: (p2, w2, e2), 3: (p3, w3, e3)}
        points["B"] = (O1 + L3 * e(p3), L3 * w3 * e_perp(p3),
                       L3 * (e3 * e_perp(p3) - w3 * w3 * e(p3)))
    elif m.kind == "RRP":
        # F = A + L e(phi2) - G - s u, q = (phi2, s)
        L, G, gam = g["L"], g["G"], math.radians(g["gamma_deg"])
        u = e(gam)
        F = lambda q: A + L * e(q[0]) - G - q[1] * u                   # noqa: E731
        J = lambda q: np.column_stack([L * e_perp(q[0]), -u])          # noqa: E731
        p2, s = newton(F, J, guess, m.size)
        Jq = J((p2, s))
        w2, vs = np.linalg.solve(Jq, -vA)
        e2, as_ = np.linalg.solve(Jq, -(aA - L * w2 * w2 * e(p2)))
        links = {2: (p2, w2, e2), 3: (gam, 0.0, 0.0)}
        points["B"] = (G + s * u, vs * u, as_ * u)
        slides["B"] = (s, vs, as_)
    else:
        # F = A - O1 - s u(th) - off n(th), q = (th, s); d(s u + off n)/dth = s n - off u
        off, O1 = g["offset"], m.frame["O1"]
        F = lambda q: A - O1 - q[1] * e(q[0]) - off * e_perp(q[0])                      # noqa: E731
        J = lambda q: np.column_stack([-(q[1] * e_perp(q[0]) - off * e(q[0])), -e(q[0])])  # noqa: E731
        th, s = newton(F, J, guess, m.size)
        Jq, u, n = J((th, s)), e(th), e_perp(th)
        w3, vs = np.linalg.solve(Jq, -vA)
        # d2(s u + off n)/dt2 = as u + eps3 (s n - off u) + 2 vs w3 n - s w3^2 u - off w3^2 n
        e3, as_ = np.linalg.solve(Jq, -(aA - 2 * vs * w3 * n + s * w3 * w3 * u + off * w3 * w3 * n))
        links = {2: (th, w3, e3), 3: (th, w3, e3)}
        slides["A"] = (s, vs, as_)

    for p in m.points:
        points[p.name] = carried(points[p.origin], *links[p.link], p.along, p.across)
    return {"links": links, "points": points, "slides": slides}


@pytest.mark.parametrize("kind", KINDS)
@PROPERTY
@given(data=st.data())
def test_independent_newton_solve_agrees(kind, data):
    """(e): an independent Newton solve, started ~0.05 rad / 5 % off the solver's answer,
    lands on the solver's configuration, and its rates match the solver's."""
    m = draw_mechanism(data, kind)
    kick = data.draw(st.tuples(signs, signs), label="perturbation signs")
    df = sheetkin.compute(m.scene(), at=m.angles)
    v_char, a_char = m.size * m.omega_scale, m.size * m.eps_scale
    for i, phi1_deg in enumerate(m.angles):
        row = df.iloc[i]
        if m.kind == "RRR":
            guess = (math.radians(row["phi_2"]) + 0.05 * kick[0], math.radians(row["phi_3"]) + 0.05 * kick[1])
        elif m.kind == "RRP":
            # 5 % of the coupler length, not of s: s may be ~0 when N passes the `through` point
            guess = (math.radians(row["phi_2"]) + 0.05 * kick[0], row["s_B"] + 0.05 * kick[1] * m.group["L"])
        else:
            guess = (math.radians(row["phi_3"]) + 0.05 * kick[0], row["s_A"] * (1 + 0.05 * kick[1]))
        ref = reference(m, phi1_deg, guess)
        at = f"at phi_1 = {phi1_deg!r}"
        for k, (phi, w, eps) in ref["links"].items():
            assert_abs(angle_diff(math.radians(row[f"phi_{k}"]), phi), 0.0, NEWTON_POS_TOL, f"phi_{k} {at}")
            assert_close(row[f"omega_{k}"], w, NEWTON_RATE_TOL, m.omega_scale, f"omega_{k} {at}")
            assert_close(row[f"eps_{k}"], eps, NEWTON_RATE_TOL, m.eps_scale, f"eps_{k} {at}")
        for name in ["A"] + m.new_joints + [p.name for p in m.points]:
            pos, vel, acc = ref["points"][name]
            assert_abs([row[f"x_{name}"], row[f"y_{name}"]], pos, NEWTON_POS_TOL * m.size, f"{name} {at}")
            assert_close([row[f"vx_{name}"], row[f"vy_{name}"]], vel, NEWTON_RATE_TOL, v_char, f"v_{name} {at}")
            assert_close([row[f"ax_{name}"], row[f"ay_{name}"]], acc, NEWTON_RATE_TOL, a_char, f"a_{name} {at}")
        for name, (s, vs, as_) in ref["slides"].items():
            assert_abs(row[f"s_{name}"], s, NEWTON_POS_TOL * m.size, f"s_{name} {at}")
            assert_close(row[f"vs_{name}"], vs, NEWTON_RATE_TOL, v_char, f"vs_{name} {at}")
            assert_close(row[f"as_{name}"], as_, NEWTON_RATE_TOL, a_char, f"as_{name} {at}")


# --------------------------------------------------------------------------- examples
@pytest.mark.parametrize("workbook", ["fourbar.toml", "slotted_lever.toml", "shaper.toml"])
def test_crank_epsilon_is_honoured(workbook):
    """Only the accelerations depend on the crank's epsilon, and linearly: going from
    epsilon = 0 to 5 adds exactly 5 * (first-order analog) to every acceleration."""
    text = (WORKBOOKS / workbook).read_text(encoding="utf-8")
    text0, count = re.subn(r"^epsilon\s*=.*$", "epsilon = 0.0", text, flags=re.M)
    assert count == 1, "the workbook's [crank] epsilon line was not found"
    text5 = text0.replace("epsilon = 0.0", "epsilon = 5.0")
    df0 = sheetkin.compute(sheetkin.parse_scene(text0, workbook), analogs=True)
    df5 = sheetkin.compute(sheetkin.parse_scene(text5, workbook), analogs=True)
    heads = {c.split("_", 1)[0] for c in df0.columns}
    assert heads >= {"ax", "ay", "eps"}
    changed = 0
    for col in df0.columns:
        head, _, subject = col.partition("_")
        if head in FIRST_ORDER_OF:
            first = f"{FIRST_ORDER_OF[head]}_{subject}"
            diff = df5[col].to_numpy() - df0[col].to_numpy()
            scale = max(1.0, float(np.max(np.abs(df0[col]))))
            assert_close(diff, 5.0 * df0[f"{ANALOG_OF[FIRST_ORDER_OF[head]]}_{subject}"], 1e-12, scale,
                         f"{col}(eps=5) - {col}(eps=0) = 5 * analog of {first}")
            changed += np.any(np.abs(diff) > 1e-9 * scale)
        elif head in ("x", "y", "phi", "s", "vx", "vy", "omega", "vs"):
            assert_close(df5[col], df0[col], 1e-14, 1.0, f"{col} does not depend on epsilon")
    assert changed > 0, "epsilon changed no acceleration at all"


def test_near_toggle_is_flagged():
    """A crank-rocker whose transmission angle drops to 0.3 deg (sin = 0.0052 < 0.01) is
    flagged there, and not where the transmission angle is 100 deg.

    Built as in `fourbars`: mu in [0.3, 100] deg; the smallest diagonal |A O1| = D - L1,
    hence the smallest mu, occurs with A on the segment O -> O1 (phi_1 = 270 deg here).
    """
    L2, L3, mu_min, mu_max = 0.5, 0.34, 0.3, 100.0

    def diagonal(mu_deg):
        return math.sqrt(L2 * L2 + L3 * L3 - 2.0 * L2 * L3 * math.cos(math.radians(mu_deg)))

    D, L1 = 0.5 * (diagonal(mu_min) + diagonal(mu_max)), 0.5 * (diagonal(mu_max) - diagonal(mu_min))
    m = Mechanism("RRR", {"O": np.array([0.0, 0.0]), "O1": np.array([0.0, -D])}, L1, 20.0, 3.0,
                  {"L2": L2, "L3": L3, "branch": -1}, [], [], D)
    df = sheetkin.compute(m.scene(), at=[270.0, 90.0, 0.0])
    assert df["near_toggle"].tolist()[:2] == ["1", ""]
    # |det| of the RRR Jacobian [L2 e_perp2, -L3 e_perp3] / (L2 L3) is sin(mu)
    assert_close(abs(df["det_g1"].iloc[0]), math.sin(math.radians(mu_min)), 1e-9, 0, "|det_g1| at toggle")
    assert_close(abs(df["det_g1"].iloc[1]), math.sin(math.radians(mu_max)), 1e-9, 0, "|det_g1| at mu_max")
    phi2, phi3 = np.radians(df["phi_2"]), np.radians(df["phi_3"])
    assert_close(np.abs(df["det_g1"]), np.abs(np.sin(phi3 - phi2)), 1e-12, 0, "|det_g1| = |sin mu|")


def test_link_angle_just_below_zero_reads_0():
    """The spec: phi_k in [0, 360). A guide at 360 deg is the guide at 0 deg."""
    text = "\n".join([
        '[frame]', 'O = [0.0, 0.0]',
        '[crank]', 'pivot = "O"', 'joint = "A"', 'length = 0.1', 'omega = 10.0',
        '[[group]]', 'type = "RRP"', 'links = [2, 3]', 'joints = ["A", "B"]', 'length = 0.3',
        'guide = { through = [0.0, -0.05], angle_deg = 360.0 }', 'branch = 1', ''])
    phi3 = sheetkin.compute(sheetkin.parse_scene(text, "<guide at 360>"), at=[30.0])["phi_3"].iloc[0]
    assert 0.0 <= phi3 < 360.0, f"phi_3 = {phi3!r}"
    assert_abs(angle_diff(math.radians(phi3), 0.0), 0.0, 1e-13, "phi_3 is the guide angle")


# --------------------------------------------------------------------------- every kind, chains
@pytest.mark.parametrize("name", list(STRATEGIES))
@settings(max_examples=25, deadline=None, database=None)
@given(data=st.data())
def test_every_kind_and_chain_of_kinds(name, data):
    """Random assemblable instances of each kind and chains of kinds (tests/helpers/strategies.py)
    against tests/helpers/kinds.py's independent checks."""
    text, angles, size = data.draw(STRATEGIES[name], label="mechanism")
    note(f"scene:\n{text}\ncrank angles: {angles}")
    scene = sheetkin.parse_scene(text, f"<random {name}>")
    check_geometry(scene, angles, size)
    check_loop(scene, angles, size=size)
    check_reference(scene, angles, tol=1e-8)
    check_derivatives(scene, angles)


def test_every_kind_has_a_strategy():
    """Adding a kind adds its random instances (README, "Adding a group")."""
    from sheetkin.groups import KINDS as REGISTRY
    assert set(REGISTRY) <= set(STRATEGIES)
