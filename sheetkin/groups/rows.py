"""Workbook rows as records, and the row helpers every block uses (a leaf module).

A `Row` is one line of the lecture's sheet: its name (column A), unit, description in
Russian and English, kind, and a formula template that names other rows ("{x_A}",
"{L1}", "{x_A@prev}", "{scale:vx_A}"); `sheetkin.sheet.workbook` compiles and writes them. The
`Builder` collects rows in the lecture's order. The helpers write the blocks every group
kind shares: the eight accepted rows of a moving point, Cramer's rule with its check
(slide 20), distance and rigid-body checks, numeric-derivative checks (step 10).
Imports nothing from sheetkin: the group kinds (sheetkin.groups), the workbook writer and
the dynamics blocks all build on it.
"""
from __future__ import annotations

from dataclasses import dataclass


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



# --------------------------------------------------------------------------- the builder
class Builder:
    """Collects rows in the lecture's order; knows which names are per-position rows."""

    def __init__(self, scene):
        self.scene = scene
        self.rows: list[Row] = []
        self.frame = set(scene.frame)
        self.rot: dict[int, tuple[str, str, str, str]] = {}   # link -> cos, sin, omega, eps rows
        self.guard_of_link: dict[int, str | None] = {1: None}
        self.on_link: dict[int, list[str]] = {}                # link -> its joints and points so far
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
            return f"{{{q}_{n}}}" if q in ("x", "y") else "0"
        return f"{{{q}_{n}}}"

    def input(self, name, unit, ru, en, value):
        self.add(name, unit, ru, en, kind="input", value=value)

    def place_links(self, *links, rot=None):
        """Later groups read link k's direction and rates from the rows cos_k, sin_k,
        omega_k, eps_k (or `rot`, the same four for every link given), valid where this
        group assembles (its guard)."""
        for k in links:
            self.rot[k] = rot or (f"cos_{k}", f"sin_{k}", f"omega_{k}", f"eps_{k}")
            self.guard_of_link[k] = self.guard


def residual(i: int, what: str) -> tuple[str, str, str]:
    """cramer_rows' check row of group i's velocity ("v") or acceleration ("a") system."""
    if what == "v":
        return f"chk_vsys_g{i}", "невязка системы для скоростей", "residual of the velocity system"
    return f"chk_asys_g{i}", "невязка системы для ускорений", "residual of the acceleration system"



def motion_rows(b: Builder, n: str, ru: str, en: str, x: str, y: str, vx: str, vy: str, ax: str, ay: str):
    """The eight accepted rows of a moving point: coordinates, velocity, acceleration."""
    for q, unit, f, r, e in (("x", "m", x, "координата x", "x coordinate"),
                             ("y", "m", y, "координата y", "y coordinate"),
                             ("vx", "m/s", vx, "скорость, проекция на x", "velocity, x component"),
                             ("vy", "m/s", vy, "скорость, проекция на y", "velocity, y component")):
        b.add(f"{q}_{n}", unit, f"{r} {ru}", f"{e} of {en}", "accepted", f)
    b.add(f"v_{n}", "m/s", f"модуль скорости {ru}", f"speed of {en}", "accepted", f"SQRT({{vx_{n}}}^2+{{vy_{n}}}^2)")
    for q, f, r, e in (("ax", ax, "ускорение, проекция на x", "acceleration, x component"),
                       ("ay", ay, "ускорение, проекция на y", "acceleration, y component")):
        b.add(f"{q}_{n}", "m/s^2", f"{r} {ru}", f"{e} of {en}", "accepted", f)
    b.add(f"a_{n}", "m/s^2", f"модуль ускорения {ru}", f"acceleration magnitude of {en}", "accepted",
          f"SQRT({{ax_{n}}}^2+{{ay_{n}}}^2)")
    magnitude_check(b, f"chk_mag_{n}", [(f"v_{n}", f"vx_{n}", f"vy_{n}"), (f"a_{n}", f"ax_{n}", f"ay_{n}")],
                    f"модули v_{n}, a_{n}", f"the magnitudes v_{n}, a_{n}")


def magnitude_check(b: Builder, name: str, mags, ru: str, en: str):
    """A magnitude row against its components, for each (magnitude, x, y) of `mags`:
    |m| m - (x^2 + y^2), relative to m^2 + x^2 + y^2. Squared, so it is free of the step
    and of the row's size; |m| m rather than m^2 so that a negative magnitude fails too."""
    terms = [f"ABS(ABS({{{m}}})*{{{m}}}-{{{x}}}^2-{{{y}}}^2)/MAX({{{m}}}^2+{{{x}}}^2+{{{y}}}^2,1E-300)"
             for m, x, y in mags]
    b.add(name, "", f"проверка: {ru}: |m| m = x^2 + y^2 (относительная невязка; не зависит от шага, "
                    f"ловит и неверный знак модуля)",
          f"check: {en}: |m| m = x^2 + y^2 (relative; free of the step, a negative magnitude fails too)",
          "check", "+".join(terms))


def distance_check(b: Builder, name: str, p1: str, p2: str, length: str, ru: str, en: str):
    b.add(name, "m", ru, en, "check",
          f"SQRT(({b.p('x', p2)}-{b.p('x', p1)})^2+({b.p('y', p2)}-{b.p('y', p1)})^2)-{length}")


def fd_checks(b: Builder, n: str):
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



def cos_sin_rows(b: Builder, k: int, ru: str, en: str):
    b.add(f"cos_{k}", "", f"cos угла звена {k}", f"cos of link {k}'s angle", "calc", f"COS(RADIANS({{phi_{k}}}))")
    b.add(f"sin_{k}", "", f"sin угла звена {k}", f"sin of link {k}'s angle", "calc", f"SIN(RADIANS({{phi_{k}}}))")


# groups.motion.DEAD_POINT as the formulas write it (this module imports nothing; a test keeps them equal)
DEAD_POINT_TEXT = "1E-12"


def group_guard(b: Builder, g, disc: str, size: str):
    """The group's "assembles" row: the discriminant `disc` at least DEAD_POINT times `size` (the
    size of its terms). Not disc >= 0: at a dead point the discriminant is 0 in exact arithmetic
    and each spreadsheet program rounds it its own way (docs/dead-points.md). >= rather than >:
    an exercise's empty rows (0 >= 0) still read as assembling, as before."""
    prev = b.guard
    test = f"{{{disc}}}>={DEAD_POINT_TEXT}*({size})"
    b.add(f"asm_g{g.index}", "", f"группа {g.index} собирается (дискриминант > 0, не мёртвая точка)",
          f"group {g.index} assembles (discriminant > 0, not a dead point)",
          "guard", f"AND({{{prev}}},{test})" if prev else test)
    b.guard = f"asm_g{g.index}"



def via_link_checks(b: Builder, n: str, j: str, k: int, label: str):
    """Velocity and acceleration of joint n computed once more through link k about j
    (Euler form): |v_n - (v_j + omega_k x r)| and the same for accelerations. A wrong
    angular velocity or acceleration of link k shows here, at any step."""
    c, s, w, e = (f"{{{r}}}" for r in b.rot[k])
    X, Y = f"({b.p('x', n)}-{b.p('x', j)})", f"({b.p('y', n)}-{b.p('y', j)})"
    b.add(
        f"chk_v_{n}_{k}",
        "m/s",
        f"проверка: скорость {n} через звено {k} ({label}; не зависит от шага)",
        f"check: velocity of {n} through link {k} ({label}; free of the step)",
        "check",
        f"ABS({b.p('vx', n)}-({b.p('vx', j)}-{w}*{Y}))+ABS({b.p('vy', n)}-({b.p('vy', j)}+{w}*{X}))",
    )
    b.add(
        f"chk_a_{n}_{k}",
        "m/s^2",
        f"проверка: ускорение {n} через звено {k} ({label}; не зависит от шага)",
        f"check: acceleration of {n} through link {k} ({label}; free of the step)",
        "check",
        f"ABS({b.p('ax', n)}-({b.p('ax', j)}-{e}*{Y}-{w}^2*{X}))"
        f"+ABS({b.p('ay', n)}-({b.p('ay', j)}+{e}*{X}-{w}^2*{Y}))",
    )


def local_position_check(b: Builder, n: str, k: int, origin: str, along: str, across: str):
    """Point n of link k put back into the link's own axes: (r_n - r_origin) turned by
    -phi_k must give (along, across). The point's x, y rows are written the other way
    round (turned by +phi_k), so a sign or a factor wrong in either fails here."""
    c, s, _, _ = (f"{{{r}}}" for r in b.rot[k])
    X, Y = f"({{x_{n}}}-{b.p('x', origin)})", f"({{y_{n}}}-{b.p('y', origin)})"
    b.add(
        f"chk_local_{n}",
        "m",
        f"проверка: {n} в осях звена {k}: (r{n} - r{origin}) повёрнут на -phi_{k} "
        f"= (вдоль, поперёк) (не зависит от шага)",
        f"check: {n} in link {k}'s axes: (r{n} - r{origin}) turned by -phi_{k} = (along, across) (free of the step)",
        "check",
        f"ABS({X}*{c}+{Y}*{s}-{along})+ABS({Y}*{c}-{X}*{s}-{across})",
    )


def turns_with_check(b: Builder, name: str, angles, rates, ru: str, en: str):
    """A link that turns as one with a line or another link: its angle rows against that
    direction's cos and sin, its omega and eps rows against the rates it turns with.
    angles: [(phi row, cos formula, sin formula)]; rates: [(row, formula)]. These rows
    feed nothing the other checks see (the group's systems use the direction itself), so
    without this check a wrong one stays green at any step."""
    terms = [f"ABS(COS(RADIANS({{{phi}}}))-{c})+ABS(SIN(RADIANS({{{phi}}}))-{s})" for phi, c, s in angles]
    terms += [f"ABS({{{r}}}-({f}))" for r, f in rates]
    b.add(name, "", f"проверка: {ru} (не зависит от шага)", f"check: {en} (free of the step)", "check",
          "+".join(terms))


def system_check(b: Builder, name: str, what: tuple[str, str], m, x: str, y: str, rhs: tuple[str, str]):
    """Put the solved unknowns back into their 2x2 system: |m11 x + m12 y - b1| + |m21 x + m22 y - b2|."""
    m11, m12, m21, m22 = m
    b.add(name, "", f"проверка: {what[0]}", f"check: {what[1]}", "check",
          f"ABS({m11}*{x}+{m12}*{y}-{rhs[0]})+ABS({m21}*{x}+{m22}*{y}-{rhs[1]})")


def cramer_rows(b: Builder, m, det: str, unknowns, rhs: tuple[str, str], check: tuple[str, str, str]):
    """Two unknowns of [[m11, m12], [m21, m22]] (x, y) = (b1, b2) by Cramer's rule (slide 20):
    x = (b1 m22 - b2 m12) / det, y = (m11 b2 - m21 b1) / det; then the check that puts
    them back into the system. `unknowns` = ((name, unit, ru, en), (name, unit, ru, en))."""
    m11, m12, m21, m22 = m
    (n1, u1, ru1, en1), (n2, u2, ru2, en2) = unknowns
    b.add(n1, u1, ru1, en1, "accepted", f"({rhs[0]}*{m22}-{rhs[1]}*{m12})/{{{det}}}")
    b.add(n2, u2, ru2, en2, "accepted", f"({m11}*{rhs[1]}-{m21}*{rhs[0]})/{{{det}}}")
    system_check(b, check[0], check[1:], m, f"{{{n1}}}", f"{{{n2}}}", rhs)


def det_row(b: Builder, det: str, m, unit: str, ru: str, en: str):
    m11, m12, m21, m22 = m
    b.add(det, unit, ru, en, "calc", f"{m11}*{m22}-{m12}*{m21}")


def relative_velocity_check(b: Builder, n: str, j: str):
    """A rigid link keeps |n j|: the relative velocity is perpendicular to n - j."""
    b.add(
        f"chk_v_{n}{j}",
        "m^2/s",
        f"проверка: (v{n} - v{j}) перпендикулярна {j}{n}",
        f"check: (v{n} - v{j}) perpendicular to {j}{n}",
        "check",
        f"({b.p('vx', n)}-{b.p('vx', j)})*({b.p('x', n)}-{b.p('x', j)})"
        f"+({b.p('vy', n)}-{b.p('vy', j)})*({b.p('y', n)}-{b.p('y', j)})",
    )


def carried_rows(b: Builder, n: str, k: int, origin: str, along: str, across: str, ru: str, en: str):
    """A point fixed on link k (slide 7, Euler form): v = v_P + omega x r, a = a_P + eps x r - omega^2 r."""
    c, s, w, e = (f"{{{r}}}" for r in b.rot[k])
    rx = f"({along}*{c}-{across}*{s})" if across != "0" else f"{along}*{c}"
    ry = f"({along}*{s}+{across}*{c})" if across != "0" else f"{along}*{s}"
    X, Y = f"({{x_{n}}}-{b.p('x', origin)})", f"({{y_{n}}}-{b.p('y', origin)})"
    b.section(f"point_{n}", f"Точка {n} звена {k}", f"Point {n} of link {k}")
    motion_rows(
        b,
        n,
        ru,
        en,
        f"{b.p('x', origin)}+{rx}",
        f"{b.p('y', origin)}+{ry}",
        f"{b.p('vx', origin)}-{w}*{Y}",
        f"{b.p('vy', origin)}+{w}*{X}",
        f"{b.p('ax', origin)}-{e}*{Y}-{w}^2*{X}",
        f"{b.p('ay', origin)}+{e}*{X}-{w}^2*{Y}",
    )


@dataclass(frozen=True)
class InputRow:
    """An editable input of a group: written by the workbook, read back by the validator.
    `early`: written with the lengths, before the frame points (the lecture's order)."""
    name: str
    unit: str
    ru: str
    en: str
    value: float
    early: bool = False


class LoadRows:
    """The kinetostatics sheet's shared rows (seed 003, "Dynamic analysis"): the known loads
    on a link, reactions, Cramer's rule for a reaction, and a link's equilibrium check.
    `loads[k]`: (point, fx, fy) formula pieces acting on link k; `couples[k]`: couples."""

    def __init__(self, b: Builder, loads: dict, couples: dict):
        self.b, self.loads, self.couples = b, loads, couples

    def link_loads(self, k: int, ref: str):
        """Rows Qx_k, Qy_k, MQ_k: the known loads on link k and their moment about ref; then
        the check that takes the moment once more, about the origin."""
        b, loads, couples = self.b, self.loads, self.couples
        fx = "+".join(f for _, f, _ in loads[k]) or "0"
        fy = "+".join(f for _, _, f in loads[k]) or "0"
        mom = [f"({b.p('x', p)}-{b.p('x', ref)})*{y}-({b.p('y', p)}-{b.p('y', ref)})*{x}" for p, x, y in loads[k]]
        b.add(f"Qx_{k}", "N", f"главный вектор известных нагрузок звена {k}, x",
              f"resultant of the known loads on link {k}, x", "calc", fx)
        b.add(f"Qy_{k}", "N", f"главный вектор известных нагрузок звена {k}, y",
              f"resultant of the known loads on link {k}, y", "calc", fy)
        b.add(f"MQ_{k}", "N m", f"их момент относительно {ref}", f"their moment about {ref}", "calc",
              "+".join(mom + couples[k]) or "0")
        about_o = "+".join([f"{b.p('x', p)}*{y}-{b.p('y', p)}*{x}" for p, x, y in loads[k]] + couples[k]) or "0"
        b.add(f"chk_MQ_{k}", "",
              f"проверка: момент нагрузок звена {k} относительно начала координат (относительная невязка)",
              f"check: the moment of link {k}'s loads about the origin (relative)", "check",
              f"({about_o}-({{MQ_{k}}}+{b.p('x', ref)}*{{Qy_{k}}}-{b.p('y', ref)}*{{Qx_{k}}}))"
              f"/(1+ABS({{Qx_{k}}})+ABS({{Qy_{k}}})+ABS({{MQ_{k}}}))")

    def opposite(self, link: int, at: str, tag: str, couple: bool = False):
        """Link `link` exerts the reaction `tag` at `at`: it takes the opposite force there
        (and, with `couple`, the opposite couple M_tag) when its own group is balanced."""
        self.loads[link].append((at, f"(-{{Rx_{tag}}})", f"(-{{Ry_{tag}}})"))
        if couple:
            self.couples[link].append(f"(-{{M_{tag}}})")

    def magnitude(self, tag: str, ru: str, en: str):
        self.b.add(f"R_{tag}", "N", f"модуль реакции {ru}", f"magnitude of the reaction {en}", "accepted",
                   f"SQRT({{Rx_{tag}}}^2+{{Ry_{tag}}}^2)")
        magnitude_check(self.b, f"chk_mag_R_{tag}", [(f"R_{tag}", f"Rx_{tag}", f"Ry_{tag}")],
                        f"модуль реакции R_{tag}", f"the reaction's magnitude R_{tag}")

    def reaction(self, tag: str, rx: str, ry: str, ru: str, en: str):
        self.b.add(f"Rx_{tag}", "N", f"реакция {ru}, x", f"reaction {en}, x", "accepted", rx)
        self.b.add(f"Ry_{tag}", "N", f"реакция {ru}, y", f"reaction {en}, y", "accepted", ry)
        self.magnitude(tag, ru, en)

    def cramer_reaction(self, i: int, tag: str, mat, rhs, det_unit: str, det_text: tuple[str, str],
                        ru: str, en: str):
        """The group's determinant, the reaction at J1 by Cramer's rule (lecture slide 20),
        the check putting it back into its two equations, and its magnitude."""
        b, det = self.b, f"Delta_R_g{i}"
        det_row(b, det, mat, det_unit, *det_text)
        cramer_rows(b, mat, det, ((f"Rx_{tag}", "N", f"реакция {ru} (Крамер), x", f"reaction {en} (Cramer), x"),
                                  (f"Ry_{tag}", "N", f"реакция {ru} (Крамер), y", f"reaction {en} (Cramer), y")),
                    rhs, (f"chk_Rsys_g{i}", "реакция в её двух уравнениях",
                          "the reaction put back into its two equations"))
        self.magnitude(tag, ru, en)

    def equilibrium(self, k: int, ref: str, acting, couple: str):
        """Check row: link k's three equilibrium equations with every reaction on it, the
        moments taken about the origin (not about ref, where the loads were summed)."""
        b = self.b
        fx = "+".join([f"{{Qx_{k}}}"] + [x for _, x, _ in acting])
        fy = "+".join([f"{{Qy_{k}}}"] + [y for _, _, y in acting])
        mom = "+".join([f"{{MQ_{k}}}", f"{b.p('x', ref)}*{{Qy_{k}}}-{b.p('y', ref)}*{{Qx_{k}}}"]
                       + [f"{b.p('x', p)}*{y}-{b.p('y', p)}*{x}" for p, x, y in acting]
                       + ([couple] if couple else []))
        size = "+".join(["1", f"ABS({{Qx_{k}}})", f"ABS({{Qy_{k}}})"] + [f"ABS({x})+ABS({y})" for _, x, y in acting])
        b.add(f"chk_eq_{k}", "", f"проверка: равновесие звена {k} (силы и моменты, относительная невязка)",
              f"check: equilibrium of link {k} (forces and moments, relative)", "check",
              f"(ABS({fx})+ABS({fy})+ABS({mom}))/({size})")
