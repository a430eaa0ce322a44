"""Workbook rows as records, and the row helpers every block uses (a leaf module).

A `Row` is one line of the lecture's sheet: its name (column A), unit, description in
Russian, Ukrainian and English, kind, and a formula template that names other rows ("{x_A}",
"{L1}", "{x_A@prev}", "{scale:vx_A}"); `sheetkin.sheet.workbook` compiles and writes them. The
`Builder` collects rows in the lecture's order, one builder a kind of row: `b.section`,
`b.given` (an input), `b.derived`, `b.index`, `b.calc`, `b.accepted`, `b.check`,
`b.fdcheck`. Each takes its description as a `Text` (all three languages: nothing is
translated when a book is written), made by a module's `Texts` table from a key and format
fields:

    T = Texts({"ru": {"angle": "угол звена {k}"}, "uk": {"angle": "кут ланки {k}"},
               "en": {"angle": "angle of link {k}"}})
    b.accepted(f"phi_{k}", "deg", T("angle", k=k), formula)

one table per language, kept in the module whose rows use them (a kind's in its own
module, the helpers' below, the workbook writer's own in sheetkin.sheet.texts). The
helpers write the blocks every group kind shares: the eight accepted rows of a moving
point, Cramer's rule with its check (slide 20), distance and rigid-body checks,
numeric-derivative checks (step 10). Imports only sheetkin.groups.lang
(a leaf): the group kinds (sheetkin.groups), the workbook writer and the dynamics blocks all
build on it.
"""
from __future__ import annotations

import string
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from .lang import LANGS


@dataclass(frozen=True)
class Text:
    """A row's description in each language of the books."""
    ru: str
    uk: str
    en: str

    def say(self, lang: str) -> str:
        return {"ru": self.ru, "uk": self.uk, "en": self.en}[lang]


Field = str | int | float | Text


class Texts:
    """One module's row descriptions: format templates, one table per language,
    `{"ru": {key: template}, "uk": {...}, "en": {...}}`. T(key, **fields) is the Text of
    the row: each language's template formatted with the fields (a field that is a Text
    itself, a label, is taken in the same language)."""

    def __init__(self, tables: Mapping[str, Mapping[str, str]]):
        self.tables = tables

    def __call__(self, key: str, **fields: Field) -> Text:
        return Text(*(self.tables[lang][key].format(**{k: v.say(lang) if isinstance(v, Text) else v
                                                       for k, v in fields.items()}) for lang in LANGS))

    def fields(self, lang: str, key: str) -> set[str]:
        """The format fields of a template (the test that every language has every key reads them)."""
        return {f for _, f, _, _ in string.Formatter().parse(self.tables[lang][key]) if f is not None}


# what a row of the kinematics sheet is: a section heading, a given datum (input) or one
# derived from them, the position index, a formula's intermediate (calc), a contract
# quantity (accepted), a check row (check; fdcheck: a finite-difference one) or the
# group's "assembled" guard
RowKind = Literal["section", "input", "derived", "index", "calc", "accepted", "check", "fdcheck", "guard"]


@dataclass
class Row:
    name: str
    unit: str = ""
    ru: str = ""
    en: str = ""
    kind: RowKind = "calc"
    formula: str = ""           # template: {row}, {row@prev}, {row@next}
    value: float | None = None  # input rows
    guard: str | None = None    # the group's "assembled" row: IF(guard, formula, marker)
    uk: str = ""                # the Ukrainian description

    def say(self, lang: str) -> str:
        """The row's description in `lang` (ru, uk or en)."""
        return {"ru": self.ru, "uk": self.uk, "en": self.en}[lang]


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

    def add(self, name: str, unit: str, text: Text, kind: RowKind = "calc", formula: str = "", value=None, guard=...):
        """A row of any kind (the builders below name the kind); its description a Text."""
        g = self.guard if guard is ... else guard
        self.rows.append(Row(name, unit, text.ru, text.en, kind, formula, value,
                             g if kind in ("calc", "accepted", "check", "fdcheck") else None, text.uk))
        if kind == "check":
            self.checks.append(name)
        if kind == "fdcheck":
            self.fd_checks.append(name)

    # the row builders: one a kind of row, the description a Text (a module's Texts)
    def row(self, kind: RowKind, name: str, unit: str, text: Text, formula: str = "", value=None, guard=...):
        self.add(name, unit, text, kind, formula, value, guard)

    def calc(self, name: str, unit: str, text: Text, formula: str, guard=...):
        """An intermediate row of a block (the lecture's P, Q, F, the branches)."""
        self.row("calc", name, unit, text, formula, guard=guard)

    def accepted(self, name: str, unit: str, text: Text, formula: str, guard=...):
        """An accepted value: what the later blocks read (angles, rates, points)."""
        self.row("accepted", name, unit, text, formula, guard=guard)

    def check(self, name: str, unit: str, text: Text, formula: str, guard=...):
        """A check row (0 where the block is right; the summary counts it)."""
        self.row("check", name, unit, text, formula, guard=guard)

    def fdcheck(self, name: str, text: Text, formula: str):
        """A numeric-derivative check (step 10), relative: no unit."""
        self.row("fdcheck", name, "", text, formula)

    def section(self, name: str, text: Text):
        """A block's title row."""
        self.row("section", name, "", text)

    def given(self, name: str, unit: str, text: Text, value: float):
        """An input row: the given data (a yellow cell of column D)."""
        self.row("input", name, unit, text, value=value)

    def derived(self, name: str, unit: str, text: Text, formula: str):
        """A row of the derived data: one formula in column D on the given data (an exercise
        leaves it blank, lilac, for the student)."""
        self.row("derived", name, unit, text, formula)

    def index(self, name: str, text: Text):
        """The positions' numbers (row i)."""
        self.row("index", name, "", text)

    # references to a point's quantities (a frame point is an input and does not move)
    def p(self, q: str, n: str) -> str:
        if n in self.frame:
            return f"{{{q}_{n}}}" if q in ("x", "y") else "0"
        return f"{{{q}_{n}}}"

    def place_links(self, *links, rot=None):
        """Later groups read link k's direction and rates from the rows cos_k, sin_k,
        omega_k, eps_k (or `rot`, the same four for every link given), valid where this
        group assembles (its guard)."""
        for k in links:
            self.rot[k] = rot or (f"cos_{k}", f"sin_{k}", f"omega_{k}", f"eps_{k}")
            self.guard_of_link[k] = self.guard


# --------------------------------------------------------------------------- the helpers' texts
TEXTS = {
    "ru": {
        "vsys": "невязка системы для скоростей",
        "asys": "невязка системы для ускорений",
        "x": "координата x {of}",
        "y": "координата y {of}",
        "vx": "скорость, проекция на x {of}",
        "vy": "скорость, проекция на y {of}",
        "v": "модуль скорости {of}",
        "ax": "ускорение, проекция на x {of}",
        "ay": "ускорение, проекция на y {of}",
        "a": "модуль ускорения {of}",
        "mags": "модули v_{n}, a_{n}",
        "mag_check": "проверка: {what}: |m| m = x^2 + y^2 (относительная невязка; не зависит от шага, "
                     "ловит и неверный знак модуля)",
        "fd": "{q}: численная производная (относительная невязка)",
        "cos": "cos угла звена {k}",
        "sin": "sin угла звена {k}",
        "guard": "группа {i} собирается (дискриминант > 0, не мёртвая точка)",
        "via_v": "проверка: скорость {n} через звено {k} ({label}; не зависит от шага)",
        "via_a": "проверка: ускорение {n} через звено {k} ({label}; не зависит от шага)",
        "local": "проверка: {n} в осях звена {k}: (r{n} - r{origin}) повёрнут на -phi_{k} "
                 "= (вдоль, поперёк) (не зависит от шага)",
        "turns": "проверка: {what} (не зависит от шага)",
        "system": "проверка: {what}",
        "perp": "проверка: (v{n} - v{j}) перпендикулярна {j}{n}",
        "point": "Точка {n} звена {k}",
        "Qx": "главный вектор известных нагрузок звена {k}, x",
        "Qy": "главный вектор известных нагрузок звена {k}, y",
        "MQ": "их момент относительно {ref}",
        "MQ_check": "проверка: момент нагрузок звена {k} относительно начала координат (относительная невязка)",
        "R": "модуль реакции {of}",
        "R_mag": "модуль реакции R_{tag}",
        "Rx": "реакция {of}, x",
        "Ry": "реакция {of}, y",
        "Rx_cramer": "реакция {of} (Крамер), x",
        "Ry_cramer": "реакция {of} (Крамер), y",
        "Rsys": "реакция в её двух уравнениях",
        "equilibrium": "проверка: равновесие звена {k} (силы и моменты, относительная невязка)",
    },
    "uk": {
        "vsys": "нев'язка системи для швидкостей",
        "asys": "нев'язка системи для прискорень",
        "x": "координата x {of}",
        "y": "координата y {of}",
        "vx": "швидкість, проекція на x {of}",
        "vy": "швидкість, проекція на y {of}",
        "v": "модуль швидкості {of}",
        "ax": "прискорення, проекція на x {of}",
        "ay": "прискорення, проекція на y {of}",
        "a": "модуль прискорення {of}",
        "mags": "модулі v_{n}, a_{n}",
        "mag_check": "перевірка: {what}: |m| m = x^2 + y^2 (відносна нев'язка; не залежить від кроку, виявляє і "
                     "невірний знак модуля)",
        "fd": "{q}: чисельна похідна (відносна нев'язка)",
        "cos": "cos кута ланки {k}",
        "sin": "sin кута ланки {k}",
        "guard": "група {i} збирається (дискримінант > 0, не мертва точка)",
        "via_v": "перевірка: швидкість {n} через ланку {k} ({label}; не залежить від кроку)",
        "via_a": "перевірка: прискорення {n} через ланку {k} ({label}; не залежить від кроку)",
        "local": "перевірка: {n} в осях ланки {k}: (r{n} - r{origin}) повернутий на -phi_{k} = (уздовж, поперек) (не "
                 "залежить від кроку)",
        "turns": "перевірка: {what} (не залежить від кроку)",
        "system": "перевірка: {what}",
        "perp": "перевірка: (v{n} - v{j}) перпендикулярна {j}{n}",
        "point": "Точка {n} ланки {k}",
        "Qx": "головний вектор відомих навантажень ланки {k}, x",
        "Qy": "головний вектор відомих навантажень ланки {k}, y",
        "MQ": "їх момент відносно {ref}",
        "MQ_check": "перевірка: момент навантажень ланки {k} відносно початку координат (відносна нев'язка)",
        "R": "модуль реакції {of}",
        "R_mag": "модуль реакції R_{tag}",
        "Rx": "реакція {of}, x",
        "Ry": "реакція {of}, y",
        "Rx_cramer": "реакція {of} (Крамер), x",
        "Ry_cramer": "реакція {of} (Крамер), y",
        "Rsys": "реакція в її двох рівняннях",
        "equilibrium": "перевірка: рівновага ланки {k} (сили і моменти, відносна нев'язка)",
    },
    "en": {
        "vsys": "residual of the velocity system",
        "asys": "residual of the acceleration system",
        "x": "x coordinate of {of}",
        "y": "y coordinate of {of}",
        "vx": "velocity, x component of {of}",
        "vy": "velocity, y component of {of}",
        "v": "speed of {of}",
        "ax": "acceleration, x component of {of}",
        "ay": "acceleration, y component of {of}",
        "a": "acceleration magnitude of {of}",
        "mags": "the magnitudes v_{n}, a_{n}",
        "mag_check": "check: {what}: |m| m = x^2 + y^2 (relative; free of the step, a negative magnitude fails too)",
        "fd": "{q} against the numeric derivative (relative)",
        "cos": "cos of link {k}'s angle",
        "sin": "sin of link {k}'s angle",
        "guard": "group {i} assembles (discriminant > 0, not a dead point)",
        "via_v": "check: velocity of {n} through link {k} ({label}; free of the step)",
        "via_a": "check: acceleration of {n} through link {k} ({label}; free of the step)",
        "local": "check: {n} in link {k}'s axes: (r{n} - r{origin}) turned by -phi_{k} = (along, across) "
                 "(free of the step)",
        "turns": "check: {what} (free of the step)",
        "system": "check: {what}",
        "perp": "check: (v{n} - v{j}) perpendicular to {j}{n}",
        "point": "Point {n} of link {k}",
        "Qx": "resultant of the known loads on link {k}, x",
        "Qy": "resultant of the known loads on link {k}, y",
        "MQ": "their moment about {ref}",
        "MQ_check": "check: the moment of link {k}'s loads about the origin (relative)",
        "R": "magnitude of the reaction {of}",
        "R_mag": "the reaction's magnitude R_{tag}",
        "Rx": "reaction {of}, x",
        "Ry": "reaction {of}, y",
        "Rx_cramer": "reaction {of} (Cramer), x",
        "Ry_cramer": "reaction {of} (Cramer), y",
        "Rsys": "the reaction put back into its two equations",
        "equilibrium": "check: equilibrium of link {k} (forces and moments, relative)",
    },
}
T = Texts(TEXTS)


def residual(i: int, what: str) -> tuple[str, Text]:
    """cramer_rows' check row of group i's velocity ("v") or acceleration ("a") system."""
    if what == "v":
        return f"chk_vsys_g{i}", T("vsys")
    return f"chk_asys_g{i}", T("asys")


def motion_rows(b: Builder, n: str, of: Text, x: str, y: str, vx: str, vy: str, ax: str, ay: str):
    """The eight accepted rows of a moving point `of` (a label: "hinge B"): coordinates,
    velocity, acceleration."""
    for q, unit, f in (("x", "m", x), ("y", "m", y), ("vx", "m/s", vx), ("vy", "m/s", vy)):
        b.accepted(f"{q}_{n}", unit, T(q, of=of), f)
    b.accepted(f"v_{n}", "m/s", T("v", of=of), f"SQRT({{vx_{n}}}^2+{{vy_{n}}}^2)")
    for q, f in (("ax", ax), ("ay", ay)):
        b.accepted(f"{q}_{n}", "m/s^2", T(q, of=of), f)
    b.accepted(f"a_{n}", "m/s^2", T("a", of=of), f"SQRT({{ax_{n}}}^2+{{ay_{n}}}^2)")
    magnitude_check(b, f"chk_mag_{n}", [(f"v_{n}", f"vx_{n}", f"vy_{n}"), (f"a_{n}", f"ax_{n}", f"ay_{n}")],
                    T("mags", n=n))


def magnitude_check(b: Builder, name: str, mags, what: Text):
    """A magnitude row against its components, for each (magnitude, x, y) of `mags`:
    |m| m - (x^2 + y^2), relative to m^2 + x^2 + y^2. Squared, so it is free of the step
    and of the row's size; |m| m rather than m^2 so that a negative magnitude fails too."""
    terms = [f"ABS(ABS({{{m}}})*{{{m}}}-{{{x}}}^2-{{{y}}}^2)/MAX({{{m}}}^2+{{{x}}}^2+{{{y}}}^2,1E-300)"
             for m, x, y in mags]
    b.check(name, "", T("mag_check", what=what), "+".join(terms))


def distance_check(b: Builder, name: str, p1: str, p2: str, length: str, text: Text):
    b.check(name, "m", text, f"SQRT(({b.p('x', p2)}-{b.p('x', p1)})^2+({b.p('y', p2)}-{b.p('y', p1)})^2)-{length}")


def fd_checks(b: Builder, n: str):
    """Analytic velocity and acceleration against central differences over neighbouring
    columns (the lecture's step 10), relative to the row's largest value. With the crank's
    rates taken as given at each position: v = Fi_t dx/dFi, a = Fi_t dv/dFi + Fi_tt v / Fi_t."""
    for q, v, a in (("x", f"vx_{n}", f"ax_{n}"), ("y", f"vy_{n}", f"ay_{n}")):
        pos = f"{q}_{n}"
        b.fdcheck(f"fd_{v}", T("fd", q=v),
                  f"({{{v}}}-{{Fi_t}}*({{{pos}@next}}-{{{pos}@prev}})/(2*{{Delta_Fi_rad}}))/{{scale:{v}}}")
        b.fdcheck(f"fd_{a}", T("fd", q=a),
                  f"({{{a}}}-{{Fi_t}}*({{{v}@next}}-{{{v}@prev}})/(2*{{Delta_Fi_rad}})-{{Fi_tt}}*{{{v}}}/{{Fi_t}})"
                  f"/{{scale:{a}}}")


def cos_sin_rows(b: Builder, k: int):
    b.calc(f"cos_{k}", "", T("cos", k=k), f"COS(RADIANS({{phi_{k}}}))")
    b.calc(f"sin_{k}", "", T("sin", k=k), f"SIN(RADIANS({{phi_{k}}}))")


# groups.motion.DEAD_POINT as the formulas write it (not imported from motion; a test keeps them equal)
DEAD_POINT_TEXT = "1E-12"


def group_guard(b: Builder, g, disc: str, size: str):
    """The group's "assembles" row: the discriminant `disc` at least DEAD_POINT times `size` (the
    size of its terms). Not disc >= 0: at a dead point the discriminant is 0 in exact arithmetic
    and each spreadsheet program rounds it its own way (docs/dead-points.md). >= rather than >:
    an exercise's empty rows (0 >= 0) still read as assembling, as before."""
    prev = b.guard
    test = f"{{{disc}}}>={DEAD_POINT_TEXT}*({size})"
    b.row("guard", f"asm_g{g.index}", "", T("guard", i=g.index), f"AND({{{prev}}},{test})" if prev else test)
    b.guard = f"asm_g{g.index}"


def via_link_checks(b: Builder, n: str, j: str, k: int, label: str):
    """Velocity and acceleration of joint n computed once more through link k about j
    (Euler form): |v_n - (v_j + omega_k x r)| and the same for accelerations. A wrong
    angular velocity or acceleration of link k shows here, at any step."""
    c, s, w, e = (f"{{{r}}}" for r in b.rot[k])
    X, Y = f"({b.p('x', n)}-{b.p('x', j)})", f"({b.p('y', n)}-{b.p('y', j)})"
    b.check(f"chk_v_{n}_{k}", "m/s", T("via_v", n=n, k=k, label=label),
            f"ABS({b.p('vx', n)}-({b.p('vx', j)}-{w}*{Y}))+ABS({b.p('vy', n)}-({b.p('vy', j)}+{w}*{X}))")
    b.check(f"chk_a_{n}_{k}", "m/s^2", T("via_a", n=n, k=k, label=label),
            f"ABS({b.p('ax', n)}-({b.p('ax', j)}-{e}*{Y}-{w}^2*{X}))"
            f"+ABS({b.p('ay', n)}-({b.p('ay', j)}+{e}*{X}-{w}^2*{Y}))")


def local_position_check(b: Builder, n: str, k: int, origin: str, along: str, across: str):
    """Point n of link k put back into the link's own axes: (r_n - r_origin) turned by
    -phi_k must give (along, across). The point's x, y rows are written the other way
    round (turned by +phi_k), so a sign or a factor wrong in either fails here."""
    c, s, _, _ = (f"{{{r}}}" for r in b.rot[k])
    X, Y = f"({{x_{n}}}-{b.p('x', origin)})", f"({{y_{n}}}-{b.p('y', origin)})"
    b.check(f"chk_local_{n}", "m", T("local", n=n, k=k, origin=origin),
            f"ABS({X}*{c}+{Y}*{s}-{along})+ABS({Y}*{c}-{X}*{s}-{across})")


def turns_with_check(b: Builder, name: str, angles, rates, what: Text):
    """A link that turns as one with a line or another link: its angle rows against that
    direction's cos and sin, its omega and eps rows against the rates it turns with.
    angles: [(phi row, cos formula, sin formula)]; rates: [(row, formula)]. These rows
    feed nothing the other checks see (the group's systems use the direction itself), so
    without this check a wrong one stays green at any step."""
    terms = [f"ABS(COS(RADIANS({{{phi}}}))-{c})+ABS(SIN(RADIANS({{{phi}}}))-{s})" for phi, c, s in angles]
    terms += [f"ABS({{{r}}}-({f}))" for r, f in rates]
    b.check(name, "", T("turns", what=what), "+".join(terms))


def system_check(b: Builder, name: str, what: Text, m, x: str, y: str, rhs: tuple[str, str]):
    """Put the solved unknowns back into their 2x2 system: |m11 x + m12 y - b1| + |m21 x + m22 y - b2|."""
    m11, m12, m21, m22 = m
    b.check(name, "", T("system", what=what),
            f"ABS({m11}*{x}+{m12}*{y}-{rhs[0]})+ABS({m21}*{x}+{m22}*{y}-{rhs[1]})")


def cramer_rows(b: Builder, m, det: str, unknowns, rhs: tuple[str, str], check: tuple[str, Text]):
    """Two unknowns of [[m11, m12], [m21, m22]] (x, y) = (b1, b2) by Cramer's rule (slide 20):
    x = (b1 m22 - b2 m12) / det, y = (m11 b2 - m21 b1) / det; then the check that puts
    them back into the system. `unknowns` = ((name, unit, text), (name, unit, text))."""
    m11, m12, m21, m22 = m
    (n1, u1, t1), (n2, u2, t2) = unknowns
    b.accepted(n1, u1, t1, f"({rhs[0]}*{m22}-{rhs[1]}*{m12})/{{{det}}}")
    b.accepted(n2, u2, t2, f"({m11}*{rhs[1]}-{m21}*{rhs[0]})/{{{det}}}")
    system_check(b, check[0], check[1], m, f"{{{n1}}}", f"{{{n2}}}", rhs)


def det_row(b: Builder, det: str, m, unit: str, text: Text):
    m11, m12, m21, m22 = m
    b.calc(det, unit, text, f"{m11}*{m22}-{m12}*{m21}")


def relative_velocity_check(b: Builder, n: str, j: str):
    """A rigid link keeps |n j|: the relative velocity is perpendicular to n - j."""
    b.check(f"chk_v_{n}{j}", "m^2/s", T("perp", n=n, j=j),
            f"({b.p('vx', n)}-{b.p('vx', j)})*({b.p('x', n)}-{b.p('x', j)})"
            f"+({b.p('vy', n)}-{b.p('vy', j)})*({b.p('y', n)}-{b.p('y', j)})")


def carried_rows(b: Builder, n: str, k: int, origin: str, along: str, across: str, of: Text):
    """A point fixed on link k (slide 7, Euler form): v = v_P + omega x r, a = a_P + eps x r - omega^2 r."""
    c, s, w, e = (f"{{{r}}}" for r in b.rot[k])
    rx = f"({along}*{c}-{across}*{s})" if across != "0" else f"{along}*{c}"
    ry = f"({along}*{s}+{across}*{c})" if across != "0" else f"{along}*{s}"
    X, Y = f"({{x_{n}}}-{b.p('x', origin)})", f"({{y_{n}}}-{b.p('y', origin)})"
    b.section(f"point_{n}", T("point", n=n, k=k))
    motion_rows(
        b,
        n,
        of,
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
    text: Text
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
        b.calc(f"Qx_{k}", "N", T("Qx", k=k), fx)
        b.calc(f"Qy_{k}", "N", T("Qy", k=k), fy)
        b.calc(f"MQ_{k}", "N m", T("MQ", ref=ref), "+".join(mom + couples[k]) or "0")
        about_o = "+".join([f"{b.p('x', p)}*{y}-{b.p('y', p)}*{x}" for p, x, y in loads[k]] + couples[k]) or "0"
        b.check(f"chk_MQ_{k}", "", T("MQ_check", k=k),
                f"({about_o}-({{MQ_{k}}}+{b.p('x', ref)}*{{Qy_{k}}}-{b.p('y', ref)}*{{Qx_{k}}}))"
                f"/(1+ABS({{Qx_{k}}})+ABS({{Qy_{k}}})+ABS({{MQ_{k}}}))")

    def opposite(self, link: int, at: str, tag: str, couple: bool = False):
        """Link `link` exerts the reaction `tag` at `at`: it takes the opposite force there
        (and, with `couple`, the opposite couple M_tag) when its own group is balanced."""
        self.loads[link].append((at, f"(-{{Rx_{tag}}})", f"(-{{Ry_{tag}}})"))
        if couple:
            self.couples[link].append(f"(-{{M_{tag}}})")

    def magnitude(self, tag: str, of: Text):
        """R_tag, the magnitude of the reaction `of` ("of link 2 on link 3 at B"), and its check."""
        self.b.accepted(f"R_{tag}", "N", T("R", of=of), f"SQRT({{Rx_{tag}}}^2+{{Ry_{tag}}}^2)")
        magnitude_check(self.b, f"chk_mag_R_{tag}", [(f"R_{tag}", f"Rx_{tag}", f"Ry_{tag}")], T("R_mag", tag=tag))

    def reaction(self, tag: str, rx: str, ry: str, of: Text):
        self.b.accepted(f"Rx_{tag}", "N", T("Rx", of=of), rx)
        self.b.accepted(f"Ry_{tag}", "N", T("Ry", of=of), ry)
        self.magnitude(tag, of)

    def cramer_reaction(self, i: int, tag: str, mat, rhs, det_unit: str, det_text: Text, of: Text):
        """The group's determinant, the reaction at J1 by Cramer's rule (lecture slide 20),
        the check putting it back into its two equations, and its magnitude."""
        b, det = self.b, f"Delta_R_g{i}"
        det_row(b, det, mat, det_unit, det_text)
        cramer_rows(b, mat, det, ((f"Rx_{tag}", "N", T("Rx_cramer", of=of)), (f"Ry_{tag}", "N", T("Ry_cramer", of=of))),
                    rhs, (f"chk_Rsys_g{i}", T("Rsys")))
        self.magnitude(tag, of)

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
        b.check(f"chk_eq_{k}", "", T("equilibrium", k=k), f"(ABS({fx})+ABS({fy})+ABS({mom}))/({size})")
