"""RPP (ВПП): a block hinged at J1 sliding in the slot of a link b that moves straight.

The lecture's "kulisa that moves straight" (seed 003: "Кулисы бывают вращающиеся,
качающиеся, прямолинейно движущиеся"), the Scotch yoke: the block a turns about J1 and
slides in a straight slot of link b; b does not turn and slides along its own guide on the
frame (through G, direction gamma). The slot's direction alpha is absolute (b translates).
K is the point of b where the slot line through J1 crosses b's guide: a point of b, so its
motion is b's motion.

Constraint:  J1 = G + s_K u_g + s_J1 u_s,  u_g = e(gamma), u_s = e(alpha),
two unknowns s_K (K along the guide from G) and s_J1 (J1 along the slot from K). The matrix
[u_g, u_s] is constant, with the determinant sin(alpha - gamma): the rates follow from
v_J1 and a_J1 by the same Cramer's rule (no Coriolis term: nothing turns). Toggle measure:
sin(alpha - gamma), the sine of the angle between slot and guide: free of position and
size, constant over the cycle, zero when the slot is parallel to the guide (no K).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .group import Family, Group, Guide, crank_scene
from .motion import GroupMotion, Motion, Pair, Rotation, Slide, cramer, inverse_det
from .parts import BlockPart, Parts, scene_guide, slot
from .rows import (
    Builder,
    InputRow,
    LoadRows,
    Text,
    Texts,
    cos_sin_rows,
    cramer_rows,
    fd_checks,
    motion_rows,
    turns_with_check,
)

# --------------------------------------------------------------------------- what it is
KIND = "RPP"
LECTURE = "ВПП"
SLIDES = "кулисы, движущиеся прямолинейно"
TITLE = Text(ru="камень в J1 в пазу кулисы, движущейся прямолинейно по неподвижной направляющей (синусный механизм)",
             uk="камінь у J1 в пазу куліси, що рухається прямолінійно по нерухомій напрямній (синусний механізм)",
             en="block on J1 in the slot of a kulisa that moves straight along a fixed guide (Scotch yoke)")
KEYS = ("type", "links", "joints", "slot_angle_deg", "guide")
PARALLEL = 1e-9      # |sin(alpha - gamma)| below this: the slot runs along the guide, no K


# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language (fields: group i, block la, kulisa lb, joints J1 K)
TEXTS = {
    "ru": {
        "gx": "направляющая кулисы {lb}: x точки",
        "gy": "направляющая кулисы {lb}: y точки",
        "gamma": "угол наклона направляющей кулисы",
        "alpha": "угол паза кулисы (камень {J1})",
        "group": "Группа {i} (ВПП {J1}{K}): кулиса {lb}, движущаяся прямолинейно (синусный механизм)",
        "D": "определитель [u_g, u_s] = sin(alpha - gamma) (0: паз вдоль направляющей, K нет)",
        "guard": "группа {i} собирается (паз пересекает направляющую)",
        "det": "sin(alpha - gamma): синус угла между пазом и направляющей",
        "accepted": "Принятые значения: положение, скорость, ускорение вдоль направляющей и паза",
        "travel": "положение",
        "velocity": "скорость",
        "acceleration": "ускорение",
        "s_K": "{what} кулисы: {K} вдоль направляющей (Крамер)",
        "s_J1": "{what} камня {J1} вдоль паза от {K} (Крамер)",
        "sys": "{what}: невязка системы",
        "phi_a": "угол паза (камень {la} и кулиса {lb} не вращаются)",
        "phi_b": "угол кулисы {lb} (= угол паза)",
        "chk_acc": "проверка принятых значений: G + s_{K} u_g + s_{J1} u_s - {J1}",
        "block": "камня",
        "kulisa": "кулисы",
        "omega": "угловая скорость {what} {k}",
        "eps": "угловое ускорение {what} {k}",
        "rot": "камень {la} и кулиса {lb} повёрнуты по пазу (alpha)",
        "point_K": "Точка {K} кулисы {lb} на её направляющей",
        "point": "точки {K}",
        "chk_J1": "проверка: {K} + s_{J1} u_s совпадает с {J1}",
        "chk_v_J1": "проверка: скорость {K} + vs_{J1} u_s равна скорости {J1}",
        "chk_a_J1": "проверка: ускорение {K} + as_{J1} u_s равно ускорению {J1} (не зависит от шага)",
        "R_det": "определитель: sin(gamma - alpha)",
        "P": "нормальная сила паза на камень {J1} (Крамер)",
        "Q": "нормальная сила направляющей на кулису (Крамер)",
        "chk_Rsys": "проверка: нормальные силы в их двух уравнениях",
        "R_1": "звена {o} на камень {a} в {J1}",
        "R_ab": "камня {a} на кулису {bl} (через {J1})",
        "M_ab": "момент камня {a} на кулису {bl}",
        "R_0": "направляющей на кулису {bl} (через {K})",
        "M_0": "момент направляющей на кулису {bl}",
    },
    "uk": {
        "gx": "напрямна куліси {lb}: x точки",
        "gy": "напрямна куліси {lb}: y точки",
        "gamma": "кут нахилу напрямної куліси",
        "alpha": "кут паза куліси (камінь {J1})",
        "group": "Група {i} (ОПП {J1}{K}): куліса {lb}, рухома прямолінійно (синусний механізм)",
        "D": "визначник [u_g, u_s] = sin(alpha - gamma) (0: паз уздовж напрямної, K немає)",
        "guard": "група {i} збирається (паз перетинає напрямну)",
        "det": "sin(alpha - gamma): синус кута між пазом і напрямної",
        "accepted": "Прийняті значення: положення, швидкість, прискорення уздовж напрямної і паза",
        "travel": "положення",
        "velocity": "швидкість",
        "acceleration": "прискорення",
        "s_K": "{what} куліси: {K} уздовж напрямної (Крамер)",
        "s_J1": "{what} каменя {J1} уздовж паза від {K} (Крамер)",
        "sys": "{what}: нев'язка системи",
        "phi_a": "кут паза (камінь {la} і куліса {lb} не обертаються)",
        "phi_b": "кут куліси {lb} (= кут паза)",
        "chk_acc": "перевірка прийнятих значень: G + s_{K} u_g + s_{J1} u_s - {J1}",
        "block": "каменя",
        "kulisa": "куліси",
        "omega": "кутова швидкість {what} {k}",
        "eps": "кутове прискорення {what} {k}",
        "rot": "камінь {la} і куліса {lb} повернуті за пазу (alpha)",
        "point_K": "Точка {K} куліси {lb} на її напрямної",
        "point": "точки {K}",
        "chk_J1": "перевірка: {K} + s_{J1} u_s збігається з {J1}",
        "chk_v_J1": "перевірка: швидкість {K} + vs_{J1} u_s дорівнює швидкості {J1}",
        "chk_a_J1": "перевірка: прискорення {K} + as_{J1} u_s дорівнює прискоренню {J1} (не залежить від кроку)",
        "R_det": "визначник: sin(gamma - alpha)",
        "P": "нормальна сила паза на камінь {J1} (Крамер)",
        "Q": "нормальна сила напрямної на кулісу (Крамер)",
        "chk_Rsys": "перевірка: нормальні сили в їх двох рівняннях",
        "R_1": "ланки {o} на камінь {a} в {J1}",
        "R_ab": "каменя {a} на кулісу {bl} (через {J1})",
        "M_ab": "момент каменя {a} на кулісу {bl}",
        "R_0": "напрямної на кулісу {bl} (через {K})",
        "M_0": "момент напрямної на кулісу {bl}",
    },
    "en": {
        "gx": "kulisa {lb}'s guide: x of a point",
        "gy": "kulisa {lb}'s guide: y of a point",
        "gamma": "the kulisa's guide's angle",
        "alpha": "the kulisa's slot angle (block {J1})",
        "group": "Group {i} (RPP {J1}{K}): kulisa {lb} moving straight (Scotch yoke)",
        "D": "determinant [u_g, u_s] = sin(alpha - gamma) (0: the slot along the guide, no K)",
        "guard": "group {i} assembles (the slot crosses the guide)",
        "det": "sin(alpha - gamma): sine of the angle between the slot and the guide",
        "accepted": "Accepted values: position, velocity, acceleration along the guide and the slot",
        "travel": "travel",
        "velocity": "velocity",
        "acceleration": "acceleration",
        "s_K": "{what} of the kulisa: {K} along the guide (Cramer)",
        "s_J1": "{what} of block {J1} along the slot from {K} (Cramer)",
        "sys": "{what}: residual of the system",
        "phi_a": "the slot's angle (block {la} and kulisa {lb} do not turn)",
        "phi_b": "angle of kulisa {lb} (= the slot's)",
        "chk_acc": "check of the accepted values: G + s_{K} u_g + s_{J1} u_s - {J1}",
        "block": "block",
        "kulisa": "kulisa",
        "omega": "angular velocity of {what} {k}",
        "eps": "angular acceleration of {what} {k}",
        "rot": "block {la} and kulisa {lb} point along the slot (alpha)",
        "point_K": "Point {K} of kulisa {lb} on its guide",
        "point": "point {K}",
        "chk_J1": "check: {K} + s_{J1} u_s is {J1}",
        "chk_v_J1": "check: velocity of {K} + vs_{J1} u_s is {J1}'s",
        "chk_a_J1": "check: acceleration of {K} + as_{J1} u_s is {J1}'s (free of the step)",
        "R_det": "determinant: sin(gamma - alpha)",
        "P": "normal force of the slot on block {J1} (Cramer)",
        "Q": "normal force of the guide on the kulisa (Cramer)",
        "chk_Rsys": "check: the normal forces put back into their two equations",
        "R_1": "of link {o} on block {a} at {J1}",
        "R_ab": "of block {a} on kulisa {bl} (through {J1})",
        "M_ab": "couple of block {a} on kulisa {bl}",
        "R_0": "of the guide on kulisa {bl} (through {K})",
        "M_0": "couple of the guide on kulisa {bl}",
    },
}
T = Texts(TEXTS)


# --------------------------------------------------------------------------- scene keys
@dataclass(frozen=True)
class Params:
    slot_angle_deg: float   # alpha: the slot's absolute direction (b does not turn)
    guide: Guide            # b's guide, on the frame


def parse(tbl, frame) -> tuple[tuple[str, ...], Params]:
    joints = tbl.array("joints", 2, "name")
    if joints[0] == joints[1]:
        tbl.fail("joints", f"the new joint '{joints[1]}' (second name) must differ from the block's "
                           f"joint, got {list(joints)}")
    alpha = tbl.get("slot_angle_deg", "a number")
    guide = tbl.guide("guide", frame)
    if guide.moving:
        tbl.fail("guide", f"the kulisa's guide is on the frame (link = 0), got link = {guide.link}")
    if abs(math.sin(math.radians(alpha - guide.angle_deg))) < PARALLEL:
        tbl.fail("slot_angle_deg", f"the slot ({alpha:g} deg) runs along the guide ({guide.angle_deg:g} deg): "
                                   "the kulisa could not move; expected different directions")
    return joints, Params(alpha, guide)


def needs(g: Group) -> list[str]:
    return [g.joints[0]]


def on_links(g: Group) -> list[tuple[str, str, int]]:
    return []


def new_joints(g: Group) -> list[str]:
    return [g.joints[1]]


def carries(g: Group) -> dict[int, list[str]]:
    (j1, k), (a, b) = g.joints, g.links
    return {a: [j1], b: [k]}


def sliders(g: Group) -> list[str]:
    """s_K along b's guide, s_J1 along the slot from K (the contract)."""
    return [g.joints[1], g.joints[0]]


def fourbar(g: Group, crank_joint: str, frame) -> None:
    """Not a four-bar's dyad (only an RRR closes one with the crank: sheetkin.studies.synthesis)."""
    return None


def parts(g: Group) -> Parts:
    """The kulisa b at K slides on its frame guide (inputs gamma_g<i>, gx_g<i>, gy_g<i>);
    the block a at J1 slides in b's slot, the line through K and J1 along phi_b = alpha."""
    (j1, k), (a, b), i = g.joints, g.links, g.index
    guide = scene_guide(g.guide, k, i, f"gamma_g{i}", (f"gx_g{i}", f"gy_g{i}"))
    line = slot(b, j1, k, i)
    return Parts({a: (j1,), b: (k,)}, (guide, line), (BlockPart(b, k, guide), BlockPart(a, j1, line)))


# --------------------------------------------------------------------------- positions and rates
def toggle(gamma_rad: float, alpha_rad: float) -> float:
    """sin(alpha - gamma): the sine of the angle between the slot and b's guide."""
    return float(np.sin(alpha_rad - gamma_rad))


def solve_rpp(j1: Motion, through, gamma_rad: float, alpha_rad: float):
    """K (on b's guide), the slides s_K and s_J1, the discriminant (negative where the slot
    is parallel to the guide), the toggle measure and the common direction of links a, b."""
    gx, gy, sx, sy = np.cos(gamma_rad), np.sin(gamma_rad), np.cos(alpha_rad), np.sin(alpha_rad)
    det, inv = inverse_det(gx, sx, gy, sy)
    sk, sj = cramer(gx, sx, gy, sy, j1.x - through[0], j1.y - through[1], inv)
    vk, vj = cramer(gx, sx, gy, sy, j1.vx, j1.vy, inv)
    ak, aj = cramer(gx, sx, gy, sy, j1.ax, j1.ay, inv)
    joint = Motion(through[0] + sk * gx, through[1] + sk * gy, vk * gx, vk * gy, ak * gx, ak * gy)
    zero = 0.0 * sk
    slot = Rotation(sx + zero, sy + zero, zero, zero)
    disc = zero + (1.0 if det != 0 else -1.0)
    return joint, Slide(sk, vk, ak), Slide(sj, vj, aj), disc, det + zero, slot


def solve(g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion:
    (j1, k), (a, b) = g.joints, g.links
    joint, sk, sj, disc, sine, slot = solve_rpp(known[j1], g.guide.point, math.radians(g.guide.angle_deg),
                                                math.radians(g.slot_angle_deg))
    return GroupMotion({k: joint}, {a: slot, b: slot}, {k: sk, j1: sj}, disc, sine)


# --------------------------------------------------------------------------- the workbook
def input_rows(g: Group) -> list[InputRow]:
    i, j1, gd, lb = g.index, g.joints[0], g.guide, g.links[1]
    return [InputRow(f"gx_g{i}", "m", T("gx", lb=lb), gd.point[0]),
            InputRow(f"gy_g{i}", "m", T("gy", lb=lb), gd.point[1]),
            InputRow(f"gamma_g{i}", "deg", T("gamma"), gd.angle_deg),
            InputRow(f"alpha_g{i}", "deg", T("alpha", J1=j1), g.slot_angle_deg)]


def with_inputs(g: Group, num) -> Group:
    i, gd = g.index, g.guide
    guide = dataclasses.replace(gd, point=(num(f"gx_g{i}", gd.point[0]), num(f"gy_g{i}", gd.point[1])),
                                angle_deg=num(f"gamma_g{i}", gd.angle_deg))
    return dataclasses.replace(g, params=Params(num(f"alpha_g{i}", g.slot_angle_deg), guide))


def _guide_slot(g: Group):
    """The guide's and the slot's directions u_g = e(gamma), u_s = e(alpha) as formulas."""
    i = g.index
    ug = (f"COS(RADIANS({{gamma_g{i}}}))", f"SIN(RADIANS({{gamma_g{i}}}))")
    us = (f"COS(RADIANS({{alpha_g{i}}}))", f"SIN(RADIANS({{alpha_g{i}}}))")
    return ug, us


def rows(b: Builder, g: Group):
    """J1 = G + s_K u_g + s_J1 u_s: the point's position, velocity and acceleration each
    split along the guide and the slot by Cramer's rule (one constant matrix)."""
    i, (la, lb), (J1, K) = g.index, g.links, g.joints
    b.section(f"group_{i}", T("group", i=i, J1=J1, K=K, lb=lb))
    ug, us = _guide_slot(g)
    det = f"D_g{i}"
    m = (ug[0], us[0], ug[1], us[1])
    b.calc(det, "", T("D"), f"{m[0]}*{m[3]}-{m[1]}*{m[2]}", guard=b.guard)
    prev = b.guard
    b.row("guard", f"asm_g{i}", "", T("guard", i=i), f"AND({{{prev}}},{{{det}}}<>0)" if prev else f"{{{det}}}<>0")
    b.guard = f"asm_g{i}"
    b.calc(f"det_g{i}", "", T("det"), f"{{{det}}}")
    b.section(f"accepted_g{i}", T("accepted"))
    _split(b, g, m, "", "x", "m", T("travel"))
    _accepted_rows(b, g)
    _split(b, g, m, "v", "vx", "m/s", T("velocity"))
    _split(b, g, m, "a", "ax", "m/s^2", T("acceleration"))
    b.place_links(la, lb)
    _kulisa_point_rows(b, g)


def _split(b: Builder, g: Group, m, q: str, pre: str, unit: str, what):
    """J1's position (from G), velocity or acceleration along u_g and u_s (Cramer, slide 20)."""
    i, (J1, K) = g.index, g.joints
    if q:
        rhs = (b.p(pre, J1), b.p(pre.replace("x", "y"), J1))
    else:
        rhs = (f"({b.p('x', J1)}-{{gx_g{i}}})", f"({b.p('y', J1)}-{{gy_g{i}}})")
    cramer_rows(b, m, f"D_g{i}", ((f"{q}s_{K}", unit, T("s_K", what=what, K=K)),
                                  (f"{q}s_{J1}", unit, T("s_J1", what=what, J1=J1, K=K))),
                rhs, (f"chk_{q or 'p'}sys_g{i}", T("sys", what=what)))


def _accepted_rows(b: Builder, g: Group):
    """The block and the kulisa do not turn: their angle is the slot's, their rates 0; the
    check of the accepted travels."""
    i, (la, lb), (J1, K) = g.index, g.links, g.joints
    ug, us = _guide_slot(g)
    b.accepted(f"phi_{la}", "deg", T("phi_a", la=la, lb=lb), f"MOD({{alpha_g{i}}},360)")
    b.accepted(f"phi_{lb}", "deg", T("phi_b", lb=lb), f"{{phi_{la}}}")
    cos_sin_rows(b, la)
    cos_sin_rows(b, lb)
    cs, ss = f"{{cos_{la}}}", f"{{sin_{la}}}"
    b.check(f"chk_acc_g{i}", "m", T("chk_acc", K=K, J1=J1),
            f"ABS({{gx_g{i}}}+{{s_{K}}}*{ug[0]}+{{s_{J1}}}*{cs}-{b.p('x', J1)})"
            f"+ABS({{gy_g{i}}}+{{s_{K}}}*{ug[1]}+{{s_{J1}}}*{ss}-{b.p('y', J1)})")
    for k, what in ((la, T("block")), (lb, T("kulisa"))):
        b.accepted(f"omega_{k}", "rad/s", T("omega", what=what, k=k), "0")
        b.accepted(f"eps_{k}", "rad/s^2", T("eps", what=what, k=k), "0")
    turns_with_check(b, f"chk_rot_g{i}", [(f"phi_{la}", us[0], us[1]), (f"phi_{lb}", us[0], us[1])], [],
                     T("rot", la=la, lb=lb))


def _kulisa_point_rows(b: Builder, g: Group):
    """The kulisa's point K on its guide, and J1 = K + s_J1 u_s once more in position,
    velocity and acceleration (the slot does not turn: no Coriolis term)."""
    i, lb, (J1, K) = g.index, g.links[1], g.joints
    ug, _ = _guide_slot(g)
    cs, ss = f"{{cos_{g.links[0]}}}", f"{{sin_{g.links[0]}}}"
    b.section(f"point_{K}", T("point_K", K=K, lb=lb))
    motion_rows(b, K, T("point", K=K), f"{{gx_g{i}}}+{{s_{K}}}*{ug[0]}", f"{{gy_g{i}}}+{{s_{K}}}*{ug[1]}",
                f"{{vs_{K}}}*{ug[0]}", f"{{vs_{K}}}*{ug[1]}", f"{{as_{K}}}*{ug[0]}", f"{{as_{K}}}*{ug[1]}")
    b.check(f"chk_{J1}_g{i}", "m", T("chk_J1", K=K, J1=J1),
            f"ABS({{x_{K}}}+{{s_{J1}}}*{cs}-{b.p('x', J1)})+ABS({{y_{K}}}+{{s_{J1}}}*{ss}-{b.p('y', J1)})")
    b.check(f"chk_v_{J1}_g{i}", "m/s", T("chk_v_J1", K=K, J1=J1),
            f"ABS({{vx_{K}}}+{{vs_{J1}}}*{cs}-{b.p('vx', J1)})+ABS({{vy_{K}}}+{{vs_{J1}}}*{ss}-{b.p('vy', J1)})")
    # the same for accelerations: the slot does not turn, so no Coriolis term; without it
    # K's acceleration rows had only the numeric derivative (inactive above 3 deg)
    b.check(f"chk_a_{J1}_g{i}", "m/s^2", T("chk_a_J1", K=K, J1=J1),
            f"ABS({{ax_{K}}}+{{as_{J1}}}*{cs}-{b.p('ax', J1)})+ABS({{ay_{K}}}+{{as_{J1}}}*{ss}-{b.p('ay', J1)})")
    fd_checks(b, K)


# --------------------------------------------------------------------------- kinetostatics
def reaction_forces(fa, fb, ma_j1, mb_k, j1_minus_k, gamma_rad: float, alpha_rad: float):
    """The group's pair forces from its links' loads (pure arithmetic over arrays).

    fa, fb: resultant loads (x, y) on block a and yoke b; ma_j1: a's moment about J1; mb_k:
    b's moment about K. The yoke acts on the block with P n_s through J1 and a couple C, the
    frame on the yoke with Q n_g through K and a couple Cq; R1 is the force on the block at
    J1. Block: R1 + P n_s + Fa = 0, C + Ma(J1) = 0. Yoke: -P n_s + Q n_g + Fb = 0,
    (J1 - K) x (-P n_s) - C + Cq + Mb(K) = 0. Forces on b: P n_s - Q n_g = Fb (Cramer, the
    determinant sin(gamma - alpha) up to sign).
    Returns R1, (P n_s, C) the yoke on the block, (Q n_g, Cq) the frame on the yoke.
    """
    nsx, nsy = -np.sin(alpha_rad), np.cos(alpha_rad)
    ngx, ngy = -np.sin(gamma_rad), np.cos(gamma_rad)
    _, inv = inverse_det(nsx, -ngx, nsy, -ngy)
    p, q = cramer(nsx, -ngx, nsy, -ngy, fb[0], fb[1], inv)
    c = -ma_j1
    dx, dy = j1_minus_k
    cq = c - mb_k + dx * p * nsy - dy * p * nsx
    r1 = (-p * nsx - fa[0], -p * nsy - fa[1])
    return r1, ((p * nsx, p * nsy), c), ((q * ngx, q * ngy), cq)


def pin_owner(g: Group) -> dict[str, int]:
    """K is a point of the kulisa b."""
    return {g.joints[1]: g.links[1]}


def pairs(g: Group, owner: dict[str, int]) -> list[Pair]:
    (j1, k), (a, b) = g.joints, g.links
    return [Pair(owner[j1], a, j1), Pair(a, b, j1, True), Pair(0, b, k, True)]


def reactions(g: Group, known, links, loads, owner) -> dict[str, tuple]:
    (J1, K), (a, b) = g.joints, g.links
    j1, kj = known[J1], known[K]
    r1, (p, c), (q, cq) = reaction_forces(loads[a].resultant(), loads[b].resultant(),
                                          loads[a].moment(j1.x, j1.y), loads[b].moment(kj.x, kj.y),
                                          (j1.x - kj.x, j1.y - kj.y), math.radians(g.guide.angle_deg),
                                          math.radians(g.slot_angle_deg))
    loads[owner[J1]].add(j1, -r1[0], -r1[1])
    loads[0].add(kj, -q[0], -q[1])
    loads[0].couple = loads[0].couple - cq
    return {f"{owner[J1]}_{a}": (r1[0], r1[1], None), f"{a}_{b}": (-p[0], -p[1], -c), f"0_{b}": (q[0], q[1], cq)}


def reaction_rows(b: Builder, g: Group, owner: dict[str, int], k: LoadRows):
    """The yoke's forces: P n_s - Q n_g = Q_b (Cramer), then the block's pin at J1."""
    i, (a, bl), (J1, K) = g.index, g.links, g.joints
    o1 = owner[J1]
    k.link_loads(a, J1)
    k.link_loads(bl, K)
    cs, ss = f"{{cos_{a}}}", f"{{sin_{a}}}"
    cg, sg = f"COS(RADIANS({{gamma_g{i}}}))", f"SIN(RADIANS({{gamma_g{i}}}))"
    m = (f"(-{ss})", sg, cs, f"(-{cg})")
    rhs = (f"{{Qx_{bl}}}", f"{{Qy_{bl}}}")
    det, P, Q = f"Delta_R_g{i}", f"P_g{i}", f"Qg_g{i}"
    b.calc(det, "", T("R_det"), f"{m[0]}*{m[3]}-{m[1]}*{m[2]}")
    b.calc(P, "N", T("P", J1=J1), f"({rhs[0]}*{m[3]}-{rhs[1]}*{m[1]})/{{{det}}}")
    b.calc(Q, "N", T("Q"), f"({m[0]}*{rhs[1]}-{m[2]}*{rhs[0]})/{{{det}}}")
    b.check(f"chk_Rsys_g{i}", "", T("chk_Rsys"),
            f"(ABS({m[0]}*{{{P}}}+{m[1]}*{{{Q}}}-{rhs[0]})+ABS({m[2]}*{{{P}}}+{m[3]}*{{{Q}}}-{rhs[1]}))"
            f"/(1+ABS({{Qx_{bl}}})+ABS({{Qy_{bl}}}))")
    t1, tab, t0 = f"{o1}_{a}", f"{a}_{bl}", f"0_{bl}"
    k.reaction(t1, f"{{{P}}}*{ss}-{{Qx_{a}}}", f"-{{{P}}}*{cs}-{{Qy_{a}}}", T("R_1", o=o1, a=a, J1=J1))
    k.reaction(tab, f"{{{P}}}*{ss}", f"-{{{P}}}*{cs}", T("R_ab", a=a, bl=bl, J1=J1))
    b.accepted(f"M_{tab}", "N m", T("M_ab", a=a, bl=bl), f"{{MQ_{a}}}")
    k.equilibrium(a, J1, [(J1, f"{{Rx_{t1}}}", f"{{Ry_{t1}}}"), (J1, f"(-{{Rx_{tab}}})", f"(-{{Ry_{tab}}})")],
                  f"(-{{M_{tab}}})")
    k.reaction(t0, f"-{{{Q}}}*{sg}", f"{{{Q}}}*{cg}", T("R_0", bl=bl, K=K))
    dx, dy = f"({b.p('x', J1)}-{{x_{K}}})", f"({b.p('y', J1)}-{{y_{K}}})"
    b.accepted(f"M_{t0}", "N m", T("M_0", bl=bl),
               f"-{{MQ_{a}}}-{{MQ_{bl}}}+{{{P}}}*({dx}*{cs}+{dy}*{ss})")
    k.equilibrium(bl, K, [(J1, f"{{Rx_{tab}}}", f"{{Ry_{tab}}}"), (K, f"{{Rx_{t0}}}", f"{{Ry_{t0}}}")],
                  f"{{M_{tab}}}+{{M_{t0}}}")
    k.opposite(o1, J1, t1)


# --------------------------------------------------------------------------- loop equations
def loop_lines(lib, j1, through, gamma, alpha):
    """F(q) = G + s_K u_g + s_J1 u_s - J1 = 0 in q = (s_K, s_J1), for any number type
    `lib` (sheetkin.studies.bench). j1: ((x, y), (vx, vy), (ax, ay)); through: (x, y) on the frame;
    gamma, alpha: angles in radians of lib's type. place gives K, the links'
    (alpha, 0, 0) twice and the slides (s_K, ...), (s_J1, ...)."""
    p1, v1, a1 = j1
    ug, us = (lib.cos(gamma), lib.sin(gamma)), (lib.cos(alpha), lib.sin(alpha))

    def F(q):
        return [through[i] + q[0] * ug[i] + q[1] * us[i] - p1[i] for i in (0, 1)]

    def J(q):
        return [[ug[0], us[0]], [ug[1], us[1]]]

    def b_v(q):
        return [v1[0], v1[1]]

    def b_a(q, qt):
        return [a1[0], a1[1]]

    def place(q, qt, qtt):
        k = (tuple(through[i] + q[0] * ug[i] for i in (0, 1)), (qt[0] * ug[0], qt[0] * ug[1]),
             (qtt[0] * ug[0], qtt[0] * ug[1]))
        still = (alpha, lib.num(0), lib.num(0))
        return k, (still, still), ((q[0], qt[0], qtt[0]), (q[1], qt[1], qtt[1]))
    return F, J, b_v, b_a, place


def loop(lib, g: Group, known, links):
    """J1 = G + s_K u_g + s_J1 u_s (loop_lines); q = (s_K, s_J1)."""
    (j1, k), n = g.joints, lib.num
    F, J, b_v, b_a, place_lines = loop_lines(lib, known[j1], (n(g.guide.point[0]), n(g.guide.point[1])),
                                             n(g.guide.angle_deg) * lib.pi() / 180,
                                             n(g.slot_angle_deg) * lib.pi() / 180)

    def place(q, qt, qtt):
        joint, rots, (sk, sj) = place_lines(q, qt, qtt)
        return {k: joint}, rots, {k: sk, j1: sj}
    return F, J, b_v, b_a, place


def side_ok(lib, g: Group, known, links, q, joints) -> bool:
    """A line crosses a line once: RPP has no branch."""
    return True


def discriminant(lib, g: Group, known, links):
    """sin^2(alpha - gamma): constant, positive for every scene the parser accepts."""
    return lib.sin((lib.num(g.slot_angle_deg) - lib.num(g.guide.angle_deg)) * lib.pi() / 180) ** 2


def unknowns(g: Group, sol) -> tuple[np.ndarray, np.ndarray]:
    j1, k = g.joints
    return sol.slides[k].s, sol.slides[j1].s


# --------------------------------------------------------------------------- stability families
# The Scotch yoke's toggle measure sin(alpha - gamma) is constant over the cycle: no crank
# angle is singular. What degenerates is the scene: the slot turned towards the direction
# of the yoke's guide, K runs off along it (s_K ~ 1/d, and so its rates). The family varies
# slot_angle_deg towards the guide's 30 deg (not along an axis, so the determinant
# cos(gamma) sin(alpha) - sin(gamma) cos(alpha) loses digits to cancellation as in a real
# scene) at one crank angle; within PARALLEL the parser refuses the scene.
STABILITY = (
    Family("parallel-slot", "RPP (Scotch yoke): the slot turned towards its guide's direction (K runs off)",
           crank_scene("Scotch yoke whose slot nearly runs along the yoke's guide", """\
[[group]]
type           = "RPP"
links          = [2, 3]
joints         = ["A", "K"]
slot_angle_deg = {value}
guide          = { through = "O", angle_deg = 30.0 }
""", phi0_deg=100.0), 1, 30.0, vary="slot_angle_deg"),
)
