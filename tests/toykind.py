"""A toy sixth group kind, kept outside sheetkin: one module and one `register` line
(tests/groups/test_toy_kind.py). docs/adding-a-kind.md walks through it.

"TOY": a coupler J1 N of length L and a slider N on a straight line of the frame, given
as `line = [x, y, angle_deg]`. The mechanism is RRP's on a fixed guide, so its answers can
be checked against RRP's; what differs is everything a stage could have hard-coded: the
scene keys, the input rows (`lx_g<i>`, `ly_g<i>`, `tilt_g<i>`), the rows' names and texts.
Its kinetostatics and loop equations are RRP's (its Params have RRP's fields: length,
guide, branch), the arithmetic of solve is rrp.solve_rrp.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from sheetkin.groups import rrp
from sheetkin.groups.group import Group, Guide
from sheetkin.groups.motion import GroupMotion, Motion, Rotation, fixed
from sheetkin.groups.parts import BlockPart, Parts, scene_guide
from sheetkin.groups.rows import (
    Builder,
    InputRow,
    cos_sin_rows,
    cramer_rows,
    det_row,
    distance_check,
    group_guard,
    motion_rows,
    residual,
)

# --------------------------------------------------------------------------- what it is
KIND = "TOY"
LECTURE = "ВВП*"
SLIDES = "13-15"
TITLE = ("шатун и ползун на прямой стойки (пример нового вида группы)",
         "coupler and slider on a line of the frame (an example of a new group kind)")
KEYS = ("type", "links", "joints", "length", "line", "branch")


# --------------------------------------------------------------------------- scene keys
@dataclass(frozen=True)
class Params:
    length: float
    guide: Guide            # the line, on the frame
    branch: int


def parse(tbl, frame) -> tuple[tuple[str, ...], Params]:
    joints = tbl.array("joints", 2, "name")
    x, y, angle = tbl.array("line", 3, "number")
    branch = tbl.get("branch", "an integer")
    if branch not in (1, -1):
        tbl.fail("branch", f"expected +1 or -1, got {branch}")
    return joints, Params(tbl.positive("length"), Guide(None, (x, y), angle), branch)


def needs(g: Group) -> list[str]:
    return [g.joints[0]]


def on_links(g: Group) -> list[tuple[str, str, int]]:
    return []


def new_joints(g: Group) -> list[str]:
    return [g.joints[1]]


def carries(g: Group) -> dict[int, list[str]]:
    (j1, n), (a, b) = g.joints, g.links
    return {a: [j1, n], b: [n]}


def sliders(g: Group) -> list[str]:
    return [g.joints[1]]


def fourbar(g: Group, crank_joint: str, frame) -> None:
    return None


def parts(g: Group) -> Parts:
    (j1, n), (a, b), i = g.joints, g.links, g.index
    line = scene_guide(g.guide, n, i, f"tilt_g{i}", (f"lx_g{i}", f"ly_g{i}"))
    return Parts({a: (j1, n), b: (n,)}, (line,), (BlockPart(b, n, line),))


# --------------------------------------------------------------------------- positions and rates
def solve(g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion:
    (j1, n), (a, b) = g.joints, g.links
    t = np.radians(g.guide.angle_deg)
    u = Rotation(np.cos(t), np.sin(t), 0.0, 0.0)
    joint, ra, slide, disc, toggle = rrp.solve_rrp(known[j1], g.length, fixed(*g.guide.point), u, g.branch)
    zero = np.zeros_like(slide.s)
    return GroupMotion({n: joint}, {a: ra, b: Rotation(u.c + zero, u.s + zero, zero, zero)}, {n: slide},
                       disc, toggle)


# --------------------------------------------------------------------------- the workbook
def input_rows(g: Group) -> list[InputRow]:
    i, la, (x, y) = g.index, g.links[0], g.guide.point
    return [InputRow(f"L{la}", "m", f"длина шатуна {la}", f"length of coupler {la}", g.length, True),
            InputRow(f"lx_g{i}", "m", "прямая: x точки", "the line: x of a point", x),
            InputRow(f"ly_g{i}", "m", "прямая: y точки", "the line: y of a point", y),
            InputRow(f"tilt_g{i}", "deg", "наклон прямой", "the line's tilt", g.guide.angle_deg),
            InputRow(f"branch_g{i}", "", "ветвь (+1 или -1)", "branch (+1 or -1)", g.branch)]


def with_inputs(g: Group, num) -> Group:
    i = g.index
    guide = Guide(None, (num(f"lx_g{i}", g.guide.point[0]), num(f"ly_g{i}", g.guide.point[1])),
                  num(f"tilt_g{i}", g.guide.angle_deg))
    return dataclasses.replace(g, params=Params(num(f"L{g.links[0]}", g.length), guide,
                                                int(num(f"branch_g{i}", g.branch, choices=(1, -1)))))


def rows(b: Builder, g: Group) -> None:
    """J1 + L e(phi) = P + s u: h, J1's distance from the line, then s = foot +- sqrt(L^2 - h^2)."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    L, X, Y, T = f"{{L{la}}}", f"{{lx_g{i}}}", f"{{ly_g{i}}}", f"RADIANS({{tilt_g{i}}})"
    xj, yj = b.p("x", J1), b.p("y", J1)
    b.section(f"group_{i}", f"Группа {i} (игрушечная {J1}{N})", f"Group {i} (toy {J1}{N})")
    h, foot, D = f"h_g{i}", f"foot_g{i}", f"D_g{i}"
    b.add(h, "m", "h", f"distance of {J1} from the line", "calc", f"-({xj}-{X})*SIN({T})+({yj}-{Y})*COS({T})")
    b.add(foot, "m", "foot", f"{J1}'s foot on the line", "calc", f"({xj}-{X})*COS({T})+({yj}-{Y})*SIN({T})")
    b.add(D, "m^2", "L^2 - h^2", "discriminant L^2 - h^2", "calc", f"{L}^2-{{{h}}}^2")
    group_guard(b, g, D, f"{L}^2")    # the size of the discriminant's terms (the dead-point rule), as RRP
    b.section(f"accepted_g{i}", "Принятые значения", "Accepted values")
    S = f"{{s_{N}}}"
    b.add(f"s_{N}", "m", "s", f"travel of slider {N}", "accepted", f"{{{foot}}}+{{branch_g{i}}}*SQRT({{{D}}})")
    b.add(f"phi_{la}", "deg", "phi", f"angle of coupler {la}", "accepted",
          f"MOD(DEGREES(ATAN2({X}+{S}*COS({T})-{xj},{Y}+{S}*SIN({T})-{yj})),360)")
    b.add(f"phi_{lb}", "deg", "phi", f"angle of slider {lb}", "accepted", f"MOD({{tilt_g{i}}},360)")
    cos_sin_rows(b, la, "", "")
    cos_sin_rows(b, lb, "", "")
    ca, sa, ux, uy = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    b.add(f"omega_{lb}", "rad/s", "omega", f"angular velocity of slider {lb}", "accepted", "0")
    b.add(f"eps_{lb}", "rad/s^2", "eps", f"angular acceleration of slider {lb}", "accepted", "0")
    m = (f"(-{L}*{sa})", f"(-{ux})", f"({L}*{ca})", f"(-{uy})")
    det_row(b, f"Delta_g{i}", m, "m", "det", "determinant L cos(phi - tilt)")
    b.add(f"det_g{i}", "", "det/L", "cos(phi - tilt) (near 0: toggle)", "calc", f"{{Delta_g{i}}}/{L}")
    cramer_rows(b, m, f"Delta_g{i}", ((f"omega_{la}", "rad/s", "omega", f"angular velocity of coupler {la}"),
                                      (f"vs_{N}", "m/s", "vs", f"velocity of slider {N} along the line")),
                (f"(-{b.p('vx', J1)})", f"(-{b.p('vy', J1)})"), residual(i, "v"))
    wa = f"{{omega_{la}}}"
    b.add(f"f1_g{i}", "m/s^2", "f1", "right side f1", "calc", f"-{b.p('ax', J1)}+{L}*{wa}^2*{ca}")
    b.add(f"f2_g{i}", "m/s^2", "f2", "right side f2", "calc", f"-{b.p('ay', J1)}+{L}*{wa}^2*{sa}")
    cramer_rows(b, m, f"Delta_g{i}", ((f"eps_{la}", "rad/s^2", "eps", f"angular acceleration of coupler {la}"),
                                      (f"as_{N}", "m/s^2", "as", f"acceleration of slider {N} along the line")),
                (f"{{f1_g{i}}}", f"{{f2_g{i}}}"), residual(i, "a"))
    b.place_links(la, lb)
    b.section(f"point_{N}", f"Ползун {N}", f"Slider {N}")
    vs, as_ = f"{{vs_{N}}}", f"{{as_{N}}}"
    motion_rows(b, N, f"ползуна {N}", f"slider {N}", f"{X}+{S}*{ux}", f"{Y}+{S}*{uy}",
                f"{vs}*{ux}", f"{vs}*{uy}", f"{as_}*{ux}", f"{as_}*{uy}")
    distance_check(b, f"chk_{J1}{N}", J1, N, L, f"|{J1}{N}| - L", f"check: |{J1}{N}| - L{la}")


# --------------------------------------------------------------------------- the rest: RRP's
pin_owner, pairs, reactions, reaction_rows = rrp.pin_owner, rrp.pairs, rrp.reactions, rrp.reaction_rows
loop, side_ok, discriminant, unknowns = rrp.loop, rrp.side_ok, rrp.discriminant, rrp.unknowns
STABILITY: tuple = ()
