"""One small scene per group kind and per generalisation (guide on a moving link, kulisa
about a moving axis, chains), shared by tests/test_groups.py and the other test files.

CASES: id -> (kind under test, scene text). Every kind in sheetkin.groups.KINDS has at
least one case (test_groups checks it); DYNAMICS adds masses and loads to every case so the
kinetostatics of each kind is checked by the energy balance.
"""
from __future__ import annotations

from pathlib import Path

WORKBOOKS = Path(__file__).resolve().parents[1] / "workbooks"


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
    from sheetkin.scene import override_crank
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
    import sheetkin
    scene = sheetkin.parse_scene(text)
    from sheetkin.scene import link_joints
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


# --------------------------------------------------------------------------- random chains
def random_chains():
    """Hypothesis strategy: a random assemblable four-bar (tests/test_properties.py) extended
    by a random chain of the generalised groups: an RRP on a guide of its rocker (two
    rockers with a slotted pair), an RPR about a point E of the rocker (a kulisa with a
    moving axis), or both with the RRP's guide on that kulisa. Every added group assembles
    over the whole revolution, away from its toggle (|det| >= 0.5). Returns
    (scene text, crank angles, length scale)."""
    import math

    import numpy as np
    from hypothesis import strategies as st

    import sheetkin
    from test_properties import fl, fourbars

    @st.composite
    def build(draw):
        m = draw(fourbars())
        S = m.size
        text = m.toml
        revolution = np.arange(0.0, 360.0, 1.0)
        what = draw(st.sampled_from(["slotted", "moving_axis", "both"]))

        def line_distances(text, through, k, angle_deg, point):
            """|h| of `point` from the line through `through` at phi_k + A, over a revolution."""
            sol = sheetkin.solve(sheetkin.parse_scene(text), revolution)
            g = sol.points.get(through)
            gx, gy = (g.x, g.y) if g is not None else sheetkin.parse_scene(text).frame[through]
            r = sol.links[k]
            th = np.arctan2(r.s, r.c) + math.radians(angle_deg)
            return np.abs(-(point[0] - gx) * np.sin(th) + (point[1] - gy) * np.cos(th))

        def add_rrp(text, links, through, k):
            O = m.frame["O"]
            p = O + S * np.array([draw(st.floats(-2.0, 2.0)), draw(st.floats(-2.0, 2.0))])
            A = draw(st.floats(-90.0, 90.0))
            text = text.replace("[crank]", f"Q{k} = [{fl(p[0])}, {fl(p[1])}]\n\n[crank]", 1)
            h = line_distances(text, through, k, A, p)
            L = float(h.max()) / draw(st.floats(0.1, 0.85)) + 1e-3 * S
            return text + (f'\n[[group]]\ntype = "RRP"\nlinks = [{links[0]}, {links[1]}]\njoints = ["Q{k}", "N{k}"]\n'
                           f"length = {fl(L)}\nguide = {{ through = \"{through}\", angle_deg = {fl(A)}, link = {k} }}\n"
                           f"branch = {draw(st.sampled_from([-1, 1]))}\n")

        def add_rpr(text):
            along, across = S * draw(st.floats(0.2, 1.5)), S * draw(st.floats(-0.5, 0.5))
            text += f'\n[[point]]\nname = "E"\nlink = 3\nfrom = "O1"\nalong = {fl(along)}\nacross = {fl(across)}\n'
            sol = sheetkin.solve(sheetkin.parse_scene(text), revolution)
            d = np.hypot(sol.points["A"].x - sol.points["E"].x, sol.points["A"].y - sol.points["E"].y)
            from hypothesis import assume
            assume(d.min() > 0.05 * S)
            off = draw(st.sampled_from([0.0, 0.3, -0.5])) * float(d.min())
            return text + (f'\n[[group]]\ntype = "RPR"\nlinks = [4, 5]\njoints = ["A", "E"]\noffset = {fl(off)}\n')

        if what == "slotted":
            text = add_rrp(text, (4, 5), "O1", 3)
        elif what == "moving_axis":
            text = add_rpr(text)
        else:
            text = add_rrp(add_rpr(text), (6, 7), "E", 5)
        return text, m.angles, S
    return build()
