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
from .rows import Builder, InputRow, LoadRows, cos_sin_rows, cramer_rows, fd_checks, motion_rows, turns_with_check

# --------------------------------------------------------------------------- what it is
KIND = "RPP"
LECTURE = "ВПП"
SLIDES = "кулисы, движущиеся прямолинейно"
TITLE = ("камень в J1 в пазу кулисы, движущейся прямолинейно по неподвижной направляющей (синусный механизм)",
         "block on J1 in the slot of a kulisa that moves straight along a fixed guide (Scotch yoke)")
KEYS = ("type", "links", "joints", "slot_angle_deg", "guide")
PARALLEL = 1e-9      # |sin(alpha - gamma)| below this: the slot runs along the guide, no K


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
    i, j1, gd = g.index, g.joints[0], g.guide
    return [InputRow(f"gx_g{i}", "m", f"направляющая кулисы {g.links[1]}: x точки",
                     f"kulisa {g.links[1]}'s guide: x of a point",
                     gd.point[0]),
            InputRow(f"gy_g{i}", "m", f"направляющая кулисы {g.links[1]}: y точки",
                     f"kulisa {g.links[1]}'s guide: y of a point",
                     gd.point[1]),
            InputRow(f"gamma_g{i}", "deg", "угол наклона направляющей кулисы", "the kulisa's guide's angle",
                     gd.angle_deg),
            InputRow(f"alpha_g{i}", "deg", f"угол паза кулисы (камень {j1})", f"the kulisa's slot angle (block {j1})",
                     g.slot_angle_deg)]


def with_inputs(g: Group, num) -> Group:
    i, gd = g.index, g.guide
    guide = dataclasses.replace(gd, point=(num(f"gx_g{i}", gd.point[0]), num(f"gy_g{i}", gd.point[1])),
                                angle_deg=num(f"gamma_g{i}", gd.angle_deg))
    return dataclasses.replace(g, params=Params(num(f"alpha_g{i}", g.slot_angle_deg), guide))


def rows(b: Builder, g: Group):
    """J1 = G + s_K u_g + s_J1 u_s: the point's position, velocity and acceleration each
    split along the guide and the slot by Cramer's rule (one constant matrix)."""
    i, (la, lb), (J1, K) = g.index, g.links, g.joints
    gx, gy = f"{{gx_g{i}}}", f"{{gy_g{i}}}"
    ug = (f"COS(RADIANS({{gamma_g{i}}}))", f"SIN(RADIANS({{gamma_g{i}}}))")
    b.section(f"group_{i}", f"Группа {i} (ВПП {J1}{K}): кулиса {lb}, движущаяся прямолинейно (синусный механизм)",
              f"Group {i} (RPP {J1}{K}): kulisa {lb} moving straight (Scotch yoke)")
    us = (f"COS(RADIANS({{alpha_g{i}}}))", f"SIN(RADIANS({{alpha_g{i}}}))")
    det = f"D_g{i}"
    m = (ug[0], us[0], ug[1], us[1])
    b.add(det, "", "определитель [u_g, u_s] = sin(alpha - gamma) (0: паз вдоль направляющей, K нет)",
          "determinant [u_g, u_s] = sin(alpha - gamma) (0: the slot along the guide, no K)", "calc",
          f"{m[0]}*{m[3]}-{m[1]}*{m[2]}", guard=b.guard)
    prev = b.guard
    b.add(f"asm_g{i}", "", f"группа {i} собирается (паз пересекает направляющую)",
          f"group {i} assembles (the slot crosses the guide)",
          "guard", f"AND({{{prev}}},{{{det}}}<>0)" if prev else f"{{{det}}}<>0")
    b.guard = f"asm_g{i}"
    b.add(f"det_g{i}", "", "sin(alpha - gamma): синус угла между пазом и направляющей",
          "sin(alpha - gamma): sine of the angle between the slot and the guide", "calc", f"{{{det}}}")
    b.section(f"accepted_g{i}", "Принятые значения: положение, скорость, ускорение вдоль направляющей и паза",
              "Accepted values: position, velocity, acceleration along the guide and the slot")
    systems = (("", "x", "m", "положение", "travel"), ("v", "vx", "m/s", "скорость", "velocity"),
               ("a", "ax", "m/s^2", "ускорение", "acceleration"))

    def split(q, pre, unit, ru, en):
        """J1's position (from G), velocity or acceleration along u_g and u_s (Cramer)."""
        if q:
            rhs = (b.p(pre, J1), b.p(pre.replace("x", "y"), J1))
        else:
            rhs = (f"({b.p('x', J1)}-{gx})", f"({b.p('y', J1)}-{gy})")
        cramer_rows(b, m, det, ((f"{q}s_{K}", unit, f"{ru} кулисы: {K} вдоль направляющей (Крамер)",
                                 f"{en} of the kulisa: {K} along the guide (Cramer)"),
                                (f"{q}s_{J1}", unit, f"{ru} камня {J1} вдоль паза от {K} (Крамер)",
                                 f"{en} of block {J1} along the slot from {K} (Cramer)")),
                    rhs, (f"chk_{q or 'p'}sys_g{i}", f"{ru}: невязка системы", f"{en}: residual of the system"))
    split(*systems[0])
    b.add(f"phi_{la}", "deg", f"угол паза (камень {la} и кулиса {lb} не вращаются)",
          f"the slot's angle (block {la} and kulisa {lb} do not turn)", "accepted", f"MOD({{alpha_g{i}}},360)")
    b.add(f"phi_{lb}", "deg", f"угол кулисы {lb} (= угол паза)", f"angle of kulisa {lb} (= the slot's)", "accepted",
          f"{{phi_{la}}}")
    cos_sin_rows(b, la, "", "")
    cos_sin_rows(b, lb, "", "")
    cs, ss = f"{{cos_{la}}}", f"{{sin_{la}}}"
    b.add(f"chk_acc_g{i}", "m", f"проверка принятых значений: G + s_{K} u_g + s_{J1} u_s - {J1}",
          f"check of the accepted values: G + s_{K} u_g + s_{J1} u_s - {J1}", "check",
          f"ABS({gx}+{{s_{K}}}*{ug[0]}+{{s_{J1}}}*{cs}-{b.p('x', J1)})"
          f"+ABS({gy}+{{s_{K}}}*{ug[1]}+{{s_{J1}}}*{ss}-{b.p('y', J1)})")
    for k, what in ((la, ("камня", "block")), (lb, ("кулисы", "kulisa"))):
        b.add(f"omega_{k}", "rad/s", f"угловая скорость {what[0]} {k}", f"angular velocity of {what[1]} {k}",
              "accepted", "0")
        b.add(f"eps_{k}", "rad/s^2", f"угловое ускорение {what[0]} {k}", f"angular acceleration of {what[1]} {k}",
              "accepted", "0")
    turns_with_check(b, f"chk_rot_g{i}", [(f"phi_{la}", us[0], us[1]), (f"phi_{lb}", us[0], us[1])], [],
                     f"камень {la} и кулиса {lb} повёрнуты по пазу (alpha)",
                     f"block {la} and kulisa {lb} point along the slot (alpha)")
    split(*systems[1])
    split(*systems[2])
    b.place_links(la, lb)
    b.section(f"point_{K}", f"Точка {K} кулисы {lb} на её направляющей", f"Point {K} of kulisa {lb} on its guide")
    motion_rows(b, K, f"точки {K}", f"point {K}", f"{gx}+{{s_{K}}}*{ug[0]}", f"{gy}+{{s_{K}}}*{ug[1]}",
                f"{{vs_{K}}}*{ug[0]}", f"{{vs_{K}}}*{ug[1]}", f"{{as_{K}}}*{ug[0]}", f"{{as_{K}}}*{ug[1]}")
    b.add(f"chk_{J1}_g{i}", "m", f"проверка: {K} + s_{J1} u_s совпадает с {J1}", f"check: {K} + s_{J1} u_s is {J1}",
          "check",
          f"ABS({{x_{K}}}+{{s_{J1}}}*{cs}-{b.p('x', J1)})+ABS({{y_{K}}}+{{s_{J1}}}*{ss}-{b.p('y', J1)})")
    b.add(
        f"chk_v_{J1}_g{i}",
        "m/s",
        f"проверка: скорость {K} + vs_{J1} u_s равна скорости {J1}",
        f"check: velocity of {K} + vs_{J1} u_s is {J1}'s",
        "check",
        f"ABS({{vx_{K}}}+{{vs_{J1}}}*{cs}-{b.p('vx', J1)})+ABS({{vy_{K}}}+{{vs_{J1}}}*{ss}-{b.p('vy', J1)})",
    )
    # the same for accelerations: the slot does not turn, so no Coriolis term; without it
    # K's acceleration rows had only the numeric derivative (inactive above 3 deg)
    b.add(
        f"chk_a_{J1}_g{i}",
        "m/s^2",
        f"проверка: ускорение {K} + as_{J1} u_s равно ускорению {J1} (не зависит от шага)",
        f"check: acceleration of {K} + as_{J1} u_s is {J1}'s (free of the step)",
        "check",
        f"ABS({{ax_{K}}}+{{as_{J1}}}*{cs}-{b.p('ax', J1)})+ABS({{ay_{K}}}+{{as_{J1}}}*{ss}-{b.p('ay', J1)})",
    )
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
    b.add(det, "", "определитель: sin(gamma - alpha)", "determinant: sin(gamma - alpha)", "calc",
          f"{m[0]}*{m[3]}-{m[1]}*{m[2]}")
    b.add(P, "N", f"нормальная сила паза на камень {J1} (Крамер)", f"normal force of the slot on block {J1} (Cramer)",
          "calc",
          f"({rhs[0]}*{m[3]}-{rhs[1]}*{m[1]})/{{{det}}}")
    b.add(Q, "N", "нормальная сила направляющей на кулису (Крамер)",
          "normal force of the guide on the kulisa (Cramer)", "calc",
          f"({m[0]}*{rhs[1]}-{m[2]}*{rhs[0]})/{{{det}}}")
    b.add(f"chk_Rsys_g{i}", "", "проверка: нормальные силы в их двух уравнениях",
          "check: the normal forces put back into their two equations", "check",
          f"(ABS({m[0]}*{{{P}}}+{m[1]}*{{{Q}}}-{rhs[0]})+ABS({m[2]}*{{{P}}}+{m[3]}*{{{Q}}}-{rhs[1]}))"
          f"/(1+ABS({{Qx_{bl}}})+ABS({{Qy_{bl}}}))")
    t1, tab, t0 = f"{o1}_{a}", f"{a}_{bl}", f"0_{bl}"
    k.reaction(t1, f"{{{P}}}*{ss}-{{Qx_{a}}}", f"-{{{P}}}*{cs}-{{Qy_{a}}}", f"звена {o1} на камень {a} в {J1}",
               f"of link {o1} on block {a} at {J1}")
    k.reaction(tab, f"{{{P}}}*{ss}", f"-{{{P}}}*{cs}", f"камня {a} на кулису {bl} (через {J1})",
               f"of block {a} on kulisa {bl} (through {J1})")
    b.add(f"M_{tab}", "N m", f"момент камня {a} на кулису {bl}", f"couple of block {a} on kulisa {bl}", "accepted",
          f"{{MQ_{a}}}")
    k.equilibrium(a, J1, [(J1, f"{{Rx_{t1}}}", f"{{Ry_{t1}}}"), (J1, f"(-{{Rx_{tab}}})", f"(-{{Ry_{tab}}})")],
                  f"(-{{M_{tab}}})")
    k.reaction(t0, f"-{{{Q}}}*{sg}", f"{{{Q}}}*{cg}", f"направляющей на кулису {bl} (через {K})",
               f"of the guide on kulisa {bl} (through {K})")
    dx, dy = f"({b.p('x', J1)}-{{x_{K}}})", f"({b.p('y', J1)}-{{y_{K}}})"
    b.add(f"M_{t0}", "N m", f"момент направляющей на кулису {bl}", f"couple of the guide on kulisa {bl}", "accepted",
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
