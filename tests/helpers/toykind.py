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
    Text,
    Texts,
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
TITLE = Text(ru="шатун и ползун на прямой стойки (пример нового вида группы)",
             uk="шатун і повзун на прямій стояка (приклад нового виду групи)",
             en="coupler and slider on a line of the frame (an example of a new group kind)")
KEYS = ("type", "links", "joints", "length", "line", "branch")


# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language: every key in all three, with the same fields
# (tests/groups/test_row_texts.py); the rows ask for them by key, T("h", J1=J1)
TEXTS = {
    "ru": {
        "L": "длина шатуна {la}",
        "lx": "прямая: x точки",
        "ly": "прямая: y точки",
        "tilt": "наклон прямой",
        "branch": "ветвь (+1 или -1)",
        "group": "Группа {i} (игрушечная {J1}{N})",
        "h": "расстояние от {J1} до прямой",
        "foot": "проекция {J1} на прямую",
        "D": "дискриминант L^2 - h^2",
        "accepted": "Принятые значения",
        "s": "перемещение ползуна {N}",
        "phi_a": "угол шатуна {la}",
        "phi_b": "угол ползуна {lb}",
        "omega_b": "угловая скорость ползуна {lb}",
        "eps_b": "угловое ускорение ползуна {lb}",
        "det": "определитель L cos(phi - tilt)",
        "toggle": "cos(phi - tilt) (около 0: мёртвое положение)",
        "omega_a": "угловая скорость шатуна {la}",
        "vs": "скорость ползуна {N} вдоль прямой",
        "f1": "правая часть f1",
        "f2": "правая часть f2",
        "eps_a": "угловое ускорение шатуна {la}",
        "as": "ускорение ползуна {N} вдоль прямой",
        "slider": "Ползун {N}",
        "of_slider": "ползуна {N}",
        "chk_L": "проверка: |{J1}{N}| - L{la}",
    },
    "uk": {
        "L": "довжина шатуна {la}",
        "lx": "пряма: x точки",
        "ly": "пряма: y точки",
        "tilt": "нахил прямої",
        "branch": "гілка (+1 або -1)",
        "group": "Група {i} (іграшкова {J1}{N})",
        "h": "відстань від {J1} до прямої",
        "foot": "проекція {J1} на пряму",
        "D": "дискримінант L^2 - h^2",
        "accepted": "Прийняті значення",
        "s": "переміщення повзуна {N}",
        "phi_a": "кут шатуна {la}",
        "phi_b": "кут повзуна {lb}",
        "omega_b": "кутова швидкість повзуна {lb}",
        "eps_b": "кутове прискорення повзуна {lb}",
        "det": "визначник L cos(phi - tilt)",
        "toggle": "cos(phi - tilt) (близько 0: мертве положення)",
        "omega_a": "кутова швидкість шатуна {la}",
        "vs": "швидкість повзуна {N} уздовж прямої",
        "f1": "права частина f1",
        "f2": "права частина f2",
        "eps_a": "кутове прискорення шатуна {la}",
        "as": "прискорення повзуна {N} уздовж прямої",
        "slider": "Повзун {N}",
        "of_slider": "повзуна {N}",
        "chk_L": "перевірка: |{J1}{N}| - L{la}",
    },
    "en": {
        "L": "length of coupler {la}",
        "lx": "the line: x of a point",
        "ly": "the line: y of a point",
        "tilt": "the line's tilt",
        "branch": "branch (+1 or -1)",
        "group": "Group {i} (toy {J1}{N})",
        "h": "distance of {J1} from the line",
        "foot": "{J1}'s foot on the line",
        "D": "discriminant L^2 - h^2",
        "accepted": "Accepted values",
        "s": "travel of slider {N}",
        "phi_a": "angle of coupler {la}",
        "phi_b": "angle of slider {lb}",
        "omega_b": "angular velocity of slider {lb}",
        "eps_b": "angular acceleration of slider {lb}",
        "det": "determinant L cos(phi - tilt)",
        "toggle": "cos(phi - tilt) (near 0: toggle)",
        "omega_a": "angular velocity of coupler {la}",
        "vs": "velocity of slider {N} along the line",
        "f1": "right side f1",
        "f2": "right side f2",
        "eps_a": "angular acceleration of coupler {la}",
        "as": "acceleration of slider {N} along the line",
        "slider": "Slider {N}",
        "of_slider": "slider {N}",
        "chk_L": "check: |{J1}{N}| - L{la}",
    },
}
T = Texts(TEXTS)


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
    return [InputRow(f"L{la}", "m", T("L", la=la), g.length, True),
            InputRow(f"lx_g{i}", "m", T("lx"), x),
            InputRow(f"ly_g{i}", "m", T("ly"), y),
            InputRow(f"tilt_g{i}", "deg", T("tilt"), g.guide.angle_deg),
            InputRow(f"branch_g{i}", "", T("branch"), g.branch)]


def with_inputs(g: Group, num) -> Group:
    i = g.index
    guide = Guide(None, (num(f"lx_g{i}", g.guide.point[0]), num(f"ly_g{i}", g.guide.point[1])),
                  num(f"tilt_g{i}", g.guide.angle_deg))
    return dataclasses.replace(g, params=Params(num(f"L{g.links[0]}", g.length), guide,
                                                int(num(f"branch_g{i}", g.branch, choices=(1, -1)))))


def rows(b: Builder, g: Group) -> None:
    """J1 + L e(phi) = P + s u: h, J1's distance from the line, then s = foot +- sqrt(L^2 - h^2).
    One builder a kind of row (b.calc, b.accepted, b.check), each row's text a key of TEXTS."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    L, X, Y, tilt = f"{{L{la}}}", f"{{lx_g{i}}}", f"{{ly_g{i}}}", f"RADIANS({{tilt_g{i}}})"
    xj, yj = b.p("x", J1), b.p("y", J1)
    b.section(f"group_{i}", T("group", i=i, J1=J1, N=N))
    h, foot, D = f"h_g{i}", f"foot_g{i}", f"D_g{i}"
    b.calc(h, "m", T("h", J1=J1), f"-({xj}-{X})*SIN({tilt})+({yj}-{Y})*COS({tilt})")
    b.calc(foot, "m", T("foot", J1=J1), f"({xj}-{X})*COS({tilt})+({yj}-{Y})*SIN({tilt})")
    b.calc(D, "m^2", T("D"), f"{L}^2-{{{h}}}^2")
    group_guard(b, g, D, f"{L}^2")    # the size of the discriminant's terms (the dead-point rule), as RRP
    b.section(f"accepted_g{i}", T("accepted"))
    S = f"{{s_{N}}}"
    b.accepted(f"s_{N}", "m", T("s", N=N), f"{{{foot}}}+{{branch_g{i}}}*SQRT({{{D}}})")
    b.accepted(f"phi_{la}", "deg", T("phi_a", la=la),
               f"MOD(DEGREES(ATAN2({X}+{S}*COS({tilt})-{xj},{Y}+{S}*SIN({tilt})-{yj})),360)")
    b.accepted(f"phi_{lb}", "deg", T("phi_b", lb=lb), f"MOD({{tilt_g{i}}},360)")
    cos_sin_rows(b, la)
    cos_sin_rows(b, lb)
    ca, sa, ux, uy = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    b.accepted(f"omega_{lb}", "rad/s", T("omega_b", lb=lb), "0")
    b.accepted(f"eps_{lb}", "rad/s^2", T("eps_b", lb=lb), "0")
    m = (f"(-{L}*{sa})", f"(-{ux})", f"({L}*{ca})", f"(-{uy})")
    det_row(b, f"Delta_g{i}", m, "m", T("det"))
    b.calc(f"det_g{i}", "", T("toggle"), f"{{Delta_g{i}}}/{L}")
    cramer_rows(b, m, f"Delta_g{i}", ((f"omega_{la}", "rad/s", T("omega_a", la=la)), (f"vs_{N}", "m/s", T("vs", N=N))),
                (f"(-{b.p('vx', J1)})", f"(-{b.p('vy', J1)})"), residual(i, "v"))
    wa = f"{{omega_{la}}}"
    b.calc(f"f1_g{i}", "m/s^2", T("f1"), f"-{b.p('ax', J1)}+{L}*{wa}^2*{ca}")
    b.calc(f"f2_g{i}", "m/s^2", T("f2"), f"-{b.p('ay', J1)}+{L}*{wa}^2*{sa}")
    cramer_rows(b, m, f"Delta_g{i}", ((f"eps_{la}", "rad/s^2", T("eps_a", la=la)), (f"as_{N}", "m/s^2", T("as", N=N))),
                (f"{{f1_g{i}}}", f"{{f2_g{i}}}"), residual(i, "a"))
    b.place_links(la, lb)
    b.section(f"point_{N}", T("slider", N=N))
    vs, as_ = f"{{vs_{N}}}", f"{{as_{N}}}"
    motion_rows(b, N, T("of_slider", N=N), f"{X}+{S}*{ux}", f"{Y}+{S}*{uy}",
                f"{vs}*{ux}", f"{vs}*{uy}", f"{as_}*{ux}", f"{as_}*{uy}")
    distance_check(b, f"chk_{J1}{N}", J1, N, L, T("chk_L", J1=J1, N=N, la=la))


# --------------------------------------------------------------------------- the rest: RRP's
pin_owner, pairs, reactions, reaction_rows = rrp.pin_owner, rrp.pairs, rrp.reactions, rrp.reaction_rows
loop, side_ok, discriminant, unknowns = rrp.loop, rrp.side_ok, rrp.discriminant, rrp.unknowns
STABILITY: tuple = ()
