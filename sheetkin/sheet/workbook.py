"""The lecture's workbook (seed 003, steps 7-10) with live formulas, written with openpyxl.

Layout of the sheet, top to bottom (the lecture's "programming by rows"):
  rows 1-2  the student's name and group (their own cells D1, D2) and the scheme's title
            (E1); row 3 the summary of all checks; row 4 the headers (positions by i);
  the instruction block (what to fill, in which order, the legend of the statuses);
  given data: lengths, frame points, Fi0, Fi_t, Fi_tt, Delta_Fi (deg), branches, points'
            offsets, tolerances (locked: the sheet is protected without a password), then
            Delta_Fi_rad, Alfa_A, Betta_A (computed: the student's in an exercise);
  crank block ("angular characteristics of the crank"), hinge A;
  for each group its kinematic-constraint block: intermediate variables (P, Q, F ...),
            every solution branch, check rows that put each branch back into the
            original equations, the "accepted values" rows (contract names) that all
            later rows reference, then velocities and accelerations (Cramer's rule);
  driven joints and points, each followed by its check rows.
Columns: A the row's name (contract names on accepted rows), B the unit, C a
description, D the input value (input rows) or the row's check status (check rows: 0
pass, 1 fail), E... one column per crank position. Every computed cell is a formula
referring to the input block. Every word is in the book's language (ru, the default;
uk; en: sheetkin.groups.lang, sheetkin.sheet.texts).

Rows are built as records whose formulas name other rows ("{x_A}", "{L1}",
"{x_A@prev}"); they are compiled once into per-column templates, so a 360-column
workbook costs one str.format per cell.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import cast

from openpyxl import Workbook
from openpyxl.chart import Reference, ScatterChart, Series
from openpyxl.chart.data_source import NumFmt
from openpyxl.styles import Font, PatternFill, Protection
from openpyxl.utils import get_column_letter

from sheetkin.errors import InputError
from sheetkin.groups import kind_of
from sheetkin.groups.lang import LANGS, check_lang
from sheetkin.groups.lang import unit as say_unit
from sheetkin.groups.rows import (
    Builder,
    Row,
    RowKind,
    Text,
    Texts,
    carried_rows,
    distance_check,
    fd_checks,
    local_position_check,
    motion_rows,
    via_link_checks,
)
from sheetkin.kinematics.scene import Group, Point, Scene

from .cached import CachedWorkbook
from .checks import colour_check_row, status_formula, write_summary
from .dynamics import dynamics_inputs, energy_rows, kinetostatics_rows
from .texts import CHARTS, GUIDE, SHEET, TEXTS

T = Texts(TEXTS)

FIRST_COL = 5                      # column E: the first crank position
SCENE_SHEET = "scene"              # hidden sheet holding the scene's TOML text
ISSUED_LABELS = ("variant", "seal")  # scene sheet B1:B2, values in C1:C2 (sheetkin variants)
# scene!B4:C4 in every book (B3:C3 is the student an issued book is sealed to): the version
# that wrote it, so that a later version grades it by the rules it was issued with (issue 31)
VERSION_LABEL, VERSION_ROW = "sheetkin_version", len(ISSUED_LABELS) + 2
# Central differences only where the step allows: their error, h^2/6 of the third
# derivative, is within Tol_FD = 1% of a row's scale at 3 deg for every bundled mechanism,
# but not at 4-5 deg for the quick-return ones (slotted lever, shaper).
FD_MAX_STEP_DEG = 3.0
MARKERS = {"ru": "не собирается", "uk": "не збирається", "en": "cannot assemble"}
# Bounded work (docs/verification.md, "Caps"): a workbook is refused in one line past these.
# 3,000 rows hold a chain of 41 groups (about 72 rows a group, 20 a point); the cells cap
# keeps a book within a minute and 1 GB to build, evaluate and save (measured there).
WORKBOOK_MAX_ROWS = 3_000
WORKBOOK_MAX_CELLS = 500_000        # position cells: rows x positions
MAX_FORMULA_CHARS = 8_192           # Excel's limit on a formula's length
SHEET_TITLES = {"ru": ("Кинематика", "Графики"), "uk": ("Кінематика", "Графіки"), "en": ("Kinematics", "Charts")}

# the student's identity: books issued before 0.16 had these input rows (name, ru, en),
# the validator still reads them there; a book now has them in rows 1-2 (IDENTITY_CELLS)
IDENTITY_ROWS = (("student", "студент: фамилия, имя", "student: family name, first name"),
                 ("group", "учебная группа", "the student's group"))
# the lecture's step 7.1: the author of the work and the group in rows 1-2 (label in A,
# what it is in C, the student's own text in D, unlocked); the scheme's title in E1
IDENTITY_CELLS = {"student": (1, 4), "group": (2, 4)}
TITLE_CELL = "E1"
# one colour says "do not change", another "fill in" (the student's guide names them):
# yellow, the given data (locked); lilac, every cell the student fills (D1, D2, the
# derived values of column D and, in an exercise, the computed rows' empty cells);
# blue, the names of the accepted values, in the exercise as in the key
INPUT_FILL = PatternFill("solid", fgColor="FFF2CC")
ACCEPTED_FILL = PatternFill("solid", fgColor="DDEBF7")
TO_FILL = PatternFill("solid", fgColor="E4DFEC")
SECTION_FONT = Font(bold=True)
GUIDE_FONT = Font(italic=True, color="404040")
UNLOCKED = Protection(locked=False)


class WorkbookTooLarge(InputError):
    """A scene whose workbook would pass the caps above; str() is one line."""


def _check_rows(b: Builder, what: str) -> None:
    # checked as the rows grow, so that a scene of 20,000 points is refused in a moment
    # (its 400,000 rows would take minutes to build)
    if len(b.rows) > WORKBOOK_MAX_ROWS:
        raise WorkbookTooLarge(f"the workbook would have more than {WORKBOOK_MAX_ROWS:,} rows (the cap; "
                               f"passed at {what}): a workbook holds about 40 groups or 140 points; "
                               "`sheetkin compute` takes the whole scene")


# --------------------------------------------------------------------------- the rows
def sheet_rows(scene: Scene) -> Builder:
    """The kinematics sheet's rows, top to bottom (see the module's docstring)."""
    b = Builder(scene)
    c = scene.crank
    for k in range(len(GUIDE["ru"])):             # what to fill and how to read the checks
        b.section(f"guide_{k + 1}", Text(*(GUIDE[lang][k] for lang in LANGS)))
    b.section("input", T("input"))
    b.given("L1", "m", T("L1", O=c.pivot, A=c.joint), c.length)
    for g in scene.groups:
        for r in kind_of(g).input_rows(g):
            if r.early:
                b.given(r.name, r.unit, r.text, r.value)
    for name, (x, y) in scene.frame.items():
        b.given(f"x_{name}", "m", T("x_frame", name=name), x)
        b.given(f"y_{name}", "m", T("y_frame", name=name), y)
    for g in scene.groups:
        for r in kind_of(g).input_rows(g):
            if not r.early:
                b.given(r.name, r.unit, r.text, r.value)
    for p in scene.points:
        b.given(f"along_{p.name}", "m", T("along", P=p.name, k=p.link, origin=p.origin), p.along)
        b.given(f"across_{p.name}", "m", T("across", P=p.name, k=p.link), p.across)
    b.given("Fi0", "deg", T("Fi0"), c.phi0_deg)
    b.given("Fi_t0", "rad/s", T("Fi_t0"), c.omega)
    b.given("Fi_tt0", "rad/s^2", T("Fi_tt0"), c.epsilon)
    b.given("Delta_Fi", "deg", T("Delta_Fi"), c.step_deg)
    if scene.has_dynamics:
        dynamics_inputs(b)
    b.given("Tol", "", T("Tol"), 1e-9)
    b.given("Tol_FD", "", T("Tol_FD", step=f"{FD_MAX_STEP_DEG:g}"), 0.01)
    # computed from the given data in column D: the student's first formulas (an exercise
    # leaves them blank, lilac), apart from the given data they must not change
    b.section("derived", T("derived"))
    b.derived("Delta_Fi_rad", "rad", T("Delta_Fi_rad"), "RADIANS({Delta_Fi})")
    b.derived("Alfa_A", "m", T("Alfa_A", A=c.joint, O=c.pivot), "{L1}*COS(RADIANS({Fi0}))")
    b.derived("Betta_A", "m", T("Betta_A", A=c.joint, O=c.pivot), "{L1}*SIN(RADIANS({Fi0}))")

    # the joints each link carries: a [[point]]'s velocity is checked through a second one
    b.on_link[1] = [scene.crank.pivot, scene.crank.joint]
    for g in scene.groups:
        for k, joints in kind_of(g).carries(g).items():
            b.on_link.setdefault(k, []).extend(j for j in joints if j not in b.on_link.get(k, []))
    _check_rows(b, "the input block")
    _crank_rows(b)
    for kind, item in scene.plan:
        if kind == "group":
            kind_of(item).rows(b, cast(Group, item))
            _check_rows(b, f"group {cast(Group, item).index}")
        elif kind == "point":
            _point_rows(b, cast(Point, item))
            _check_rows(b, f"point {cast(Point, item).name}")
    if scene.has_dynamics:
        energy_rows(b)
        kinetostatics_rows(b)
        _check_rows(b, "the dynamics")
    return b


def _crank_rows(b: Builder):
    c = b.scene.crank
    A, O = c.joint, c.pivot
    b.section("crank", T("crank"))
    b.index("i", T("i"))
    b.accepted("phi_1", "deg", T("phi_1"), "{Fi0}+{i}*{Delta_Fi}")
    b.calc("Fi", "rad", T("Fi"), "RADIANS({phi_1})")
    b.calc("dFi", "rad", T("dFi"), "{Fi}-RADIANS({Fi0})")
    b.calc("Fi_t", "rad/s", T("Fi_t"), "{Fi_t0}")
    b.calc("Fi_tt", "rad/s^2", T("Fi_tt"), "{Fi_tt0}")
    b.calc("cos_1", "", T("cos_1"), "COS({Fi})")
    b.calc("sin_1", "", T("sin_1"), "SIN({Fi})")
    # modulo a full turn, as angles are compared: Fi taken MOD 2*PI() passes too
    b.check("chk_Fi", "rad", T("chk_Fi"), "MOD({Fi}-(RADIANS({Fi0})+{i}*{Delta_Fi_rad})+PI(),2*PI())-PI()")
    b.rot[1] = ("cos_1", "sin_1", "Fi_t", "Fi_tt")
    b.section(f"hinge_{A}", T("hinge", A=A))
    rx, ry = f"({{x_{A}}}-{{x_{O}}})", f"({{y_{A}}}-{{y_{O}}})"
    motion_rows(b, A, T("of_hinge", A=A),
                 f"{{x_{O}}}+{{Alfa_A}}*COS({{dFi}})-{{Betta_A}}*SIN({{dFi}})",
                 f"{{y_{O}}}+{{Alfa_A}}*SIN({{dFi}})+{{Betta_A}}*COS({{dFi}})",
                 f"-{{Fi_t}}*{ry}", f"{{Fi_t}}*{rx}",
                 f"-{{Fi_tt}}*{ry}-{{Fi_t}}*{{vy_{A}}}", f"{{Fi_tt}}*{rx}+{{Fi_t}}*{{vx_{A}}}")
    distance_check(b, f"chk_{O}{A}", O, A, "{L1}", T("chk_OA", O=O, A=A))
    b.check(f"chk_v_{A}", "m^2/s", T("chk_v", A=A, O=O), f"{{vx_{A}}}*{rx}+{{vy_{A}}}*{ry}")
    # the crank in the other form of slide 6, x = L1 cos Fi, and its derivatives: each of
    # the hinge's rows against a formula that does not use it (free of the step)
    L, c1, s1 = "{L1}", "{cos_1}", "{sin_1}"
    b.check(f"chk_pos_{A}", "m", T("chk_pos", A=A, O=O),
            f"ABS({{x_{A}}}-{{x_{O}}}-{L}*{c1})+ABS({{y_{A}}}-{{y_{O}}}-{L}*{s1})")
    b.check(f"chk_vel_{A}", "m/s", T("chk_vel", A=A),
            f"ABS({{vx_{A}}}+{L}*{{Fi_t}}*{s1})+ABS({{vy_{A}}}-{L}*{{Fi_t}}*{c1})")
    b.check(f"chk_acc_{A}", "m/s^2", T("chk_acc", A=A),
            f"ABS({{ax_{A}}}+{L}*({{Fi_tt}}*{s1}+{{Fi_t}}^2*{c1}))+ABS({{ay_{A}}}-{L}*({{Fi_tt}}*{c1}-{{Fi_t}}^2*{s1}))")
    fd_checks(b, A)


def _point_rows(b: Builder, p: Point):
    saved, b.guard = b.guard, b.guard_of_link.get(p.link)
    carried_rows(b, p.name, p.link, p.origin, f"{{along_{p.name}}}", f"{{across_{p.name}}}",
                  T("of_point", P=p.name))
    distance_check(b, f"chk_{p.origin}{p.name}", p.origin, p.name,
                    f"SQRT({{along_{p.name}}}^2+{{across_{p.name}}}^2)",
                    T("chk_kept", origin=p.origin, P=p.name))
    local_position_check(b, p.name, p.link, p.origin, f"{{along_{p.name}}}", f"{{across_{p.name}}}")
    # the velocity and acceleration once more through another joint of the link (the rows
    # above go through `from`); a link with one joint only: through `from`, from its rows
    others = [j for j in b.on_link.get(p.link, []) if j not in (p.origin, p.name)]
    j = others[0] if others else p.origin
    via_link_checks(b, p.name, j, p.link, f"{j}, omega_{p.link}, eps_{p.link}")
    b.on_link.setdefault(p.link, []).append(p.name)
    fd_checks(b, p.name)
    b.guard = saved


# --------------------------------------------------------------------------- writing
_REF = re.compile(r"\{(scale:)?([^{}@:]+)(?:@(prev|next))?\}")
_VARIANT = re.compile(r" \(variant ([^()]+)\)$")
_EXERCISE_KEEP = {"i", "phi_1"}
# the header row's texts in every language, by column (name, unit, desc, value): the
# validator finds a student's columns by them (sheetkin/course/layout.py)
HEADERS = {key: frozenset(t[key] for t in SHEET.values()) for key in ("name", "unit", "desc", "value")}


def prefilled_in_exercise(name: str, kind: str) -> bool:
    """Rows an exercise workbook gives filled in: the position's number and crank angle, and
    the rows that are not computed values (guards: does the group assemble?). They are the
    exercise's, not the student's work, so grades leave them out (sheetkin/course/grades.py). The
    derived values of column D (Alfa_A ...) are left blank in an exercise: graded."""
    return kind == "guard" or name in _EXERCISE_KEEP


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
        return "{" + {"prev": "p", "next": "n"}.get(shift, "c") + "}" + str(r)

    templates = {}
    for r in rows:
        if r.formula:
            templates[r.name] = "=" + _REF.sub(ref, r.formula)
            # the longest a cell's formula gets: {c} {p} {n} become up to 3 letters, and the
            # guard and numeric-derivative wrappers add less than 200 characters
            longest = len(templates[r.name]) - 1 + templates[r.name].count("{") + 200
            if longest > MAX_FORMULA_CHARS:
                raise WorkbookTooLarge(f"row {r.name!r}: its formula would pass Excel's {MAX_FORMULA_CHARS:,} "
                                       "characters (too many masses or forces for one workbook)")
    return where, templates


def build_workbook(scene: Scene, *, lang: str = "ru", exercise: bool = False,
                   scene_text: str | None = None, charts: bool = True,
                   issued: tuple[str, str] | None = None) -> Workbook:
    """The lecture's workbook for `scene` (see the module's docstring); charts=False leaves
    out the charts sheet (and its hidden paths sheet): the validator's reference needs only
    the kinematics sheet. issued = (variant id, seal): a variant made by `sheetkin
    variants`, recorded beside the embedded scene (sheetkin/course/issued.py reads them back)."""
    text = SHEET[check_lang(lang)]
    b = sheet_rows(scene)
    rows = b.rows
    n = scene.crank.positions
    last_col = get_column_letter(FIRST_COL + n - 1)
    first_row = 5
    if len(rows) * n > WORKBOOK_MAX_CELLS:
        raise WorkbookTooLarge(f"{len(rows):,} rows x {n:,} positions would pass the workbook's cap of "
                               f"{WORKBOOK_MAX_CELLS:,} cells; use at most {WORKBOOK_MAX_CELLS // len(rows):,} "
                               "positions (`sheetkin compute` takes more)")
    where, templates = _compile(rows, first_row, last_col)
    marker = MARKERS[lang]
    kinds = {r.name: r.kind for r in rows}
    cols = [get_column_letter(FIRST_COL + k) for k in range(n)]

    wb = CachedWorkbook()        # saved with every formula's value (sheetkin/sheet/cached.py)
    ws = wb.active
    ws.title = SHEET_TITLES[lang][0]
    _head_rows(ws, scene, lang)
    ws["A3"] = text["checks"]
    ws["A3"].font = SECTION_FONT
    for col, key in zip("ABCD", ("name", "unit", "desc", "value"), strict=False):
        ws[f"{col}4"] = text[key]
        ws[f"{col}4"].font = SECTION_FONT
    for k, c in enumerate(cols):
        ws[f"{c}4"] = k                     # the position's number: the row i's, from 0
        ws[f"{c}4"].font = SECTION_FONT
    book = _Layout(where, templates, cols, kinds, text, marker, lang, exercise)
    status_cells = [cell for row in rows if (cell := _write_row(ws, row, book))]
    last_row = first_row + len(rows) - 1
    first_status = min((where[r.name] for r in rows if r.kind in ("check", "fdcheck")), default=last_row)
    # the summary counts the statuses by range: no input or derived value may sit in it
    if any(where[r.name] >= first_status for r in rows if r.kind in ("input", "derived")):
        raise RuntimeError("workbook layout: an input row below the first check row")
    write_summary(ws, lang, status_cells, f"D{first_status}:D{last_row}")
    ws.freeze_panes = f"{cols[0]}5"
    _protect(ws)
    from .printing import setup_page  # widths, alignment, pages (sheetkin/sheet/printing.py)
    setup_page(ws, rows, where, cols, FIRST_COL)
    if charts:
        from .charts import SheetRows
        _add_charts(wb, ws, scene, where, cols, lang,
                    SheetRows(ws, rows, where, templates, cols, marker, lang, exercise))
    _embed_scene(wb, scene, scene_text, issued)
    return wb


@dataclass
class _Layout:
    """Where build_workbook writes: each row's number, its formula template, the position
    columns, each row's kind, the sheet's texts and marker, its language, an exercise or not."""
    where: dict[str, int]
    templates: dict[str, str]
    cols: list[str]
    kinds: dict[str, RowKind]
    text: dict[str, str]
    marker: str
    lang: str
    exercise: bool


def _write_row(ws, row, book: _Layout) -> str | None:
    """One row of the kinematics sheet in the lecture's columns (name, unit, description,
    value, then a cell per position); returns its status cell for a check row."""
    r, lang, n = book.where[row.name], book.lang, len(book.cols)
    if row.kind == "section":
        guide = row.name.startswith("guide_")
        ws.cell(r, 1, row.say(lang)).font = SECTION_FONT if not guide or row.name == "guide_1" else GUIDE_FONT
        return None
    ws.cell(r, 1, row.name)
    ws.cell(r, 2, say_unit(row.unit, lang))
    ws.cell(r, 3, row.say(lang))
    if row.kind == "input":
        ws.cell(r, 4, row.value).fill = INPUT_FILL
        return None
    if row.kind == "derived":
        if not book.exercise:
            ws.cell(r, 4, book.templates[row.name])
        else:
            ws.cell(r, 4).fill = TO_FILL
        ws.cell(r, 4).protection = UNLOCKED
        return None
    if row.kind == "index":
        for k in range(n):
            ws.cell(r, FIRST_COL + k, k)
        return None
    if row.kind == "accepted":
        ws.cell(r, 1).fill = ACCEPTED_FILL
    if row.kind in ("calc", "accepted") and row.name not in _EXERCISE_KEEP:
        for k in range(n):              # the student's cells: open under the sheet's protection
            ws.cell(r, FIRST_COL + k).protection = UNLOCKED
            if book.exercise:
                ws.cell(r, FIRST_COL + k).fill = TO_FILL
        if book.exercise:
            return None
    _position_cells(ws, row, r, book)
    if row.kind in ("check", "fdcheck"):
        return _check_status(ws, row, r, book)
    return None


def _position_cells(ws, row, r: int, book: _Layout) -> None:
    """The row's formula at every position: guarded where its group may not assemble, and
    a numeric derivative only where the step allows and the crank turns."""
    where, cols, n, text = book.where, book.cols, len(book.cols), book.text
    tpl = book.templates[row.name]
    fd = "{p}" in tpl or "{n}" in tpl
    if fd:
        # central differences: only where the step allows and the crank turns
        tpl = (f'=IF(OR(ABS($D${where["Delta_Fi"]})>{FD_MAX_STEP_DEG:g},$D${where["Fi_t0"]}=0),'
               f'"{text["na"]}",{tpl[1:]})')
    if row.guard:
        tpl = f'=IF({{c}}{where[row.guard]},{tpl[1:]},"{book.marker}")'
    fmt = {"check": "0.0E+00", "fdcheck": "0.0E+00", "guard": "General"}.get(row.kind, "0.000000")
    for k, c in enumerate(cols):
        if fd and (k == 0 or k == n - 1):
            ws.cell(r, FIRST_COL + k, text["na"])
            continue
        p = cols[k - 1] if k else c
        nx = cols[k + 1] if k + 1 < n else c
        ws.cell(r, FIRST_COL + k, tpl.format(c=c, p=p, n=nx)).number_format = fmt


def _check_status(ws, row, r: int, book: _Layout) -> str:
    """A check row's status (column D) and its colours; returns the status cell."""
    where, cols, n = book.where, book.cols, len(book.cols)
    fd_range = f"{cols[0]}{{r}}:{cols[-1]}{{r}}"
    rng = fd_range.format(r=r)
    tol = f"$D${where['Tol_FD' if row.kind == 'fdcheck' else 'Tol']}"
    expected = None
    if row.kind == "check":
        expected = (f"SUMPRODUCT(--({cols[0]}{where[row.guard]}:{cols[-1]}{where[row.guard]}))"
                    if row.guard else str(n))
    reads = sorted({where[m.group(2)] for m in _REF.finditer(row.formula)
                    if book.kinds[m.group(2)] in ("calc", "accepted")})
    ws.cell(r, 4, status_formula(book.lang, rng, tol, [fd_range.format(r=k) for k in reads], expected))
    colour_check_row(ws, rng, f"{cols[0]}{r}", f"D{r}", tol, book.lang)
    return f"D{r}"


def _head_rows(ws, scene: Scene, lang: str) -> None:
    """Rows 1-2 (the lecture's step 7.1): the student's name and group, their cells in D
    (lilac: to fill in; unlocked, text), and the scheme's title in E1 ("variant" in the book's
    language). The scheme's author stays in the embedded scene."""
    text = SHEET[lang]
    for key, (r, c) in IDENTITY_CELLS.items():
        label, desc = text[key]
        ws.cell(r, 1, label).font = SECTION_FONT
        ws.cell(r, 3, desc)
        cell = ws.cell(r, c)
        cell.number_format = "@"            # text, whatever is typed (a group "101" stays "101")
        cell.fill, cell.protection = TO_FILL, UNLOCKED
    title = _VARIANT.sub(lambda m: f" ({text['variant']} {m.group(1)})", scene.title)
    _text_cell(ws[TITLE_CELL], title)
    ws[TITLE_CELL].font = Font(bold=True)       # 11 pt: it prints over the first page's 4-6 positions


def _protect(ws) -> None:
    """The given data are given: the sheet is protected without a password, so a slip cannot
    change them (the seal still catches a deliberate edit, sheetkin/course/issued.py); the
    student's cells are unlocked. Column widths and row heights stay free."""
    p = ws.protection
    p.sheet = True
    p.formatColumns = p.formatRows = p.formatCells = False      # False: allowed
    p.selectLockedCells = p.selectUnlockedCells = False


def _add_charts(wb, ws, scene: Scene, where, cols, lang, rows_info):
    """The mechanism at a chosen position and the trajectories, to scale
    (sheetkin/sheet/charts.py); speeds and accelerations against the crank angle,
    angular velocities of the links."""
    from .charts import add_drawing_charts, add_plotted_sheet
    cs = wb.create_sheet(SHEET_TITLES[lang][1])
    cs.page_setup.orientation = "landscape"
    cs.sheet_properties.pageSetUpPr.fitToPage = True
    first, last = FIRST_COL, FIRST_COL + len(cols) - 1
    points = scene.moving_joints + [p.name for p in scene.points]
    t = CHARTS[lang]
    specs = [
        (t["speeds"], t["phi"], t["v"], [("phi_1", f"v_{p}", f"v_{p}") for p in points]),
        (t["accs"], t["phi"], t["a"], [("phi_1", f"a_{p}", f"a_{p}") for p in points]),
        (t["omegas"], t["phi"], t["w"], [("phi_1", f"omega_{k}", f"omega_{k}") for k in scene.links]),
    ]
    if scene.has_dynamics:
        from sheetkin.kinematics.dynamics import reaction_pairs
        specs.append((t["power"], t["phi"], t["pw"],
                      [("phi_1", n, n) for n in ("M_bal", "P_bal", "P_ext", "T_t") if n in where]))
        specs.append((t["reactions"], t["phi"], t["r"],
                      [("phi_1", f"R_{p.tag}", f"R_{p.tag}") for p in reaction_pairs(scene)]))
    # the charts read the hidden sheet `plotted`: numbers or #N/A, never text (charts.py)
    data = add_plotted_sheet(wb, rows_info, [n for *_, ser in specs for x, y, _ in ser for n in (x, y)]
                             + [f"{q}_{p}" for p in points for q in "xy"])

    def row_ref(name: str) -> Reference:
        return Reference(data, min_col=first, max_col=last, min_row=where[name], max_row=where[name])
    top = add_drawing_charts(wb, cs, scene, rows_info)
    for k, (title, xt, yt, series) in enumerate(specs):
        ch = ScatterChart()
        ch.scatterStyle = "lineMarker"   # required by the schema; each series sets its own lines and markers
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


def _text_cell(cell, text: str) -> None:
    """Text from the scene (title, author) is written as text: openpyxl would store a
    string starting with "=" as a formula, and "+", "-", "@" are formulas to a spreadsheet
    program that retypes the cell (formula injection). A string cell keeps it text."""
    cell.value = text
    cell.data_type = "s"


def _embed_scene(wb, scene: Scene, scene_text: str | None, issued: tuple[str, str] | None = None):
    """The scene travels inside the workbook (a hidden sheet), so the file alone is enough
    to evaluate and validate it later. An issued variant's id and seal go in C1, C2
    (labels in B1, B2), beside the scene's lines in column A."""
    if scene_text is None:
        try:
            scene_text = Path(scene.source).read_text(encoding="utf-8-sig")
        except OSError:
            raise ValueError("the scene's text is needed to embed it; pass scene_text") from None
    ws = wb.create_sheet(SCENE_SHEET)
    ws.sheet_state = "hidden"
    for k, line in enumerate(scene_text.splitlines(), 1):
        ws.cell(k, 1, line if line else None).data_type = "s"
    if issued:
        for r, (label, value) in enumerate(zip(ISSUED_LABELS, issued, strict=False), 1):
            _text_cell(ws.cell(r, 2), label)
            _text_cell(ws.cell(r, 3), value)
    from sheetkin import __version__
    _text_cell(ws.cell(VERSION_ROW, 2), VERSION_LABEL)
    _text_cell(ws.cell(VERSION_ROW, 3), __version__)
    wb.properties.subject = f"sheetkin workbook; the scene is in the hidden sheet '{SCENE_SHEET}'"


def embedded_scene_text(sheet) -> str:
    """The scene's TOML text as the hidden sheet SCENE_SHEET holds it, one line a row in
    column A; `sheet` is that sheet as the spreadsheet engine reads it (sheetkin.xlsx:
    read_book(path).sheets[SCENE_SHEET], or an evaluated Book's)."""
    lines = [sheet.consts.get((r, 1), "") for r in range(1, sheet.max_row + 1)]
    return "\n".join(str(x) for x in lines) + "\n"


def write_workbook(scene: Scene, path, *, lang: str = "ru", exercise: bool = False,
                   scene_text: str | None = None) -> None:
    build_workbook(scene, lang=lang, exercise=exercise, scene_text=scene_text).save(path)


def existing_fingerprint(path) -> dict:
    """What a workbook on disk says (every sheet's state, constants and formulas as written,
    its charts' data references), read by the reader `validate` uses, through the same gate
    and limits (sheetkin.xlsx.cells.read_book): `workbook --check` may meet any file under
    that name (openpyxl took 2.66 GB and 101 s on a 41 MB one)."""
    from sheetkin.xlsx.cells import read_book
    from sheetkin.xlsx.package import open_package
    raw = read_book(path)
    out: dict = {name: (sh.state, sh.consts, sh.formulas) for name, sh in raw.sheets.items()}
    if SCENE_SHEET in raw.sheets:
        # the version that wrote it is no content: a release alone does not make a book stale
        sh = raw.sheets[SCENE_SHEET]
        out[SCENE_SHEET] = (sh.state, {k: v for k, v in sh.consts.items() if k[0] != VERSION_ROW or k[1] == 1},
                            sh.formulas)
    pkg = open_package(path)
    charts = sorted(n for n in pkg.names if n.startswith("xl/charts/chart"))
    out["charts"] = [re.findall(r"<(?:c:)?f>([^<]*)</(?:c:)?f>", pkg.read(n).decode("utf-8", "replace"))
                     for n in charts]
    return out


def built_fingerprint(wb) -> dict:
    """existing_fingerprint() of an openpyxl workbook as it would be saved: `workbook
    --check` compares the two to tell a stale committed workbook."""
    import tempfile
    with tempfile.TemporaryDirectory(prefix="sheetkin-check-") as tmp:
        path = Path(tmp) / "built.xlsx"
        # formulas as written: the cached values (CachedWorkbook.save evaluates them) are not compared
        Workbook.save(wb, path)
        return existing_fingerprint(path)
