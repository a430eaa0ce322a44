"""RPR (ВПВ): a block (камень) hinged at J1 slides in a kulisa b that turns about J2
(slides 22-24: the crank-slotted-lever mechanism; J2 may itself move: the lecture's
"kulisa with a moving axis", Направляющая с подвижной осью).

Line through a point. The slot line passes at distance e (`offset`) from J2:
    J1 - J2 = s u + e n,   u = e(theta), n = u turned +90 deg,
unknowns theta = phi_a = phi_b and s = s_J1 = sqrt(|J1 - J2|^2 - e^2) (the seeds' L_TEK, S_AB,
l31; s > 0). Velocities by Cramer: theta_t (s n - e u) + s_t u = v_J1 - v_J2; accelerations:
the same matrix, the right side loses the Coriolis 2 s_t theta_t n and the centripetal
-s theta_t^2 u - e theta_t^2 n. Toggle measure: s / L1 (the determinant is -s, a length,
divided by the crank's: free of the mechanism's size and place; near 0 the block passes
over the kulisa's axis and the slot's direction is undefined).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .group import Family, Group, crank_scene
from .motion import (
    GroupMotion,
    Motion,
    Pair,
    Rotation,
    Slide,
    at_dead_points_zero,
    cramer,
    cross,
    hinge,
    inverse_det,
    resultants,
    sqrt_or_nan,
)
from .parts import BlockPart, Parts, slot
from .rows import (
    Builder,
    InputRow,
    LoadRows,
    Text,
    Texts,
    cramer_rows,
    det_row,
    group_guard,
    residual,
    turns_with_check,
)

# --------------------------------------------------------------------------- what it is
KIND = "RPR"
LECTURE = "ВПВ"
SLIDES = "22-24"
TITLE = Text(ru="камень на J1 в кулисе, вращающейся вокруг J2 (ось неподвижна или движется)",
             uk="камінь на J1 у кулісі, що обертається навколо J2 (вісь нерухома або рухається)",
             en="block on J1 in a kulisa (slotted lever) turning about J2 (a fixed or a moving axis)")
KEYS = ("type", "links", "joints", "offset")


# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language (fields: group i, block la, lever lb, joints J1 J2)
TEXTS = {
    "ru": {
        "e": "смещение оси кулисы {lb} от {J2}",
        "group": "Группа {i} (ВПВ: камень {J1} в кулисе, ось {J2}): слайды 22-24",
        "group_moving": "Группа {i} (ВПВ: камень {J1} в кулисе с подвижной осью {J2}): "
                        "L_ТЕК^2 = (x{J2} - x{J1})^2 + (y{J2} - y{J1})^2, слайды 22-24",
        "dx": "x{J1} - x{J2}",
        "dy": "y{J1} - y{J2}",
        "r2": "L_TEK^2 = |{J2}{J1}|^2",
        "D": "дискриминант L_TEK^2 - e^2 (< 0: группа не собирается)",
        "accepted": "Принятые значения",
        "s": "положение камня {J1} вдоль кулисы (L_TEK при e = 0)",
        "cu": "cos угла кулисы: (s dx + e dy) / L_TEK^2",
        "su": "sin угла кулисы: (s dy - e dx) / L_TEK^2",
        "chk_e": "проверка: расстояние {J1} от оси кулисы - e",
        "phi_b": "угол кулисы {lb}",
        "phi_a": "угол камня {la} (= углу кулисы)",
        "det": "определитель: -s",
        "toggle": "s / L1 (около 0: кулиса не определена)",
        "omega_b": "угловая скорость кулисы {lb} (Крамер)",
        "vs": "относительная скорость камня {J1} вдоль кулисы",
        "bx": "кориолисово и центростремительное: проекция на x",
        "by": "кориолисово и центростремительное: проекция на y",
        "eps_b": "угловое ускорение кулисы {lb}",
        "as": "относительное ускорение камня {J1} вдоль кулисы",
        "omega_a": "угловая скорость камня {la}",
        "eps_a": "угловое ускорение камня {la}",
        "rot": "кулиса {lb} и камень {la} повёрнуты по оси кулисы (cu, su), камень вращается с кулисой",
        "chk_s": "проверка: s_{J1} = +sqrt(L_TEK^2 - e^2) >= 0 (относительная невязка)",
        "cos": "cos угла кулисы {lb}",
        "sin": "sin угла кулисы {lb}",
        "chk_v": "проверка: v{J1} = v{J2} + omega x r + vs u",
        "chk_a": "проверка: a{J1} = a{J2} + eps x r - omega^2 r + as u + 2 omega vs n",
        "Pn": "давление кулисы {bl} на камень {a} по нормали к кулисе",
        "R_ab": "камня {a} на кулису {bl} (через {J1})",
        "M_ab": "момент реакции камня {a} на кулису {bl}",
        "R_1": "звена {o} на камень {a} в {J1}",
        "R_2": "звена {o} на кулису {bl} в {J2}",
    },
    "uk": {
        "e": "зміщення осі куліси {lb} від {J2}",
        "group": "Група {i} (ОПО: камінь {J1} в кулісі, вісь {J2}): слайди 22-24",
        "group_moving": "Група {i} (ОПО: камінь {J1} в кулісі з рухомої віссю {J2}): L_ПОТ^2 = (x{J2} - x{J1})^2 + "
                        "(y{J2} - y{J1})^2, слайди 22-24",
        "dx": "x{J1} - x{J2}",
        "dy": "y{J1} - y{J2}",
        "r2": "L_TEK^2 = |{J2}{J1}|^2",
        "D": "дискримінант L_TEK^2 - e^2 (< 0: група не збирається)",
        "accepted": "Прийняті значення",
        "s": "положення каменя {J1} уздовж куліси (L_TEK при e = 0)",
        "cu": "cos кута куліси: (s dx + e dy) / L_TEK^2",
        "su": "sin кута куліси: (s dy - e dx) / L_TEK^2",
        "chk_e": "перевірка: відстань {J1} від осі куліси - e",
        "phi_b": "кут куліси {lb}",
        "phi_a": "кут каменя {la} (= куту куліси)",
        "det": "визначник: -s",
        "toggle": "s / L1 (близько 0: куліса не визначена)",
        "omega_b": "кутова швидкість куліси {lb} (Крамер)",
        "vs": "відносна швидкість каменя {J1} уздовж куліси",
        "bx": "коріолісове і доцентрове: проекція на x",
        "by": "коріолісове і доцентрове: проекція на y",
        "eps_b": "кутове прискорення куліси {lb}",
        "as": "відносне прискорення каменя {J1} уздовж куліси",
        "omega_a": "кутова швидкість каменя {la}",
        "eps_a": "кутове прискорення каменя {la}",
        "rot": "куліса {lb} і камінь {la} повернуті за осі куліси (cu, su), камінь обертається з кулісою",
        "chk_s": "перевірка: s_{J1} = +sqrt(L_TEK^2 - e^2) >= 0 (відносна нев'язка)",
        "cos": "cos кута куліси {lb}",
        "sin": "sin кута куліси {lb}",
        "chk_v": "перевірка: v{J1} = v{J2} + omega x r + vs u",
        "chk_a": "перевірка: a{J1} = a{J2} + eps x r - omega^2 r + as u + 2 omega vs n",
        "Pn": "тиск куліси {bl} на камінь {a} за нормалі до кулісі",
        "R_ab": "каменя {a} на кулісу {bl} (через {J1})",
        "M_ab": "момент реакції каменя {a} на кулісу {bl}",
        "R_1": "ланки {o} на камінь {a} в {J1}",
        "R_2": "ланки {o} на кулісу {bl} в {J2}",
    },
    "en": {
        "e": "offset of slot {lb} from {J2}",
        "group": "Group {i} (RPR: block {J1} in the slotted lever about {J2}): slides 22-24",
        "group_moving": "Group {i} (RPR: block {J1} in a kulisa with a moving axis {J2}): "
                        "L_TEK^2 = (x{J2} - x{J1})^2 + (y{J2} - y{J1})^2, slides 22-24",
        "dx": "x{J1} - x{J2}",
        "dy": "y{J1} - y{J2}",
        "r2": "L_TEK^2 = |{J2}{J1}|^2",
        "D": "discriminant L_TEK^2 - e^2 (< 0: cannot assemble)",
        "accepted": "Accepted values",
        "s": "block {J1}'s place along the slot (L_TEK when e = 0)",
        "cu": "cos of the slot's angle: (s dx + e dy) / L_TEK^2",
        "su": "sin of the slot's angle: (s dy - e dx) / L_TEK^2",
        "chk_e": "check: distance of {J1} from the slot line - e",
        "phi_b": "angle of the slotted lever {lb}",
        "phi_a": "angle of the block {la} (= the lever's)",
        "det": "determinant: -s",
        "toggle": "s / L1 (near 0: the slot is undefined)",
        "omega_b": "angular velocity of the lever {lb} (Cramer)",
        "vs": "velocity of block {J1} along the slot",
        "bx": "Coriolis and centripetal terms, x",
        "by": "Coriolis and centripetal terms, y",
        "eps_b": "angular acceleration of the lever {lb}",
        "as": "acceleration of block {J1} along the slot",
        "omega_a": "angular velocity of the block {la}",
        "eps_a": "angular acceleration of the block {la}",
        "rot": "lever {lb} and block {la} point along the slot (cu, su), the block turns with the lever",
        "chk_s": "check: s_{J1} = +sqrt(L_TEK^2 - e^2) >= 0 (relative)",
        "cos": "cos of lever {lb}'s angle",
        "sin": "sin of lever {lb}'s angle",
        "chk_v": "check: v{J1} = v{J2} + omega x r + vs u",
        "chk_a": "check: a{J1} = a{J2} + eps x r - omega^2 r + as u + 2 omega vs n",
        "Pn": "push of lever {bl} on block {a} across the slot",
        "R_ab": "of block {a} on lever {bl} (through {J1})",
        "M_ab": "couple of block {a} on lever {bl}",
        "R_1": "of link {o} on block {a} at {J1}",
        "R_2": "of link {o} on lever {bl} at {J2}",
    },
}
T = Texts(TEXTS)


# --------------------------------------------------------------------------- scene keys
@dataclass(frozen=True)
class Params:
    offset: float = 0.0      # the slot line's distance from J2 (to the left of J2 -> J1)


def parse(tbl, frame) -> tuple[tuple[str, ...], Params]:
    joints = tbl.array("joints", 2, "name")
    offset = tbl.get("offset", "a number", 0.0)
    if joints[0] == joints[1]:
        tbl.fail("joints", f"expected two different points, got {list(joints)}")
    return joints, Params(offset)


def needs(g: Group) -> list[str]:
    return list(g.joints)


def on_links(g: Group) -> list[tuple[str, str, int]]:
    return []


def new_joints(g: Group) -> list[str]:
    return []


def carries(g: Group) -> dict[int, list[str]]:
    (j1, j2), (a, b) = g.joints, g.links
    return {a: [j1], b: [j2]}


def sliders(g: Group) -> list[str]:
    return [g.joints[0]]


def fourbar(g: Group, crank_joint: str, frame) -> None:
    """Not a four-bar's dyad (only an RRR closes one with the crank: sheetkin.studies.synthesis)."""
    return None


def parts(g: Group) -> Parts:
    """The block (link a) at J1 in the slot of the kulisa b, which turns about J2: the slot
    is drawn through J1 along phi_b from the foot of J2 (the offset e is J2's distance)."""
    (j1, j2), (a, b) = g.joints, g.links
    line = slot(b, j1, j2, g.index)
    return Parts({a: (j1,), b: (j2,)}, (line,), (BlockPart(a, j1, line),))


# --------------------------------------------------------------------------- positions and rates
def solve_rpr(j1: Motion, j2: Motion, offset: float, scale: float):
    """The kulisa's rotation, the block's slide, the discriminant, the toggle measure."""
    e = offset
    dx, dy = j1.x - j2.x, j1.y - j2.y
    r2 = dx * dx + dy * dy
    disc = at_dead_points_zero(np.where(r2 > 0, r2 - e * e, -1.0), r2)   # J1 on J2 with no offset: slot undefined
    s = sqrt_or_nan(disc)
    c, sn = (s * dx + e * dy) / r2, (s * dy - e * dx) / r2
    col1x, col1y = -s * sn - e * c, s * c - e * sn      # d/dtheta of (s u + e n)
    det, inv = inverse_det(col1x, c, col1y, sn)
    w, vs = cramer(col1x, c, col1y, sn, j1.vx - j2.vx, j1.vy - j2.vy, inv)
    # bias: 2 s_t theta_t n - s theta_t^2 u - e theta_t^2 n
    bn, bu = 2.0 * vs * w - e * w * w, -s * w * w
    bx, by = bu * c - bn * sn, bu * sn + bn * c
    eps, as_ = cramer(col1x, c, col1y, sn, j1.ax - j2.ax - bx, j1.ay - j2.ay - by, inv)
    return Rotation(c, sn, w, eps), Slide(s, vs, as_), disc, -det / scale


def solve(g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion:
    (j1, j2), (a, b) = g.joints, g.links
    r, slide, disc, toggle = solve_rpr(known[j1], known[j2], g.offset, scale)
    return GroupMotion({}, {a: r, b: r}, {j1: slide}, disc, toggle)


# --------------------------------------------------------------------------- the workbook
def input_rows(g: Group) -> list[InputRow]:
    i, lb, j2 = g.index, g.links[1], g.joints[1]
    return [InputRow(f"e_g{i}", "m", T("e", lb=lb, J2=j2), g.offset)]


def with_inputs(g: Group, num) -> Group:
    return dataclasses.replace(g, params=Params(num(f"e_g{g.index}", g.offset)))


def rows(b: Builder, g: Group):
    """Lecture slides 22-24: block on J1 in the slotted lever (kulisa) turning about J2.
    J1 - J2 = s u + e n (u along the slot, n = u turned +90 deg). J2 may move (a kulisa
    with a moving axis): its velocity and acceleration enter the right sides."""
    i, (la, lb), (J1, J2) = g.index, g.links, g.joints
    e = f"{{e_g{i}}}"
    # a moving axis: the lecture's "Кулисные механизмы. Направляющая с подвижной осью"
    b.section(f"group_{i}", T("group" if J2 in b.frame else "group_moving", i=i, J1=J1, J2=J2))
    dx, dy, r2, D = f"dx_g{i}", f"dy_g{i}", f"r2_g{i}", f"D_g{i}"
    b.calc(dx, "m", T("dx", J1=J1, J2=J2), f"{b.p('x', J1)}-{b.p('x', J2)}", guard=b.guard)
    b.calc(dy, "m", T("dy", J1=J1, J2=J2), f"{b.p('y', J1)}-{b.p('y', J2)}", guard=b.guard)
    b.calc(r2, "m^2", T("r2", J1=J1, J2=J2), f"{{{dx}}}^2+{{{dy}}}^2", guard=b.guard)
    b.calc(D, "m^2", T("D"), f"IF({{{r2}}}>0,{{{r2}}}-{e}^2,-1)", guard=b.guard)
    group_guard(b, g, D, f"{{{r2}}}")
    b.section(f"accepted_g{i}", T("accepted"))
    sJ = f"s_{J1}"
    b.accepted(sJ, "m", T("s", J1=J1), f"SQRT({{{D}}})")
    cu, su = f"cu_g{i}", f"su_g{i}"
    b.calc(cu, "", T("cu"), f"({{{sJ}}}*{{{dx}}}+{e}*{{{dy}}})/{{{r2}}}")
    b.calc(su, "", T("su"), f"({{{sJ}}}*{{{dy}}}-{e}*{{{dx}}})/{{{r2}}}")
    b.check(f"chk_e_g{i}", "m", T("chk_e", J1=J1), f"-{{{dx}}}*{{{su}}}+{{{dy}}}*{{{cu}}}-{e}")
    b.accepted(f"phi_{lb}", "deg", T("phi_b", lb=lb), f"MOD(DEGREES(ATAN2({{{cu}}},{{{su}}})),360)")
    b.accepted(f"phi_{la}", "deg", T("phi_a", la=la), f"{{phi_{lb}}}")
    _rate_rows(b, g)


def _rate_rows(b: Builder, g: Group) -> None:
    """Cramer's rule for the lever's omega and the block's slide, then (Coriolis, centripetal
    bias) their accelerations; the block turns with the lever; v and a of J1 checked on it."""
    i, (la, lb), (J1, J2) = g.index, g.links, g.joints
    e, sJ, cu, su = f"{{e_g{i}}}", f"s_{J1}", f"cu_g{i}", f"su_g{i}"
    dx, dy, r2 = f"dx_g{i}", f"dy_g{i}", f"r2_g{i}"
    c, s = f"{{{cu}}}", f"{{{su}}}"
    det = f"Delta_g{i}"
    # unknowns theta_t, s_t: columns (-s sin - e cos, s cos - e sin) and (cos, sin); determinant -s
    m11, m21 = f"(-{{{sJ}}}*{s}-{e}*{c})", f"({{{sJ}}}*{c}-{e}*{s})"
    m = (m11, c, m21, s)
    det_row(b, det, m, "m", T("det"))
    b.calc(f"det_g{i}", "", T("toggle"), f"-{{{det}}}/{{L1}}")
    b1, b2 = f"({b.p('vx', J1)}-{b.p('vx', J2)})", f"({b.p('vy', J1)}-{b.p('vy', J2)})"
    cramer_rows(b, m, det, ((f"omega_{lb}", "rad/s", T("omega_b", lb=lb)), (f"vs_{J1}", "m/s", T("vs", J1=J1))),
                (b1, b2), residual(i, "v"))
    w, vs = f"{{omega_{lb}}}", f"{{vs_{J1}}}"
    bx, by = f"bx_g{i}", f"by_g{i}"
    # bias of the acceleration system: 2 s_t theta_t n (Coriolis) - s theta_t^2 u - e theta_t^2 n
    b.calc(bx, "m/s^2", T("bx"), f"-{{{sJ}}}*{w}^2*{c}-(2*{vs}*{w}-{e}*{w}^2)*{s}")
    b.calc(by, "m/s^2", T("by"), f"-{{{sJ}}}*{w}^2*{s}+(2*{vs}*{w}-{e}*{w}^2)*{c}")
    f1, f2 = f"({b.p('ax', J1)}-{b.p('ax', J2)}-{{{bx}}})", f"({b.p('ay', J1)}-{b.p('ay', J2)}-{{{by}}})"
    cramer_rows(b, m, det, ((f"eps_{lb}", "rad/s^2", T("eps_b", lb=lb)), (f"as_{J1}", "m/s^2", T("as", J1=J1))),
                (f1, f2), residual(i, "a"))
    ep = f"{{eps_{lb}}}"
    b.accepted(f"omega_{la}", "rad/s", T("omega_a", la=la), f"{{omega_{lb}}}")
    b.accepted(f"eps_{la}", "rad/s^2", T("eps_a", la=la), f"{{eps_{lb}}}")
    turns_with_check(b, f"chk_rot_g{i}", [(f"phi_{lb}", c, s), (f"phi_{la}", c, s)],
                     [(f"omega_{la}", w), (f"eps_{la}", ep)],
                     T("rot", la=la, lb=lb))
    # s is the root +sqrt(D): -sqrt(D) also closes the loop (the slot turned by 180 deg),
    # so only its sign tells; relative to L_TEK, free of the step
    b.check(f"chk_s_g{i}", "", T("chk_s", J1=J1),
            f"ABS({{{sJ}}}^2+{e}^2-{{{r2}}})/{{{r2}}}+(ABS({{{sJ}}})-{{{sJ}}})/SQRT({{{r2}}})")
    b.calc(f"cos_{lb}", "", T("cos", lb=lb), c)
    b.calc(f"sin_{lb}", "", T("sin", lb=lb), s)
    b.place_links(la, lb, rot=(f"cos_{lb}", f"sin_{lb}", f"omega_{lb}", f"eps_{lb}"))
    # the block's motion seen on the lever: v_J1 = v_J2 + omega x r + vs u,
    # a_J1 = a_J2 + eps x r - omega^2 r + as u + 2 omega vs n (Coriolis)
    as_ = f"{{as_{J1}}}"
    b.check(f"chk_v_g{i}", "m/s", T("chk_v", J1=J1, J2=J2),
            f"ABS({b.p('vx', J1)}-({b.p('vx', J2)}-{w}*{{{dy}}}+{vs}*{c}))"
            f"+ABS({b.p('vy', J1)}-({b.p('vy', J2)}+{w}*{{{dx}}}+{vs}*{s}))")
    b.check(f"chk_a_g{i}", "m/s^2", T("chk_a", J1=J1, J2=J2),
            f"ABS({b.p('ax', J1)}-({b.p('ax', J2)}-{ep}*{{{dy}}}-{w}^2*{{{dx}}}+{as_}*{c}-2*{w}*{vs}*{s}))"
            f"+ABS({b.p('ay', J1)}-({b.p('ay', J2)}+{ep}*{{{dx}}}-{w}^2*{{{dy}}}+{as_}*{s}+2*{w}*{vs}*{c}))")


# --------------------------------------------------------------------------- kinetostatics
def pin_owner(g: Group) -> dict[str, int]:
    return {}


def pairs(g: Group, owner: dict[str, int]) -> list[Pair]:
    (j1, j2), (a, b) = g.joints, g.links
    return [Pair(owner[j1], a, j1), Pair(a, b, j1, True), Pair(owner[j2], b, j2)]


def reactions(g: Group, known, links, loads, owner) -> dict[str, tuple]:
    """Block a on J1, kulisa b about J2, slot direction u, normal n. The kulisa acts on the
    block with P n through J1 and a couple C: block: R1 + P n + Fa = 0, C + Ma(J1) = 0;
    kulisa about J2: (J1 - J2) x (-P n) - C + Mb(J2) = 0, R2 - P n + Fb = 0."""
    (J1, J2), (a, b) = g.joints, g.links
    la, lb = loads[a], loads[b]
    (fax, fay), (fbx, fby), _ = resultants(loads, a, b)
    j1, j2 = known[J1], known[J2]
    rot = links[b]
    nx, ny = -rot.s, rot.c
    c = -la.moment(j1.x, j1.y)
    p = (lb.moment(j2.x, j2.y) - c) / cross(j1.x - j2.x, j1.y - j2.y, nx, ny)   # /s: 0 at the pivot
    r1x, r1y = -p * nx - fax, -p * ny - fay
    r2x, r2y = p * nx - fbx, p * ny - fby
    return dict([hinge(loads, owner[J1], a, j1, (r1x, r1y)), (f"{a}_{b}", (-p * nx, -p * ny, -c)),
                 hinge(loads, owner[J2], b, j2, (r2x, r2y))])


def reaction_rows(b: Builder, g: Group, owner: dict[str, int], k: LoadRows):
    i, (a, bl), (J1, J2) = g.index, g.links, g.joints
    o1, o2 = owner[J1], owner[J2]
    t1, tab, t2 = f"{o1}_{a}", f"{a}_{bl}", f"{o2}_{bl}"
    r1, rab = (f"{{Rx_{t1}}}", f"{{Ry_{t1}}}"), (f"{{Rx_{tab}}}", f"{{Ry_{tab}}}")
    k.link_loads(a, J1)
    k.link_loads(bl, J2)
    c, s = f"{{cos_{bl}}}", f"{{sin_{bl}}}"
    # the lever acts on the block with P n through J1 (n = (-sin, cos)) and a couple
    # C = -MQ_a; the lever's moments about J2: (J1 - J2) x (-P n) - C + MQ_b = 0
    crs = f"(({b.p('x', J1)}-{b.p('x', J2)})*{c}+({b.p('y', J1)}-{b.p('y', J2)})*{s})"
    b.calc(f"Pn_g{i}", "N", T("Pn", bl=bl, a=a), f"({{MQ_{bl}}}+{{MQ_{a}}})/{crs}")
    P = f"{{Pn_g{i}}}"
    k.reaction(tab, f"-{P}*(-{s})", f"-{P}*{c}", T("R_ab", a=a, bl=bl, J1=J1))
    b.accepted(f"M_{tab}", "N m", T("M_ab", a=a, bl=bl), f"{{MQ_{a}}}")
    k.reaction(t1, f"-{P}*(-{s})-{{Qx_{a}}}", f"-{P}*{c}-{{Qy_{a}}}", T("R_1", o=o1, a=a, J1=J1))
    k.equilibrium(a, J1, [(J1, *r1), (J1, f"(-{rab[0]})", f"(-{rab[1]})")], f"(-{{M_{tab}}})")
    k.reaction(t2, f"{P}*(-{s})-{{Qx_{bl}}}", f"{P}*{c}-{{Qy_{bl}}}", T("R_2", o=o2, bl=bl, J2=J2))
    k.equilibrium(bl, J2, [(J1, *rab), (J2, f"{{Rx_{t2}}}", f"{{Ry_{t2}}}")], f"{{M_{tab}}}")
    k.opposite(o2, J2, t2)
    k.opposite(o1, J1, t1)


# --------------------------------------------------------------------------- loop equations
def loop(lib, g: Group, known, links):
    """J1 - J2 = s u(th) + off n(th); q = (th, s)."""
    (p1, v1, a1), (p2, v2, a2) = known[g.joints[0]], known[g.joints[1]]
    off = lib.num(g.offset)

    def _u(th):
        c, s = lib.cos(th), lib.sin(th)
        return c, s, -s, c

    def F(q):
        c, s, nc, ns = _u(q[0])
        return [p1[0] - p2[0] - q[1] * c - off * nc, p1[1] - p2[1] - q[1] * s - off * ns]

    def J(q):
        c, s, nc, ns = _u(q[0])
        return [[-(q[1] * nc - off * c), -c], [-(q[1] * ns - off * s), -s]]

    def b_v(q):
        return [v2[0] - v1[0], v2[1] - v1[1]]

    def b_a(q, qt):
        # d2(s u + off n)/dt2 = s_tt u + th_tt (s n - off u) + 2 s_t th_t n - s th_t^2 u - off th_t^2 n
        c, s, nc, ns = _u(q[0])
        w, vs = qt
        return [a2[0] - a1[0] + 2 * vs * w * nc - q[1] * w * w * c - off * w * w * nc,
                a2[1] - a1[1] + 2 * vs * w * ns - q[1] * w * w * s - off * w * w * ns]

    def place(q, qt, qtt):
        lever = (q[0], qt[0], qtt[0])
        return {}, (lever, lever), {g.joints[0]: (q[1], qt[1], qtt[1])}
    return F, J, b_v, b_a, place


def side_ok(lib, g: Group, known, links, q, joints) -> bool:
    """The contract has s > 0: the slot points from J2 towards the block."""
    return q[1] > 0


def discriminant(lib, g: Group, known, links):
    """L_TEK^2 - e^2: 0 where the block passes over the kulisa's axis (offset 0)."""
    (p1, _, _), (p2, _, _) = known[g.joints[0]], known[g.joints[1]]
    off = lib.num(g.offset)
    return (p1[0] - p2[0]) ** 2 + (p1[1] - p2[1]) ** 2 - off * off


def unknowns(g: Group, sol) -> tuple[np.ndarray, np.ndarray]:
    rb = sol.links[g.links[1]]
    return np.arctan2(rb.s, rb.c), sol.slides[g.joints[0]].s


# --------------------------------------------------------------------------- stability families
# A slot offset from the kulisa's axis (e = 0.375) that the crank (0.25, the axis 0.5 away)
# cannot always reach: where |J1 - J2| = e the block stands at the foot of the perpendicular
# from J2 to the slot (s = L_TEK -> 0, the discriminant L_TEK^2 - e^2 -> 0 and the toggle
# measure s / L1 -> 0 like sqrt(d)); beyond it the group does not assemble. Binary lengths:
# the edge cos(phi) = -0.6875 holds in floats.
STABILITY = (
    Family("kulisa-edge", "RPR: a slot offset from the kulisa's axis, towards the edge of its range (s -> 0)",
           crank_scene("Slotted lever with an offset slot: the crank cannot always reach it", """\
[[group]]
type   = "RPR"
links  = [2, 3]
joints = ["A", "C"]
offset = 0.375
""", frame="""\
O  = [0.0, 0.0]
C  = [-0.5, 0.0]"""), 1, discriminant),
)
