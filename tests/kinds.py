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
