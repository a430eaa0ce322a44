"""RRP (ВВП): a coupler J1 N and a slider N on a guide (slides 13-15, 29-31; the lecture's
"two rockers with a slotted pair" when the guide is on a moving link).

Circle-line intersection. The guide is a straight line fixed on link k (the frame, k = 0, or
a moving link: a kulisa), through its point G with direction u = e(phi_k + A). Constraint:
    J1 + L e(phi_a) = G + s u,
unknowns phi_a and s = s_N (N's travel from G along the guide, measured in the guide's own
moving frame: the lecture's L_tek = |O1 D| for two rockers with a slotted pair). h, the
signed distance of J1 from the guide, gives N = K +- sqrt(L^2 - h^2) u, K the foot of the
perpendicular from J1 (the lecture's point K); branch +1 puts N ahead of K along u.
Velocities (Cramer): L omega_a e'(phi_a) - vs u = v_G + s omega_k n - v_J1 (n = u turned +90
deg); accelerations: the same matrix, the right side gains L omega_a^2 e(phi_a) and, for a
moving guide, the Coriolis 2 vs omega_k n, s eps_k n and -s omega_k^2 u. Link b, the slider,
turns with the guide: phi_b = phi_k + A. Toggle measure: det / L = cos(phi_a - phi_b), zero
with the coupler across the guide.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .group import Family, Group, Guide, crank_scene
from .motion import (
    GroupMotion,
    Motion,
    Pair,
    Rotation,
    Slide,
    at_dead_points_zero,
    cramer,
    guide_line,
    guide_loop,
    hinge,
    inverse_det,
    on_line,
    resultants,
    sqrt_or_nan,
)
from .parts import BlockPart, Parts, scene_guide
from .rows import (
    Builder,
    InputRow,
    LoadRows,
    Text,
    Texts,
    cos_sin_rows,
    cramer_rows,
    det_row,
    distance_check,
    fd_checks,
    group_guard,
    motion_rows,
    relative_velocity_check,
    residual,
    turns_with_check,
    via_link_checks,
)

# --------------------------------------------------------------------------- what it is
KIND = "RRP"
LECTURE = "ВВП"
SLIDES = "13-15, 29-31"
TITLE = Text(ru="шатун и ползун на направляющей (неподвижной или на подвижном звене: два коромысла с кулисной парой)",
             uk="шатун і повзун на напрямній (нерухомій або на рухомій ланці: два коромисла з кулісною парою)",
             en="coupler and slider on a guide (fixed, or on a moving link: two rockers with a slotted pair)")
KEYS = ("type", "links", "joints", "length", "guide", "branch")


# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language (fields: group i, coupler la, slider or block lb,
# joints J1 N, the guide's point G and link k). Every language has the same fields: where the
# English does not say one, it is written {field!s:.0} (formatted as nothing)
TEXTS = {
    "ru": {
        "L": "длина шатуна {la} ({J1}{N})",
        "gx": "направляющая ползуна {N}: x точки",
        "gy": "направляющая ползуна {N}: y точки",
        "gamma": "угол наклона направляющей",
        "gamma_k": "угол направляющей ползуна {N} к звену {k}",
        "branch": "ветвь решения группы {i} (+1 или -1)",
        "group": "Группа {i} (ВВП {J1}{N}, ползун на направляющей): слайды 13-15, 29-31",
        "h": "расстояние от {J1} до направляющей (влево +)",
        "along": "проекция {J1} на направляющую",
        "D": "дискриминант L^2 - h^2 (< 0: группа не собирается)",
        "branch_p": "ветвь +1",
        "branch_m": "ветвь -1",
        "s": "{br}: s = проекция {sign} sqrt(D)",
        "chk_branch": "проверка {br}: |{J1}{N}| - L{la}",
        "accepted": "Принятые значения",
        "s_N": "перемещение ползуна {N} вдоль направляющей",
        "phi_a": "угол шатуна {la} ({J1}->{N})",
        "phi_b": "угол ползуна {lb} (направляющая)",
        "chk_acc": "проверка принятых значений: {J1} + L e(phi) - {G} - s u",
        "G": "(gx_g{i}, gy_g{i})",
        "omega_b": "угловая скорость ползуна {lb}",
        "eps_b": "угловое ускорение ползуна {lb}",
        "det": "определитель: L cos(phi - gamma)",
        "toggle": "cos(phi - gamma) (около 0: мёртвое положение)",
        "omega_a": "угловая скорость шатуна {la} (Крамер)",
        "vs": "скорость ползуна {N} вдоль направляющей",
        "f1": "правая часть для ускорений f1",
        "f2": "правая часть для ускорений f2",
        "eps_a": "угловое ускорение шатуна {la}",
        "as": "ускорение ползуна {N} вдоль направляющей",
        "slider": "Ползун {N}",
        "of_slider": "ползуна {N}",
        "chk_L": "проверка: |{J1}{N}| - L{la}",
        "k_group": "Группа {i} (ВВП {J1}{N}: камень {N} на кулисе {k}, два коромысла с кулисной парой)",
        "ux": "cos угла направляющей: phi_{k} + gamma",
        "uy": "sin угла направляющей: phi_{k} + gamma",
        "k_along": "{G}K: проекция {J1} на направляющую",
        "xK": "x_K: основание перпендикуляра из {J1} на прямую {G}{N} (через cos и sin, не tg: "
              "конечно и для вертикальной прямой)",
        "yK": "y_K",
        "k_h": "h: расстояние от {J1} до прямой {G}{N} (влево +)",
        "chk_h": "проверка: h^2 = (x_K - x{J1})^2 + (y_K - y{J1})^2",
        "Ltek": "{br}: L_tek = {G}K {sign} sqrt(D)",
        "k_s_N": "L_tek: положение камня {N} на кулисе от {G}",
        "k_phi_a": "угол звена {la} ({J1}->{N})",
        "k_phi_b": "угол камня {lb} (= phi_{k} + gamma)",
        "k_cos": "cos угла камня {lb}",
        "k_sin": "sin угла камня {lb}",
        "k_chk_acc": "проверка принятых значений: {J1} + L e(phi) - {G} - L_tek u",
        "k_omega_b": "угловая скорость камня {lb} (= кулисы {k})",
        "k_eps_b": "угловое ускорение камня {lb}",
        "k_rot": "камень {lb} повёрнут по направляющей и вращается с кулисой {k}",
        "k_det": "определитель: L cos(phi - phi_направляющей)",
        "k_toggle": "cos угла шатуна к направляющей (около 0: мёртвое положение)",
        "k_omega_a": "угловая скорость звена {la} (Крамер)",
        "k_vs": "(L_tek)_t: скорость камня {N} по кулисе",
        "k_f1": "правая часть f1 (с кориолисовым ускорением 2 vs omega_k)",
        "k_f2": "правая часть f2",
        "k_eps_a": "угловое ускорение звена {la}",
        "k_as": "(L_tek)_tt: ускорение камня {N} по кулисе",
        "block": "Камень {N}: движение вместе с кулисой и по ней",
        "of_block": "камня {N}",
        "chk_line": "проверка: {N} на прямой {G}{N} кулисы {k}",
        "chk_Ltek_t": "проверка (L_tek)_t: (xD - a)(xD)_t + (yD - b)(yD)_t = L_tek (L_tek)_t",
        "chk_Ltek_tt": "проверка (L_tek)_tt: производная предыдущего равенства",
        "R_det": "определитель: ({J1}-{N}).u (0, когда шатун поперёк направляющей)",
        "R_1": "звена {o} на звено {a} в {J1}",
        "R_ab": "звена {a} на ползун {bl} в {N}",
        "R_g": "направляющей на ползун {bl} (через {N})",
        "M_g": "момент реакции направляющей на ползун {bl}",
    },
    "uk": {
        "L": "довжина шатуна {la} ({J1}{N})",
        "gx": "напрямна повзуна {N}: x точки",
        "gy": "напрямна повзуна {N}: y точки",
        "gamma": "кут нахилу напрямної",
        "gamma_k": "кут напрямної повзуна {N} до ланці {k}",
        "branch": "гілка розв'язку групи {i} (+1 або -1)",
        "group": "Група {i} (ООП {J1}{N}, повзун на напрямної): слайди 13-15, 29-31",
        "h": "відстань від {J1} до напрямної (ліворуч +)",
        "along": "проекція {J1} на напрямну",
        "D": "дискримінант L^2 - h^2 (< 0: група не збирається)",
        "branch_p": "гілка +1",
        "branch_m": "гілка -1",
        "s": "{br}: s = проекція {sign} sqrt(D)",
        "chk_branch": "перевірка {br}: |{J1}{N}| - L{la}",
        "accepted": "Прийняті значення",
        "s_N": "переміщення повзуна {N} уздовж напрямної",
        "phi_a": "кут шатуна {la} ({J1}->{N})",
        "phi_b": "кут повзуна {lb} (напрямна)",
        "chk_acc": "перевірка прийнятих значень: {J1} + L e(phi) - {G} - s u",
        "G": "(gx_g{i}, gy_g{i})",
        "omega_b": "кутова швидкість повзуна {lb}",
        "eps_b": "кутове прискорення повзуна {lb}",
        "det": "визначник: L cos(phi - gamma)",
        "toggle": "cos(phi - gamma) (близько 0: мертве положення)",
        "omega_a": "кутова швидкість шатуна {la} (Крамер)",
        "vs": "швидкість повзуна {N} уздовж напрямної",
        "f1": "права частина для прискорень f1",
        "f2": "права частина для прискорень f2",
        "eps_a": "кутове прискорення шатуна {la}",
        "as": "прискорення повзуна {N} уздовж напрямної",
        "slider": "Повзун {N}",
        "of_slider": "повзуна {N}",
        "chk_L": "перевірка: |{J1}{N}| - L{la}",
        "k_group": "Група {i} (ООП {J1}{N}: камінь {N} на кулісі {k}, два коромисла з кулісної парою)",
        "ux": "cos кута напрямної: phi_{k} + gamma",
        "uy": "sin кута напрямної: phi_{k} + gamma",
        "k_along": "{G}K: проекція {J1} на напрямну",
        "xK": "x_K: основа перпендикуляра из {J1} на пряму {G}{N} (через cos і sin, не tg: скінченно і для "
              "вертикальної прямої)",
        "yK": "y_K",
        "k_h": "h: відстань від {J1} до прямої {G}{N} (ліворуч +)",
        "chk_h": "перевірка: h^2 = (x_K - x{J1})^2 + (y_K - y{J1})^2",
        "Ltek": "{br}: L_tek = {G}K {sign} sqrt(D)",
        "k_s_N": "L_tek: положення каменя {N} на кулісі від {G}",
        "k_phi_a": "кут ланки {la} ({J1}->{N})",
        "k_phi_b": "кут каменя {lb} (= phi_{k} + gamma)",
        "k_cos": "cos кута каменя {lb}",
        "k_sin": "sin кута каменя {lb}",
        "k_chk_acc": "перевірка прийнятих значень: {J1} + L e(phi) - {G} - L_tek u",
        "k_omega_b": "кутова швидкість каменя {lb} (= куліси {k})",
        "k_eps_b": "кутове прискорення каменя {lb}",
        "k_rot": "камінь {lb} повернутий за напрямної і обертається з кулісою {k}",
        "k_det": "визначник: L cos(phi - phi_напрямної)",
        "k_toggle": "cos кута шатуна до напрямної (близько 0: мертве положення)",
        "k_omega_a": "кутова швидкість ланки {la} (Крамер)",
        "k_vs": "(L_tek)_t: швидкість каменя {N} за кулісі",
        "k_f1": "права частина f1 (з коріолісовим прискоренням 2 vs omega_k)",
        "k_f2": "права частина f2",
        "k_eps_a": "кутове прискорення ланки {la}",
        "k_as": "(L_tek)_tt: прискорення каменя {N} за кулісі",
        "block": "Камінь {N}: рух разом з кулісою і за неї",
        "of_block": "каменя {N}",
        "chk_line": "перевірка: {N} на прямої {G}{N} куліси {k}",
        "chk_Ltek_t": "перевірка (L_tek)_t: (xD - a)(xD)_t + (yD - b)(yD)_t = L_tek (L_tek)_t",
        "chk_Ltek_tt": "перевірка (L_tek)_tt: похідна попереднього рівності",
        "R_det": "визначник: ({J1}-{N}).u (0, коли шатун поперек напрямної)",
        "R_1": "ланки {o} на ланку {a} в {J1}",
        "R_ab": "ланки {a} на повзун {bl} в {N}",
        "R_g": "напрямної на повзун {bl} (через {N})",
        "M_g": "момент реакції напрямної на повзун {bl}",
    },
    "en": {
        "L": "length of coupler {la} ({J1}{N})",
        "gx": "slider {N}'s guide: x of a point",
        "gy": "slider {N}'s guide: y of a point",
        "gamma": "the guide's angle",
        "gamma_k": "angle of slider {N}'s guide to link {k}",
        "branch": "solution branch of group {i} (+1 or -1)",
        "group": "Group {i} (RRP {J1}{N}, slider on a fixed guide): slides 13-15, 29-31",
        "h": "distance of {J1} from the guide (left +)",
        "along": "{J1}'s foot on the guide",
        "D": "discriminant L^2 - h^2 (< 0: cannot assemble)",
        "branch_p": "branch +1",
        "branch_m": "branch -1",
        "s": "{br}: s = foot {sign} sqrt(D)",
        "chk_branch": "check {br}: |{J1}{N}| - L{la}",
        "accepted": "Accepted values",
        "s_N": "travel of slider {N} along the guide",
        "phi_a": "angle of coupler {la} ({J1}->{N})",
        "phi_b": "angle of slider {lb} (the guide)",
        "chk_acc": "check of the accepted values: {J1} + L e(phi) - {G} - s u",
        "G": "G{i!s:.0}",
        "omega_b": "angular velocity of slider {lb}",
        "eps_b": "angular acceleration of slider {lb}",
        "det": "determinant: L cos(phi - gamma)",
        "toggle": "cos(phi - gamma) (near 0: toggle)",
        "omega_a": "angular velocity of coupler {la} (Cramer)",
        "vs": "velocity of slider {N} along the guide",
        "f1": "right side of the acceleration system f1",
        "f2": "right side of the acceleration system f2",
        "eps_a": "angular acceleration of coupler {la}",
        "as": "acceleration of slider {N} along the guide",
        "slider": "Slider {N}",
        "of_slider": "slider {N}",
        "chk_L": "check: |{J1}{N}| - L{la}",
        "k_group": "Group {i} (RRP {J1}{N}: block {N} on the kulisa {k}, two rockers with a slotted pair)",
        "ux": "cos of the guide's angle: phi_{k} + gamma",
        "uy": "sin of the guide's angle: phi_{k} + gamma",
        "k_along": "{G}K: {J1}'s foot on the guide",
        "xK": "x_K: foot of the perpendicular from {J1} on line {G}{N} (by cos and sin, not tg: "
              "finite for a vertical line too)",
        "yK": "y_K",
        "k_h": "h: distance of {J1} from line {G}{N} (left +)",
        "chk_h": "check: h^2 = (x_K - x{J1})^2 + (y_K - y{J1})^2",
        "Ltek": "{br}: L_tek = {G}K {sign} sqrt(D)",
        "k_s_N": "L_tek: block {N}'s place on the kulisa from {G}",
        "k_phi_a": "angle of link {la} ({J1}->{N})",
        "k_phi_b": "angle of block {lb} (= phi_{k} + gamma)",
        "k_cos": "cos of block {lb}'s angle",
        "k_sin": "sin of block {lb}'s angle",
        "k_chk_acc": "check of the accepted values: {J1} + L e(phi) - {G} - L_tek u",
        "k_omega_b": "angular velocity of block {lb} (= kulisa {k}'s)",
        "k_eps_b": "angular acceleration of block {lb}",
        "k_rot": "block {lb} points along the guide and turns with the kulisa {k}",
        "k_det": "determinant: L cos(phi - the guide's angle)",
        "k_toggle": "cos of the coupler's angle to the guide (near 0: toggle)",
        "k_omega_a": "angular velocity of link {la} (Cramer)",
        "k_vs": "(L_tek)_t: velocity of block {N} along the kulisa",
        "k_f1": "right side f1 (with the Coriolis term 2 vs omega_k)",
        "k_f2": "right side f2",
        "k_eps_a": "angular acceleration of link {la}",
        "k_as": "(L_tek)_tt: acceleration of block {N} along the kulisa",
        "block": "Block {N}: carried by the kulisa and sliding on it",
        "of_block": "block {N}",
        "chk_line": "check: {N} on the kulisa {k}'s line{G!s:.0}",
        "chk_Ltek_t": "check of (L_tek)_t: (xD - a)(xD)_t + (yD - b)(yD)_t = L_tek (L_tek)_t",
        "chk_Ltek_tt": "check of (L_tek)_tt: the derivative of the equation above",
        "R_det": "determinant: ({J1}-{N}).u (0 with the coupler across the guide)",
        "R_1": "of link {o} on link {a} at {J1}",
        "R_ab": "of link {a} on slider {bl} at {N}",
        "R_g": "of the guide on slider {bl} (through {N})",
        "M_g": "couple of the guide on slider {bl}",
    },
}
T = Texts(TEXTS)


# --------------------------------------------------------------------------- scene keys
@dataclass(frozen=True)
class Params:
    length: float           # |J1 N|, the coupler (link a)
    guide: Guide
    branch: int             # +1: N ahead of the foot K of the perpendicular from J1

    @property
    def lengths(self) -> tuple[float]:
        return (self.length,)



def parse(tbl, frame) -> tuple[tuple[str, ...], Params]:
    joints = tbl.array("joints", 2, "name")
    if joints[1] == joints[0]:
        tbl.fail("joints", f"the new joint '{joints[1]}' (second name) must differ from the "
                           f"known joint(s) it is attached to, got {list(joints)}")
    branch = tbl.get("branch", "an integer")
    if branch not in (1, -1):
        tbl.fail("branch", f"expected +1 or -1, got {branch}")
    length = tbl.positive("length")
    return joints, Params(length, tbl.guide("guide", frame), branch)


def needs(g: Group) -> list[str]:
    return [g.joints[0]] + ([g.guide.through] if g.guide.moving else [])


def on_links(g: Group) -> list[tuple[str, str, int]]:
    """(key, point, link): a moving guide's `through` must be a point of its link."""
    return [("guide.through", g.guide.through, g.guide.link)] if g.guide.moving else []


def new_joints(g: Group) -> list[str]:
    return [g.joints[1]]


def carries(g: Group) -> dict[int, list[str]]:
    (j1, n), (a, b) = g.joints, g.links
    return {a: [j1, n], b: [n]}


def sliders(g: Group) -> list[str]:
    return [g.joints[1]]


def fourbar(g: Group, crank_joint: str, frame) -> None:
    """Not a four-bar's dyad (only an RRR closes one with the crank: sheetkin.studies.synthesis)."""
    return None


def parts(g: Group) -> Parts:
    """The coupler J1 N, and the slider's block (link b) at N on the guide; the guide's
    angle is the input gamma_g<i>, its point on the frame gx_g<i>, gy_g<i>."""
    (j1, n), (a, b), i = g.joints, g.links, g.index
    guide = scene_guide(g.guide, n, i, f"gamma_g{i}", (f"gx_g{i}", f"gy_g{i}"))
    return Parts({a: (j1, n), b: (n,)}, (guide,), (BlockPart(b, n, guide),))


# --------------------------------------------------------------------------- positions and rates
def solve_rrp(j1: Motion, length: float, origin: Motion, u: Rotation, branch: int):
    """J1 + L e(phi) = G + s u: h, the signed distance of J1 from the guide, gives the
    coupler's angle to the guide, sin(mu) = h / L (slides 13-15, 29); N lies sqrt(L^2 - h^2)
    ahead (+1) or behind (-1) the foot K. Returns N, the coupler's rotation, the slide,
    the discriminant and the toggle measure."""
    ux, uy, wk, ek = u.c, u.s, u.omega, u.eps
    dx, dy = j1.x - origin.x, j1.y - origin.y
    along = dx * ux + dy * uy
    h = -dx * uy + dy * ux                     # left of the guide is positive
    disc = at_dead_points_zero(length * length - h * h, length * length)
    ahead = branch * sqrt_or_nan(disc)
    s = along + ahead
    c2, s2 = (ahead * ux + h * uy) / length, (ahead * uy - h * ux) / length
    # velocities: L omega e_perp(phi) - vs u = v_G + s omega_k n - v_J1
    m11, m12, m21, m22 = -length * s2, -ux, length * c2, -uy
    det, inv = inverse_det(m11, m12, m21, m22)
    w2, vs = cramer(m11, m12, m21, m22, origin.vx - s * wk * uy - j1.vx, origin.vy + s * wk * ux - j1.vy, inv)
    # accelerations: + L omega^2 e(phi) and the moving guide's 2 vs omega_k n + s eps_k n - s omega_k^2 u
    tn, tu = 2.0 * vs * wk + s * ek, -s * wk * wk
    b1 = origin.ax - j1.ax + length * w2 * w2 * c2 + tu * ux - tn * uy
    b2 = origin.ay - j1.ay + length * w2 * w2 * s2 + tu * uy + tn * ux
    e2, as_ = cramer(m11, m12, m21, m22, b1, b2, inv)
    slide = Slide(s, vs, as_)
    return on_line(origin, u, slide), Rotation(c2, s2, w2, e2), slide, disc, det / length


def solve(g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion:
    (j1, n), (a, b) = g.joints, g.links
    origin, u = guide_line(g.guide, known, rot)
    joint, ra, slide, disc, toggle = solve_rrp(known[j1], g.length, origin, u, g.branch)
    zero = np.zeros_like(slide.s)
    rb = Rotation(u.c + zero, u.s + zero, u.omega + zero, u.eps + zero)
    return GroupMotion({n: joint}, {a: ra, b: rb}, {n: slide}, disc, toggle)


# --------------------------------------------------------------------------- the workbook
def input_rows(g: Group) -> list[InputRow]:
    (j1, n), la, i, gd = g.joints, g.links[0], g.index, g.guide
    out = [InputRow(f"L{la}", "m", T("L", la=la, J1=j1, N=n), g.length, True)]
    if not gd.moving:
        out += [InputRow(f"gx_g{i}", "m", T("gx", N=n), gd.point[0]),
                InputRow(f"gy_g{i}", "m", T("gy", N=n), gd.point[1]),
                InputRow(f"gamma_g{i}", "deg", T("gamma"), gd.angle_deg)]
    else:
        out += [InputRow(f"gamma_g{i}", "deg", T("gamma_k", N=n, k=gd.link), gd.angle_deg)]
    return out + [InputRow(f"branch_g{i}", "", T("branch", i=i), g.branch)]


def with_inputs(g: Group, num) -> Group:
    i, gd = g.index, g.guide
    point = (num(f"gx_g{i}", gd.point[0]), num(f"gy_g{i}", gd.point[1])) if not gd.moving else None
    guide = dataclasses.replace(gd, point=point, angle_deg=num(f"gamma_g{i}", gd.angle_deg))
    return dataclasses.replace(g, params=Params(num(f"L{g.links[0]}", g.length), guide,
                                                int(num(f"branch_g{i}", g.branch, choices=(1, -1)))))


def rows(b: Builder, g: Group):
    if g.guide.moving:
        _moving_guide_rows(b, g)
    else:
        _fixed_guide_rows(b, g)


def _fixed_guide_rows(b: Builder, g: Group):
    """Lecture slides 13-15 and 29-31: coupler J1 N, slider N on the fixed guide G + s u."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    b.section(f"group_{i}", T("group", i=i, J1=J1, N=N))
    _slider_line_rows(b, g)
    b.section(f"accepted_g{i}", T("accepted"))
    _slider_accepted_rows(b, g)
    _slider_rate_rows(b, g)
    b.place_links(la, lb)
    _slider_joint_rows(b, g)


def _guide(g: Group) -> tuple[str, str, str]:
    """The fixed guide's point G (its input rows) and angle, as formulas."""
    i = g.index
    return f"{{gx_g{i}}}", f"{{gy_g{i}}}", f"RADIANS({{gamma_g{i}}})"


def _slider_line_rows(b: Builder, g: Group):
    """J1's distance h from the guide and its foot on it, D = L^2 - h^2 and the guard, the
    slider's travel s on both branches, each with its check (slides 13-14)."""
    i, la, (J1, N) = g.index, g.links[0], g.joints
    L = f"{{L{la}}}"
    gx, gy, gam = _guide(g)
    h, al, D = f"h_g{i}", f"along_g{i}", f"D_g{i}"
    b.calc(h, "m", T("h", J1=J1), f"-({b.p('x', J1)}-{gx})*SIN({gam})+({b.p('y', J1)}-{gy})*COS({gam})",
           guard=b.guard)
    b.calc(al, "m", T("along", J1=J1), f"({b.p('x', J1)}-{gx})*COS({gam})+({b.p('y', J1)}-{gy})*SIN({gam})",
           guard=b.guard)
    b.calc(D, "m^2", T("D"), f"{L}^2-{{{h}}}^2", guard=b.guard)
    group_guard(b, g, D, f"{L}^2")
    for s, sign, br in (("p", "+", T("branch_p")), ("m", "-", T("branch_m"))):
        b.calc(f"s_{s}_g{i}", "m", T("s", br=br, sign=sign), f"{{{al}}}{sign}SQRT({{{D}}})")
        b.check(f"chk_{s}_g{i}", "m", T("chk_branch", br=br, J1=J1, N=N, la=la),
                f"SQRT(({gx}+{{s_{s}_g{i}}}*COS({gam})-{b.p('x', J1)})^2"
                f"+({gy}+{{s_{s}_g{i}}}*SIN({gam})-{b.p('y', J1)})^2)-{L}")


def _slider_accepted_rows(b: Builder, g: Group):
    """The slider's travel on the scene's branch, the coupler's and the slider's angles, the
    check of constraint J1 + L e(phi) = G + s u; the slider does not turn."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    L = f"{{L{la}}}"
    gx, gy, gam = _guide(g)
    sN = f"s_{N}"
    b.accepted(sN, "m", T("s_N", N=N), f"IF({{branch_g{i}}}=1,{{s_p_g{i}}},{{s_m_g{i}}})")
    b.accepted(f"phi_{la}", "deg", T("phi_a", la=la, J1=J1, N=N),
               f"MOD(DEGREES(ATAN2({gx}+{{{sN}}}*COS({gam})-{b.p('x', J1)},{gy}+{{{sN}}}*SIN({gam})"
               f"-{b.p('y', J1)})),360)")
    b.accepted(f"phi_{lb}", "deg", T("phi_b", lb=lb), f"MOD({{gamma_g{i}}},360)")
    cos_sin_rows(b, la)
    cos_sin_rows(b, lb)
    ca, sa, ux, uy = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    # the English says J1 and G; the Russian names the joint and the guide's input rows
    b.check(f"chk_acc_g{i}", "m", T("chk_acc", J1=Text(J1, J1, "J1"), G=T("G", i=i)),
            f"ABS({b.p('x', J1)}+{L}*{ca}-{gx}-{{{sN}}}*{ux})+ABS({b.p('y', J1)}+{L}*{sa}-{gy}-{{{sN}}}*{uy})")
    b.accepted(f"omega_{lb}", "rad/s", T("omega_b", lb=lb), "0")
    b.accepted(f"eps_{lb}", "rad/s^2", T("eps_b", lb=lb), "0")


def _slider_rate_rows(b: Builder, g: Group):
    """L omega e_perp(phi) - vs u = -v_J1 by Cramer (m11 = -L sin, m12 = -ux, m21 = L cos,
    m22 = -uy; slide 15), then the accelerations with the same matrix (slides 29-31)."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    L = f"{{L{la}}}"
    ca, sa, ux, uy = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    det = f"Delta_g{i}"
    m = (f"(-{L}*{sa})", f"(-{ux})", f"({L}*{ca})", f"(-{uy})")
    det_row(b, det, m, "m", T("det"))
    b.calc(f"det_g{i}", "", T("toggle"), f"{{{det}}}/{L}")
    b1, b2 = f"(-{b.p('vx', J1)})", f"(-{b.p('vy', J1)})"
    cramer_rows(b, m, det, ((f"omega_{la}", "rad/s", T("omega_a", la=la)), (f"vs_{N}", "m/s", T("vs", N=N))),
                (b1, b2), residual(i, "v"))
    f1, f2 = f"f1_g{i}", f"f2_g{i}"
    wa = f"{{omega_{la}}}"
    b.calc(f1, "m/s^2", T("f1"), f"-{b.p('ax', J1)}+{L}*{wa}^2*{ca}")
    b.calc(f2, "m/s^2", T("f2"), f"-{b.p('ay', J1)}+{L}*{wa}^2*{sa}")
    cramer_rows(b, m, det, ((f"eps_{la}", "rad/s^2", T("eps_a", la=la)), (f"as_{N}", "m/s^2", T("as", N=N))),
                (f"{{{f1}}}", f"{{{f2}}}"), residual(i, "a"))


def _slider_joint_rows(b: Builder, g: Group):
    """The slider N on the guide, G + s u, and its checks through the coupler."""
    (la, lb), (J1, N) = g.links, g.joints
    gx, gy, _ = _guide(g)
    ux, uy = f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    b.section(f"point_{N}", T("slider", N=N))
    s, vs, as_ = f"{{s_{N}}}", f"{{vs_{N}}}", f"{{as_{N}}}"
    motion_rows(b, N, T("of_slider", N=N), f"{gx}+{s}*{ux}", f"{gy}+{s}*{uy}",
                f"{vs}*{ux}", f"{vs}*{uy}", f"{as_}*{ux}", f"{as_}*{uy}")
    distance_check(b, f"chk_{J1}{N}", J1, N, f"{{L{la}}}", T("chk_L", J1=J1, N=N, la=la))
    relative_velocity_check(b, N, J1)
    via_link_checks(b, N, J1, la, f"omega_{la}, eps_{la}")
    fd_checks(b, N)


def _moving_guide_rows(b: Builder, g: Group):
    """The lecture's two rockers with a slotted pair ("Два коромысла с кулисной парой" 1-3):
    the guide is the line O1 B of rocker k through G = O1; K is the foot of the perpendicular
    from J1 = O2, h = |O2 K|, the block N = D slides along it, L_tek = s_N = G D. The lecture
    writes the lines as y = b + tg(xi)(x - a), which a vertical guide makes infinite; these
    rows use the guide's cos and sin instead (the same point K, h and D)."""
    _kulisa_line_rows(b, g)
    _kulisa_accepted_rows(b, g)
    _kulisa_rate_rows(b, g)
    b.place_links(*g.links)
    _kulisa_joint_rows(b, g)


def _kulisa(b: Builder, g: Group) -> tuple:
    """The names the kulisa's rows share: i, links a and b, J1, N, the guide's point G on
    link k, {L}, the cos, sin, omega, eps of link k, the guide's direction {ux}, {uy} and
    {s_N}."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    G, k = g.guide.through, g.guide.link
    ck, sk, wk, ek = (f"{{{r}}}" for r in b.rot[k])
    return i, la, lb, J1, N, G, k, f"{{L{la}}}", ck, sk, wk, ek, f"{{ux_g{i}}}", f"{{uy_g{i}}}", f"{{s_{N}}}"


def _kulisa_line_rows(b: Builder, g: Group) -> None:
    """The guide's direction, the foot K of the perpendicular from J1, h, D, both branches."""
    i, la, lb, J1, N, G, k, L, ck, sk, wk, ek, U, V, S = _kulisa(b, g)
    b.section(f"group_{i}", T("k_group", i=i, J1=J1, N=N, k=k))
    ux, uy = f"ux_g{i}", f"uy_g{i}"
    gam = f"RADIANS({{gamma_g{i}}})"
    b.calc(ux, "", T("ux", k=k), f"{ck}*COS({gam})-{sk}*SIN({gam})", guard=b.guard)
    b.calc(uy, "", T("uy", k=k), f"{sk}*COS({gam})+{ck}*SIN({gam})", guard=b.guard)
    U, V = f"{{{ux}}}", f"{{{uy}}}"
    al, xK, yK, h, D = f"along_g{i}", f"xK_g{i}", f"yK_g{i}", f"h_g{i}", f"D_g{i}"
    dx, dy = f"({b.p('x', J1)}-{b.p('x', G)})", f"({b.p('y', J1)}-{b.p('y', G)})"
    b.calc(al, "m", T("k_along", G=G, J1=J1), f"{dx}*{U}+{dy}*{V}", guard=b.guard)
    b.calc(xK, "m", T("xK", J1=J1, G=G, N=N), f"{b.p('x', G)}+{{{al}}}*{U}", guard=b.guard)
    b.calc(yK, "m", T("yK"), f"{b.p('y', G)}+{{{al}}}*{V}", guard=b.guard)
    b.calc(h, "m", T("k_h", J1=J1, G=G, N=N), f"-{dx}*{V}+{dy}*{U}", guard=b.guard)
    b.check(f"chk_h_g{i}", "m", T("chk_h", J1=J1),
            f"SQRT(({{{xK}}}-{b.p('x', J1)})^2+({{{yK}}}-{b.p('y', J1)})^2)-ABS({{{h}}})")
    b.calc(D, "m^2", T("D"), f"{L}^2-{{{h}}}^2")
    group_guard(b, g, D, f"{L}^2")
    for s, sign, br in (("p", "+", T("branch_p")), ("m", "-", T("branch_m"))):
        b.calc(f"s_{s}_g{i}", "m", T("Ltek", br=br, G=G, sign=sign), f"{{{al}}}{sign}SQRT({{{D}}})")
        b.check(f"chk_{s}_g{i}", "m", T("chk_branch", br=br, J1=J1, N=N, la=la),
                f"SQRT(({b.p('x', G)}+{{s_{s}_g{i}}}*{U}-{b.p('x', J1)})^2"
                f"+({b.p('y', G)}+{{s_{s}_g{i}}}*{V}-{b.p('y', J1)})^2)-{L}")


def _kulisa_accepted_rows(b: Builder, g: Group) -> None:
    """L_tek = s_N on the scene's branch, the links' angles; the block turns with the kulisa."""
    i, la, lb, J1, N, G, k, L, ck, sk, wk, ek, U, V, S = _kulisa(b, g)
    b.section(f"accepted_g{i}", T("accepted"))
    sN = f"s_{N}"
    S = f"{{{sN}}}"
    b.accepted(sN, "m", T("k_s_N", N=N, G=G), f"IF({{branch_g{i}}}=1,{{s_p_g{i}}},{{s_m_g{i}}})")
    b.accepted(f"phi_{la}", "deg", T("k_phi_a", la=la, J1=J1, N=N),
               f"MOD(DEGREES(ATAN2({b.p('x', G)}+{S}*{U}-{b.p('x', J1)},{b.p('y', G)}+{S}*{V}-{b.p('y', J1)})),360)")
    b.accepted(f"phi_{lb}", "deg", T("k_phi_b", lb=lb, k=k), f"MOD({{phi_{k}}}+{{gamma_g{i}}},360)")
    cos_sin_rows(b, la)
    ca, sa = f"{{cos_{la}}}", f"{{sin_{la}}}"
    b.calc(f"cos_{lb}", "", T("k_cos", lb=lb), U)
    b.calc(f"sin_{lb}", "", T("k_sin", lb=lb), V)
    b.check(f"chk_acc_g{i}", "m", T("k_chk_acc", J1=J1, G=G),
            f"ABS({b.p('x', J1)}+{L}*{ca}-{b.p('x', G)}-{S}*{U})+ABS({b.p('y', J1)}+{L}*{sa}-{b.p('y', G)}-{S}*{V})")
    b.accepted(f"omega_{lb}", "rad/s", T("k_omega_b", lb=lb, k=k), wk)
    b.accepted(f"eps_{lb}", "rad/s^2", T("k_eps_b", lb=lb), ek)
    turns_with_check(b, f"chk_rot_g{i}", [(f"phi_{lb}", U, V)], [(f"omega_{lb}", wk), (f"eps_{lb}", ek)],
                     T("k_rot", lb=lb, k=k))


def _kulisa_rate_rows(b: Builder, g: Group) -> None:
    """Cramer's rule for omega_a and (L_tek)_t, then (with the Coriolis term) eps_a, (L_tek)_tt."""
    i, la, lb, J1, N, G, k, L, ck, sk, wk, ek, U, V, S = _kulisa(b, g)
    ca, sa = f"{{cos_{la}}}", f"{{sin_{la}}}"
    # L omega e'(phi) - vs u = v_G + s omega_k n - v_J1, n = (-uy, ux)
    det = f"Delta_g{i}"
    m = (f"(-{L}*{sa})", f"(-{U})", f"({L}*{ca})", f"(-{V})")
    det_row(b, det, m, "m", T("k_det"))
    b.calc(f"det_g{i}", "", T("k_toggle"), f"{{{det}}}/{L}")
    b1 = f"({b.p('vx', G)}-{S}*{wk}*{V}-{b.p('vx', J1)})"
    b2 = f"({b.p('vy', G)}+{S}*{wk}*{U}-{b.p('vy', J1)})"
    cramer_rows(b, m, det, ((f"omega_{la}", "rad/s", T("k_omega_a", la=la)), (f"vs_{N}", "m/s", T("k_vs", N=N))),
                (b1, b2), residual(i, "v"))
    f1, f2 = f"f1_g{i}", f"f2_g{i}"
    wa, vs = f"{{omega_{la}}}", f"{{vs_{N}}}"
    tn = f"(2*{vs}*{wk}+{S}*{ek})"
    b.calc(f1, "m/s^2", T("k_f1"), f"{b.p('ax', G)}-{b.p('ax', J1)}+{L}*{wa}^2*{ca}-{S}*{wk}^2*{U}-{tn}*{V}")
    b.calc(f2, "m/s^2", T("k_f2"), f"{b.p('ay', G)}-{b.p('ay', J1)}+{L}*{wa}^2*{sa}-{S}*{wk}^2*{V}+{tn}*{U}")
    cramer_rows(b, m, det, ((f"eps_{la}", "rad/s^2", T("k_eps_a", la=la)), (f"as_{N}", "m/s^2", T("k_as", N=N))),
                (f"{{{f1}}}", f"{{{f2}}}"), residual(i, "a"))


def _kulisa_joint_rows(b: Builder, g: Group) -> None:
    """The block N carried by the kulisa and sliding on it, and its checks."""
    i, la, lb, J1, N, G, k, L, ck, sk, wk, ek, U, V, S = _kulisa(b, g)
    vs = f"{{vs_{N}}}"
    tn = f"(2*{vs}*{wk}+{S}*{ek})"
    b.section(f"point_{N}", T("block", N=N))
    as_ = f"{{as_{N}}}"
    tu = f"({as_}-{S}*{wk}^2)"
    motion_rows(b, N, T("of_block", N=N), f"{b.p('x', G)}+{S}*{U}", f"{b.p('y', G)}+{S}*{V}",
                f"{b.p('vx', G)}+{vs}*{U}-{S}*{wk}*{V}", f"{b.p('vy', G)}+{vs}*{V}+{S}*{wk}*{U}",
                f"{b.p('ax', G)}+{tu}*{U}-{tn}*{V}", f"{b.p('ay', G)}+{tu}*{V}+{tn}*{U}")
    distance_check(b, f"chk_{J1}{N}", J1, N, L, T("chk_L", J1=J1, N=N, la=la))
    b.check(f"chk_line_g{i}", "m", T("chk_line", N=N, G=G, k=k),
            f"-({{x_{N}}}-{b.p('x', G)})*{V}+({{y_{N}}}-{b.p('y', G)})*{U}")
    # the lecture's L_tek^2 = (x_D - a)^2 + (y_D - b)^2 differentiated ("Два коромысла с
    # кулисной парой - 3"): (N - G).(v_N - v_G) = L_tek (L_tek)_t and
    # (N - G).(a_N - a_G) + |v_N - v_G|^2 = (L_tek)_t^2 + L_tek (L_tek)_tt, with G moving too
    rx, ry = f"({{x_{N}}}-{b.p('x', G)})", f"({{y_{N}}}-{b.p('y', G)})"
    wx, wy = f"({{vx_{N}}}-{b.p('vx', G)})", f"({{vy_{N}}}-{b.p('vy', G)})"
    b.check(f"chk_Ltek_t_g{i}", "m^2/s", T("chk_Ltek_t"), f"{rx}*{wx}+{ry}*{wy}-{S}*{vs}")
    b.check(f"chk_Ltek_tt_g{i}", "m^2/s^2", T("chk_Ltek_tt"),
            f"{rx}*({{ax_{N}}}-{b.p('ax', G)})+{ry}*({{ay_{N}}}-{b.p('ay', G)})+{wx}^2+{wy}^2-{vs}^2-{S}*{as_}")
    relative_velocity_check(b, N, J1)
    via_link_checks(b, N, J1, la, f"omega_{la}, eps_{la}")
    fd_checks(b, N)


# --------------------------------------------------------------------------- kinetostatics
def pin_owner(g: Group) -> dict[str, int]:
    """A later group hinged at N is taken to hinge on the slider (link b)."""
    return {g.joints[1]: g.links[1]}


def pairs(g: Group, owner: dict[str, int]) -> list[Pair]:
    (j1, n), (a, b) = g.joints, g.links
    return [Pair(owner[j1], a, j1), Pair(a, b, n), Pair(g.guide.link, b, n, True)]


def reactions(g: Group, known, links, loads, owner) -> dict[str, tuple]:
    """a: R1 + X + Fa = 0, (J1 - N) x R1 + Ma(N) = 0; slider b: -X + Q n + Fb = 0 and the
    guide's couple Mq = -Mb(N). Along the guide u: R1.u = -F.u (Q n has no u part). The
    link that carries the guide (k) takes -Q n at N and -Mq."""
    (J1, N), (a, b) = g.joints, g.links
    la, lb = loads[a], loads[b]
    (fax, fay), _, (fx, fy) = resultants(loads, a, b)
    j1, nj = known[J1], known[N]
    ux, uy = links[b].c, links[b].s          # the slider turns with its guide
    d1x, d1y = j1.x - nj.x, j1.y - nj.y
    m11, m12, m21, m22 = ux, uy, -d1y, d1x
    _, inv = inverse_det(m11, m12, m21, m22)     # zero when the coupler is across the guide
    r1x, r1y = cramer(m11, m12, m21, m22, -(fx * ux + fy * uy), -la.moment(nj.x, nj.y), inv)
    q = (r1x + fx) * uy - (r1y + fy) * ux     # -(R1 + F).n with n = (-uy, ux)
    mq = -lb.moment(nj.x, nj.y)
    j1_pair = hinge(loads, owner[J1], a, j1, (r1x, r1y))
    k = g.guide.link
    loads[k].add(nj, q * uy, -q * ux)
    loads[k].couple = loads[k].couple - mq
    # a on b at N: R1 + Fa (link a's balance)
    return dict([j1_pair, (f"{a}_{b}", (r1x + fax, r1y + fay, None)), (f"{k}_{b}", (-q * uy, q * ux, mq))])


def reaction_rows(b: Builder, g: Group, owner: dict[str, int], k: LoadRows):
    i, (a, bl), (J1, N) = g.index, g.links, g.joints
    o1, gk = owner[J1], g.guide.link
    t1, tab = f"{o1}_{a}", f"{a}_{bl}"
    r1, rab = (f"{{Rx_{t1}}}", f"{{Ry_{t1}}}"), (f"{{Rx_{tab}}}", f"{{Ry_{tab}}}")
    k.link_loads(a, N)
    k.link_loads(bl, N)
    if g.guide.moving:
        ux, uy = f"{{cos_{bl}}}", f"{{sin_{bl}}}"
    else:
        ux, uy = f"COS(RADIANS({{gamma_g{i}}}))", f"SIN(RADIANS({{gamma_g{i}}}))"
    d1x, d1y = f"({b.p('x', J1)}-{b.p('x', N)})", f"({b.p('y', J1)}-{b.p('y', N)})"
    # along the guide: R1.u = -(Q_a + Q_b).u; moments of link a about N: d1 x R1 = -MQ_a
    qx, qy = f"({{Qx_{a}}}+{{Qx_{bl}}})", f"({{Qy_{a}}}+{{Qy_{bl}}})"
    k.cramer_reaction(i, t1, (ux, uy, f"(-{d1y})", d1x), (f"(-({qx}*{ux}+{qy}*{uy}))", f"(-{{MQ_{a}}})"),
                      "m", T("R_det", J1=J1, N=N), T("R_1", o=o1, a=a, J1=J1))
    k.reaction(tab, f"{r1[0]}+{{Qx_{a}}}", f"{r1[1]}+{{Qy_{a}}}", T("R_ab", a=a, bl=bl, N=N))
    tg = f"{gk}_{bl}"
    # the guide pushes across itself: -(R1 + Q).n n with n = (-uy, ux)
    qn = f"(({r1[0]}+{qx})*{uy}-({r1[1]}+{qy})*{ux})"
    k.reaction(tg, f"-{qn}*{uy}", f"{qn}*{ux}", T("R_g", bl=bl, N=N))
    b.accepted(f"M_{tg}", "N m", T("M_g", bl=bl), f"-{{MQ_{bl}}}")
    k.equilibrium(a, N, [(J1, *r1), (N, f"(-{rab[0]})", f"(-{rab[1]})")], "")
    k.equilibrium(bl, N, [(N, *rab), (N, f"{{Rx_{tg}}}", f"{{Ry_{tg}}}")], f"{{M_{tg}}}")
    if g.guide.moving:     # the kulisa k carries the guide: the block pushes back on it
        k.opposite(gk, N, tg, couple=True)
    k.opposite(o1, J1, t1)


# --------------------------------------------------------------------------- loop equations
def loop(lib, g: Group, known, links):
    """J1 + L e(p2) = G + s u(th); q = (p2, s); th = phi_k + A turns with link k."""
    p1, v1, a1 = known[g.joints[0]]
    (pg, vg, ag), (th, w, eps) = guide_loop(lib, g.guide, known, links)
    length = lib.num(g.length)
    ux, uy = lib.cos(th), lib.sin(th)
    nx, ny = -uy, ux

    def F(q):
        c, s = lib.cos(q[0]), lib.sin(q[0])
        return [p1[0] + length * c - pg[0] - q[1] * ux, p1[1] + length * s - pg[1] - q[1] * uy]

    def J(q):
        c, s = lib.cos(q[0]), lib.sin(q[0])
        return [[-length * s, -ux], [length * c, -uy]]

    def b_v(q):
        return [vg[0] + q[1] * w * nx - v1[0], vg[1] + q[1] * w * ny - v1[1]]

    def b_a(q, qt):
        c, s = lib.cos(q[0]), lib.sin(q[0])
        tn, tu = 2 * qt[1] * w + q[1] * eps, -q[1] * w * w
        return [ag[0] - a1[0] + length * qt[0] ** 2 * c + tu * ux + tn * nx,
                ag[1] - a1[1] + length * qt[0] ** 2 * s + tu * uy + tn * ny]

    def place(q, qt, qtt):
        s, vs, as_ = q[1], qt[1], qtt[1]
        tn, tu = 2 * vs * w + s * eps, as_ - s * w * w
        joint = ((pg[0] + s * ux, pg[1] + s * uy),
                 (vg[0] + vs * ux + s * w * nx, vg[1] + vs * uy + s * w * ny),
                 (ag[0] + tu * ux + tn * nx, ag[1] + tu * uy + tn * ny))
        return {g.joints[1]: joint}, ((q[0], qt[0], qtt[0]), (th, w, eps)), {g.joints[1]: (s, vs, as_)}
    return F, J, b_v, b_a, place


def side_ok(lib, g: Group, known, links, q, joints) -> bool:
    """+1 if N is ahead of the foot of the perpendicular from J1, along the guide."""
    p1 = known[g.joints[0]][0]
    _, (th, _, _) = guide_loop(lib, g.guide, known, links)
    nj = joints[g.joints[1]][0]
    v = (nj[0] - p1[0]) * lib.cos(th) + (nj[1] - p1[1]) * lib.sin(th)
    return (1 if v > 0 else -1) == g.branch


def discriminant(lib, g: Group, known, links):
    """L^2 - h^2, h the distance of J1 from the guide: 0 with the coupler across the guide."""
    p1 = known[g.joints[0]][0]
    (pg, _, _), (th, _, _) = guide_loop(lib, g.guide, known, links)
    h = -(p1[0] - pg[0]) * lib.sin(th) + (p1[1] - pg[1]) * lib.cos(th)
    length = lib.num(g.length)
    return length * length - h * h


def unknowns(g: Group, sol) -> tuple[np.ndarray, np.ndarray]:
    ra = sol.links[g.links[0]]
    return np.arctan2(ra.s, ra.c), sol.slides[g.joints[1]].s


# --------------------------------------------------------------------------- stability families
# Both ranges end where the coupler stands across its guide (L^2 - h^2 -> 0, the toggle
# measure cos(phi - gamma) -> 0), approached from inside, as the four-bar's toggle.
STABILITY = (
    Family("slider-toggle", "RRP: towards the coupler standing across its guide (edge of the range)",
           crank_scene("Crank-slider with a short coupler: it stands across the guide at the edge of its range", """\
[[group]]
type = "RRP"
links = [2, 3]
joints = ["A", "B"]
length = 0.2
guide = { through = [0.0, 0.05], angle_deg = 0.0 }
branch = 1
"""), 1, discriminant),
    Family("slotted-toggle", "RRP on a moving guide (two rockers, slotted pair): rocker across the kulisa",
           crank_scene("Two rockers with a slotted pair: rocker O2 D stands across the kulisa O1 B at the edge", """\
[[group]]
type    = "RRR"
links   = [2, 3]
joints  = ["A", "B", "O1"]
lengths = [0.5, 0.34]
branch  = -1
[[group]]
type   = "RRP"
links  = [4, 5]
joints = ["O2", "D"]
length = 0.3
guide  = { through = "O1", angle_deg = 0.0, link = 3 }
branch = -1
""", frame="""\
O  = [0.0, 0.0]
O1 = [0.0, -0.53]
O2 = [-0.45, -0.2]""", length=0.14, omega=20.0), 2, discriminant),
)
