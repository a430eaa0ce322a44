"""RRR (ВВВ): a coupler and a rocker, or two couplers, three revolute joints (slides 16-21).

Circle-circle intersection. The group J1 - N - J2 hangs between two known points J1, J2:
link a = J1 N (length L2), link b = J2 N (length L3). Constraint (a):
    J1 + L2 e(psi) = J2 + L3 e(xi),
unknowns psi = phi_a (J1 -> N) and xi = phi_b (J2 -> N). With P = xJ2 - xJ1, Q = yJ2 - yJ1,
F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2): tg(psi/2) = (Q +- sqrt(P^2 + Q^2 - F^2)) / (P + F)
(branch +1: N left of the directed line J1 -> J2). Velocities, system (b) (slide 19):
    -L2 sin psi psi_t + L3 sin xi xi_t = vx_J2 - vx_J1,  L2 cos psi psi_t - L3 cos xi xi_t = ...
solved by Cramer (slide 20); accelerations: the same matrix, the right side f1, f2 gains the
centripetal terms (slide 21). Toggle measure: det / (L2 L3) = sin(psi - xi), the sine of the
transmission angle.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .group import Family, Group
from .motion import (
    GroupMotion,
    Motion,
    Pair,
    Rotation,
    at_dead_points_zero,
    carried_point,
    cramer,
    cross,
    hinge,
    inverse_det,
    resultants,
    sqrt_or_nan,
)
from .parts import Parts
from .rows import (
    Builder,
    InputRow,
    LoadRows,
    Text,
    Texts,
    carried_rows,
    cos_sin_rows,
    cramer_rows,
    det_row,
    distance_check,
    fd_checks,
    group_guard,
    relative_velocity_check,
    residual,
    via_link_checks,
)

# --------------------------------------------------------------------------- what it is
KIND = "RRR"
LECTURE = "ВВВ"
SLIDES = "16-21"
TITLE = Text(ru="шатун и коромысло (или два шатуна): три вращательные пары",
             uk="шатун і коромисло (або два шатуни): три обертальні пари",
             en="coupler and rocker (or two couplers): three revolute joints")
KEYS = ("type", "links", "joints", "lengths", "branch")

# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language (the fields: group i, links la lb, joints J1 N J2)
TEXTS = {
    "ru": {
        "L_a": "длина звена {la} ({J1}{N})",
        "L_b": "длина звена {lb} ({N}{J2})",
        "branch": "ветвь решения группы {i} (+1 или -1)",
        "group": "Группа {i} (ВВВ {J1}{N}{J2}): кинематические связи, слайды 16-21",
        "P": "P = x{J2} - x{J1}",
        "Q": "Q = y{J2} - y{J1}",
        "F": "F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2)",
        "D": "дискриминант P^2 + Q^2 - F^2 (< 0: группа не собирается)",
        "branch_p": "ветвь +1",
        "branch_m": "ветвь -1",
        "psi": "{br}: psi = 2 arctg((Q {sign} sqrt(D)) / (P + F))",
        "xi": "{br}: xi из cos xi = (L2 cos psi - P)/L3, sin xi = (L2 sin psi - Q)/L3",
        "chk_loop": "проверка {br}: {axis}{J1} + L2 {fn} psi - L3 {fn} xi - {axis}{J2}",
        "accepted": "Принятые значения",
        "phi_a": "угол звена {la} ({J1}->{N})",
        "phi_b": "угол звена {lb} ({J2}->{N})",
        "chk_acc": "проверка принятых значений: невязка системы (a)",
        "det": "определитель системы (b): L2 L3 sin(psi - xi)",
        "toggle": "sin угла передачи (около 0: мёртвое положение)",
        "omega": "угловая скорость звена {k} (Крамер)",
        "vsys": "невязка системы (b) для скоростей",
        "f1": "правая часть для ускорений f1 (слайд 21)",
        "f2": "правая часть для ускорений f2 (слайд 21)",
        "eps": "угловое ускорение звена {k}",
        "hinge": "шарнира {N}",
        "chk_a": "проверка: |{J1}{N}| - L{la}",
        "chk_b": "проверка: |{N}{J2}| - L{lb}",
        "R_det": "определитель: ({J1}-{N}) x ({J2}-{N}) (0 в мёртвом положении)",
        "R_on": "звена {o} на звено {k} в {at}",
    },
    "uk": {
        "L_a": "довжина ланки {la} ({J1}{N})",
        "L_b": "довжина ланки {lb} ({N}{J2})",
        "branch": "гілка розв'язку групи {i} (+1 або -1)",
        "group": "Група {i} (ООО {J1}{N}{J2}): кінематичні зв'язки, слайди 16-21",
        "P": "P = x{J2} - x{J1}",
        "Q": "Q = y{J2} - y{J1}",
        "F": "F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2)",
        "D": "дискримінант P^2 + Q^2 - F^2 (< 0: група не збирається)",
        "branch_p": "гілка +1",
        "branch_m": "гілка -1",
        "psi": "{br}: psi = 2 arctg((Q {sign} sqrt(D)) / (P + F))",
        "xi": "{br}: xi из cos xi = (L2 cos psi - P)/L3, sin xi = (L2 sin psi - Q)/L3",
        "chk_loop": "перевірка {br}: {axis}{J1} + L2 {fn} psi - L3 {fn} xi - {axis}{J2}",
        "accepted": "Прийняті значення",
        "phi_a": "кут ланки {la} ({J1}->{N})",
        "phi_b": "кут ланки {lb} ({J2}->{N})",
        "chk_acc": "перевірка прийнятих значень: нев'язка системи (a)",
        "det": "визначник системи (b): L2 L3 sin(psi - xi)",
        "toggle": "sin кута передачі (близько 0: мертве положення)",
        "omega": "кутова швидкість ланки {k} (Крамер)",
        "vsys": "нев'язка системи (b) для швидкостей",
        "f1": "права частина для прискорень f1 (слайд 21)",
        "f2": "права частина для прискорень f2 (слайд 21)",
        "eps": "кутове прискорення ланки {k}",
        "hinge": "шарніра {N}",
        "chk_a": "перевірка: |{J1}{N}| - L{la}",
        "chk_b": "перевірка: |{N}{J2}| - L{lb}",
        "R_det": "визначник: ({J1}-{N}) x ({J2}-{N}) (0 в мертвому положенні)",
        "R_on": "ланки {o} на ланку {k} в {at}",
    },
    "en": {
        "L_a": "length of link {la} ({J1}{N})",
        "L_b": "length of link {lb} ({N}{J2})",
        "branch": "solution branch of group {i} (+1 or -1)",
        "group": "Group {i} (RRR {J1}{N}{J2}): kinematic constraints, slides 16-21",
        "P": "P = x{J2} - x{J1}",
        "Q": "Q = y{J2} - y{J1}",
        "F": "F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2)",
        "D": "discriminant P^2 + Q^2 - F^2 (< 0: cannot assemble)",
        "branch_p": "branch +1",
        "branch_m": "branch -1",
        "psi": "{br}: psi = 2 atan((Q {sign} sqrt(D)) / (P + F))",
        "xi": "{br}: xi from cos xi = (L2 cos psi - P)/L3, sin xi = (L2 sin psi - Q)/L3",
        "chk_loop": "check {br}: {axis}{J1} + L2 {fn} psi - L3 {fn} xi - {axis}{J2}",
        "accepted": "Accepted values",
        "phi_a": "angle of link {la} ({J1}->{N})",
        "phi_b": "angle of link {lb} ({J2}->{N})",
        "chk_acc": "check of the accepted values: residual of system (a)",
        "det": "determinant of system (b): L2 L3 sin(psi - xi)",
        "toggle": "sine of the transmission angle (near 0: toggle)",
        "omega": "angular velocity of link {k} (Cramer)",
        "vsys": "residual of the velocity system (b)",
        "f1": "right side of the acceleration system f1 (slide 21)",
        "f2": "right side of the acceleration system f2 (slide 21)",
        "eps": "angular acceleration of link {k}",
        "hinge": "hinge {N}",
        "chk_a": "check: |{J1}{N}| - L{la}",
        "chk_b": "check: |{N}{J2}| - L{lb}",
        "R_det": "determinant: ({J1}-{N}) x ({J2}-{N}) (0 at the toggle)",
        "R_on": "of link {o} on link {k} at {at}",
    },
}
T = Texts(TEXTS)


# --------------------------------------------------------------------------- scene keys
@dataclass(frozen=True)
class Params:
    lengths: tuple[float, float]      # |J1 N| (link a), |N J2| (link b)
    branch: int                       # +1: N left of the directed line J1 -> J2


def parse(tbl, frame) -> tuple[tuple[str, ...], Params]:
    joints = tbl.array("joints", 3, "name")
    if joints[1] in (joints[0], joints[2]):
        tbl.fail("joints", f"the new joint '{joints[1]}' (second name) must differ from the "
                           f"known joint(s) it is attached to, got {list(joints)}")
    branch = tbl.get("branch", "an integer")
    if branch not in (1, -1):
        tbl.fail("branch", f"expected +1 or -1, got {branch}")
    lengths = tbl.array("lengths", 2, "number")
    if min(lengths) <= 0:
        tbl.fail("lengths", f"expected positive lengths in metres, got {list(lengths)}")
    return joints, Params(lengths, branch)


def needs(g: Group) -> list[str]:
    return [g.joints[0], g.joints[2]]


def on_links(g: Group) -> list[tuple[str, str, int]]:
    return []


def new_joints(g: Group) -> list[str]:
    return [g.joints[1]]


def carries(g: Group) -> dict[int, list[str]]:
    (j1, n, j2), (a, b) = g.joints, g.links
    return {a: [j1, n], b: [j2, n]}


def sliders(g: Group) -> list[str]:
    return []


def fourbar(g: Group, crank_joint: str, frame) -> tuple[float, float, str, int] | None:
    """(coupler, rocker, the rocker's frame pivot, branch) if the group closes a four-bar
    with the crank (J1 the crank's joint, J2 a frame point), the mechanism whose lengths
    seed 002's synthesis designs (sheetkin.studies.synthesis); else None."""
    if g.joints[0] == crank_joint and g.joints[2] in frame:
        return g.lengths[0], g.lengths[1], g.joints[2], g.branch
    return None


def parts(g: Group) -> Parts:
    """Two bars hinged at N: no guide, no block."""
    (j1, n, j2), (a, b) = g.joints, g.links
    return Parts({a: (j1, n), b: (j2, n)})


# --------------------------------------------------------------------------- positions and rates
def solve_rrr(j1: Motion, j2: Motion, l2: float, l3: float, branch: int):
    """Constraint (a) in closed form, then systems (b) and (c) by Cramer. The half-angle
    root (Q + root) / (P + F) equals (F - P) / (Q - root) (their product is (F - P)/(P + F));
    we take whichever form has no cancellation, so it never degenerates to 0/0.
    Returns N, rotations of J1->N (psi) and J2->N (xi), the discriminant, sin(psi - xi)."""
    p, q = j2.x - j1.x, j2.y - j1.y
    f = (p * p + q * q + l2 * l2 - l3 * l3) / (2.0 * l2)
    disc = at_dead_points_zero(p * p + q * q - f * f, p * p + q * q)
    root = branch * sqrt_or_nan(disc)
    num1, den1 = q + root, p + f          # the lecture's form
    num2, den2 = f - p, q - root          # the same root, rationalised
    first = num1 * num1 + den1 * den1 >= num2 * num2 + den2 * den2
    num, den = np.where(first, num1, num2), np.where(first, den1, den2)
    # sin and cos from tg(psi/2) = num/den (lecture: sin = 2t/(1+t^2), cos = (1-t^2)/(1+t^2))
    h = num * num + den * den
    c2, s2 = (den * den - num * num) / h, 2.0 * num * den / h
    # cos xi = (L2 cos psi - P) / L3, sin xi = (L2 sin psi - Q) / L3 (system (a))
    c3, s3 = (l2 * c2 - p) / l3, (l2 * s2 - q) / l3
    # velocities, system (b): -L2 sin psi psi_t + L3 sin xi xi_t = vx_J2 - vx_J1, ...
    m11, m12, m21, m22 = -l2 * s2, l3 * s3, l2 * c2, -l3 * c3
    det, inv = inverse_det(m11, m12, m21, m22)
    w2, w3 = cramer(m11, m12, m21, m22, j2.vx - j1.vx, j2.vy - j1.vy, inv)
    # accelerations: same matrix; right side gains the centripetal terms (lecture f1, f2)
    b1 = j2.ax - j1.ax + l2 * w2 * w2 * c2 - l3 * w3 * w3 * c3
    b2 = j2.ay - j1.ay + l2 * w2 * w2 * s2 - l3 * w3 * w3 * s3
    e2, e3 = cramer(m11, m12, m21, m22, b1, b2, inv)
    rot2, rot3 = Rotation(c2, s2, w2, e2), Rotation(c3, s3, w3, e3)
    return carried_point(j1, rot2, l2, 0.0), rot2, rot3, disc, det / (l2 * l3)


def solve(g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion:
    (j1, n, j2), (a, b) = g.joints, g.links
    l2, l3 = g.lengths
    joint, ra, rb, disc, toggle = solve_rrr(known[j1], known[j2], l2, l3, g.branch)
    return GroupMotion({n: joint}, {a: ra, b: rb}, {}, disc, toggle)


# --------------------------------------------------------------------------- the workbook
def input_rows(g: Group) -> list[InputRow]:
    (j1, n, j2), (la, lb), i = g.joints, g.links, g.index
    return [InputRow(f"L{la}", "m", T("L_a", la=la, J1=j1, N=n), g.lengths[0], True),
            InputRow(f"L{lb}", "m", T("L_b", lb=lb, N=n, J2=j2), g.lengths[1], True),
            InputRow(f"branch_g{i}", "", T("branch", i=i), g.branch)]


def with_inputs(g: Group, num) -> Group:
    la, lb = g.links
    lengths = (num(f"L{la}", g.lengths[0]), num(f"L{lb}", g.lengths[1]))
    branch = int(num(f"branch_g{g.index}", g.branch, choices=(1, -1)))
    return dataclasses.replace(g, params=Params(lengths, branch))


def rows(b: Builder, g: Group):
    """Lecture slides 16-21, generalised to a moving J2: J1 + L2 e(psi) = J2 + L3 e(xi)."""
    i, (la, lb), (J1, N, J2) = g.index, g.links, g.joints
    b.section(f"group_{i}", T("group", i=i, J1=J1, N=N, J2=J2))
    _constraint_rows(b, g)
    b.section(f"accepted_g{i}", T("accepted"))
    m = _accepted_rows(b, g)
    _velocity_rows(b, g, m)
    _acceleration_rows(b, g, m)
    b.place_links(la, lb)
    _hinge_rows(b, g)


def _constraint_rows(b: Builder, g: Group):
    """Constraint (a) (slides 16-18): P, Q, F, the discriminant and the group's guard, then
    psi and xi on both branches, each with its loop check."""
    i, (J1, _, J2) = g.index, g.joints
    L2, L3 = f"{{L{g.links[0]}}}", f"{{L{g.links[1]}}}"
    P, Q, F, D = f"P_g{i}", f"Q_g{i}", f"F_g{i}", f"D_g{i}"
    b.calc(P, "m", T("P", J1=J1, J2=J2), f"{b.p('x', J2)}-{b.p('x', J1)}", guard=b.guard)
    b.calc(Q, "m", T("Q", J1=J1, J2=J2), f"{b.p('y', J2)}-{b.p('y', J1)}", guard=b.guard)
    b.calc(F, "m", T("F"), f"({{{P}}}^2+{{{Q}}}^2+{L2}^2-{L3}^2)/(2*{L2})", guard=b.guard)
    b.calc(D, "m^2", T("D"), f"{{{P}}}^2+{{{Q}}}^2-{{{F}}}^2", guard=b.guard)
    group_guard(b, g, D, f"{{{P}}}^2+{{{Q}}}^2")
    for s, sign, br in (("p", "+", T("branch_p")), ("m", "-", T("branch_m"))):
        # tg(psi/2) = (Q +- sqrt(D)) / (P + F), written as ATAN2 so that P + F = 0 is no division
        b.calc(f"psi_{s}_g{i}", "rad", T("psi", br=br, sign=sign),
               f"2*ATAN2({{{P}}}+{{{F}}},{{{Q}}}{sign}SQRT({{{D}}}))")
        b.calc(f"xi_{s}_g{i}", "rad", T("xi", br=br),
               f"ATAN2({L2}*COS({{psi_{s}_g{i}}})-{{{P}}},{L2}*SIN({{psi_{s}_g{i}}})-{{{Q}}})")
        for axis, fn in (("x", "COS"), ("y", "SIN")):
            b.check(f"chk_{axis}_{s}_g{i}", "m", T("chk_loop", br=br, axis=axis, fn=fn.lower(), J1=J1, J2=J2),
                    f"{b.p(axis, J1)}+{L2}*{fn}({{psi_{s}_g{i}}})-{L3}*{fn}({{xi_{s}_g{i}}})-{b.p(axis, J2)}")


def _accepted_rows(b: Builder, g: Group) -> tuple[str, str, str, str]:
    """The accepted angles of the coupler and the rocker (the branch the scene gives), their
    cos and sin, the check of system (a); returns the matrix of systems (b) and (c)."""
    i, (la, lb), (J1, N, J2) = g.index, g.links, g.joints
    L2, L3 = f"{{L{la}}}", f"{{L{lb}}}"
    br = f"{{branch_g{i}}}"
    b.accepted(f"phi_{la}", "deg", T("phi_a", la=la, J1=J1, N=N),
               f"MOD(DEGREES(IF({br}=1,{{psi_p_g{i}}},{{psi_m_g{i}}})),360)")
    b.accepted(f"phi_{lb}", "deg", T("phi_b", lb=lb, J2=J2, N=N),
               f"MOD(DEGREES(IF({br}=1,{{xi_p_g{i}}},{{xi_m_g{i}}})),360)")
    cos_sin_rows(b, la)
    cos_sin_rows(b, lb)
    ca, sa, cb, sb = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    b.check(f"chk_acc_g{i}", "m", T("chk_acc"),
            f"ABS({b.p('x', J1)}+{L2}*{ca}-{L3}*{cb}-{b.p('x', J2)})"
            f"+ABS({b.p('y', J1)}+{L2}*{sa}-{L3}*{sb}-{b.p('y', J2)})")
    return f"(-{L2}*{sa})", f"({L3}*{sb})", f"({L2}*{ca})", f"(-{L3}*{cb})"


def _velocity_rows(b: Builder, g: Group, m):
    """System (b) (slide 19): -L2 sin psi psi_t + L3 sin xi xi_t = vx_J2 - vx_J1;
    L2 cos psi psi_t - L3 cos xi xi_t = vy_J2 - vy_J1, by Cramer (slide 20)."""
    i, (la, lb), (J1, _, J2) = g.index, g.links, g.joints
    det = f"Delta_g{i}"
    det_row(b, det, m, "m^2", T("det"))
    b.calc(f"det_g{i}", "", T("toggle"), f"{{{det}}}/({{L{la}}}*{{L{lb}}})")
    b1, b2 = f"({b.p('vx', J2)}-{b.p('vx', J1)})", f"({b.p('vy', J2)}-{b.p('vy', J1)})"
    cramer_rows(b, m, det, ((f"omega_{la}", "rad/s", T("omega", k=la)), (f"omega_{lb}", "rad/s", T("omega", k=lb))),
                (b1, b2), (f"chk_vsys_g{i}", T("vsys")))


def _acceleration_rows(b: Builder, g: Group, m):
    """System (c): the same matrix, the right side f1, f2 with the centripetal terms (slide 21)."""
    i, (la, lb), (J1, _, J2) = g.index, g.links, g.joints
    L2, L3 = f"{{L{la}}}", f"{{L{lb}}}"
    ca, sa, cb, sb = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    f1, f2 = f"f1_g{i}", f"f2_g{i}"
    wa, wb = f"{{omega_{la}}}", f"{{omega_{lb}}}"
    b.calc(f1, "m/s^2", T("f1"), f"{b.p('ax', J2)}-{b.p('ax', J1)}+{L2}*{wa}^2*{ca}-{L3}*{wb}^2*{cb}")
    b.calc(f2, "m/s^2", T("f2"), f"{b.p('ay', J2)}-{b.p('ay', J1)}+{L2}*{wa}^2*{sa}-{L3}*{wb}^2*{sb}")
    cramer_rows(b, m, f"Delta_g{i}",
                ((f"eps_{la}", "rad/s^2", T("eps", k=la)), (f"eps_{lb}", "rad/s^2", T("eps", k=lb))),
                (f"{{{f1}}}", f"{{{f2}}}"), residual(i, "a"))


def _hinge_rows(b: Builder, g: Group):
    """The hinge N carried by the coupler (slide 7), its distance and rigid-body checks."""
    (la, lb), (J1, N, J2) = g.links, g.joints
    L2, L3 = f"{{L{la}}}", f"{{L{lb}}}"
    carried_rows(b, N, la, J1, L2, "0", T("hinge", N=N))
    distance_check(b, f"chk_{J1}{N}", J1, N, L2, T("chk_a", J1=J1, N=N, la=la))
    distance_check(b, f"chk_{N}{J2}", N, J2, L3, T("chk_b", N=N, J2=J2, lb=lb))
    relative_velocity_check(b, N, J2)
    via_link_checks(b, N, J2, lb, f"omega_{lb}, eps_{lb}")
    fd_checks(b, N)


# --------------------------------------------------------------------------- kinetostatics
def pin_owner(g: Group) -> dict[str, int]:
    """A later group hinged at N is taken to hinge on the coupler (link a)."""
    return {g.joints[1]: g.links[0]}


def pairs(g: Group, owner: dict[str, int]) -> list[Pair]:
    (j1, n, j2), (a, b) = g.joints, g.links
    return [Pair(owner[j1], a, j1), Pair(a, b, n), Pair(owner[j2], b, j2)]


def reactions(g: Group, known, links, loads, owner) -> dict[str, tuple]:
    """a: R1 + X + Fa = 0, (J1 - N) x R1 + Ma(N) = 0; b: R2 - X + Fb = 0,
    (J2 - N) x R2 + Mb(N) = 0. With R2 = -F - R1 both moment equations are in R1."""
    (J1, N, J2), (a, b) = g.joints, g.links
    la, lb = loads[a], loads[b]
    (fax, fay), _, (fx, fy) = resultants(loads, a, b)
    j1, nj, j2 = known[J1], known[N], known[J2]
    d1x, d1y, d2x, d2y = j1.x - nj.x, j1.y - nj.y, j2.x - nj.x, j2.y - nj.y
    m11, m12, m21, m22 = -d1y, d1x, -d2y, d2x
    _, inv = inverse_det(m11, m12, m21, m22)     # zero at the toggle, as the kinematics'
    r1x, r1y = cramer(m11, m12, m21, m22, -la.moment(nj.x, nj.y),
                      lb.moment(nj.x, nj.y) - cross(d2x, d2y, fx, fy), inv)
    r2x, r2y = -fx - r1x, -fy - r1y
    # a on b at N: R1 + Fa (link a's balance)
    return dict([hinge(loads, owner[J1], a, j1, (r1x, r1y)), (f"{a}_{b}", (r1x + fax, r1y + fay, None)),
                 hinge(loads, owner[J2], b, j2, (r2x, r2y))])


def reaction_rows(b: Builder, g: Group, owner: dict[str, int], k: LoadRows):
    i, (a, bl), (J1, N, J2) = g.index, g.links, g.joints
    o1, o2 = owner[J1], owner[J2]
    t1, tab, t2 = f"{o1}_{a}", f"{a}_{bl}", f"{o2}_{bl}"
    r1, rab = (f"{{Rx_{t1}}}", f"{{Ry_{t1}}}"), (f"{{Rx_{tab}}}", f"{{Ry_{tab}}}")
    k.link_loads(a, N)
    k.link_loads(bl, N)
    d1x, d1y = f"({b.p('x', J1)}-{b.p('x', N)})", f"({b.p('y', J1)}-{b.p('y', N)})"
    d2x, d2y = f"({b.p('x', J2)}-{b.p('x', N)})", f"({b.p('y', J2)}-{b.p('y', N)})"
    # moments about N: d1 x R1 = -MQ_a and d2 x R2 = -MQ_b with R2 = -(Q_a + Q_b) - R1
    qx, qy = f"({{Qx_{a}}}+{{Qx_{bl}}})", f"({{Qy_{a}}}+{{Qy_{bl}}})"
    k.cramer_reaction(i, t1, (f"(-{d1y})", d1x, f"(-{d2y})", d2x),
                      (f"(-{{MQ_{a}}})", f"({{MQ_{bl}}}-({d2x}*{qy}-{d2y}*{qx}))"),
                      "m^2", T("R_det", J1=J1, N=N, J2=J2), T("R_on", o=o1, k=a, at=J1))
    k.reaction(tab, f"{r1[0]}+{{Qx_{a}}}", f"{r1[1]}+{{Qy_{a}}}", T("R_on", o=a, k=bl, at=N))
    k.reaction(t2, f"-{qx}-{r1[0]}", f"-{qy}-{r1[1]}", T("R_on", o=o2, k=bl, at=J2))
    k.equilibrium(a, N, [(J1, *r1), (N, f"(-{rab[0]})", f"(-{rab[1]})")], "")
    k.equilibrium(bl, N, [(N, *rab), (J2, f"{{Rx_{t2}}}", f"{{Ry_{t2}}}")], "")
    k.opposite(o2, J2, t2)
    k.opposite(o1, J1, t1)


# --------------------------------------------------------------------------- loop equations
def _e(lib, a):
    return lib.cos(a), lib.sin(a)


def loop(lib, g: Group, known, links):
    """J1 + L2 e(p2) = J2 + L3 e(p3); q = (p2, p3) the directions J1->N and J2->N."""
    (p1, v1, a1), (p2, v2, a2) = known[g.joints[0]], known[g.joints[2]]
    n = lib.num
    l2, l3 = n(g.lengths[0]), n(g.lengths[1])

    def F(q):
        (c2, s2), (c3, s3) = _e(lib, q[0]), _e(lib, q[1])
        return [p1[0] + l2 * c2 - l3 * c3 - p2[0], p1[1] + l2 * s2 - l3 * s3 - p2[1]]

    def J(q):
        (c2, s2), (c3, s3) = _e(lib, q[0]), _e(lib, q[1])
        return [[-l2 * s2, l3 * s3], [l2 * c2, -l3 * c3]]

    def b_v(q):
        return [v2[0] - v1[0], v2[1] - v1[1]]

    def b_a(q, qt):
        (c2, s2), (c3, s3) = _e(lib, q[0]), _e(lib, q[1])
        w2, w3 = qt
        return [a2[0] - a1[0] + l2 * w2 * w2 * c2 - l3 * w3 * w3 * c3,
                a2[1] - a1[1] + l2 * w2 * w2 * s2 - l3 * w3 * w3 * s3]

    def place(q, qt, qtt):
        la, lb = (q[0], qt[0], qtt[0]), (q[1], qt[1], qtt[1])
        (c2, s2) = _e(lib, q[0])
        # N = J1 + L2 e(p2), carried by link a (slide 7)
        nx, ny = -s2, c2
        pos = (p1[0] + l2 * c2, p1[1] + l2 * s2)
        vel = (v1[0] + qt[0] * l2 * nx, v1[1] + qt[0] * l2 * ny)
        acc = (a1[0] + qtt[0] * l2 * nx - qt[0] ** 2 * l2 * c2, a1[1] + qtt[0] * l2 * ny - qt[0] ** 2 * l2 * s2)
        return {g.joints[1]: (pos, vel, acc)}, (la, lb), {}
    return F, J, b_v, b_a, place


def side_ok(lib, g: Group, known, links, q, joints) -> bool:
    """The side of J1 -> J2 the new joint lies on (+1 left) is the scene's branch."""
    (p1, _, _), (p2, _, _) = known[g.joints[0]], known[g.joints[2]]
    n_ = joints[g.joints[1]][0]
    v = (p2[0] - p1[0]) * (n_[1] - p1[1]) - (p2[1] - p1[1]) * (n_[0] - p1[0])
    return (1 if v > 0 else -1) == g.branch


def discriminant(lib, g: Group, known, links):
    """P^2 + Q^2 - F^2 (constraint (a)): >= 0 where the group assembles, 0 at its toggle."""
    (p1, _, _), (p2, _, _) = known[g.joints[0]], known[g.joints[2]]
    l2, l3 = lib.num(g.lengths[0]), lib.num(g.lengths[1])
    p, q = p2[0] - p1[0], p2[1] - p1[1]
    f = (p * p + q * q + l2 * l2 - l3 * l3) / (2 * l2)
    return p * p + q * q - f * f


def unknowns(g: Group, sol) -> tuple[np.ndarray, np.ndarray]:
    ra, rb = sol.links[g.links[0]], sol.links[g.links[1]]
    return np.arctan2(ra.s, ra.c), np.arctan2(rb.s, rb.c)


def closed_q(lib, g: Group, known, links):
    """q = (psi, xi) by the circles' intersection written for any number type (the
    reference's start where the branches meet: at a change point Newton cannot tell them
    apart); None where the circles do not meet."""
    (ax, ay), _, _ = known[g.joints[0]]
    (jx, jy), _, _ = known[g.joints[2]]
    l2, l3 = lib.num(g.lengths[0]), lib.num(g.lengths[1])
    px, py = jx - ax, jy - ay
    r = lib.sqrt(px * px + py * py)
    a = (r * r + l2 * l2 - l3 * l3) / (2 * r)          # along J1 -> J2
    h2 = l2 * l2 - a * a
    if h2 < 0:
        return None
    h = lib.sqrt(h2) * g.branch                        # left of J1 -> J2: +
    ux, uy = px / r, py / r
    nx, ny = ax + a * ux - h * uy, ay + a * uy + h * ux
    return [lib.atan2(ny - ay, nx - ax), lib.atan2(ny - jy, nx - jx)]


# --------------------------------------------------------------------------- stability families
# Four-bars with every length a binary fraction, so the float scene IS the mechanism studied
# (0.45 + 0.25 != 0.7 in binary would move a change point by ~1e-8 rad, or open a gap there).
FOURBAR = """\
title = "{title}"
author = "sheetkin stability study"

[frame]
O  = [0.0, 0.0]
O1 = [{frame!r}, 0.0]

[crank]
pivot = "O"
joint = "A"
length = {crank!r}
phi0_deg = 0.0
step_deg = 30.0
positions = 1
omega = 10.0
epsilon = 0.0

[[group]]
type = "RRR"
links = [2, 3]
joints = ["A", "B", "O1"]
lengths = [{coupler!r}, {rocker!r}]
branch = {branch}
"""
_NON_GRASHOF = FOURBAR.format(title="Non-Grashof four-bar: the crank's range ends in a toggle",
                              frame=0.5, crank=0.25, coupler=0.375, rocker=0.25, branch=1)
STABILITY = (
    # non-Grashof (s + l = 0.75 > p + q = 0.625): at the edge of the crank's range coupler
    # and rocker stand in line, the dyad's toggle (P^2 + Q^2 - F^2 -> 0, sin(psi - xi) -> 0)
    Family("toggle", "towards a toggle (non-Grashof crank, edge of its range)", _NON_GRASHOF, 1,
           discriminant, start=closed_q),
    # Grashof sum equal (s + l = 0.625 = p + q): at 180 deg all four links are in line and
    # the two branches meet (the discriminant touches 0 from above)
    Family("change-point", "towards a change point (s + l = p + q, links in line)",
           FOURBAR.format(title="Change-point four-bar: s + l = p + q", frame=0.5, crank=0.125,
                          coupler=0.375, rocker=0.25, branch=1), 1, 180.0, start=closed_q),
    # the toggle seen from the far side, where no real position exists: the right answer
    # is a refusal
    Family("gap-edge", "just outside the edge of a non-assembling interval", _NON_GRASHOF, 1,
           discriminant, side=1, start=closed_q),
)
