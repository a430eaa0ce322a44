"""PRP (ПВП): two blocks hinged together at N, each sliding on its own guide.

The lecture's "slider on the coupler with a fixed guide" (seed 003, "КУЛИСНАЯ ПАРА С
ПОЛЗУШКОЙ НА ШАТУНЕ И ФИКСИРОВАННОЙ НАПРАВЛЯЮЩЕЙ", equations (1)-(7)): N is the point L
where two straight lines cross, line (1) y = m + x tg(theta) (the fixed guide) and line (2)
y = n + x tg(eta) (the coupler AB, tg(eta) by (4), n by (3a)); x_L, y_L by (7).
A guide may sit on the frame or on a moving link k (a kulisa): it passes through a point P
of link k and its direction is phi_k + A.

Constraint (the vector form of (5a), (5b)):  N = P_a + s1 u_a = P_b + s2 u_b,
two unknowns s1 = s_N (along guides[0]) and s2 = s2_N (along guides[1]); the 2x2 matrix
[u_a, -u_b] has the determinant -sin(theta_b - theta_a), so Cramer's rule gives s1, s2 and,
differentiated once and twice in time, the relative velocities and accelerations:
    u_a vs1 - u_b vs2 = v_Pb - v_Pa - s1 w_a n_a + s2 w_b n_b,
    u_a as1 - u_b as2 = a_Pb - a_Pa - (2 vs1 w_a + s1 e_a) n_a + s1 w_a^2 u_a
                                    + (2 vs2 w_b + s2 e_b) n_b - s2 w_b^2 u_b,
with n = u turned +90 deg and (w, e) the rates of the link carrying the guide (2 vs w n is
the Coriolis term). Toggle measure: sin(theta_b - theta_a), the sine of the angle between
the two lines: free of position and size; zero when the guides are parallel (no N).

The functions below take and return plain numbers or numpy arrays (vectorised over crank
positions); `through` is a point with x, y, vx, vy, ax, ay and `guide` a direction with
c, s, omega, eps (the solver's Motion and Rotation).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .group import Family, Group, Guide, crank_scene
from .motion import (
    DEAD_POINT,
    GroupMotion,
    Motion,
    Pair,
    Rotation,
    Slide,
    cramer,
    guide_line,
    guide_loop,
    inverse_det,
)
from .parts import BlockPart, Parts, scene_guide
from .rows import (
    DEAD_POINT_TEXT,
    Builder,
    InputRow,
    LoadRows,
    Text,
    Texts,
    cos_sin_rows,
    cramer_rows,
    det_row,
    fd_checks,
    motion_rows,
    residual,
    turns_with_check,
)

# --------------------------------------------------------------------------- what it is
KIND = "PRP"
LECTURE = "ПВП"
SLIDES = "ползушка на шатуне и фиксированная направляющая, (1)-(7)"
TITLE = Text(ru="два камня, шарнирно связанные в N, каждый на своей направляющей (ползушка на шатуне и фиксированная "
                "направляющая)",
             uk="два камені, шарнірно з'єднані в N, кожен на своїй напрямній (повзунок на шатуні і фіксована напрямна)",
             en="two blocks hinged together at N, each sliding on its own guide (a slider on the coupler with a "
                "fixed guide)")
KEYS = ("type", "links", "joints", "guides")


# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language (fields: group i, block la, slider lb, joint N,
# guide j); the numbers (1)-(7) are the lecture's equations
TEXTS = {
    "ru": {
        "guide": "направляющая {j} камня {ab} (узел {N})",
        "gamma_k": "{which}: угол к звену {k}",
        "gx": "{which}: x точки",
        "gy": "{which}: y точки",
        "gamma": "{which}: угол наклона",
        "group": "Группа {i} (ПВП {N}): ползушка на шатуне и фиксированная направляющая, уравнения (1)-(7)",
        "eta": "(4) наклон прямой (2) (направляющая 1): tg eta = (yB - yA)/(xB - xA) записан углом eta, "
               "чтобы вертикальная прямая (tg = бесконечность) оставалась конечной",
        "n": "(3a) n cos(eta) = y cos(eta) - x sin(eta) точки прямой (2): n, умноженное на cos(eta), "
             "конечно и для вертикальной прямой",
        "theta": "(1) наклон прямой (1) (направляющая 2), угол theta",
        "m": "(1) m cos(theta) = y cos(theta) - x sin(theta) точки прямой (1)",
        "D": "(7) знаменатель tg theta - tg eta, умноженный на cos theta cos eta: sin(theta - eta) "
             "(0: прямые параллельны, группа не собирается)",
        "guard": "группа {i} собирается (прямые не параллельны)",
        "xL": "(7) x_L = (n - m)/(tg theta - tg eta), умножено на cos theta cos eta: "
              "(n cos eta cos theta - m cos theta cos eta)/sin(theta - eta)",
        "yL": "(7) y_L = (n tg theta - m tg eta)/(tg theta - tg eta), умножено на cos theta cos eta",
        "chk_5a": "проверка (5a): L на прямой (2)",
        "chk_5b": "проверка (5b): L на прямой (1)",
        "accepted": "Принятые значения",
        "s": "положение камня {N} вдоль направляющей 1 от её точки",
        "s2": "положение ползуна {N} вдоль направляющей 2 от её точки",
        "phi_a": "угол камня {la} (направляющая 1)",
        "phi_b": "угол ползуна {lb} (направляющая 2)",
        "chk_acc": "проверка принятых значений: P1 + s u1 - P2 - s2 u2",
        "block": "камня",
        "slider": "ползуна",
        "omega": "угловая скорость {what} {k} (вместе с направляющей)",
        "eps": "угловое ускорение {what} {k}",
        "rot": "камень {la} и ползун {lb} повёрнуты и вращаются вместе со своими направляющими",
        "det": "определитель: -sin(theta - eta)",
        "toggle": "sin(theta - eta): синус угла между направляющими (около 0: мёртвое положение)",
        "vs": "скорость камня {N} вдоль направляющей 1 (Крамер)",
        "vs2": "скорость ползуна {N} вдоль направляющей 2 (Крамер)",
        "t1": "2 vs omega1 + s eps1: кориолисово и касательное ускорения поперёк направляющей 1",
        "t2": "2 vs2 omega2 + s2 eps2: то же для направляющей 2",
        "f1": "правая часть для ускорений f1",
        "f2": "правая часть для ускорений f2",
        "as": "ускорение камня {N} вдоль направляющей 1",
        "as2": "ускорение ползуна {N} вдоль направляющей 2",
        "hinge": "Шарнир {N} = точка L: движение с направляющей 1 и по ней",
        "of_hinge": "шарнира {N}",
        "chk_pos": "проверка: {N} = P1 + s u1 = P2 + s2 u2 (на обеих направляющих)",
        "chk_v": "проверка: скорость {N} через направляющую 2",
        "chk_a": "проверка: ускорение {N} через направляющую 2",
        "R_det": "определитель: sin(theta - eta) (0: направляющие параллельны)",
        "Qa": "нормальная сила направляющей 1 на камень (Крамер)",
        "Qb": "нормальная сила направляющей 2 на ползун (Крамер)",
        "chk_Rsys": "проверка: нормальные силы в их двух уравнениях",
        "R_1": "направляющей 1 (звено {k}) на камень {a} (через {N})",
        "M_1": "момент реакции направляющей 1 на камень {a}",
        "R_ab": "камня {a} на ползун {bl} в {N}",
        "R_2": "направляющей 2 (звено {k}) на ползун {bl} (через {N})",
        "M_2": "момент реакции направляющей 2 на ползун {bl}",
    },
    "uk": {
        "guide": "напрямна {j} каменя {ab} (вузол {N})",
        "gamma_k": "{which}: кут до ланці {k}",
        "gx": "{which}: x точки",
        "gy": "{which}: y точки",
        "gamma": "{which}: кут нахилу",
        "group": "Група {i} (ПОП {N}): повзунок на шатуні і фіксована напрямна, рівняння (1)-(7)",
        "eta": "(4) нахил прямої (2) (напрямна 1): tg eta = (yB - yA)/(xB - xA) записаний кутом eta, щоб вертикальна "
               "пряма (tg = нескінченність) залишалася скінченної",
        "n": "(3a) n cos(eta) = y cos(eta) - x sin(eta) точки прямої (2): n, помножене на cos(eta), скінченно і для "
             "вертикальної прямої",
        "theta": "(1) нахил прямої (1) (напрямна 2), кут theta",
        "m": "(1) m cos(theta) = y cos(theta) - x sin(theta) точки прямої (1)",
        "D": "(7) знаменник tg theta - tg eta, помножений на cos theta cos eta: sin(theta - eta) (0: прямі "
             "паралельні, група не збирається)",
        "guard": "група {i} збирається (прямі не паралельні)",
        "xL": "(7) x_L = (n - m)/(tg theta - tg eta), помножено на cos theta cos eta: (n cos eta cos theta - m cos "
              "theta cos eta)/sin(theta - eta)",
        "yL": "(7) y_L = (n tg theta - m tg eta)/(tg theta - tg eta), помножено на cos theta cos eta",
        "chk_5a": "перевірка (5a): L на прямої (2)",
        "chk_5b": "перевірка (5b): L на прямої (1)",
        "accepted": "Прийняті значення",
        "s": "положення каменя {N} уздовж напрямної 1 від її точки",
        "s2": "положення повзуна {N} уздовж напрямної 2 від її точки",
        "phi_a": "кут каменя {la} (напрямна 1)",
        "phi_b": "кут повзуна {lb} (напрямна 2)",
        "chk_acc": "перевірка прийнятих значень: P1 + s u1 - P2 - s2 u2",
        "block": "каменя",
        "slider": "повзуна",
        "omega": "кутова швидкість {what} {k} (разом з напрямної)",
        "eps": "кутове прискорення {what} {k}",
        "rot": "камінь {la} і повзун {lb} повернуті і обертаються разом зі своїми напрямними",
        "det": "визначник: -sin(theta - eta)",
        "toggle": "sin(theta - eta): синус кута між напрямними (близько 0: мертве положення)",
        "vs": "швидкість каменя {N} уздовж напрямної 1 (Крамер)",
        "vs2": "швидкість повзуна {N} уздовж напрямної 2 (Крамер)",
        "t1": "2 vs omega1 + s eps1: коріолісове і дотичне прискорення поперек напрямної 1",
        "t2": "2 vs2 omega2 + s2 eps2: то ж для напрямної 2",
        "f1": "права частина для прискорень f1",
        "f2": "права частина для прискорень f2",
        "as": "прискорення каменя {N} уздовж напрямної 1",
        "as2": "прискорення повзуна {N} уздовж напрямної 2",
        "hinge": "Шарнір {N} = точка L: рух з напрямної 1 і за неї",
        "of_hinge": "шарніра {N}",
        "chk_pos": "перевірка: {N} = P1 + s u1 = P2 + s2 u2 (на обох напрямних)",
        "chk_v": "перевірка: швидкість {N} через напрямну 2",
        "chk_a": "перевірка: прискорення {N} через напрямну 2",
        "R_det": "визначник: sin(theta - eta) (0: напрямні паралельні)",
        "Qa": "нормальна сила напрямної 1 на камінь (Крамер)",
        "Qb": "нормальна сила напрямної 2 на повзун (Крамер)",
        "chk_Rsys": "перевірка: нормальні сили в їх двох рівняннях",
        "R_1": "напрямної 1 (ланка {k}) на камінь {a} (через {N})",
        "M_1": "момент реакції напрямної 1 на камінь {a}",
        "R_ab": "каменя {a} на повзун {bl} в {N}",
        "R_2": "напрямної 2 (ланка {k}) на повзун {bl} (через {N})",
        "M_2": "момент реакції напрямної 2 на повзун {bl}",
    },
    "en": {
        "guide": "guide {j} of block {ab} (joint {N})",
        "gamma_k": "{which}: angle to link {k}",
        "gx": "{which}: x of a point",
        "gy": "{which}: y of a point",
        "gamma": "{which}: its angle",
        "group": "Group {i} (PRP {N}): slider on the coupler with a fixed guide, equations (1)-(7)",
        "eta": "(4) slope of line (2) (guide 1): tg eta = (yB - yA)/(xB - xA) kept as the angle eta, so that a "
               "vertical line (infinite tg) stays finite",
        "n": "(3a) n cos(eta) = y cos(eta) - x sin(eta) of a point of line (2): n times cos(eta), finite for a "
             "vertical line too",
        "theta": "(1) slope of line (1) (guide 2), the angle theta",
        "m": "(1) m cos(theta) = y cos(theta) - x sin(theta) of a point of line (1)",
        "D": "(7) denominator tg theta - tg eta times cos theta cos eta: sin(theta - eta) (0: parallel lines, "
             "cannot assemble)",
        "guard": "group {i} assembles (the lines cross)",
        "xL": "(7) x_L = (n - m)/(tg theta - tg eta), times cos theta cos eta: "
              "(n cos eta cos theta - m cos theta cos eta)/sin(theta - eta)",
        "yL": "(7) y_L = (n tg theta - m tg eta)/(tg theta - tg eta), times cos theta cos eta",
        "chk_5a": "check (5a): L on line (2)",
        "chk_5b": "check (5b): L on line (1)",
        "accepted": "Accepted values",
        "s": "travel of block {N} along guide 1 from its point",
        "s2": "travel of slider {N} along guide 2 from its point",
        "phi_a": "angle of block {la} (guide 1)",
        "phi_b": "angle of slider {lb} (guide 2)",
        "chk_acc": "check of the accepted values: P1 + s u1 - P2 - s2 u2",
        "block": "block",
        "slider": "slider",
        "omega": "angular velocity of {what} {k} (turns with its guide)",
        "eps": "angular acceleration of {what} {k}",
        "rot": "block {la} and slider {lb} point along and turn with their guides",
        "det": "determinant: -sin(theta - eta)",
        "toggle": "sin(theta - eta): sine of the angle between the guides (near 0: toggle)",
        "vs": "velocity of block {N} along guide 1 (Cramer)",
        "vs2": "velocity of slider {N} along guide 2 (Cramer)",
        "t1": "2 vs omega1 + s eps1: Coriolis and tangential terms across guide 1",
        "t2": "2 vs2 omega2 + s2 eps2: the same for guide 2",
        "f1": "right side of the acceleration system f1",
        "f2": "right side of the acceleration system f2",
        "as": "acceleration of block {N} along guide 1",
        "as2": "acceleration of slider {N} along guide 2",
        "hinge": "Hinge {N} = the point L: carried by guide 1 and sliding on it",
        "of_hinge": "hinge {N}",
        "chk_pos": "check: {N} = P1 + s u1 = P2 + s2 u2 (on both guides)",
        "chk_v": "check: velocity of {N} through guide 2",
        "chk_a": "check: acceleration of {N} through guide 2",
        "R_det": "determinant: sin(theta - eta) (0: parallel guides)",
        "Qa": "normal force of guide 1 on the block (Cramer)",
        "Qb": "normal force of guide 2 on the slider (Cramer)",
        "chk_Rsys": "check: the normal forces put back into their two equations",
        "R_1": "of guide 1 (link {k}) on block {a} (through {N})",
        "M_1": "couple of guide 1 on block {a}",
        "R_ab": "of block {a} on slider {bl} at {N}",
        "R_2": "of guide 2 (link {k}) on slider {bl} (through {N})",
        "M_2": "couple of guide 2 on slider {bl}",
    },
}
T = Texts(TEXTS)


# --------------------------------------------------------------------------- scene keys
@dataclass(frozen=True)
class Params:
    guides: tuple[Guide, Guide]     # guides[0]: block a's line (the lecture's (2), the coupler);
                                    # guides[1]: block b's line (the lecture's (1), fixed)


def parse(tbl, frame) -> tuple[tuple[str, ...], Params]:
    joints = tbl.array("joints", 1, "name")
    guides = tbl.guides("guides", 2, frame)
    if not guides[0].moving and not guides[1].moving:
        tbl.fail("guides", "both guides are on the frame: N could not move; put at least one "
                           "guide on a moving link (e.g. the coupler: {through = \"A\", angle_deg = 0, link = 2})")
    return joints, Params(guides)


def needs(g: Group) -> list[str]:
    return [gd.through for gd in g.guides if gd.moving]


def on_links(g: Group) -> list[tuple[str, str, int]]:
    """(key, point, link): a moving guide's `through` must be a point of its link."""
    return [(f"guides[{j}].through", gd.through, gd.link) for j, gd in enumerate(g.guides) if gd.moving]


def new_joints(g: Group) -> list[str]:
    return [g.joints[0]]


def carries(g: Group) -> dict[int, list[str]]:
    a, b = g.links
    return {a: [g.joints[0]], b: [g.joints[0]]}


def sliders(g: Group) -> list[str]:
    """s_N along guides[0], s2_N along guides[1] (the contract)."""
    return [g.joints[0], f"2_{g.joints[0]}"]


def fourbar(g: Group, crank_joint: str, frame) -> None:
    """Not a four-bar's dyad (only an RRR closes one with the crank: sheetkin.studies.synthesis)."""
    return None


def parts(g: Group) -> Parts:
    """Two blocks at N, block a on guides[0] and block b on guides[1]; guide j's angle is
    the input gamma<j>_g<i>, its point on the frame gx<j>_g<i>, gy<j>_g<i>."""
    (n,), (a, b), i = g.joints, g.links, g.index
    ga, gb = (scene_guide(gd, n, i, f"gamma{j}_g{i}", (f"gx{j}_g{i}", f"gy{j}_g{i}"))
              for j, gd in enumerate(g.guides, 1))
    return Parts({a: (n,), b: (n,)}, (ga, gb), (BlockPart(a, n, ga), BlockPart(b, n, gb)))


# --------------------------------------------------------------------------- positions and rates
def solve_prp(pa: Motion, ga: Rotation, pb: Motion, gb: Rotation):
    """N, the two slides (s_N along guide a, s2_N along guide b), the discriminant
    (negative where the guides are parallel) and the toggle measure sin(theta_b - theta_a)."""
    m11, m12, m21, m22 = ga.c, -gb.c, ga.s, -gb.s
    det, inv = inverse_det(m11, m12, m21, m22)
    s1, s2 = cramer(m11, m12, m21, m22, pb.x - pa.x, pb.y - pa.y, inv)
    nax, nay, nbx, nby = -ga.s, ga.c, -gb.s, gb.c
    wa, ea, wb, eb = ga.omega, ga.eps, gb.omega, gb.eps
    # velocities: the guides' turning moves the crossing point along the other line
    b1 = pb.vx - pa.vx - s1 * wa * nax + s2 * wb * nbx
    b2 = pb.vy - pa.vy - s1 * wa * nay + s2 * wb * nby
    vs1, vs2 = cramer(m11, m12, m21, m22, b1, b2, inv)
    # accelerations: same matrix; Coriolis 2 vs w n, tangential s e n, centripetal -s w^2 u
    ta, tb = 2.0 * vs1 * wa + s1 * ea, 2.0 * vs2 * wb + s2 * eb
    ra, rb = s1 * wa * wa, s2 * wb * wb
    b1 = pb.ax - pa.ax - ta * nax + ra * ga.c + tb * nbx - rb * gb.c
    b2 = pb.ay - pa.ay - ta * nay + ra * ga.s + tb * nby - rb * gb.s
    as1, as2 = cramer(m11, m12, m21, m22, b1, b2, inv)
    joint = Motion(pa.x + s1 * ga.c, pa.y + s1 * ga.s,
                   pa.vx + vs1 * ga.c + s1 * wa * nax, pa.vy + vs1 * ga.s + s1 * wa * nay,
                   pa.ax + as1 * ga.c + ta * nax - ra * ga.c, pa.ay + as1 * ga.s + ta * nay - ra * ga.s)
    sine = -det + np.zeros(np.shape(s1))
    disc = np.where(np.abs(sine) > DEAD_POINT, sine * sine, -1.0)    # parallel within DEAD_POINT: no crossing
    return joint, Slide(s1, vs1, as1), Slide(s2, vs2, as2), disc, sine


def solve(g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion:
    (n,), (a, b) = g.joints, g.links
    (pa, ua), (pb, ub) = (guide_line(gd, known, rot) for gd in g.guides)
    joint, sa, sb, disc, sine = solve_prp(pa, ua, pb, ub)
    zero = np.zeros_like(sa.s)
    ra = Rotation(ua.c + zero, ua.s + zero, ua.omega + zero, ua.eps + zero)
    rb = Rotation(ub.c + zero, ub.s + zero, ub.omega + zero, ub.eps + zero)
    return GroupMotion({n: joint}, {a: ra, b: rb}, {n: sa, f"2_{n}": sb}, disc, sine)


# --------------------------------------------------------------------------- the lecture's form
def lecture_intersection(xa, ya, eta, m_cos, theta):
    """x_L, y_L by the lecture's (3a), (7), multiplied through by cos(theta) cos(eta).

    The lecture writes line (2) through A as y = n + x tg(eta) with n = y_A - x_A tg(eta)
    (3a), line (1) as y = m + x tg(theta), and x_L = (n - m)/(tg theta - tg eta),
    y_L = (n tg theta - m tg eta)/(tg theta - tg eta) (7). A vertical line makes tg
    infinite; with n' = n cos(eta) = y_A cos(eta) - x_A sin(eta) and m' = m cos(theta)
    (the lines' signed distances from the origin) the same formulas read
        x_L = (n' cos theta - m' cos eta) / sin(theta - eta),
        y_L = (n' sin theta - m' sin eta) / sin(theta - eta),
    finite for every pair of non-parallel lines. Returns (n', x_L, y_L).
    """
    n_cos = ya * np.cos(eta) - xa * np.sin(eta)
    d = np.sin(theta - eta)
    return n_cos, (n_cos * np.cos(theta) - m_cos * np.cos(eta)) / d, \
        (n_cos * np.sin(theta) - m_cos * np.sin(eta)) / d


# --------------------------------------------------------------------------- the workbook
def input_rows(g: Group) -> list[InputRow]:
    i, (n,) = g.index, g.joints
    out = []
    for j, gd in enumerate(g.guides, 1):
        which = T("guide", j=j, ab="a" if j == 1 else "b", N=n)
        if gd.moving:
            out.append(InputRow(f"gamma{j}_g{i}", "deg", T("gamma_k", which=which, k=gd.link), gd.angle_deg))
        else:
            out += [InputRow(f"gx{j}_g{i}", "m", T("gx", which=which), gd.point[0]),
                    InputRow(f"gy{j}_g{i}", "m", T("gy", which=which), gd.point[1]),
                    InputRow(f"gamma{j}_g{i}", "deg", T("gamma", which=which), gd.angle_deg)]
    return out


def with_inputs(g: Group, num) -> Group:
    i, guides = g.index, []
    for j, gd in enumerate(g.guides, 1):
        point = None if gd.moving else (num(f"gx{j}_g{i}", gd.point[0]), num(f"gy{j}_g{i}", gd.point[1]))
        guides.append(dataclasses.replace(gd, point=point, angle_deg=num(f"gamma{j}_g{i}", gd.angle_deg)))
    return dataclasses.replace(g, params=Params(tuple(guides)))


def _line_refs(b: Builder, g: Group, j: int):
    """Formula pieces of guide j (1 or 2): its point's x y vx vy ax ay, its direction
    (radians) and the omega, eps it turns with."""
    i, gd = g.index, g.guides[j - 1]
    gam = f"RADIANS({{gamma{j}_g{i}}})"
    if not gd.moving:
        return (f"{{gx{j}_g{i}}}", f"{{gy{j}_g{i}}}", "0", "0", "0", "0"), gam, "0", "0"
    ck, sk, wk, ek = (f"{{{r}}}" for r in b.rot[gd.link])
    P = gd.through
    return tuple(b.p(q, P) for q in ("x", "y", "vx", "vy", "ax", "ay")), f"ATAN2({ck},{sk})+{gam}", wk, ek


def rows(b: Builder, g: Group):
    """The lecture's slider on the coupler with a fixed guide, equations (1)-(7): line (2)
    is guides[0] (the coupler AB: tg eta by (4), n by (3a)), line (1) is guides[1]
    (y = m + x tg theta); N = L by (7). Every tangent is multiplied out (see
    lecture_intersection), so vertical lines stay finite; the rows say so."""
    refs = _line_refs(b, g, 1), _line_refs(b, g, 2)
    _crossing_rows(b, g, refs)
    _accepted_rows(b, g, refs)
    _rate_rows(b, g, refs)
    b.place_links(*g.links)
    _joint_rows(b, g, refs)


def _crossing_rows(b: Builder, g: Group, refs) -> None:
    """Equations (1)-(7): the two lines, their crossing L and the checks (5a), (5b)."""
    i, (N,) = g.index, g.joints
    (pa, eta_f, _, _), (pb, th_f, _, _) = refs
    b.section(f"group_{i}", T("group", i=i, N=N))
    eta, nn, th, mm, D = f"eta_g{i}", f"n_g{i}", f"theta_g{i}", f"m_g{i}", f"D_g{i}"
    b.calc(eta, "rad", T("eta"), eta_f, guard=b.guard)
    b.calc(nn, "m", T("n"), f"{pa[1]}*COS({{{eta}}})-{pa[0]}*SIN({{{eta}}})", guard=b.guard)
    b.calc(th, "rad", T("theta"), th_f, guard=b.guard)
    b.calc(mm, "m", T("m"), f"{pb[1]}*COS({{{th}}})-{pb[0]}*SIN({{{th}}})", guard=b.guard)
    b.calc(D, "", T("D"), f"SIN({{{th}}}-{{{eta}}})", guard=b.guard)
    prev = b.guard
    b.row("guard", f"asm_g{i}", "", T("guard", i=i),
          f"AND({{{prev}}},ABS({{{D}}})>{DEAD_POINT_TEXT})" if prev else f"ABS({{{D}}})>{DEAD_POINT_TEXT}")
    b.guard = f"asm_g{i}"
    xL, yL = f"xL_g{i}", f"yL_g{i}"
    b.calc(xL, "m", T("xL"), f"({{{nn}}}*COS({{{th}}})-{{{mm}}}*COS({{{eta}}}))/{{{D}}}")
    b.calc(yL, "m", T("yL"), f"({{{nn}}}*SIN({{{th}}})-{{{mm}}}*SIN({{{eta}}}))/{{{D}}}")
    b.check(f"chk_5a_g{i}", "m", T("chk_5a"), f"{{{yL}}}*COS({{{eta}}})-{{{xL}}}*SIN({{{eta}}})-{{{nn}}}")
    b.check(f"chk_5b_g{i}", "m", T("chk_5b"), f"{{{yL}}}*COS({{{th}}})-{{{xL}}}*SIN({{{th}}})-{{{mm}}}")


def _accepted_rows(b: Builder, g: Group, refs) -> None:
    """The slides s, s2 from L, the blocks' angles and rates (they turn with their guides)."""
    i, (la, lb), (N,) = g.index, g.links, g.joints
    (pa, _, wa_f, ea_f), (pb, _, wb_f, eb_f) = refs
    eta, th, xL, yL = f"eta_g{i}", f"theta_g{i}", f"xL_g{i}", f"yL_g{i}"
    b.section(f"accepted_g{i}", T("accepted"))
    s1, s2 = f"s_{N}", f"s2_{N}"
    b.accepted(s1, "m", T("s", N=N), f"({{{xL}}}-{pa[0]})*COS({{{eta}}})+({{{yL}}}-{pa[1]})*SIN({{{eta}}})")
    b.accepted(s2, "m", T("s2", N=N), f"({{{xL}}}-{pb[0]})*COS({{{th}}})+({{{yL}}}-{pb[1]})*SIN({{{th}}})")
    b.accepted(f"phi_{la}", "deg", T("phi_a", la=la), f"MOD(DEGREES({{{eta}}}),360)")
    b.accepted(f"phi_{lb}", "deg", T("phi_b", lb=lb), f"MOD(DEGREES({{{th}}}),360)")
    cos_sin_rows(b, la)
    cos_sin_rows(b, lb)
    ca, sa, cb, sb = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    S1, S2 = f"{{{s1}}}", f"{{{s2}}}"
    b.check(f"chk_acc_g{i}", "m", T("chk_acc"),
            f"ABS({pa[0]}+{S1}*{ca}-{pb[0]}-{S2}*{cb})+ABS({pa[1]}+{S1}*{sa}-{pb[1]}-{S2}*{sb})")
    for k, w, e, what in ((la, wa_f, ea_f, T("block")), (lb, wb_f, eb_f, T("slider"))):
        b.accepted(f"omega_{k}", "rad/s", T("omega", what=what, k=k), w)
        b.accepted(f"eps_{k}", "rad/s^2", T("eps", what=what, k=k), e)
    turns_with_check(b, f"chk_rot_g{i}", [(f"phi_{la}", f"COS({{{eta}}})", f"SIN({{{eta}}})"),
                                          (f"phi_{lb}", f"COS({{{th}}})", f"SIN({{{th}}})")],
                     [(f"omega_{la}", wa_f), (f"eps_{la}", ea_f), (f"omega_{lb}", wb_f), (f"eps_{lb}", eb_f)],
                     T("rot", la=la, lb=lb))


def _rate_rows(b: Builder, g: Group, refs) -> None:
    """Cramer's rule for the slides' velocities, then (Coriolis terms t1, t2) accelerations."""
    i, (la, lb), (N,) = g.index, g.links, g.joints
    (pa, *_), (pb, *_) = refs
    ca, sa, cb, sb = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    S1, S2 = f"{{s_{N}}}", f"{{s2_{N}}}"
    wa, ea, wb, eb = f"{{omega_{la}}}", f"{{eps_{la}}}", f"{{omega_{lb}}}", f"{{eps_{lb}}}"
    # u1 vs - u2 vs2 = v_P2 - v_P1 - s w1 n1 + s2 w2 n2 (n = u turned +90 deg)
    det = f"Delta_g{i}"
    m = (ca, f"(-{cb})", sa, f"(-{sb})")
    det_row(b, det, m, "", T("det"))
    b.calc(f"det_g{i}", "", T("toggle"), f"-{{{det}}}")
    v1 = f"({pb[2]}-{pa[2]}+{S1}*{wa}*{sa}-{S2}*{wb}*{sb})"
    v2 = f"({pb[3]}-{pa[3]}-{S1}*{wa}*{ca}+{S2}*{wb}*{cb})"
    cramer_rows(b, m, det, ((f"vs_{N}", "m/s", T("vs", N=N)), (f"vs2_{N}", "m/s", T("vs2", N=N))),
                (v1, v2), residual(i, "v"))
    f1, f2, t1, t2 = f"f1_g{i}", f"f2_g{i}", f"t1_g{i}", f"t2_g{i}"
    b.calc(t1, "m/s^2", T("t1"), f"2*{{vs_{N}}}*{wa}+{S1}*{ea}")
    b.calc(t2, "m/s^2", T("t2"), f"2*{{vs2_{N}}}*{wb}+{S2}*{eb}")
    T1, T2 = f"{{{t1}}}", f"{{{t2}}}"
    b.calc(f1, "m/s^2", T("f1"), f"{pb[4]}-{pa[4]}+{T1}*{sa}+{S1}*{wa}^2*{ca}-{T2}*{sb}-{S2}*{wb}^2*{cb}")
    b.calc(f2, "m/s^2", T("f2"), f"{pb[5]}-{pa[5]}-{T1}*{ca}+{S1}*{wa}^2*{sa}+{T2}*{cb}-{S2}*{wb}^2*{sb}")
    cramer_rows(b, m, det, ((f"as_{N}", "m/s^2", T("as", N=N)), (f"as2_{N}", "m/s^2", T("as2", N=N))),
                (f"{{{f1}}}", f"{{{f2}}}"), residual(i, "a"))


def _joint_rows(b: Builder, g: Group, refs) -> None:
    """N = L carried by guide 1 and sliding on it, checked through guide 2."""
    i, (la, lb), (N,) = g.index, g.links, g.joints
    (pa, *_), (pb, *_) = refs
    ca, sa, cb, sb = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    S1, S2 = f"{{s_{N}}}", f"{{s2_{N}}}"
    wa, wb = f"{{omega_{la}}}", f"{{omega_{lb}}}"
    T1, T2 = f"{{t1_g{i}}}", f"{{t2_g{i}}}"
    xL, yL = f"xL_g{i}", f"yL_g{i}"
    b.section(f"point_{N}", T("hinge", N=N))
    tu = f"({{as_{N}}}-{S1}*{wa}^2)"
    motion_rows(b, N, T("of_hinge", N=N), f"{{{xL}}}", f"{{{yL}}}",
                f"{pa[2]}+{{vs_{N}}}*{ca}-{S1}*{wa}*{sa}", f"{pa[3]}+{{vs_{N}}}*{sa}+{S1}*{wa}*{ca}",
                f"{pa[4]}+{tu}*{ca}-{T1}*{sa}", f"{pa[5]}+{tu}*{sa}+{T1}*{ca}")
    # x_N, y_N are written as the crossing point (7); nothing in the kinematics reads them
    # back, so here they are put on each guide at its travel s, s2 (free of the step)
    b.check(f"chk_pos_{N}_g{i}", "m", T("chk_pos", N=N),
            f"ABS({{x_{N}}}-({pa[0]}+{S1}*{ca}))+ABS({{y_{N}}}-({pa[1]}+{S1}*{sa}))"
            f"+ABS({{x_{N}}}-({pb[0]}+{S2}*{cb}))+ABS({{y_{N}}}-({pb[1]}+{S2}*{sb}))")
    tu2 = f"({{as2_{N}}}-{S2}*{wb}^2)"
    b.check(f"chk_v_{N}_g{i}", "m/s", T("chk_v", N=N),
            f"ABS({{vx_{N}}}-({pb[2]}+{{vs2_{N}}}*{cb}-{S2}*{wb}*{sb}))"
            f"+ABS({{vy_{N}}}-({pb[3]}+{{vs2_{N}}}*{sb}+{S2}*{wb}*{cb}))")
    b.check(f"chk_a_{N}_g{i}", "m/s^2", T("chk_a", N=N),
            f"ABS({{ax_{N}}}-({pb[4]}+{tu2}*{cb}-{T2}*{sb}))+ABS({{ay_{N}}}-({pb[5]}+{tu2}*{sb}+{T2}*{cb}))")
    fd_checks(b, N)


# --------------------------------------------------------------------------- kinetostatics
def reaction_forces(fa, fb, ma_n, mb_n, ga: Rotation, gb: Rotation):
    """The group's pair forces from its links' loads (pure arithmetic over arrays).

    fa, fb: resultant loads (x, y) on blocks a and b; ma_n, mb_n: their moments about N.
    Guide k_a acts on block a with Qa n_a through N and a couple Ca; guide k_b on block b
    with Qb n_b and Cb; block b on block a with X at N. Block a: Qa n_a + X + Fa = 0,
    Ca + Ma(N) = 0; block b: Qb n_b - X + Fb = 0, Cb + Mb(N) = 0. The sum gives
    Qa n_a + Qb n_b = -(Fa + Fb): Cramer with the determinant sin(theta_b - theta_a),
    zero (no answer) exactly where the kinematics has its toggle.
    Returns (Qa n_a, Ca), (Qb n_b, Cb), X: forces as (x, y) pairs.
    """
    nax, nay, nbx, nby = -ga.s, ga.c, -gb.s, gb.c
    _, inv = inverse_det(nax, nbx, nay, nby)
    qa, qb = cramer(nax, nbx, nay, nby, -(fa[0] + fb[0]), -(fa[1] + fb[1]), inv)
    xx, xy = -qa * nax - fa[0], -qa * nay - fa[1]
    return ((qa * nax, qa * nay), -ma_n), ((qb * nbx, qb * nby), -mb_n), (xx, xy)


def pin_owner(g: Group) -> dict[str, int]:
    """A later group hinged at N is taken to hinge on block a (guides[0]'s block)."""
    return {g.joints[0]: g.links[0]}


def pairs(g: Group, owner: dict[str, int]) -> list[Pair]:
    (n,), (a, b), (ga, gb) = g.joints, g.links, g.guides
    return [Pair(ga.link, a, n, True), Pair(a, b, n), Pair(gb.link, b, n, True)]


def reactions(g: Group, known, links, loads, owner) -> dict[str, tuple]:
    """reaction_forces on the two blocks' loads; the links that carry the guides take the
    guides' forces back at N (and the couples)."""
    (n,), (a, b), (ga, gb) = g.joints, g.links, g.guides
    nj = known[n]
    (qa, ca), (qb, cb), x = reaction_forces(loads[a].resultant(), loads[b].resultant(),
                                            loads[a].moment(nj.x, nj.y), loads[b].moment(nj.x, nj.y),
                                            links[a], links[b])
    for gd, q, c in ((ga, qa, ca), (gb, qb, cb)):
        loads[gd.link].add(nj, -q[0], -q[1])
        loads[gd.link].couple = loads[gd.link].couple - c
    return {f"{ga.link}_{a}": (qa[0], qa[1], ca), f"{a}_{b}": (-x[0], -x[1], None),
            f"{gb.link}_{b}": (qb[0], qb[1], cb)}


def reaction_rows(b: Builder, g: Group, owner: dict[str, int], k: LoadRows):
    """The same in the sheet: Qa n_a + Qb n_b = -(Q_a + Q_b) by Cramer, then the pairs."""
    i, (a, bl), (N,), (ga, gb) = g.index, g.links, g.joints, g.guides
    k.link_loads(a, N)
    k.link_loads(bl, N)
    ca, sa, cb, sb = f"{{cos_{a}}}", f"{{sin_{a}}}", f"{{cos_{bl}}}", f"{{sin_{bl}}}"
    m = (f"(-{sa})", f"(-{sb})", ca, cb)
    rhs = (f"(-({{Qx_{a}}}+{{Qx_{bl}}}))", f"(-({{Qy_{a}}}+{{Qy_{bl}}}))")
    det, qa, qb = f"Delta_R_g{i}", f"Qa_g{i}", f"Qb_g{i}"
    det_row(b, det, m, "", T("R_det"))
    b.calc(qa, "N", T("Qa"), f"({rhs[0]}*{m[3]}-{rhs[1]}*{m[1]})/{{{det}}}")
    b.calc(qb, "N", T("Qb"), f"({m[0]}*{rhs[1]}-{m[2]}*{rhs[0]})/{{{det}}}")
    b.check(f"chk_Rsys_g{i}", "", T("chk_Rsys"),
            f"(ABS({m[0]}*{{{qa}}}+{m[1]}*{{{qb}}}-{rhs[0]})+ABS({m[2]}*{{{qa}}}+{m[3]}*{{{qb}}}-{rhs[1]}))"
            f"/(1+ABS({{Qx_{a}}})+ABS({{Qy_{a}}})+ABS({{Qx_{bl}}})+ABS({{Qy_{bl}}}))")
    t1, tab, t2 = f"{ga.link}_{a}", f"{a}_{bl}", f"{gb.link}_{bl}"
    k.reaction(t1, f"-{{{qa}}}*{sa}", f"{{{qa}}}*{ca}", T("R_1", k=ga.link, a=a, N=N))
    b.accepted(f"M_{t1}", "N m", T("M_1", a=a), f"-{{MQ_{a}}}")
    k.reaction(tab, f"-{{{qa}}}*{sa}+{{Qx_{a}}}", f"{{{qa}}}*{ca}+{{Qy_{a}}}", T("R_ab", a=a, bl=bl, N=N))
    k.equilibrium(a, N, [(N, f"{{Rx_{t1}}}", f"{{Ry_{t1}}}"), (N, f"(-{{Rx_{tab}}})", f"(-{{Ry_{tab}}})")],
                  f"{{M_{t1}}}")
    k.reaction(t2, f"-{{{qb}}}*{sb}", f"{{{qb}}}*{cb}", T("R_2", k=gb.link, bl=bl, N=N))
    b.accepted(f"M_{t2}", "N m", T("M_2", bl=bl), f"-{{MQ_{bl}}}")
    k.equilibrium(bl, N, [(N, f"{{Rx_{tab}}}", f"{{Ry_{tab}}}"), (N, f"{{Rx_{t2}}}", f"{{Ry_{t2}}}")], f"{{M_{t2}}}")
    for gd, t in ((ga, t1), (gb, t2)):
        if gd.moving:      # the link that carries the guide: the block pushes back on it
            k.opposite(gd.link, N, t, couple=True)


# --------------------------------------------------------------------------- loop equations
def loop_lines(lib, pa, guide_a, pb, guide_b):
    """The loop-closure equation F(q) = P_a + s1 u_a - P_b - s2 u_b = 0 in q = (s1, s2),
    for any number type `lib` (mpmath or float, sheetkin.studies.bench). pa, pb: ((x, y), (vx, vy),
    (ax, ay)); guide_*: (theta, omega, eps) of the guide's direction.
    Returns F, J, b_v, b_a, place as bench's loops do; place gives N, the two links'
    (theta, omega, eps) and the two slides (s, vs, as)."""
    (p1, v1, a1), (p2, v2, a2) = pa, pb
    (ta, wa, ea), (tb, wb, eb) = guide_a, guide_b
    ua, ub = (lib.cos(ta), lib.sin(ta)), (lib.cos(tb), lib.sin(tb))
    na, nb = (-ua[1], ua[0]), (-ub[1], ub[0])

    def F(q):
        return [p1[i] + q[0] * ua[i] - p2[i] - q[1] * ub[i] for i in (0, 1)]

    def J(q):
        return [[ua[0], -ub[0]], [ua[1], -ub[1]]]

    def b_v(q):
        return [v2[i] - v1[i] - q[0] * wa * na[i] + q[1] * wb * nb[i] for i in (0, 1)]

    def b_a(q, qt):
        return [a2[i] - a1[i] - (2 * qt[0] * wa + q[0] * ea) * na[i] + q[0] * wa * wa * ua[i]
                + (2 * qt[1] * wb + q[1] * eb) * nb[i] - q[1] * wb * wb * ub[i] for i in (0, 1)]

    def place(q, qt, qtt):
        pos = tuple(p1[i] + q[0] * ua[i] for i in (0, 1))
        vel = tuple(v1[i] + qt[0] * ua[i] + q[0] * wa * na[i] for i in (0, 1))
        acc = tuple(a1[i] + qtt[0] * ua[i] + (2 * qt[0] * wa + q[0] * ea) * na[i]
                    - q[0] * wa * wa * ua[i] for i in (0, 1))
        slides = ((q[0], qt[0], qtt[0]), (q[1], qt[1], qtt[1]))
        return (pos, vel, acc), (guide_a, guide_b), slides
    return F, J, b_v, b_a, place


def loop(lib, g: Group, known, links):
    """P1 + s u1 = P2 + s2 u2 (loop_lines) with the scene's guides; q = (s_N, s2_N)."""
    n = g.joints[0]
    F, J, b_v, b_a, place_lines = loop_lines(lib, *guide_loop(lib, g.guides[0], known, links),
                                             *guide_loop(lib, g.guides[1], known, links))

    def place(q, qt, qtt):
        joint, rots, (sa, sb) = place_lines(q, qt, qtt)
        return {n: joint}, rots, {n: sa, f"2_{n}": sb}
    return F, J, b_v, b_a, place


def side_ok(lib, g: Group, known, links, q, joints) -> bool:
    """Two lines cross once: PRP has no branch."""
    return True


def discriminant(lib, g: Group, known, links):
    """sin^2(theta_b - theta_a): two lines always cross unless parallel, where it touches 0
    (the toggle; PRP has no range edge)."""
    (_, (ta, _, _)), (_, (tb, _, _)) = (guide_loop(lib, gd, known, links) for gd in g.guides)
    return lib.sin(tb - ta) ** 2


def unknowns(g: Group, sol) -> tuple[np.ndarray, np.ndarray]:
    n = g.joints[0]
    return sol.slides[n].s, sol.slides[f"2_{n}"].s


def parallel(lib, g: Group, known, links):
    """sin(theta_b - theta_a), signed: its simple root is where the two lines turn parallel
    (the stability study's edge; the discriminant, its square, touches 0 there)."""
    (_, (ta, _, _)), (_, (tb, _, _)) = (guide_loop(lib, gd, known, links) for gd in g.guides)
    return lib.sin(tb - ta)


# --------------------------------------------------------------------------- stability families
# Two lines always cross unless parallel: PRP has no edge of a range. Its failure is the
# coupler's line turning parallel to the fixed guide: N runs off to infinity (s ~ 1/d,
# vs ~ 1/d^2, as ~ 1/d^3) and the toggle measure sin(theta - eta) -> 0 like d. Past it
# the group assembles again, N coming back from the other side.
STABILITY = (
    Family("parallel-lines", "PRP: the coupler's line turning parallel to the fixed guide (N runs off)",
           crank_scene("Slider on the coupler of a crank-slider, a fixed guide at 20 deg that the coupler reaches", """\
[[group]]
type = "RRP"
links = [2, 3]
joints = ["A", "B"]
length = 0.5
guide = { through = "O", angle_deg = 0.0 }
branch = 1
[[group]]
type   = "PRP"
links  = [4, 5]
joints = ["L"]
guides = [{ through = "A", angle_deg = 0.0, link = 2 }, { through = [0.0, 0.25], angle_deg = 20.0 }]
"""), 2, parallel, near_deg=220.0),
)
