"""One small scene per group kind and per generalisation (guide on a moving link, kulisa
about a moving axis, chains), shared by tests/groups/test_groups.py and the other test files.

CASES: id -> (kind under test, scene text). Every kind in sheetkin.groups.KINDS has at
least one case (test_groups checks it); DYNAMICS adds masses and loads to every case so the
kinetostatics of each kind is checked by the energy balance.

The checks both the cases (tests/groups/test_groups.py) and the random instances of every kind
and chain (tests/helpers/strategies.py, tests/kinematics/test_properties.py) go through, each kind's next to
the others: check_geometry (kept distances, points on their lines, loop closure, written
out here from the contract), check_loop (the kinds' loop equations and Cramer residuals at
the closed form), check_reference (the mpmath solution), check_derivatives (8th-order
finite differences).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import sheetkin
from sheetkin.groups import kind_of
from sheetkin.studies.bench import FLOAT, reference_mp

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"


def bundled(stem: str) -> str:
    return (WORKBOOKS / f"{stem}.toml").read_text(encoding="utf-8")


def kinematics(stem: str) -> str:
    """A bundled scene without its [[mass]] and [[force]] tables (they come last)."""
    text = bundled(stem)
    cut = min(i for i in (text.find("\n[[mass]]"), text.find("\n[[force]]"), len(text)) if i >= 0)
    return text[:cut] + "\n"


def _crank(text: str, **values) -> str:
    """The scene with some [crank] values replaced (the bundled scenes' epsilon is 0: a
    nonzero one exercises every eps term)."""
    from sheetkin.kinematics.scene import override_crank
    return override_crank(text, "case.toml", **values)[0]


# a guide on the crank itself: the slider N moves in a slot of link 1 through A, at 90 deg
# to the crank, driven by a rocker O2 N (RRP on a moving guide whose link is the driver)
SLOT_ON_CRANK = """\
title = "Rocker with its block in a slot of the crank"
[frame]
O  = [0.0, 0.0]
O2 = [0.3, 0.1]
[crank]
pivot = "O"
joint = "A"
length = 0.1
positions = 13
omega = 6.0
epsilon = -4.0
[[group]]
type   = "RRP"
links  = [2, 3]
joints = ["O2", "N"]
length = 0.5
guide  = { through = "A", angle_deg = 90.0, link = 1 }
branch = 1
[[point]]
name = "S2"
link = 2
from = "O2"
along = 0.12
across = 0.02
"""

# a chain of three groups through a [[point]]: four-bar, a kulisa about the moving point E
# of the rocker, and a slider driven from the kulisa's end F on a fixed, inclined guide
CHAIN = bundled("kulisa_moving_axis") + """
[[group]]
type   = "RRP"
links  = [6, 7]
joints = ["F", "G"]
length = 0.5
guide  = { through = [0.0, 0.35], angle_deg = 10.0 }
branch = 1
"""

CASES = {
    "rrr_fourbar": ("RRR", bundled("fourbar")),
    "rrp_crank_slider": ("RRP", bundled("crank_slider")),
    "rrp_two_rockers": ("RRP", _crank(bundled("two_rockers_slotted"), epsilon=35.0)),
    "rrp_slot_on_crank": ("RRP", SLOT_ON_CRANK),
    "rpr_slotted_lever": ("RPR", bundled("slotted_lever")),
    "rpr_moving_axis": ("RPR", _crank(bundled("kulisa_moving_axis"), epsilon=-20.0)),
    "chain_three_groups": ("RRP", CHAIN),
    # PRP and RPP (branch groups-new): the bundled scenes without their masses and forces
    "prp_slider_on_coupler": ("PRP", _crank(kinematics("slider_on_coupler"), epsilon=25.0)),
    "rpp_scotch_yoke": ("RPP", _crank(kinematics("scotch_yoke"), epsilon=-15.0)),
    "prp_rpp_chain": ("PRP", _crank(kinematics("three_group_chain"), epsilon=12.0)),
}


def _mass(link, m, J, centre) -> str:
    return f'[[mass]]\nlink = {link}\nmass = {float(m)!r}\ninertia = {float(J)!r}\ncentre = "{centre}"\n'


def with_loads(text: str) -> str:
    """The scene with gravity, a mass on every moving link (at one of its joints) and an
    external force and moment on the last link: every reaction then carries load."""
    scene = sheetkin.parse_scene(text)
    from sheetkin.kinematics.scene import link_joints
    on = link_joints(scene.crank, scene.groups)
    for p in scene.points:
        on[p.link].append(p.name)
    extra = ""
    for k in sorted(on):
        extra += _mass(k, 0.5 + 0.7 * k, 0.002 * k, on[k][-1])
    last = max(on)
    extra += f'[[force]]\nlink = {last}\nat = "{on[last][-1]}"\nforce = [-35.0, 12.0]\nmoment = 1.5\n'
    return "gravity = [0.0, -9.81]\n" + text + "\n" + extra


DYNAMICS = {key: (kind, with_loads(text)) for key, (kind, text) in CASES.items()}


# --------------------------------------------------------------------------- checks
def _xy(scene, df, name):
    """A point's positions over the rows of `df` (a frame point's repeated)."""
    if name in scene.frame:
        return np.tile(np.asarray(scene.frame[name], dtype=float)[:, None], len(df))
    return np.vstack([df[f"x_{name}"].to_numpy(), df[f"y_{name}"].to_numpy()])


def _dir(df, k):
    """Link k's direction e(phi_k) over the rows (the frame's: (1, 0))."""
    phi = np.radians(df[f"phi_{k}"].to_numpy()) if k else np.zeros(len(df))
    return np.vstack([np.cos(phi), np.sin(phi)])


def _turn(u, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.vstack([u[0] * c - u[1] * s, u[0] * s + u[1] * c])


def _guide_line(scene, df, gd):
    """A guide's point and unit direction over the rows, from the contract: through a point
    of link k (or a point on the frame) at phi_k + angle_deg."""
    p = _xy(scene, df, gd.through) if gd.moving else np.tile(np.asarray(gd.point, dtype=float)[:, None], len(df))
    return p, _turn(_dir(df, gd.link), gd.angle_deg)


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _rrr(scene, df, g, close):
    j1, n, j2 = (_xy(scene, df, p) for p in g.joints)
    la, lb = g.links
    close(np.hypot(*(n - j1)), g.lengths[0], "|J1 N| = L2")
    close(np.hypot(*(n - j2)), g.lengths[1], "|N J2| = L3")
    close(n, j1 + g.lengths[0] * _dir(df, la), "N = J1 + L2 e(phi_a)")
    close(n, j2 + g.lengths[1] * _dir(df, lb), "N = J2 + L3 e(phi_b)")
    assert np.all(np.sign(_cross(j2 - j1, n - j1)) == g.branch), f"{g.label}: N on the other side of J1 -> J2"


def _rrp(scene, df, g, close):
    j1, n = (_xy(scene, df, p) for p in g.joints)
    p, u = _guide_line(scene, df, g.guide)
    close(np.hypot(*(n - j1)), g.length, "|J1 N| = L")
    close(n, j1 + g.length * _dir(df, g.links[0]), "N = J1 + L e(phi_a)")
    close(_dir(df, g.links[1]), u, "the slider turns with its guide")
    close(n, p + df[f"s_{g.joints[1]}"].to_numpy() * u, "N = G + s_N u: on its guide")
    assert np.all(np.sign(np.sum((n - j1) * u, axis=0)) == g.branch), f"{g.label}: N behind the foot from J1"


def _rpr(scene, df, g, close):
    j1, j2 = (_xy(scene, df, p) for p in g.joints)
    u = _dir(df, g.links[1])
    s = df[f"s_{g.joints[0]}"].to_numpy()
    assert np.all(s > 0), f"{g.label}: s <= 0"
    close(_dir(df, g.links[0]), u, "block and kulisa turn together")
    close(j1 - j2, s * u + g.offset * _turn(u, 90.0), "J1 - J2 = s u + e n: the slot line is e from J2")


def _prp(scene, df, g, close):
    (n,) = g.joints
    nn = _xy(scene, df, n)
    for j, (gd, tag, k) in enumerate(zip(g.guides, (f"s_{n}", f"s2_{n}"), g.links, strict=False)):
        p, u = _guide_line(scene, df, gd)
        close(nn, p + df[tag].to_numpy() * u, f"N = P{j + 1} + {tag} u{j + 1}: on guide {j + 1}")
        close(_dir(df, k), u, f"block {k} turns with guide {j + 1}")


def _rpp(scene, df, g, close):
    j1, k = (_xy(scene, df, p) for p in g.joints)
    p, ug = _guide_line(scene, df, g.guide)
    us = _turn(_dir(df, 0), g.slot_angle_deg)
    close(k, p + df[f"s_{g.joints[1]}"].to_numpy() * ug, "K = G + s_K u_g: on the yoke's guide")
    close(j1, k + df[f"s_{g.joints[0]}"].to_numpy() * us, "J1 = K + s_J1 u_s: in the slot")
    for link in g.links:
        close(_dir(df, link), us, "block and yoke keep the slot's direction")


GEOMETRY = {"RRR": _rrr, "RRP": _rrp, "RPR": _rpr, "PRP": _prp, "RPP": _rpp}


def check_geometry(scene, angles, size=None):
    """Each group's kept distances, points on their lines and its loop closed, and every
    [[point]] at its along/across place, written out from the contract (not the kinds'
    code), at the crank angles."""
    df = sheetkin.compute(scene, at=list(angles))
    size = size or max([1.0] + [abs(c) for p in scene.frame.values() for c in p])
    tol = 1e-12 * size

    for g in scene.groups:
        def close(got, want, what, g=g):
            err = float(np.max(np.abs(np.asarray(got) - np.asarray(want)), initial=0.0))
            assert err <= max(tol, 1e-12), f"{g.label}: {what}: off by {err:.3e}"
        GEOMETRY[g.type](scene, df, g, close)
    c = _xy(scene, df, scene.crank.pivot)
    assert np.allclose(_xy(scene, df, scene.crank.joint), c + scene.crank.length * _dir(df, 1), atol=tol)
    for p in scene.points:
        u = _dir(df, p.link)
        want = _xy(scene, df, p.origin) + p.along * u + p.across * _turn(u, 90.0)
        assert np.allclose(_xy(scene, df, p.name), want, atol=tol), f"point {p.name}"


def _float_known(scene, sol, i):
    """The solver's point motions and link rotations at position i, as the loop equations
    take them (tuples of floats)."""
    known = {n: ((x, y), (0.0, 0.0), (0.0, 0.0)) for n, (x, y) in scene.frame.items()}
    for n, m in sol.points.items():
        f = lambda a: float(np.broadcast_to(a, sol.phi1_deg.shape)[i])
        known[n] = ((f(m.x), f(m.y)), (f(m.vx), f(m.vy)), (f(m.ax), f(m.ay)))
    links = {}
    for k, r in sol.links.items():
        f = lambda a: float(np.broadcast_to(a, sol.phi1_deg.shape)[i])
        links[k] = (math.atan2(f(r.s), f(r.c)), f(r.omega), f(r.eps))
    return known, links


def check_loop(scene, angles, size=None):
    """Each group's loop equations hold at the closed form; their derivatives, solved here
    by numpy, give the closed form's (Cramer's) rates, joints, links and slides."""
    ANGLES = list(angles)
    sol = sheetkin.solve(scene, ANGLES)
    size = size or max([1.0] + [abs(c) for p in scene.frame.values() for c in p])
    w = abs(scene.crank.omega) + 1.0
    for g in scene.groups:
        kind = kind_of(g)
        qa, qb = kind.unknowns(g, sol)
        for i in range(len(ANGLES)):
            known, links = _float_known(scene, sol, i)
            F, J, b_v, b_a, place = kind.loop(FLOAT, g, known, links)
            q = [float(qa[i]), float(qb[i])]
            assert np.max(np.abs(F(q))) <= 1e-13 * size, (g.label, ANGLES[i], F(q))
            # the loop's differentiated equations J q_t = b_v, J q_tt = b_a, solved here by
            # numpy, give the closed form's (Cramer's) rates, joints, links and slides
            qt = np.linalg.solve(J(q), b_v(q))
            qtt = np.linalg.solve(J(q), b_a(q, list(qt)))
            joints, (ra, rb), group_slides = place(q, list(qt), list(qtt))
            tol = dict(rtol=1e-9, atol=1e-10 * size * w * w)
            for name, (p, v, a) in joints.items():
                assert np.allclose([*p, *v, *a], [*known[name][0], *known[name][1], *known[name][2]], **tol), \
                    (g.label, name, ANGLES[i])
            for k, r in zip(g.links, (ra, rb), strict=False):
                assert math.cos(r[0] - links[k][0]) == pytest.approx(1.0, abs=1e-12), (g.label, k)
                assert np.allclose(r[1:], links[k][1:], **tol), (g.label, k, r, links[k])
            for tag, triple in group_slides.items():
                sl = sol.slides[tag]
                assert np.allclose(triple, [sl.s[i], sl.vs[i], sl.as_[i]], **tol), (g.label, tag)


def check_reference(scene, angles, tol=1e-9):
    """The 30-digit mpmath solution of the loop equations equals compute."""
    ref = reference_mp(scene, list(angles), dps=30)
    df = sheetkin.compute(scene, at=list(angles))
    for name, values in ref.items():
        got, want = df[name].to_numpy(), np.array([float(v) for v in values])
        d = np.abs(got - want)
        if name.startswith("phi_"):
            d = np.minimum(d, 360.0 - d)
        assert np.all(d <= tol * np.maximum(1.0, np.abs(want))), (name, got, want)


D1 = (4 / 5, -1 / 5, 4 / 105, -1 / 280)           # 8th-order central differences
D2 = (8 / 5, -1 / 5, 8 / 315, -1 / 560)


def check_derivatives(scene, angles):
    """v = omega dx/dphi, a = omega^2 d2x/dphi2 + eps dx/dphi (positions do not depend on the
    crank's rates); 8th-order differences at h = 1e-3 rad are good to ~1e-12."""
    w, eps = scene.crank.omega, scene.crank.epsilon
    h = 1e-3
    phis = np.array(angles)
    frames = {o: sheetkin.compute(scene, at=list(phis + math.degrees(o * h))) for o in range(-4, 5)}
    names = [c for c in sheetkin.column_names(scene) if c.split("_")[0] in ("x", "y", "s", "phi") and c != "phi_1"]
    size = max(1.0, max(float(frames[0][c].abs().max()) for c in names if not c.startswith("phi")))
    for col in names:
        head, tail = col.split("_", 1)
        f = {o: fr[col].to_numpy() for o, fr in frames.items()}
        if head == "phi":                 # radians, unwrapped about the centre
            f = {o: np.radians(f[0]) + np.radians((v - f[0] + 180.0) % 360.0 - 180.0) for o, v in f.items()}
        d1 = sum(c * (f[k + 1] - f[-k - 1]) for k, c in enumerate(D1)) / h
        d2 = sum(c * (f[k + 1] + f[-k - 1] - 2 * f[0]) for k, c in enumerate(D2)) / (h * h)
        vel = {"x": "vx", "y": "vy", "s": "vs", "phi": "omega"}[head] + "_" + tail
        acc = {"x": "ax", "y": "ay", "s": "as", "phi": "eps"}[head] + "_" + tail
        v, a = frames[0][vel].to_numpy(), frames[0][acc].to_numpy()
        assert np.max(np.abs(v - w * d1)) <= 1e-8 * size * (abs(w) + 1), (col, v, w * d1)
        assert np.max(np.abs(a - (w * w * d2 + eps * d1))) <= 1e-5 * size * (w * w + abs(eps) + 1), \
            (col, a, w * w * d2 + eps * d1)


