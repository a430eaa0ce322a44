"""The lecture's workbook (seed 003, steps 7-10) with live formulas, written with openpyxl.

Layout of the sheet, top to bottom (the lecture's "programming by rows"):
  rows 1-2  title (scheme) and author; row 3 the summary of all checks;
  input block: lengths, frame points, Alfa_A, Betta_A, Fi0, Fi_t, Fi_tt, Delta_Fi (deg
            and rad), branches, points' offsets, tolerances: the values a user may edit;
  crank block ("angular characteristics of the crank"), hinge A;
  for each group its kinematic-constraint block: intermediate variables (P, Q, F ...),
            every solution branch, check rows that put each branch back into the
            original equations, the "accepted values" rows (contract names) that all
            later rows reference, then velocities and accelerations (Cramer's rule);
  driven joints and points, each followed by its check rows.
Columns: A the row's name (contract names on accepted rows), B the unit, C a
description (Russian by default, English with lang="en"), D the input value (input
rows) or the row's check status (check rows: 0 pass, 1 fail), E... one column per crank
position. Every computed cell is a formula referring to the input block.

Rows are built as records whose formulas name other rows ("{x_A}", "{L1}",
"{x_A@prev}"); they are compiled once into per-column templates, so a 360-column
workbook costs one str.format per cell.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from openpyxl import Workbook, load_workbook
from openpyxl.chart import Reference, ScatterChart, Series
from openpyxl.chart.data_source import NumFmt
from openpyxl.formatting.rule import FormulaRule
from openpyxl.styles import Font, PatternFill
from openpyxl.utils import get_column_letter

from .scene import Group, Point, Scene

FIRST_COL = 5                      # column E: the first crank position
SCENE_SHEET = "scene"              # hidden sheet holding the scene's TOML text
# Central differences only where the step allows: their error, h^2/6 of the third
# derivative, is within Tol_FD = 1% of a row's scale at 3 deg for every bundled mechanism,
# but not at 4-5 deg for the quick-return ones (slotted lever, shaper).
FD_MAX_STEP_DEG = 3.0
MARKERS = {"ru": "не собирается", "en": "cannot assemble"}
SHEET_TITLES = {"ru": ("Кинематика", "Графики"), "en": ("Kinematics", "Charts")}

INPUT_FILL = PatternFill("solid", fgColor="FFF2CC")
ACCEPTED_FILL = PatternFill("solid", fgColor="DDEBF7")
SECTION_FONT = Font(bold=True)
GREEN = PatternFill("solid", fgColor="C6EFCE")
RED = PatternFill("solid", fgColor="FFC7CE")


@dataclass
class Row:
    name: str
    unit: str = ""
    ru: str = ""
    en: str = ""
    kind: str = "calc"          # section | input | derived | index | calc | accepted | check | fdcheck | guard
    formula: str = ""           # template: {row}, {row@prev}, {row@next}
    value: float | None = None  # input rows
    guard: str | None = None    # the group's "assembled" row: IF(guard, formula, marker)


def _t(ru: str, en: str) -> dict:
    return {"ru": ru, "en": en}


# --------------------------------------------------------------------------- the rows
class _Builder:
    """Collects rows in the lecture's order; knows which names are per-position rows."""

    def __init__(self, scene: Scene):
        self.scene = scene
        self.rows: list[Row] = []
        self.frame = set(scene.frame)
        self.rot: dict[int, tuple[str, str, str, str]] = {}   # link -> cos, sin, omega, eps rows
        self.guard_of_link: dict[int, str | None] = {1: None}
        self.guard: str | None = None                         # the latest group's assembled row
        self.checks: list[str] = []
        self.fd_checks: list[str] = []

    def add(self, name, unit="", ru="", en="", kind="calc", formula="", value=None, guard=...):
        g = self.guard if guard is ... else guard
        self.rows.append(Row(name, unit, ru, en, kind, formula, value,
                             g if kind in ("calc", "accepted", "check", "fdcheck") else None))
        if kind == "check":
            self.checks.append(name)
        if kind == "fdcheck":
            self.fd_checks.append(name)

    def section(self, name, ru, en):
        self.add(name, "", ru, en, kind="section")

    # references to a point's quantities (a frame point is an input and does not move)
    def p(self, q: str, n: str) -> str:
        if n in self.frame:
            return "{%s_%s}" % (q, n) if q in ("x", "y") else "0"
        return "{%s_%s}" % (q, n)

    def input(self, name, unit, ru, en, value):
        self.add(name, unit, ru, en, kind="input", value=value)


def _rows(scene: Scene) -> _Builder:
    b = _Builder(scene)
    c = scene.crank
    b.section("input", "Исходные данные (можно изменять)", "Input data (editable)")
    b.input("L1", "m", f"длина кривошипа {c.pivot}{c.joint}", f"crank length {c.pivot}{c.joint}", c.length)
    for g in scene.groups:
        la, lb = g.links
        if g.type == "RRR":
            j1, n, j2 = g.joints
            b.input(f"L{la}", "m", f"длина звена {la} ({j1}{n})", f"length of link {la} ({j1}{n})", g.lengths[0])
            b.input(f"L{lb}", "m", f"длина звена {lb} ({n}{j2})", f"length of link {lb} ({n}{j2})", g.lengths[1])
        elif g.type == "RRP":
            j1, n = g.joints
            b.input(f"L{la}", "m", f"длина шатуна {la} ({j1}{n})", f"length of coupler {la} ({j1}{n})", g.lengths[0])
    for name, (x, y) in scene.frame.items():
        b.input(f"x_{name}", "m", f"координата x неподвижной точки {name}", f"x of the fixed point {name}", x)
        b.input(f"y_{name}", "m", f"координата y неподвижной точки {name}", f"y of the fixed point {name}", y)
    for g in scene.groups:
        i = g.index
        if g.type == "RRP":
            b.input(f"gx_g{i}", "m", f"направляющая ползуна {g.joints[1]}: x точки", f"slider {g.joints[1]}'s guide: x of a point", g.guide_point[0])
            b.input(f"gy_g{i}", "m", f"направляющая ползуна {g.joints[1]}: y точки", f"slider {g.joints[1]}'s guide: y of a point", g.guide_point[1])
            b.input(f"gamma_g{i}", "deg", "угол наклона направляющей", "the guide's angle", g.guide_angle_deg)
        if g.type == "RPR":
            b.input(f"e_g{i}", "m", f"смещение оси кулисы {g.links[1]} от {g.joints[1]}", f"offset of slot {g.links[1]} from {g.joints[1]}", g.offset)
        if g.type in ("RRR", "RRP"):
            b.input(f"branch_g{i}", "", f"ветвь решения группы {i} (+1 или -1)", f"solution branch of group {i} (+1 or -1)", g.branch)
    for p in scene.points:
        b.input(f"along_{p.name}", "m", f"точка {p.name}: вдоль звена {p.link} от {p.origin}", f"point {p.name}: along link {p.link} from {p.origin}", p.along)
        b.input(f"across_{p.name}", "m", f"точка {p.name}: поперёк звена {p.link} (влево +)", f"point {p.name}: across link {p.link} (left +)", p.across)
    b.input("Fi0", "deg", "начальный угол кривошипа", "crank angle of the first position", c.phi0_deg)
    b.input("Fi_t0", "rad/s", "(Fi_t)0: угловая скорость кривошипа", "(Fi_t)0: the crank's angular velocity", c.omega)
    b.input("Fi_tt0", "rad/s^2", "(Fi_tt)0: угловое ускорение кривошипа", "(Fi_tt)0: the crank's angular acceleration", c.epsilon)
    b.input("Delta_Fi", "deg", "шаг по углу кривошипа (градусы)", "crank angle step (degrees)", c.step_deg)
    b.add("Delta_Fi_rad", "rad", "шаг по углу кривошипа (радианы)", "crank angle step (radians)", kind="derived", formula="RADIANS({Delta_Fi})")
    b.add("Alfa_A", "m", f"начальная координата x шарнира {c.joint} относительно {c.pivot}", f"initial x of hinge {c.joint} from {c.pivot}", kind="derived", formula="{L1}*COS(RADIANS({Fi0}))")
    b.add("Betta_A", "m", f"начальная координата y шарнира {c.joint} относительно {c.pivot}", f"initial y of hinge {c.joint} from {c.pivot}", kind="derived", formula="{L1}*SIN(RADIANS({Fi0}))")
    if scene.has_dynamics:
        from .workbook_dynamics import dynamics_inputs   # (imports this module's row helpers)
        dynamics_inputs(b)
    b.input("Tol", "", "допуск проверок (невязки)", "tolerance of the checks (residuals)", 1e-9)
    b.input("Tol_FD", "", f"допуск сравнения с численным дифференцированием (шаг <= {FD_MAX_STEP_DEG:g} град)", f"tolerance against numeric derivatives (step <= {FD_MAX_STEP_DEG:g} deg)", 0.01)

    _crank_rows(b)
    for kind, item in scene.plan:
        if kind == "group":
            {"RRR": _rrr_rows, "RRP": _rrp_rows, "RPR": _rpr_rows}[item.type](b, item)
        elif kind == "point":
            _point_rows(b, item)
    if scene.has_dynamics:
        from .workbook_dynamics import energy_rows, kinetostatics_rows
        energy_rows(b)
        kinetostatics_rows(b)
    return b


def _motion_rows(b: _Builder, n: str, ru: str, en: str, x: str, y: str, vx: str, vy: str, ax: str, ay: str):
    """The eight accepted rows of a moving point: coordinates, velocity, acceleration."""
    for q, unit, f, r, e in (("x", "m", x, "координата x", "x coordinate"), ("y", "m", y, "координата y", "y coordinate"),
                             ("vx", "m/s", vx, "скорость, проекция на x", "velocity, x component"),
                             ("vy", "m/s", vy, "скорость, проекция на y", "velocity, y component")):
        b.add(f"{q}_{n}", unit, f"{r} {ru}", f"{e} of {en}", "accepted", f)
    b.add(f"v_{n}", "m/s", f"модуль скорости {ru}", f"speed of {en}", "accepted", f"SQRT({{vx_{n}}}^2+{{vy_{n}}}^2)")
    for q, f, r, e in (("ax", ax, "ускорение, проекция на x", "acceleration, x component"),
                       ("ay", ay, "ускорение, проекция на y", "acceleration, y component")):
        b.add(f"{q}_{n}", "m/s^2", f"{r} {ru}", f"{e} of {en}", "accepted", f)
    b.add(f"a_{n}", "m/s^2", f"модуль ускорения {ru}", f"acceleration magnitude of {en}", "accepted", f"SQRT({{ax_{n}}}^2+{{ay_{n}}}^2)")


def _distance_check(b: _Builder, name: str, p1: str, p2: str, length: str, ru: str, en: str):
    b.add(name, "m", ru, en, "check", f"SQRT(({b.p('x', p2)}-{b.p('x', p1)})^2+({b.p('y', p2)}-{b.p('y', p1)})^2)-{length}")


def _fd_checks(b: _Builder, n: str):
    """Analytic velocity and acceleration against central differences over neighbouring
    columns (the lecture's step 10), relative to the row's largest value. With the crank's
    rates taken as given at each position: v = Fi_t dx/dFi, a = Fi_t dv/dFi + Fi_tt v / Fi_t."""
    for q, v, a in (("x", f"vx_{n}", f"ax_{n}"), ("y", f"vy_{n}", f"ay_{n}")):
        pos = f"{q}_{n}"
        b.add(f"fd_{v}", "", f"{v}: численная производная (относительная невязка)",
              f"{v} against the numeric derivative (relative)", "fdcheck",
              f"({{{v}}}-{{Fi_t}}*({{{pos}@next}}-{{{pos}@prev}})/(2*{{Delta_Fi_rad}}))/{{scale:{v}}}")
        b.add(f"fd_{a}", "", f"{a}: численная производная (относительная невязка)",
              f"{a} against the numeric derivative (relative)", "fdcheck",
              f"({{{a}}}-{{Fi_t}}*({{{v}@next}}-{{{v}@prev}})/(2*{{Delta_Fi_rad}})-{{Fi_tt}}*{{{v}}}/{{Fi_t}})/{{scale:{a}}}")


def _crank_rows(b: _Builder):
    c = b.scene.crank
    A, O = c.joint, c.pivot
    b.section("crank", "Угловые характеристики работы кривошипа", "Angular characteristics of the crank")
    b.add("i", "", "номер положения", "position number", kind="index")
    b.add("phi_1", "deg", "угол поворота кривошипа", "crank angle", "accepted", "{Fi0}+{i}*{Delta_Fi}")
    b.add("Fi", "rad", "угол поворота кривошипа (радианы)", "crank angle (radians)", "calc", "RADIANS({phi_1})")
    b.add("dFi", "rad", "поворот от начального положения", "rotation from the first position", "calc", "{Fi}-RADIANS({Fi0})")
    b.add("Fi_t", "rad/s", "угловая скорость кривошипа", "the crank's angular velocity", "calc", "{Fi_t0}")
    b.add("Fi_tt", "rad/s^2", "угловое ускорение кривошипа", "the crank's angular acceleration", "calc", "{Fi_tt0}")
    b.add("cos_1", "", "cos угла кривошипа", "cos of the crank angle", "calc", "COS({Fi})")
    b.add("sin_1", "", "sin угла кривошипа", "sin of the crank angle", "calc", "SIN({Fi})")
    b.add("chk_Fi", "rad", "проверка: Fi - (Fi0 + i Delta_Fi) в радианах", "check: Fi - (Fi0 + i Delta_Fi) in radians", "check",
          "{Fi}-(RADIANS({Fi0})+{i}*{Delta_Fi_rad})")
    b.rot[1] = ("cos_1", "sin_1", "Fi_t", "Fi_tt")
    b.section(f"hinge_{A}", f"Шарнир {A} кривошипа (слайд 6: x = Alfa cos dFi - Betta sin dFi)",
              f"Hinge {A} of the crank (slide 6: x = Alfa cos dFi - Betta sin dFi)")
    rx, ry = f"({{x_{A}}}-{{x_{O}}})", f"({{y_{A}}}-{{y_{O}}})"
    _motion_rows(b, A, f"шарнира {A}", f"hinge {A}",
                 f"{{x_{O}}}+{{Alfa_A}}*COS({{dFi}})-{{Betta_A}}*SIN({{dFi}})",
                 f"{{y_{O}}}+{{Alfa_A}}*SIN({{dFi}})+{{Betta_A}}*COS({{dFi}})",
                 f"-{{Fi_t}}*{ry}", f"{{Fi_t}}*{rx}",
                 f"-{{Fi_tt}}*{ry}-{{Fi_t}}*{{vy_{A}}}", f"{{Fi_tt}}*{rx}+{{Fi_t}}*{{vx_{A}}}")
    _distance_check(b, f"chk_{O}{A}", O, A, "{L1}", f"проверка: |{O}{A}| - L1", f"check: |{O}{A}| - L1")
    b.add(f"chk_v_{A}", "m^2/s", f"проверка: скорость {A} перпендикулярна {O}{A}", f"check: velocity of {A} perpendicular to {O}{A}",
          "check", f"{{vx_{A}}}*{rx}+{{vy_{A}}}*{ry}")
    _fd_checks(b, A)


def _cos_sin_rows(b: _Builder, k: int, ru: str, en: str):
    b.add(f"cos_{k}", "", f"cos угла звена {k}", f"cos of link {k}'s angle", "calc", f"COS(RADIANS({{phi_{k}}}))")
    b.add(f"sin_{k}", "", f"sin угла звена {k}", f"sin of link {k}'s angle", "calc", f"SIN(RADIANS({{phi_{k}}}))")


def _group_guard(b: _Builder, g: Group, disc: str):
    prev = b.guard
    b.add(f"asm_g{g.index}", "", f"группа {g.index} собирается (дискриминант >= 0)", f"group {g.index} assembles (discriminant >= 0)",
          "guard", f"AND({{{prev}}},{{{disc}}}>=0)" if prev else f"{{{disc}}}>=0")
    b.guard = f"asm_g{g.index}"


def _rrr_rows(b: _Builder, g: Group):
    """Lecture slides 16-21, generalised to a moving J2: J1 + L2 e(psi) = J2 + L3 e(xi)."""
    i, (la, lb), (J1, N, J2) = g.index, g.links, g.joints
    L2, L3 = f"{{L{la}}}", f"{{L{lb}}}"
    b.section(f"group_{i}", f"Группа {i} (ВВВ {J1}{N}{J2}): кинематические связи, слайды 16-21",
              f"Group {i} (RRR {J1}{N}{J2}): kinematic constraints, slides 16-21")
    P, Q, F, D = f"P_g{i}", f"Q_g{i}", f"F_g{i}", f"D_g{i}"
    b.add(P, "m", f"P = x{J2} - x{J1}", f"P = x{J2} - x{J1}", "calc", f"{b.p('x', J2)}-{b.p('x', J1)}", guard=b.guard)
    b.add(Q, "m", f"Q = y{J2} - y{J1}", f"Q = y{J2} - y{J1}", "calc", f"{b.p('y', J2)}-{b.p('y', J1)}", guard=b.guard)
    b.add(F, "m", "F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2)", "F = (P^2 + Q^2 + L2^2 - L3^2) / (2 L2)", "calc",
          f"({{{P}}}^2+{{{Q}}}^2+{L2}^2-{L3}^2)/(2*{L2})", guard=b.guard)
    b.add(D, "m^2", "дискриминант P^2 + Q^2 - F^2 (< 0: группа не собирается)", "discriminant P^2 + Q^2 - F^2 (< 0: cannot assemble)",
          "calc", f"{{{P}}}^2+{{{Q}}}^2-{{{F}}}^2", guard=b.guard)
    _group_guard(b, g, D)
    for s, sign, ru, en in (("p", "+", "ветвь +1", "branch +1"), ("m", "-", "ветвь -1", "branch -1")):
        # tg(psi/2) = (Q +- sqrt(D)) / (P + F), written as ATAN2 so that P + F = 0 is no division
        b.add(f"psi_{s}_g{i}", "rad", f"{ru}: psi = 2 arctg((Q {sign} sqrt(D)) / (P + F))", f"{en}: psi = 2 atan((Q {sign} sqrt(D)) / (P + F))",
              "calc", f"2*ATAN2({{{P}}}+{{{F}}},{{{Q}}}{sign}SQRT({{{D}}}))")
        b.add(f"xi_{s}_g{i}", "rad", f"{ru}: xi из cos xi = (L2 cos psi - P)/L3, sin xi = (L2 sin psi - Q)/L3", f"{en}: xi from cos xi = (L2 cos psi - P)/L3, sin xi = (L2 sin psi - Q)/L3",
              "calc", f"ATAN2({L2}*COS({{psi_{s}_g{i}}})-{{{P}}},{L2}*SIN({{psi_{s}_g{i}}})-{{{Q}}})")
        for axis, fn in (("x", "COS"), ("y", "SIN")):
            b.add(f"chk_{axis}_{s}_g{i}", "m", f"проверка {ru}: {axis}{J1} + L2 {fn.lower()} psi - L3 {fn.lower()} xi - {axis}{J2}",
                  f"check {en}: {axis}{J1} + L2 {fn.lower()} psi - L3 {fn.lower()} xi - {axis}{J2}", "check",
                  f"{b.p(axis, J1)}+{L2}*{fn}({{psi_{s}_g{i}}})-{L3}*{fn}({{xi_{s}_g{i}}})-{b.p(axis, J2)}")
    b.section(f"accepted_g{i}", "Принятые значения", "Accepted values")
    br = f"{{branch_g{i}}}"
    b.add(f"phi_{la}", "deg", f"угол звена {la} ({J1}->{N})", f"angle of link {la} ({J1}->{N})", "accepted",
          f"MOD(DEGREES(IF({br}=1,{{psi_p_g{i}}},{{psi_m_g{i}}})),360)")
    b.add(f"phi_{lb}", "deg", f"угол звена {lb} ({J2}->{N})", f"angle of link {lb} ({J2}->{N})", "accepted",
          f"MOD(DEGREES(IF({br}=1,{{xi_p_g{i}}},{{xi_m_g{i}}})),360)")
    _cos_sin_rows(b, la, "", "")
    _cos_sin_rows(b, lb, "", "")
    ca, sa, cb, sb = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    b.add(f"chk_acc_g{i}", "m", "проверка принятых значений: невязка системы (a)", "check of the accepted values: residual of system (a)",
          "check", f"ABS({b.p('x', J1)}+{L2}*{ca}-{L3}*{cb}-{b.p('x', J2)})+ABS({b.p('y', J1)}+{L2}*{sa}-{L3}*{sb}-{b.p('y', J2)})")
    # system (b) (slide 19): -L2 sin psi psi_t + L3 sin xi xi_t = vx_J2 - vx_J1; L2 cos psi psi_t - L3 cos xi xi_t = vy_J2 - vy_J1
    det = f"Delta_g{i}"
    m = (f"(-{L2}*{sa})", f"({L3}*{sb})", f"({L2}*{ca})", f"(-{L3}*{cb})")
    _det_row(b, det, m, "m^2", "определитель системы (b): L2 L3 sin(psi - xi)", "determinant of system (b): L2 L3 sin(psi - xi)")
    b.add(f"det_g{i}", "", "sin угла передачи (около 0: мёртвое положение)", "sine of the transmission angle (near 0: toggle)",
          "calc", f"{{{det}}}/({L2}*{L3})")
    b1, b2 = f"({b.p('vx', J2)}-{b.p('vx', J1)})", f"({b.p('vy', J2)}-{b.p('vy', J1)})"
    _cramer_rows(b, m, det, ((f"omega_{la}", "rad/s", f"угловая скорость звена {la} (Крамер)", f"angular velocity of link {la} (Cramer)"),
                             (f"omega_{lb}", "rad/s", f"угловая скорость звена {lb} (Крамер)", f"angular velocity of link {lb} (Cramer)")),
                 (b1, b2), (f"chk_vsys_g{i}", "невязка системы (b) для скоростей", "residual of the velocity system (b)"))
    f1, f2 = f"f1_g{i}", f"f2_g{i}"
    wa, wb = f"{{omega_{la}}}", f"{{omega_{lb}}}"
    b.add(f1, "m/s^2", "правая часть для ускорений f1 (слайд 21)", "right side of the acceleration system f1 (slide 21)", "calc",
          f"{b.p('ax', J2)}-{b.p('ax', J1)}+{L2}*{wa}^2*{ca}-{L3}*{wb}^2*{cb}")
    b.add(f2, "m/s^2", "правая часть для ускорений f2 (слайд 21)", "right side of the acceleration system f2 (slide 21)", "calc",
          f"{b.p('ay', J2)}-{b.p('ay', J1)}+{L2}*{wa}^2*{sa}-{L3}*{wb}^2*{sb}")
    _cramer_rows(b, m, det, ((f"eps_{la}", "rad/s^2", f"угловое ускорение звена {la}", f"angular acceleration of link {la}"),
                             (f"eps_{lb}", "rad/s^2", f"угловое ускорение звена {lb}", f"angular acceleration of link {lb}")),
                 (f"{{{f1}}}", f"{{{f2}}}"), (f"chk_asys_g{i}", "невязка системы для ускорений", "residual of the acceleration system"))
    b.rot[la] = (f"cos_{la}", f"sin_{la}", f"omega_{la}", f"eps_{la}")
    b.rot[lb] = (f"cos_{lb}", f"sin_{lb}", f"omega_{lb}", f"eps_{lb}")
    b.guard_of_link[la] = b.guard_of_link[lb] = b.guard
    _carried_rows(b, N, la, J1, L2, "0", f"шарнира {N}", f"hinge {N}")
    _distance_check(b, f"chk_{J1}{N}", J1, N, L2, f"проверка: |{J1}{N}| - L{la}", f"check: |{J1}{N}| - L{la}")
    _distance_check(b, f"chk_{N}{J2}", N, J2, L3, f"проверка: |{N}{J2}| - L{lb}", f"check: |{N}{J2}| - L{lb}")
    _relative_velocity_check(b, N, J2)
    _via_link_checks(b, N, J2, lb, f"omega_{lb}, eps_{lb}")
    _fd_checks(b, N)


def _via_link_checks(b: _Builder, n: str, j: str, k: int, label: str):
    """Velocity and acceleration of joint n computed once more through link k about j
    (Euler form): |v_n - (v_j + omega_k x r)| and the same for accelerations. A wrong
    angular velocity or acceleration of link k shows here, at any step."""
    c, s, w, e = (f"{{{r}}}" for r in b.rot[k])
    X, Y = f"({b.p('x', n)}-{b.p('x', j)})", f"({b.p('y', n)}-{b.p('y', j)})"
    b.add(f"chk_v_{n}_{k}", "m/s", f"проверка: скорость {n} через звено {k} ({label})", f"check: velocity of {n} through link {k} ({label})",
          "check", f"ABS({b.p('vx', n)}-({b.p('vx', j)}-{w}*{Y}))+ABS({b.p('vy', n)}-({b.p('vy', j)}+{w}*{X}))")
    b.add(f"chk_a_{n}_{k}", "m/s^2", f"проверка: ускорение {n} через звено {k} ({label})", f"check: acceleration of {n} through link {k} ({label})",
          "check", f"ABS({b.p('ax', n)}-({b.p('ax', j)}-{e}*{Y}-{w}^2*{X}))+ABS({b.p('ay', n)}-({b.p('ay', j)}+{e}*{X}-{w}^2*{Y}))")


def _system_check(b: _Builder, name: str, what: tuple[str, str], m, x: str, y: str, rhs: tuple[str, str]):
    """Put the solved unknowns back into their 2x2 system: |m11 x + m12 y - b1| + |m21 x + m22 y - b2|."""
    m11, m12, m21, m22 = m
    b.add(name, "", f"проверка: {what[0]}", f"check: {what[1]}", "check",
          f"ABS({m11}*{x}+{m12}*{y}-{rhs[0]})+ABS({m21}*{x}+{m22}*{y}-{rhs[1]})")


def _cramer_rows(b: _Builder, m, det: str, unknowns, rhs: tuple[str, str], check: tuple[str, str, str]):
    """Two unknowns of [[m11, m12], [m21, m22]] (x, y) = (b1, b2) by Cramer's rule (slide 20):
    x = (b1 m22 - b2 m12) / det, y = (m11 b2 - m21 b1) / det; then the check that puts
    them back into the system. `unknowns` = ((name, unit, ru, en), (name, unit, ru, en))."""
    m11, m12, m21, m22 = m
    (n1, *d1), (n2, *d2) = unknowns
    b.add(n1, *d1, "accepted", f"({rhs[0]}*{m22}-{rhs[1]}*{m12})/{{{det}}}")
    b.add(n2, *d2, "accepted", f"({m11}*{rhs[1]}-{m21}*{rhs[0]})/{{{det}}}")
    _system_check(b, check[0], check[1:], m, f"{{{n1}}}", f"{{{n2}}}", rhs)


def _det_row(b: _Builder, det: str, m, unit: str, ru: str, en: str):
    m11, m12, m21, m22 = m
    b.add(det, unit, ru, en, "calc", f"{m11}*{m22}-{m12}*{m21}")


def _relative_velocity_check(b: _Builder, n: str, j: str):
    """A rigid link keeps |n j|: the relative velocity is perpendicular to n - j."""
    b.add(f"chk_v_{n}{j}", "m^2/s", f"проверка: (v{n} - v{j}) перпендикулярна {j}{n}", f"check: (v{n} - v{j}) perpendicular to {j}{n}",
          "check", f"({b.p('vx', n)}-{b.p('vx', j)})*({b.p('x', n)}-{b.p('x', j)})+({b.p('vy', n)}-{b.p('vy', j)})*({b.p('y', n)}-{b.p('y', j)})")


def _carried_rows(b: _Builder, n: str, k: int, origin: str, along: str, across: str, ru: str, en: str):
    """A point fixed on link k (slide 7, Euler form): v = v_P + omega x r, a = a_P + eps x r - omega^2 r."""
    c, s, w, e = (f"{{{r}}}" for r in b.rot[k])
    rx = f"({along}*{c}-{across}*{s})" if across != "0" else f"{along}*{c}"
    ry = f"({along}*{s}+{across}*{c})" if across != "0" else f"{along}*{s}"
    X, Y = f"({{x_{n}}}-{b.p('x', origin)})", f"({{y_{n}}}-{b.p('y', origin)})"
    b.section(f"point_{n}", f"Точка {n} звена {k}", f"Point {n} of link {k}")
    _motion_rows(b, n, ru, en, f"{b.p('x', origin)}+{rx}", f"{b.p('y', origin)}+{ry}",
                 f"{b.p('vx', origin)}-{w}*{Y}", f"{b.p('vy', origin)}+{w}*{X}",
                 f"{b.p('ax', origin)}-{e}*{Y}-{w}^2*{X}", f"{b.p('ay', origin)}+{e}*{X}-{w}^2*{Y}")


def _rrp_rows(b: _Builder, g: Group):
    """Lecture slides 13-15 and 29-31: coupler J1 N, slider N on the fixed guide G + s u."""
    i, (la, lb), (J1, N) = g.index, g.links, g.joints
    L = f"{{L{la}}}"
    gx, gy, gam = f"{{gx_g{i}}}", f"{{gy_g{i}}}", f"RADIANS({{gamma_g{i}}})"
    b.section(f"group_{i}", f"Группа {i} (ВВП {J1}{N}, ползун на направляющей): слайды 13-15, 29-31",
              f"Group {i} (RRP {J1}{N}, slider on a fixed guide): slides 13-15, 29-31")
    h, al, D = f"h_g{i}", f"along_g{i}", f"D_g{i}"
    b.add(h, "m", f"расстояние от {J1} до направляющей (влево +)", f"distance of {J1} from the guide (left +)", "calc",
          f"-({b.p('x', J1)}-{gx})*SIN({gam})+({b.p('y', J1)}-{gy})*COS({gam})", guard=b.guard)
    b.add(al, "m", f"проекция {J1} на направляющую", f"{J1}'s foot on the guide", "calc",
          f"({b.p('x', J1)}-{gx})*COS({gam})+({b.p('y', J1)}-{gy})*SIN({gam})", guard=b.guard)
    b.add(D, "m^2", "дискриминант L^2 - h^2 (< 0: группа не собирается)", "discriminant L^2 - h^2 (< 0: cannot assemble)",
          "calc", f"{L}^2-{{{h}}}^2", guard=b.guard)
    _group_guard(b, g, D)
    for s, sign, ru, en in (("p", "+", "ветвь +1", "branch +1"), ("m", "-", "ветвь -1", "branch -1")):
        b.add(f"s_{s}_g{i}", "m", f"{ru}: s = проекция {sign} sqrt(D)", f"{en}: s = foot {sign} sqrt(D)", "calc", f"{{{al}}}{sign}SQRT({{{D}}})")
        b.add(f"chk_{s}_g{i}", "m", f"проверка {ru}: |{J1}{N}| - L{la}", f"check {en}: |{J1}{N}| - L{la}", "check",
              f"SQRT(({gx}+{{s_{s}_g{i}}}*COS({gam})-{b.p('x', J1)})^2+({gy}+{{s_{s}_g{i}}}*SIN({gam})-{b.p('y', J1)})^2)-{L}")
    b.section(f"accepted_g{i}", "Принятые значения", "Accepted values")
    sN = f"s_{N}"
    b.add(sN, "m", f"перемещение ползуна {N} вдоль направляющей", f"travel of slider {N} along the guide", "accepted",
          f"IF({{branch_g{i}}}=1,{{s_p_g{i}}},{{s_m_g{i}}})")
    b.add(f"phi_{la}", "deg", f"угол шатуна {la} ({J1}->{N})", f"angle of coupler {la} ({J1}->{N})", "accepted",
          f"MOD(DEGREES(ATAN2({gx}+{{{sN}}}*COS({gam})-{b.p('x', J1)},{gy}+{{{sN}}}*SIN({gam})-{b.p('y', J1)})),360)")
    b.add(f"phi_{lb}", "deg", f"угол ползуна {lb} (направляющая)", f"angle of slider {lb} (the guide)", "accepted",
          f"MOD({{gamma_g{i}}},360)")
    _cos_sin_rows(b, la, "", "")
    _cos_sin_rows(b, lb, "", "")
    ca, sa, ux, uy = f"{{cos_{la}}}", f"{{sin_{la}}}", f"{{cos_{lb}}}", f"{{sin_{lb}}}"
    b.add(f"chk_acc_g{i}", "m", f"проверка принятых значений: {J1} + L e(phi) - ({gx}, {gy}) - s u".replace("{", "").replace("}", ""),
          "check of the accepted values: J1 + L e(phi) - G - s u", "check",
          f"ABS({b.p('x', J1)}+{L}*{ca}-{gx}-{{{sN}}}*{ux})+ABS({b.p('y', J1)}+{L}*{sa}-{gy}-{{{sN}}}*{uy})")
    b.add(f"omega_{lb}", "rad/s", f"угловая скорость ползуна {lb}", f"angular velocity of slider {lb}", "accepted", "0")
    b.add(f"eps_{lb}", "rad/s^2", f"угловое ускорение ползуна {lb}", f"angular acceleration of slider {lb}", "accepted", "0")
    # L omega e_perp(phi) - vs u = -v_J1: Cramer with m11 = -L sin, m12 = -ux, m21 = L cos, m22 = -uy
    det = f"Delta_g{i}"
    m = (f"(-{L}*{sa})", f"(-{ux})", f"({L}*{ca})", f"(-{uy})")
    _det_row(b, det, m, "m", "определитель: L cos(phi - gamma)", "determinant: L cos(phi - gamma)")
    b.add(f"det_g{i}", "", "cos(phi - gamma) (около 0: мёртвое положение)", "cos(phi - gamma) (near 0: toggle)", "calc", f"{{{det}}}/{L}")
    b1, b2 = f"(-{b.p('vx', J1)})", f"(-{b.p('vy', J1)})"
    _cramer_rows(b, m, det, ((f"omega_{la}", "rad/s", f"угловая скорость шатуна {la} (Крамер)", f"angular velocity of coupler {la} (Cramer)"),
                             (f"vs_{N}", "m/s", f"скорость ползуна {N} вдоль направляющей", f"velocity of slider {N} along the guide")),
                 (b1, b2), (f"chk_vsys_g{i}", "невязка системы для скоростей", "residual of the velocity system"))
    f1, f2 = f"f1_g{i}", f"f2_g{i}"
    wa = f"{{omega_{la}}}"
    b.add(f1, "m/s^2", "правая часть для ускорений f1", "right side of the acceleration system f1", "calc",
          f"-{b.p('ax', J1)}+{L}*{wa}^2*{ca}")
    b.add(f2, "m/s^2", "правая часть для ускорений f2", "right side of the acceleration system f2", "calc",
          f"-{b.p('ay', J1)}+{L}*{wa}^2*{sa}")
    _cramer_rows(b, m, det, ((f"eps_{la}", "rad/s^2", f"угловое ускорение шатуна {la}", f"angular acceleration of coupler {la}"),
                             (f"as_{N}", "m/s^2", f"ускорение ползуна {N} вдоль направляющей", f"acceleration of slider {N} along the guide")),
                 (f"{{{f1}}}", f"{{{f2}}}"), (f"chk_asys_g{i}", "невязка системы для ускорений", "residual of the acceleration system"))
    b.rot[la] = (f"cos_{la}", f"sin_{la}", f"omega_{la}", f"eps_{la}")
    b.rot[lb] = (f"cos_{lb}", f"sin_{lb}", f"omega_{lb}", f"eps_{lb}")
    b.guard_of_link[la] = b.guard_of_link[lb] = b.guard
    b.section(f"point_{N}", f"Ползун {N}", f"Slider {N}")
    s, vs, as_ = f"{{{sN}}}", f"{{vs_{N}}}", f"{{as_{N}}}"
    _motion_rows(b, N, f"ползуна {N}", f"slider {N}", f"{gx}+{s}*{ux}", f"{gy}+{s}*{uy}",
                 f"{vs}*{ux}", f"{vs}*{uy}", f"{as_}*{ux}", f"{as_}*{uy}")
    _distance_check(b, f"chk_{J1}{N}", J1, N, L, f"проверка: |{J1}{N}| - L{la}", f"check: |{J1}{N}| - L{la}")
    _relative_velocity_check(b, N, J1)
    _via_link_checks(b, N, J1, la, f"omega_{la}, eps_{la}")
    _fd_checks(b, N)


def _rpr_rows(b: _Builder, g: Group):
    """Lecture slides 22-24: block on J1 in the slotted lever (kulisa) turning about J2.
    J1 - J2 = s u + e n (u along the slot, n = u turned +90 deg)."""
    i, (la, lb), (J1, J2) = g.index, g.links, g.joints
    e = f"{{e_g{i}}}"
    b.section(f"group_{i}", f"Группа {i} (ВПВ: камень {J1} в кулисе, ось {J2}): слайды 22-24",
              f"Group {i} (RPR: block {J1} in the slotted lever about {J2}): slides 22-24")
    dx, dy, r2, D = f"dx_g{i}", f"dy_g{i}", f"r2_g{i}", f"D_g{i}"
    b.add(dx, "m", f"x{J1} - x{J2}", f"x{J1} - x{J2}", "calc", f"{b.p('x', J1)}-{b.p('x', J2)}", guard=b.guard)
    b.add(dy, "m", f"y{J1} - y{J2}", f"y{J1} - y{J2}", "calc", f"{b.p('y', J1)}-{b.p('y', J2)}", guard=b.guard)
    b.add(r2, "m^2", f"L_TEK^2 = |{J2}{J1}|^2", f"L_TEK^2 = |{J2}{J1}|^2", "calc", f"{{{dx}}}^2+{{{dy}}}^2", guard=b.guard)
    b.add(D, "m^2", "дискриминант L_TEK^2 - e^2 (< 0: группа не собирается)", "discriminant L_TEK^2 - e^2 (< 0: cannot assemble)",
          "calc", f"IF({{{r2}}}>0,{{{r2}}}-{e}^2,-1)", guard=b.guard)
    _group_guard(b, g, D)
    b.section(f"accepted_g{i}", "Принятые значения", "Accepted values")
    sJ = f"s_{J1}"
    b.add(sJ, "m", f"положение камня {J1} вдоль кулисы (L_TEK при e = 0)", f"block {J1}'s place along the slot (L_TEK when e = 0)",
          "accepted", f"SQRT({{{D}}})")
    cu, su = f"cu_g{i}", f"su_g{i}"
    b.add(cu, "", "cos угла кулисы: (s dx + e dy) / L_TEK^2", "cos of the slot's angle: (s dx + e dy) / L_TEK^2", "calc",
          f"({{{sJ}}}*{{{dx}}}+{e}*{{{dy}}})/{{{r2}}}")
    b.add(su, "", "sin угла кулисы: (s dy - e dx) / L_TEK^2", "sin of the slot's angle: (s dy - e dx) / L_TEK^2", "calc",
          f"({{{sJ}}}*{{{dy}}}-{e}*{{{dx}}})/{{{r2}}}")
    b.add(f"chk_e_g{i}", "m", f"проверка: расстояние {J1} от оси кулисы - e", f"check: distance of {J1} from the slot line - e", "check",
          f"-{{{dx}}}*{{{su}}}+{{{dy}}}*{{{cu}}}-{e}")
    b.add(f"phi_{lb}", "deg", f"угол кулисы {lb}", f"angle of the slotted lever {lb}", "accepted",
          f"MOD(DEGREES(ATAN2({{{cu}}},{{{su}}})),360)")
    b.add(f"phi_{la}", "deg", f"угол камня {la} (= углу кулисы)", f"angle of the block {la} (= the lever's)", "accepted", f"{{phi_{lb}}}")
    c, s = f"{{{cu}}}", f"{{{su}}}"
    det = f"Delta_g{i}"
    # unknowns theta_t, s_t: columns (-s sin - e cos, s cos - e sin) and (cos, sin); determinant -s
    m11, m21 = f"(-{{{sJ}}}*{s}-{e}*{c})", f"({{{sJ}}}*{c}-{e}*{s})"
    m = (m11, c, m21, s)
    _det_row(b, det, m, "m", "определитель: -s", "determinant: -s")
    b.add(f"det_g{i}", "", "s / L1 (около 0: кулиса не определена)", "s / L1 (near 0: the slot is undefined)", "calc", f"-{{{det}}}/{{L1}}")
    b1, b2 = f"({b.p('vx', J1)}-{b.p('vx', J2)})", f"({b.p('vy', J1)}-{b.p('vy', J2)})"
    _cramer_rows(b, m, det, ((f"omega_{lb}", "rad/s", f"угловая скорость кулисы {lb} (Крамер)", f"angular velocity of the lever {lb} (Cramer)"),
                             (f"vs_{J1}", "m/s", f"относительная скорость камня {J1} вдоль кулисы", f"velocity of block {J1} along the slot")),
                 (b1, b2), (f"chk_vsys_g{i}", "невязка системы для скоростей", "residual of the velocity system"))
    w, vs = f"{{omega_{lb}}}", f"{{vs_{J1}}}"
    bx, by = f"bx_g{i}", f"by_g{i}"
    # bias of the acceleration system: 2 s_t theta_t n (Coriolis) - s theta_t^2 u - e theta_t^2 n
    b.add(bx, "m/s^2", "кориолисово и центростремительное: проекция на x", "Coriolis and centripetal terms, x", "calc",
          f"-{{{sJ}}}*{w}^2*{c}-(2*{vs}*{w}-{e}*{w}^2)*{s}")
    b.add(by, "m/s^2", "кориолисово и центростремительное: проекция на y", "Coriolis and centripetal terms, y", "calc",
          f"-{{{sJ}}}*{w}^2*{s}+(2*{vs}*{w}-{e}*{w}^2)*{c}")
    f1, f2 = f"({b.p('ax', J1)}-{b.p('ax', J2)}-{{{bx}}})", f"({b.p('ay', J1)}-{b.p('ay', J2)}-{{{by}}})"
    _cramer_rows(b, m, det, ((f"eps_{lb}", "rad/s^2", f"угловое ускорение кулисы {lb}", f"angular acceleration of the lever {lb}"),
                             (f"as_{J1}", "m/s^2", f"относительное ускорение камня {J1} вдоль кулисы", f"acceleration of block {J1} along the slot")),
                 (f1, f2), (f"chk_asys_g{i}", "невязка системы для ускорений", "residual of the acceleration system"))
    b.add(f"omega_{la}", "rad/s", f"угловая скорость камня {la}", f"angular velocity of the block {la}", "accepted", f"{{omega_{lb}}}")
    b.add(f"eps_{la}", "rad/s^2", f"угловое ускорение камня {la}", f"angular acceleration of the block {la}", "accepted", f"{{eps_{lb}}}")
    b.add(f"cos_{lb}", "", f"cos угла кулисы {lb}", f"cos of lever {lb}'s angle", "calc", c)
    b.add(f"sin_{lb}", "", f"sin угла кулисы {lb}", f"sin of lever {lb}'s angle", "calc", s)
    b.rot[la] = b.rot[lb] = (f"cos_{lb}", f"sin_{lb}", f"omega_{lb}", f"eps_{lb}")
    b.guard_of_link[la] = b.guard_of_link[lb] = b.guard
    # the block's velocity seen on the lever: v_J1 = v_J2 + omega x (J1 - J2) + vs u
    # the block's motion seen on the lever: v_J1 = v_J2 + omega x r + vs u,
    # a_J1 = a_J2 + eps x r - omega^2 r + as u + 2 omega vs n (Coriolis)
    ep, as_ = f"{{eps_{lb}}}", f"{{as_{J1}}}"
    b.add(f"chk_v_g{i}", "m/s", f"проверка: v{J1} = v{J2} + omega x r + vs u", f"check: v{J1} = v{J2} + omega x r + vs u",
          "check", f"ABS({b.p('vx', J1)}-({b.p('vx', J2)}-{w}*{{{dy}}}+{vs}*{c}))+ABS({b.p('vy', J1)}-({b.p('vy', J2)}+{w}*{{{dx}}}+{vs}*{s}))")
    b.add(f"chk_a_g{i}", "m/s^2", f"проверка: a{J1} = a{J2} + eps x r - omega^2 r + as u + 2 omega vs n",
          f"check: a{J1} = a{J2} + eps x r - omega^2 r + as u + 2 omega vs n", "check",
          f"ABS({b.p('ax', J1)}-({b.p('ax', J2)}-{ep}*{{{dy}}}-{w}^2*{{{dx}}}+{as_}*{c}-2*{w}*{vs}*{s}))"
          f"+ABS({b.p('ay', J1)}-({b.p('ay', J2)}+{ep}*{{{dx}}}-{w}^2*{{{dy}}}+{as_}*{s}+2*{w}*{vs}*{c}))")


def _point_rows(b: _Builder, p: Point):
    saved, b.guard = b.guard, b.guard_of_link.get(p.link)
    _carried_rows(b, p.name, p.link, p.origin, f"{{along_{p.name}}}", f"{{across_{p.name}}}",
                  f"точки {p.name}", f"point {p.name}")
    _distance_check(b, f"chk_{p.origin}{p.name}", p.origin, p.name,
                    f"SQRT({{along_{p.name}}}^2+{{across_{p.name}}}^2)",
                    f"проверка: |{p.origin}{p.name}| сохраняется", f"check: |{p.origin}{p.name}| is kept")
    _fd_checks(b, p.name)
    b.guard = saved


# --------------------------------------------------------------------------- writing
_REF = re.compile(r"\{(scale:)?([^{}@:]+)(?:@(prev|next))?\}")
_TEXT = {
    "ru": {"name": "имя", "unit": "ед.", "desc": "описание", "value": "значение / проверка",
           "checks": "проверки", "pass": "все проверки выполнены", "fail": " строк проверки не выполнены",
           "na": "н/д", "author": "автор", "pos": "положение"},
    "en": {"name": "name", "unit": "unit", "desc": "description", "value": "value / check",
           "checks": "checks", "pass": "all checks pass", "fail": " check rows fail",
           "na": "n/a", "author": "author", "pos": "position"},
}
_EXERCISE_KEEP = {"i", "phi_1"}


def _compile(rows: list[Row], first_row: int, last_col: str):
    """Row number of every name, and each formula as a str.format template over the
    column letters c (this position), p (previous), n (next)."""
    where = {r.name: first_row + k for k, r in enumerate(rows)}
    kinds = {r.name: r.kind for r in rows}
    first_col = get_column_letter(FIRST_COL)

    def ref(m):
        scale, name, shift = m.groups()
        if name not in where:
            raise KeyError(f"workbook formula refers to an unknown row {name!r}")
        r = where[name]
        if scale:
            # the row's largest magnitude (MAX/MIN skip text cells), floored for all-zero rows
            return f"MAX(MAX(${first_col}${r}:${last_col}${r}),-MIN(${first_col}${r}:${last_col}${r}),1E-9)"
        if kinds[name] in ("input", "derived"):
            return f"$D${r}"
        return "{%s}%d" % ({"prev": "p", "next": "n"}.get(shift, "c"), r)

    templates = {}
    for r in rows:
        if r.formula:
            templates[r.name] = "=" + _REF.sub(ref, r.formula)
    return where, templates


def build_workbook(scene: Scene, *, lang: str = "ru", exercise: bool = False,
                   scene_text: str | None = None, charts: bool = True) -> Workbook:
    """The lecture's workbook for `scene` (see the module's docstring); charts=False leaves
    out the charts sheet (and its hidden paths sheet): the validator's reference needs only
    the kinematics sheet."""
    if lang not in _TEXT:
        raise ValueError(f"lang must be one of {', '.join(_TEXT)}, got {lang!r}")
    text = _TEXT[lang]
    b = _rows(scene)
    rows = b.rows
    n = scene.crank.positions
    last_col = get_column_letter(FIRST_COL + n - 1)
    first_row = 5
    where, templates = _compile(rows, first_row, last_col)
    marker = MARKERS[lang]
    cols = [get_column_letter(FIRST_COL + k) for k in range(n)]

    wb = Workbook()
    ws = wb.active
    ws.title = SHEET_TITLES[lang][0]
    ws["A1"] = scene.title
    ws["A1"].font = Font(bold=True, size=14)
    ws["A2"] = scene.author or ""
    ws["A3"] = text["checks"]
    ws["A3"].font = SECTION_FONT
    for col, key in zip("ABCD", ("name", "unit", "desc", "value")):
        ws[f"{col}4"] = text[key]
        ws[f"{col}4"].font = SECTION_FONT
    for k, c in enumerate(cols):
        ws[f"{c}4"] = k + 1                 # the position's number
        ws[f"{c}4"].font = SECTION_FONT

    status_cells, fd_range = [], f"{cols[0]}{{r}}:{cols[-1]}{{r}}"
    for row in rows:
        r = where[row.name]
        if row.kind == "section":
            ws.cell(r, 1, (row.ru if lang == "ru" else row.en)).font = SECTION_FONT
            continue
        ws.cell(r, 1, row.name)
        ws.cell(r, 2, row.unit)
        ws.cell(r, 3, row.ru if lang == "ru" else row.en)
        if row.kind == "input":
            ws.cell(r, 4, row.value).fill = INPUT_FILL
            continue
        if row.kind == "derived":
            if not exercise:
                ws.cell(r, 4, templates[row.name])
            continue
        if row.kind == "index":
            for k, c in enumerate(cols):
                ws.cell(r, FIRST_COL + k, k)
            continue
        if exercise and row.kind in ("calc", "accepted") and row.name not in _EXERCISE_KEEP:
            continue
        tpl = templates[row.name]
        fd = "{p}" in tpl or "{n}" in tpl
        if fd:
            # central differences: only where the step allows and the crank turns
            tpl = (f'=IF(OR(ABS($D${where["Delta_Fi"]})>{FD_MAX_STEP_DEG:g},$D${where["Fi_t0"]}=0),'
                   f'"{text["na"]}",{tpl[1:]})')
        if row.guard:
            tpl = f'=IF({{c}}{where[row.guard]},{tpl[1:]},"{marker}")'
        fmt = {"check": "0.0E+00", "fdcheck": "0.0E+00", "guard": "General"}.get(row.kind, "0.000000")
        for k, c in enumerate(cols):
            if fd and (k == 0 or k == n - 1):
                ws.cell(r, FIRST_COL + k, text["na"])
                continue
            p = cols[k - 1] if k else c
            nx = cols[k + 1] if k + 1 < n else c
            ws.cell(r, FIRST_COL + k, tpl.format(c=c, p=p, n=nx)).number_format = fmt
        if row.kind == "accepted":
            ws.cell(r, 1).fill = ACCEPTED_FILL
        if row.kind in ("check", "fdcheck"):
            rng = fd_range.format(r=r)
            tol = f"$D${where['Tol_FD' if row.kind == 'fdcheck' else 'Tol']}"
            if row.kind == "check":
                expected = (f"SUMPRODUCT(--({cols[0]}{where[row.guard]}:{cols[-1]}{where[row.guard]}))"
                            if row.guard else str(n))
                status = f"=IF(AND(COUNT({rng})={expected},MAX({rng})<={tol},MIN({rng})>=-{tol}),0,1)"
            else:
                status = f"=IF(AND(MAX({rng})<={tol},MIN({rng})>=-{tol}),0,1)"
            ws.cell(r, 4, status)
            status_cells.append(f"D{r}")
            top = f"{cols[0]}{r}"
            ws.conditional_formatting.add(rng, FormulaRule(formula=[f"AND(ISNUMBER({top}),ABS({top})<={tol})"], fill=GREEN))
            ws.conditional_formatting.add(rng, FormulaRule(formula=[f"AND(ISNUMBER({top}),ABS({top})>{tol})"], fill=RED))
            ws.conditional_formatting.add(f"D{r}", FormulaRule(formula=[f"D{r}=0"], fill=GREEN))
            ws.conditional_formatting.add(f"D{r}", FormulaRule(formula=[f"D{r}<>0"], fill=RED))
    # the summary at the top: how many check rows fail (SUM takes at most 255 arguments)
    parts = [f"SUM({','.join(status_cells[k:k + 200])})" for k in range(0, len(status_cells), 200)]
    total = "+".join(parts) or "0"
    ws["D3"] = f'=IF({total}=0,"{text["pass"]}",({total})&"{text["fail"]}")'
    ws["D3"].font = SECTION_FONT
    ws.conditional_formatting.add("D3", FormulaRule(formula=[f'D3="{text["pass"]}"'], fill=GREEN))
    ws.conditional_formatting.add("D3", FormulaRule(formula=[f'D3<>"{text["pass"]}"'], fill=RED))
    ws.freeze_panes = f"{cols[0]}5"
    from .workbook_print import setup_page      # widths, alignment, pages (sheetkin/workbook_print.py)
    setup_page(ws, rows, where, cols, FIRST_COL)
    if charts:
        from .workbook_charts import SheetRows
        _add_charts(wb, ws, scene, where, cols, lang,
                    SheetRows(ws, rows, where, templates, cols, marker, lang, exercise))
    _embed_scene(wb, scene, scene_text)
    return wb


def _add_charts(wb, ws, scene: Scene, where, cols, lang, rows_info):
    """The mechanism at a chosen position and the trajectories, to scale
    (sheetkin/workbook_charts.py); speeds and accelerations against the crank angle,
    angular velocities of the links."""
    from .workbook_charts import add_drawing_charts
    cs = wb.create_sheet(SHEET_TITLES[lang][1])
    cs.page_setup.orientation = "landscape"
    cs.sheet_properties.pageSetUpPr.fitToPage = True
    first, last = FIRST_COL, FIRST_COL + len(cols) - 1
    row_ref = lambda name: Reference(ws, min_col=first, max_col=last, min_row=where[name], max_row=where[name])
    points = scene.moving_joints + [p.name for p in scene.points]
    ru = lang == "ru"
    top = add_drawing_charts(wb, cs, scene, rows_info)
    specs = [
        ("Скорости точек" if ru else "Speeds of points", "phi_1, deg", "v, m/s",
         [("phi_1", f"v_{p}", f"v_{p}") for p in points]),
        ("Ускорения точек" if ru else "Accelerations of points", "phi_1, deg", "a, m/s^2",
         [("phi_1", f"a_{p}", f"a_{p}") for p in points]),
        ("Угловые скорости звеньев" if ru else "Angular velocities of links", "phi_1, deg", "omega, rad/s",
         [("phi_1", f"omega_{k}", f"omega_{k}") for k in scene.links]),
    ]
    if scene.has_dynamics:
        from .dynamics import reaction_pairs
        specs.append(("Уравновешивающий момент и мощности" if ru else "Balancing moment and powers", "phi_1, deg",
                      "N m, W", [("phi_1", n, n) for n in ("M_bal", "P_bal", "P_ext", "T_t") if n in where]))
        specs.append(("Реакции в кинематических парах" if ru else "Joint reactions", "phi_1, deg", "R, N",
                      [("phi_1", f"R_{p.tag}", f"R_{p.tag}") for p in reaction_pairs(scene)]))
    for k, (title, xt, yt, series) in enumerate(specs):
        ch = ScatterChart()
        ch.title, ch.style, ch.height, ch.width = title, 2, 9, 16
        ch.x_axis.title, ch.y_axis.title = xt, yt
        for axis in (ch.x_axis, ch.y_axis):
            axis.delete = False             # openpyxl >= 3.1 hides axes unless told
            axis.crosses = "min"            # axes at the bottom and the left, not through 0
            axis.numFmt = NumFmt(formatCode="General", sourceLinked=False)   # not the cells' 0.000000
        for x, y, label in series:
            s = Series(row_ref(y), row_ref(x), title=label)
            s.marker.symbol = "circle"
            s.smooth = False
            ch.series.append(s)
        cs.add_chart(ch, f"{'A' if k % 2 == 0 else 'K'}{top + (k // 2) * 20}")
    cs.print_area = f"A1:T{top + ((len(specs) + 1) // 2) * 20}"    # the charts, not the helper cells


def _embed_scene(wb, scene: Scene, scene_text: str | None):
    """The scene travels inside the workbook (a hidden sheet), so the file alone is enough
    to evaluate and validate it later."""
    if scene_text is None:
        try:
            scene_text = Path(scene.source).read_text(encoding="utf-8-sig")
        except OSError:
            raise ValueError("the scene's text is needed to embed it; pass scene_text") from None
    ws = wb.create_sheet(SCENE_SHEET)
    ws.sheet_state = "hidden"
    for k, line in enumerate(scene_text.splitlines(), 1):
        ws.cell(k, 1, line if line else None).data_type = "s"
    wb.properties.subject = f"sheetkin workbook; the scene is in the hidden sheet '{SCENE_SHEET}'"


def embedded_scene_text(path) -> str:
    """The scene TOML text stored in a sheetkin workbook."""
    wb = load_workbook(path, read_only=True)
    try:
        if SCENE_SHEET not in wb.sheetnames:
            raise ValueError(f"{path}: no embedded scene (no sheet '{SCENE_SHEET}'); not a sheetkin workbook?")
        lines = [row[0] if row and row[0] is not None else "" for row in wb[SCENE_SHEET].iter_rows(values_only=True)]
    finally:
        wb.close()
    return "\n".join(str(x) for x in lines) + "\n"


def write_workbook(scene: Scene, path, *, lang: str = "ru", exercise: bool = False,
                   scene_text: str | None = None) -> None:
    build_workbook(scene, lang=lang, exercise=exercise, scene_text=scene_text).save(path)


def fingerprint(source) -> dict:
    """What a workbook says, independent of when it was saved: every sheet's cells
    (formulas as written), its visibility, and the data references of its charts.
    `source` is a path or an in-memory Workbook. Used to tell a stale committed workbook."""
    import io
    import zipfile
    if isinstance(source, Workbook):
        buf = io.BytesIO()
        source.save(buf)
        source = buf
    wb = load_workbook(source)
    out = {ws.title: (ws.sheet_state, {c.coordinate: c.value for row in ws.iter_rows() for c in row
                                       if c.value is not None}) for ws in wb.worksheets}
    if hasattr(source, "seek"):
        source.seek(0)
    with zipfile.ZipFile(source) as z:
        charts = sorted(n for n in z.namelist() if n.startswith("xl/charts/chart"))
        out["charts"] = [re.findall(r"<(?:c:)?f>([^<]*)</(?:c:)?f>", z.read(n).decode("utf-8")) for n in charts]
    return out
