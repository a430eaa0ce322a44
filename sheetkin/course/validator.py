"""The validator of student workbooks: which rows are right, which are wrong, and why.

For one workbook:
1. open it safely (xlsxsafe) and read the scene embedded in its hidden sheet;
2. take the student's input block (column D of the input rows) as their variant: the
   scene with those lengths, coordinates, branches, Fi0, Fi_t, Fi_tt, Delta_Fi, and as many
   positions as the sheet has columns;
3. the reference for every named row: the workbook sheetkin generates for that variant,
   evaluated by the evaluator (its accepted values equal the solver, tested); so the
   intermediate rows (P, Q, F, ...) have references too;
4. the student's values: their formulas evaluated by the evaluator; where a cell has no
   formula, the number typed (checked to the precision it was typed with); where a formula
   cannot be evaluated, the value the spreadsheet cached; a formula that does not reach the
   given data through formulas (sheetkin.xlsx.precedents: it reads only typed numbers, such
   as values pasted on a scratch sheet) is typed, as the numbers it reads are;
5. row by row: correct / wrong (largest error, first wrong column) / missing / empty; each
   row is also judged on the student's own values of what it reads (sheetkin.course.localjudge):
   the likely causes are the rows wrong on their own inputs and the rounded typed numbers
   a wrong row below depends on; the others are wrong because they depend on a cause (in
   the lecture's dependency order). Cells whose formula disagrees with the value the
   spreadsheet cached are listed too.
"""
from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Set
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import numpy as np

from sheetkin.groups import kind_of
from sheetkin.groups.group import Group
from sheetkin.kinematics.scene import Point, Scene, SceneError, parse_scene
from sheetkin.sheet.charts import PATHS_SHEET, PLOTTED_SHEET
from sheetkin.sheet.checks import STATUS as CHECK_STATUS
from sheetkin.sheet.checks import failing as check_fails
from sheetkin.sheet.checks import not_applicable as check_na
from sheetkin.sheet.checks import passing as check_passes
from sheetkin.sheet.workbook import (
    FIRST_COL,
    SCENE_SHEET,
    SHEET_TITLES,
    build_workbook,
    prefilled_in_exercise,
    sheet_rows,
)
from sheetkin.xlsx.cells import Sheet, read_book
from sheetkin.xlsx.evaluator import Book, EvaluationError, evaluate_sheets
from sheetkin.xlsx.functions import XlError
from sheetkin.xlsx.package import Limits, UnusableWorkbook
from sheetkin.xlsx.parse import ParseError, functions_of, names_of, parse_formula, refs_of
from sheetkin.xlsx.precedents import POSITIONAL, reaching

from . import issued
from .copies import submission_marks  # the raw cells copy detection compares
from .layout import Layout, find_layout, standard_view, without_unread
from .localjudge import TURN, angle_difference, judge, name_causes
from .localjudge import typed_tolerance as _typed_tolerance

RTOL = 1e-9            # formulas: the same numbers up to rounding
ATOL = 1e-9


# Caps on the scene embedded in a book, for validation (docs/reliability.md): the course's
# scenes have 1-3 groups and 0-3 points; a reference of rows x positions cells is built
# and evaluated for each variant, so these bound a book's work whatever its scene sheet says.
MAX_EMBEDDED_GROUPS = 12
MAX_EMBEDDED_POINTS = 40
MAX_REFERENCE_CELLS = 1_000_000


def check_embedded_size(scene_text: str, path: str) -> None:
    """Count the tables before parsing (a 400-group scene sheet took minutes to read)."""
    heads = re.findall(r"(?m)^\s*\[\[\s*(group|point)\s*\]\]", scene_text)
    for kind, cap in (("group", MAX_EMBEDDED_GROUPS), ("point", MAX_EMBEDDED_POINTS)):
        n = heads.count(kind)
        if n > cap:
            raise UnusableInput(f"{path}: the embedded scene has {n} [[{kind}]] tables; a book "
                                f"sheetkin validates may have at most {cap}")


def check_embedded_scene(scene: Scene, path: str) -> None:
    rows = len(sheet_rows(scene).rows)
    cells = rows * scene.crank.positions
    if cells > MAX_REFERENCE_CELLS:
        raise UnusableInput(f"{path}: the embedded scene needs a reference of {rows:,} rows x "
                            f"{scene.crank.positions:,} positions = {cells:,} cells; sheetkin validates "
                            f"books of at most {MAX_REFERENCE_CELLS:,}")


class UnusableInput(ValueError):
    """A workbook that cannot be validated at all; str() is one line naming the file."""


@dataclass
class RowReport:
    name: str
    row: int | None                  # the student's row number
    status: str                      # correct | wrong | missing | empty
    max_error: float = 0.0
    first_wrong: int | None = None   # position number (1-based) of the first wrong cell
    wrong_cells: list[int] = field(default_factory=list)   # position numbers
    expected: object = None          # at the first wrong cell
    got: object = None
    cause: bool = False              # wrong, and no ancestor is wrong
    because_of: list[str] = field(default_factory=list)    # the causes it depends on
    kind: str = ""                   # accepted | calc | guard (the reference's kind of row)
    source: str = "formula"          # formula | typed | cached
    local: str = ""                  # right | wrong | "" (not judged): on the student's own inputs
    note: str = ""                   # for a cause: one line why (a typed number: cell, digits, error below)
    # issue 21: positions (1-based) where the row holds a typed value, no formula: a computed
    # row earns credit only where it computes (sheetkin/course/grades.py)
    typed_cells: list[int] = field(default_factory=list)
    formula_cells: int = 0           # cells holding a formula (their own, or an array's)
    # positions (1-based, among typed_cells) whose formula reads only typed numbers: none of
    # the given data, through any formulas (a number pasted elsewhere, then "=Лист2!E5")
    reads_typed: list[int] = field(default_factory=list)

    @property
    def is_typed(self) -> bool:
        """A typed value where a formula belongs: at some position, or (a derived row) its
        value in column D."""
        return bool(self.typed_cells) or (self.kind == "derived" and self.source == "typed")


class _UsableBookParts:
    """What validate sets on the report of a usable book only: not fields (not in to_dict,
    and a plain base class, so no dataclass field), absent on a report that stopped early
    (readers getattr them with a default). Declared here for the types only."""
    layout: Layout                   # the student's cells (report texts)
    roster_differs: bool             # one warning for the class (cli)
    lang: str                        # the reports' default language
    variant_scene: Scene             # the report's picture
    marks: dict                      # the raw cells copy detection compares (copies.py)
    checks_total: int                # check rows in the sheet
    checks_apply: int                # issued check rows with a number somewhere
    checks_passing: int
    checks_na: int
    checks_unfilled: int


@dataclass
class Report(_UsableBookParts):
    path: str
    author: str = ""
    title: str = ""
    rows: list[RowReport] = field(default_factory=list)
    cache_mismatch: list[str] = field(default_factory=list)   # cells: formula != cached value
    failing_checks: list[str] = field(default_factory=list)   # the student's check rows that fail
    problems: list[str] = field(default_factory=list)         # unsupported functions ...
    positions: int = 0
    error: str | None = None         # unusable input: the one-line reason
    # (i, phi_1) of each position column, as the sheet's rows i and phi_1 name it (the
    # reference for the student's variant); the reports name positions this way
    position_names: list[tuple[float, float]] = field(default_factory=list)
    # issue 13: who filled it in (their own input rows; A2 is the scheme's author), the
    # issued variant, the given data the student changed, the scene sheet's seal (issued.py)
    student: str = ""
    group: str = ""
    variant: str = ""
    given_changed: list[dict] = field(default_factory=list)
    seal: str = ""                   # "" not checked | "ok" | why it fails
    accepted_changes: bool = False   # --accept-changed-inputs: graded on the student's inputs
    accepted_typed: bool = False     # --accept-typed: typed numbers right to their digits earn credit
    # issue 21: the issued check rows deleted from the sheet, and those whose status (column
    # D) is typed over its formula: they lose their share of the grade
    checks_deleted: list[str] = field(default_factory=list)
    checks_typed: list[str] = field(default_factory=list)
    checks_issued: int = 0
    issued_to: str = ""              # the identifier sealed in it by `variants --class-list`
    notes: list[str] = field(default_factory=list)

    @property
    def wrong(self) -> list[RowReport]:
        return [r for r in self.rows if r.status == "wrong"]

    @property
    def missing(self) -> list[RowReport]:
        return [r for r in self.rows if r.status in ("missing", "empty")]

    @property
    def causes(self) -> list[RowReport]:
        return [r for r in self.rows if r.cause]

    @property
    def reason(self) -> str:
        """The unusable file's reason without its leading "path: " (the tables name the
        file in a column of their own); "" for a usable file."""
        if not self.error:
            return ""
        return self.error[len(self.path) + 2:] if self.error.startswith(self.path + ": ") else self.error

    @property
    def typed(self) -> list[RowReport]:
        """Rows holding typed values where formulas belong ("typed, not computed")."""
        return [r for r in self.rows if r.is_typed and r.status not in ("missing", "empty")]

    @property
    def ok(self) -> bool:
        """"all correct": full marks (sheetkin/course/grades.py, the one rule every report uses)."""
        from .grades import verdict
        return verdict(self) == "all correct"

    def to_dict(self) -> dict:
        from .grades import counts, explain, score, verdict
        d = dataclasses.asdict(self)
        d["ok"] = self.ok
        d["verdict"] = verdict(self)
        d["score"] = None if self.error else score(self)
        d["score_explained"] = explain(self)
        d["summary"] = {**counts(self), "causes": [r.name for r in self.causes]}
        return d


# --------------------------------------------------------------------------- the variant
def _inputs(book: Book, sheet: str, names: dict[str, int]) -> dict[str, object]:
    return {n: book.value(sheet, r, 4) for n, r in names.items()}


def variant_scene(scene: Scene, inputs: dict[str, object], positions: int, where: dict[str, str]) -> Scene:
    """The scene with the student's input block: raises UnusableInput on a non-number."""
    def num(name, default, choices=None):
        if name not in inputs:
            return default
        v = inputs[name]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise UnusableInput(f"input {name} ({where.get(name, '?')}): expected a number, got {v!r}")
        if choices is not None and v not in choices:
            raise UnusableInput(f"input {name} ({where.get(name, '?')}): expected "
                                f"{' or '.join(f'{c:+g}' for c in choices)}, got {v:g}")
        return float(v)

    c = scene.crank
    crank = dataclasses.replace(c, length=num("L1", c.length), phi0_deg=num("Fi0", c.phi0_deg),
                                step_deg=num("Delta_Fi", c.step_deg), positions=positions,
                                omega=num("Fi_t0", c.omega), epsilon=num("Fi_tt0", c.epsilon))
    frame = {p: (num(f"x_{p}", x), num(f"y_{p}", y)) for p, (x, y) in scene.frame.items()}
    groups = [kind_of(g).with_inputs(g, num) for g in scene.groups]
    points = tuple(dataclasses.replace(p, along=num(f"along_{p.name}", p.along),
                                       across=num(f"across_{p.name}", p.across)) for p in scene.points)
    by_index, by_name = {g.index: g for g in groups}, {p.name: p for p in points}
    # scene.plan pairs each kind with its item: ("group", Group), ("point", Point)
    plan = tuple((k, crank if k == "crank" else by_index[cast(Group, it).index] if k == "group"
                  else by_name[cast(Point, it).name]) for k, it in scene.plan)
    gravity = (num("g_x", scene.gravity[0]), num("g_y", scene.gravity[1]))
    masses = tuple(dataclasses.replace(m, mass=num(f"m_{m.link}", m.mass), inertia=num(f"J_{m.link}", m.inertia))
                   for m in scene.masses)
    forces = []
    for f in scene.forces:
        n = f.name
        interval = f.interval_deg and (num(f"from_{n}", f.interval_deg[0]), num(f"to_{n}", f.interval_deg[1]))
        forces.append(dataclasses.replace(f, force=(num(f"Fx_{n}", f.force[0]), num(f"Fy_{n}", f.force[1])),
                                          moment=num(f"Mz_{n}", f.moment), interval_deg=interval))
    return dataclasses.replace(scene, frame=frame, crank=crank, groups=tuple(groups), points=points, plan=plan,
                               gravity=gravity, masses=masses, forces=tuple(forces))


# --------------------------------------------------------------------------- dependencies
def row_ancestors(scene: Scene) -> dict[str, set[str]]:
    """For every row of the lecture's workbook, all rows it depends on (transitively)."""
    rows = sheet_rows(scene).rows
    ref = re.compile(r"\{(?:scale:)?([^{}@:]+)(?:@(?:prev|next))?\}")
    direct = {r.name: set(ref.findall(r.formula)) | ({r.guard} if r.guard else set()) for r in rows}
    out: dict[str, set[str]] = {}
    for r in rows:                                   # rows come after what they use
        acc = set()
        for d in direct[r.name]:
            acc |= {d} | out.get(d, set())
        out[r.name] = acc - {r.name}
    return out


def _close(got, exp, name: str, typed: bool, period: float | None = None):
    """(ok, error) of one cell against its reference."""
    if isinstance(exp, bool) or isinstance(got, bool):
        return (isinstance(got, bool) and isinstance(exp, bool) and got == exp), (0.0 if got == exp else 1.0)
    if not isinstance(exp, float):
        # the reference is a marker ("cannot assemble", "n/a") or an error: any non-number is fine
        return (not isinstance(got, float)), (0.0 if not isinstance(got, float) else math.inf)
    if not isinstance(got, float):
        return False, math.inf
    d = float(angle_difference(abs(got - exp), period))      # angles: modulo a full turn
    tol = max(ATOL, RTOL * abs(exp))
    if typed:
        tol = max(tol, _typed_tolerance(got))
    return d <= tol, d


# --------------------------------------------------------------------------- validation
def validate(path: str | Path, limits: Limits = Limits(), options: issued.Options | None = None) -> Report:
    """Validate one workbook; unusable input comes back as Report.error, not an exception.
    options: the roster, the teacher's key, --accept-changed-inputs (sheetkin/course/issued.py)."""
    path = str(path)
    try:
        return _validate(path, limits, options)
    except (UnusableWorkbook, UnusableInput, SceneError, EvaluationError) as e:
        msg = str(e)
        return Report(path, error=msg if msg.startswith(path) else f"{path}: {msg}")
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as e:     # RecursionError, MemoryError, a bug: this file's error only
        return Report(path, error=internal_error(path, e))


def internal_error(path: str, e: BaseException) -> str:
    """The one line for an unexpected exception while validating `path`: the batch goes
    on, and the teacher learns that this is sheetkin's fault, not the student's."""
    from sheetkin import __version__
    what = " ".join(str(e).split())[:200]
    return (f"{path}: internal error while validating ({type(e).__name__}{': ' + what if what else ''}); "
            f"this is a bug in sheetkin {__version__}: please report it with this file")


def _validate(path: str, limits: Limits, options: issued.Options | None = None) -> Report:
    book = read_book(path, limits, skip=frozenset({PATHS_SHEET}))    # never graded: not parsed
    from . import scratch  # hook (issue 33): a book built from scratch, graded by value
    if SCENE_SHEET not in book.sheets and scratch.applies(options):
        return scratch.grade_book(book, path, options)
    scene, scene_text = _embedded_scene(book, path, options)
    # the graded sheet and its columns, found by their content (sheetkin/course/layout.py);
    # graded through a view in the issued layout (names A, value D, positions from E)
    ref_rows = sheet_rows(scene).rows
    issued_positions = scene.crank.positions
    layout = find_layout(book.sheets, book.order, {r.name for r in ref_rows if r.kind != "section"}, "",
                         issued_positions, list(range(issued_positions)), {SCENE_SHEET, PATHS_SHEET})
    if layout is None:
        raise UnusableInput(f"{path}: no sheet holds the rows of the issued table (names such as "
                            f"{', '.join(r.name for r in ref_rows if r.kind == 'calc')[:60]}... in a column)")
    raw = _evaluate_student(book, layout)
    evaluated, sh = standard_view(raw, layout)
    names: dict[str, int] = {}
    for r in range(5, sh.max_row + 1):
        v = sh.consts.get((r, 1))
        if isinstance(v, str) and v and v not in names:
            names[v] = r
    g = _Graded(path, scene, ref_rows, layout, evaluated, sh, names)
    g.from_given = _from_given(raw, g, issued_positions)
    report = _new_report(g, book, scene_text, options)
    _grade_rows(report, g)
    _read_checks(report, evaluated, layout.sheet, sh, names, ref_rows, cast(Book, g.ref_book), g.ref_names)
    return scratch.own_table(book, path, options, report)   # hook (issue 33): the issued sheet empty


def _embedded_scene(book, path: str, options: issued.Options | None) -> tuple[Scene, str]:
    """The scene of the book's hidden sheet, and its text."""
    if SCENE_SHEET not in book.sheets:
        raise UnusableInput(f"{path}: no embedded scene (hidden sheet '{SCENE_SHEET}'); "
                            "expected a workbook made by `sheetkin workbook`")
    lines = [book.sheets[SCENE_SHEET].consts.get((r, 1), "") for r in range(1, book.sheets[SCENE_SHEET].max_row + 1)]
    scene_text = "\n".join(str(x) for x in lines) + "\n"
    check_embedded_size(scene_text, path)
    try:
        scene = parse_scene(scene_text, f"{path} (embedded scene)")
    except SceneError as e:
        # an issued book whose hidden sheet was edited until it no longer reads: say so
        # (the seal) rather than only the line that does not parse
        vid, found = issued.marks(book.sheets[SCENE_SHEET].consts)
        broken = issued.seal_status(options.key if options else None, vid, scene_text, found) if vid else ""
        if broken.startswith("scene sheet edited"):
            raise UnusableInput(f"{path}: {broken}; and it no longer reads: {e}") from e
        raise
    check_embedded_scene(scene, path)
    return scene, scene_text


@dataclass
class _Graded:
    """What grading one book shares between its steps: the student's sheet (a view in the
    issued layout), its rows by name, and (set by _new_report) the variant's reference."""
    path: str
    scene: Scene
    ref_rows: list
    layout: Layout
    evaluated: Book
    sh: Sheet
    names: dict[str, int]
    from_given: np.ndarray | None = None       # view cells (r, c) whose formulas reach the given data
    inputs: dict = field(default_factory=dict)
    student_scene: Scene | None = None
    ref_book: Book | None = None
    ref_names: dict = field(default_factory=dict)

    @property
    def main(self) -> str:
        return self.layout.sheet

    def reaches(self, r: int, c: int) -> bool:
        """Whether the view's cell (r, c) is given data or a formula that reads it (through formulas)."""
        a = self.from_given
        return a is None or (0 < r < a.shape[0] and 0 < c < a.shape[1] and bool(a[r, c]))


def _from_given(raw: Book, g: _Graded, positions: int) -> np.ndarray:
    """The cells of the graded sheet, in the issued layout (view columns), that are the
    book's given data or formulas reading them through formulas (sheetkin.xlsx.precedents):
    the given data are the input block's values (column D of the input rows), the rows the
    exercise gives filled in (i, phi_1, the guards) and the header's position numbers."""
    cols = g.layout.columns
    given_rows = {r.name for r in g.ref_rows if prefilled_in_exercise(r.name, r.kind)}
    sources = [(r, cols[4]) for n, r in g.names.items() if n in {x.name for x in g.ref_rows if x.kind == "input"}]
    rows = [r for n, r in g.names.items() if n in given_rows]
    if g.layout.header_row:
        rows.append(g.layout.header_row)
    sources += [(r, cols[FIRST_COL + k]) for r in rows for k in range(positions)]
    reach = reaching(raw, {g.main: sources})[g.main]
    view = np.zeros((reach.shape[0], max(cols) + 1), bool)
    for std, c in cols.items():
        if c < reach.shape[1]:
            view[:, std] = reach[:, c]
    return view


def _new_report(g: _Graded, book, scene_text: str, options: issued.Options | None) -> Report:
    """The report of a usable book before its rows are graded: the variant (the student's
    input block, checked against the issued one), its reference, who filled it in."""
    scene, ref_rows, layout, evaluated, sh, names, main = (g.scene, g.ref_rows, g.layout, g.evaluated, g.sh,
                                                          g.names, g.main)
    input_names = {r.name for r in ref_rows if r.kind == "input"}
    where = {n: f"{main}!{layout.cell(r, 4)}" for n, r in names.items()}
    g.inputs = inputs = _inputs(evaluated, main, {n: r for n, r in names.items() if n in input_names})
    positions = scene.crank.positions      # the issued ones, whatever lies right of the table
    # the given data: graded against the issued variant unless the changes are accepted
    given = issued.check_given(scene, scene_text, book.sheets[SCENE_SHEET].consts, inputs, where, options)
    accept = bool(options and options.accept_changed)
    g.student_scene = student_scene = variant_scene(scene, inputs if accept else {**inputs, **given.issued},
                                                    positions, where)
    g.ref_book = ref_book = _reference(student_scene)
    ref_sheet = ref_book.order[0]
    g.ref_names = ref_names = {ref_book.sheets[ref_sheet].consts.get((r, 1)): r
                               for r in range(5, ref_book.sheets[ref_sheet].max_row + 1)}
    # who filled it in: D1, D2 (the lecture's rows 1-2); books issued before 0.16 had input
    # rows "student", "group" (A1 the title, A2 the scheme's author, then)
    old = "student" in names
    report = Report(g.path, author=scene.author or "",
                    title=str(sh.consts.get((1, 1) if old else TITLE_AT, "") or ""),
                    positions=positions, problems=list(evaluated.problems),
                    student=_identity(evaluated, main, sh, names.get("student") if old else 1),
                    group=_identity(evaluated, main, sh, names.get("group") if old else 2),
                    variant=given.variant, given_changed=given.changed, seal=given.seal,
                    accepted_changes=accept, accepted_typed=bool(options and getattr(options, "accept_typed", False)),
                    notes=given.notes + layout.notes
                    + ([layout.outside_line()] if layout.outside else []), issued_to=given.student)
    report.layout = layout                  # not a field: the student's cells (report texts)
    report.roster_differs = given.roster_differs   # not a field: one warning for the class (cli)
    report.position_names = [(ref_book.value(ref_sheet, ref_names["i"], FIRST_COL + k),
                              ref_book.value(ref_sheet, ref_names["phi_1"], FIRST_COL + k)) for k in range(positions)]
    report.lang = book_lang(main)           # not a field: the reports' default language
    report.variant_scene = student_scene    # not a field (not in to_dict): the report's picture
    return report


def _grade_rows(report: Report, g: _Graded) -> None:
    """Every computed row against the reference, then the likely causes (each row judged on
    the student's own values of what it reads: sheetkin.course.localjudge), the cells whose
    formula and saved value disagree."""
    ref_rows, evaluated, sh, names, main = g.ref_rows, g.evaluated, g.sh, g.names, g.main
    ref_book, ref_names = cast(Book, g.ref_book), g.ref_names
    ref_sheet, positions = ref_book.order[0], report.positions
    ancestors = row_ancestors(cast(Scene, g.student_scene))
    kinds = {r.name: r.kind for r in ref_rows}
    periods = {r.name: TURN[r.unit] for r in ref_rows if r.unit in TURN}
    # not fields (not in to_dict): the raw cells copy detection compares (sheetkin/course/copies.py),
    # and how many check rows the sheet has (grades: checks passing / total)
    computed = {r.name: names[r.name] for r in ref_rows
                if r.kind in ("calc", "accepted", "guard") and r.name != "i" and r.name in names}
    # ref_names is looked up by row name only (the None of unnamed rows is never asked for)
    report.marks = submission_marks(sh, computed, FIRST_COL, positions, ref_book.sheets[ref_sheet],
                                    cast(dict[str, int], ref_names), g.inputs, ancestors)
    report.checks_total = sum(kinds.get(n) in ("check", "fdcheck") for n in names)
    for row in ref_rows:
        if row.kind not in ("calc", "accepted", "guard", "derived") or row.name in ("i",):
            continue
        rep = RowReport(row.name, names.get(row.name), "correct", kind=row.kind)
        report.rows.append(rep)
        if rep.row is None:
            rep.status = "missing"
            continue
        r, rr = rep.row, ref_names[row.name]
        if row.kind == "derived":             # its value in column D (Delta_Fi_rad, Alfa_A ...)
            _grade_derived(rep, g, ref_sheet, rr, periods.get(row.name))
            continue
        cells = [(r, FIRST_COL + k) for k in range(positions)]
        if not any(c in sh.formulas or c in sh.consts for c in cells):
            rep.status = "empty"
            continue
        _compare_cells(rep, cells, g, ref_sheet, rr, periods.get(row.name))
        if rep.wrong_cells:
            rep.status = "wrong"
    # likely causes: each row judged on the student's own values of what it reads
    # (sheetkin.course.localjudge); the wrong rows right on their inputs depend on a cause
    graded = {r.name for r in report.rows if r.status in ("correct", "wrong")}
    judged = [r.name for r in ref_rows if r.name in graded or (r.kind == "derived" and r.name in names)]
    local = judge(ref_book, evaluated, main, names, judged,
                  {r.name for r in report.rows if r.status in ("missing", "empty")}, periods, g.layout.columns)
    input_names = {r.name for r in ref_rows if r.kind == "input"}

    def derived_row(name: str, col: int) -> RowReport:
        return RowReport(name, names[name], "correct", kind="derived",
                         source="formula" if sh.computed(names[name], col) else "typed")
    name_causes(report.rows, local, ancestors, input_names, derived_row)
    report.cache_mismatch = _cache_mismatches(evaluated, main, {r for n, r in names.items() if n.startswith("phi_")},
                                              columns=g.layout.columns)


def _grade_derived(rep: RowReport, g: _Graded, ref_sheet: str, rr: int, period: float | None) -> None:
    """A derived value of the input block (column D: Delta_Fi_rad, Alfa_A, Betta_A), which the
    student computes, graded as a computed row is: right, wrong (first_wrong None: it has no
    positions), empty, or typed (a number, or a formula reading only typed numbers: it earns
    nothing)."""
    r = cast(int, rep.row)
    if (r, 4) not in g.sh.formulas and (r, 4) not in g.sh.consts:
        rep.status = "empty"
        return
    got = g.evaluated.value(g.main, r, 4)
    typed = not computes(g.sh, r, 4) or not g.reaches(r, 4)
    if typed:
        rep.source = "typed"
        if computes(g.sh, r, 4):
            rep.reads_typed = [1]
    else:
        rep.formula_cells = 1
        if g.evaluated.tag[g.main][r, 4] == 14 and (r, 4) in g.sh.cached:
            got, rep.source = g.sh.cached[(r, 4)], "cached"        # a formula we cannot evaluate
            got = float(got) if isinstance(got, (int, float)) and not isinstance(got, bool) else got
    exp = cast(Book, g.ref_book).value(ref_sheet, rr, 4)
    ok, err = _close(got, exp, rep.name, typed, period)
    rep.max_error = err
    if not ok:
        rep.status, rep.expected, rep.got = "wrong", exp, got


def _compare_cells(rep: RowReport, cells: list[tuple[int, int]], g: _Graded, ref_sheet: str, rr: int,
                   period: float | None) -> None:
    """A row's cells (r, c) against the reference's row rr: where it computes or holds typed
    numbers, its wrong cells, the first wrong one, its largest error. A formula that reads
    only typed numbers (none of the given data, through any formulas) computes nothing: it
    is typed, as the numbers it reads are."""
    evaluated, main, sh, ref_book = g.evaluated, g.main, g.sh, cast(Book, g.ref_book)
    for k, (r, c) in enumerate(cells):
        got = evaluated.value(main, r, c)
        typed = not computes(sh, r, c)                # a spilled cell is computed, not typed
        if not typed and not g.reaches(r, c):
            typed = True
            rep.reads_typed.append(k + 1)
        if not typed and evaluated.tag[main][r, c] == 14 and (r, c) in sh.cached:
            got, rep.source = sh.cached[(r, c)], "cached"        # a formula we cannot evaluate
            got = float(got) if isinstance(got, (int, float)) and not isinstance(got, bool) else got
        if not typed:
            rep.formula_cells += 1
        if typed:
            rep.source = "typed"
            if got is not None:
                rep.typed_cells.append(k + 1)
        exp = ref_book.value(ref_sheet, rr, c)
        ok, err = _close(got, exp, rep.name, typed, period)
        if not ok:
            rep.wrong_cells.append(k + 1)
            if rep.first_wrong is None:
                rep.first_wrong, rep.expected, rep.got = k + 1, exp, got
        if np.isfinite(err):
            rep.max_error = max(rep.max_error, err)
        else:
            rep.max_error = math.inf


# functions whose value depends on the cell or the sheet, not only on their arguments
_POSITIONAL = POSITIONAL


def computes(sh: Sheet, r: int, c: int) -> bool:
    """Whether the cell computes its value: a formula (or a spilled cell) that reads some
    cell or name. A formula of constants ("=0.1234", "=-1.5E-3", a 0 typed as "=0" over a
    check status) is a typed number with an "=" before it: it earns what a typed one does."""
    if not sh.computed(r, c):
        return False
    text = sh.formulas.get((r, c))
    if text is None:                                   # a spilled cell of an array formula
        return True
    try:
        tree = parse_formula("=" + text.lstrip("="), r, c, {})
    except ParseError:
        return True                                    # its evaluation reports what is wrong
    return bool(refs_of(tree) or names_of(tree) or functions_of(tree) & _POSITIONAL)


def _read_checks(report: Report, evaluated: Book, main: str, sh: Sheet, names: dict[str, int], ref_rows,
                 ref_book: Book, ref_names: dict) -> None:
    """The student's check rows (issue 21, item 3): their statuses, which fail, which were
    deleted or typed over, and how many of the issued ones apply to the variant."""
    kinds = {r.name: r.kind for r in ref_rows}
    ref_sheet, positions = ref_book.order[0], report.positions
    # status 1 or an error fails; 0, n/a and "not filled in" do not (sheetkin/sheet/checks.py)
    # a status typed over its formula (a 0 typed to make the row green) says nothing: it
    # fails, as an error would (it once hid the failing checks and raised the score)
    statuses = {n: evaluated.value(main, r, 4) if computes(sh, r, 4) else "#TYPED"
                for n, r in names.items()
                if n.startswith(("chk", "fd_")) and kinds.get(n) in ("check", "fdcheck")}
    _turns_pass(statuses, evaluated, main, names, ref_rows, ref_book, ref_names, positions)
    # issue 21: the check rows are part of the work (the lecture's step 10): a check row
    # deleted, or its status typed over, loses its share of the grade
    issued_checks = [r.name for r in ref_rows if r.kind in ("check", "fdcheck")]
    report.checks_issued = len(issued_checks)
    # the check rows that apply: those with a number at some position of the reference (the
    # others are "н/д" in every book of the variant: numeric derivatives above 3 deg ...)
    report.checks_apply = sum(any(isinstance(ref_book.value(ref_sheet, ref_names[n], FIRST_COL + k), float)
                                  for k in range(positions)) for n in issued_checks if n in ref_names)
    report.checks_deleted = [n for n in issued_checks if n not in names]
    report.checks_typed = [n for n, v in statuses.items() if v == "#TYPED"]
    if report.checks_typed:
        report.notes.append(f"check status typed over its formula (column D; counted as failing, its share of "
                            "the grade lost): "
                            f"{', '.join(report.checks_typed)}")
    if report.checks_deleted:
        report.notes.append(f"check rows deleted (counted as failing, their share of the grade lost): "
                            f"{', '.join(report.checks_deleted)}")
    # deleted or typed over, a check row also counts as failing: hiding a failing check
    # must never pay (it costs its share and the failing check's points)
    report.failing_checks = [n for n, s in statuses.items() if check_fails(s)] + report.checks_deleted
    # not fields: grades count the checks that pass (0) of those that apply (not "н/д"), as the
    # sheet's summary does; "не заполнено" and "н/д" are not passing (an empty book passes none)
    report.checks_passing = sum(check_passes(s) for s in statuses.values())
    report.checks_na = sum(check_na(s) for s in statuses.values())
    unfilled = {t["unfilled"] for t in CHECK_STATUS.values()}
    report.checks_unfilled = sum(isinstance(s, str) and s in unfilled for s in statuses.values())


def _turns_pass(statuses: dict, evaluated: Book, main: str, names: dict[str, int], ref_rows, ref_book: Book,
                ref_names: dict, positions: int) -> None:
    """A check row of an angle (chk_Fi: Fi - (Fi0 + i Delta_Fi), in radians) whose status
    fails only because its residuals are whole turns (Fi taken MOD 2*PI()) passes: angles are
    compared modulo a full turn everywhere else, so the check is judged the same way (its
    residuals within the sheet's Tol of a multiple of the turn, numbers where the reference
    has numbers). Sets the status to 0 in `statuses`."""
    units = {r.name: r.unit for r in ref_rows}
    tol = evaluated.value(main, names["Tol"], 4) if "Tol" in names else None
    tol = tol if isinstance(tol, float) and not isinstance(tol, bool) and math.isfinite(tol) and tol >= 0 else 1e-9
    ref_sheet = ref_book.order[0]
    for n, status in statuses.items():
        period = TURN.get(units.get(n, ""))
        if not period or not check_fails(status) or status == "#TYPED" or n not in ref_names:
            continue
        cells = [(evaluated.value(main, names[n], FIRST_COL + k),
                  ref_book.value(ref_sheet, ref_names[n], FIRST_COL + k)) for k in range(positions)]
        if all(isinstance(v, float) and float(angle_difference(abs(v), period)) <= tol if isinstance(e, float)
               else not isinstance(v, float) for v, e in cells):
            statuses[n] = 0.0


TITLE_AT = (1, 5)       # E1: the scheme's title (sheetkin.sheet.workbook.TITLE_CELL)


def book_lang(sheet_title: str) -> str:
    """The language a book was written in, told by its first sheet's title; ru otherwise."""
    return next((lang for lang, (kin, _) in SHEET_TITLES.items() if kin == sheet_title), "ru")


def _identity(evaluated, main: str, sh, row: int | None) -> str:
    """The student's own name or group cell as text; a formula typed there that sheetkin
    cannot compute (=HYPERLINK(...)) is what the spreadsheet saved, not "#NAME?"."""
    if row is None:
        return ""
    v = evaluated.value(main, row, 4)
    if sh.computed(row, 4) and evaluated.tag[main][row, 4] == 14 and (row, 4) in sh.cached:
        v = sh.cached[(row, 4)]
    return _text(v)


def _text(v) -> str:
    """A typed identity cell as text (a group typed as a number: 101.0 -> "101")."""
    if v is None or isinstance(v, bool):
        return ""
    if isinstance(v, float):
        return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)
    return " ".join(str(v).split())[:200]


def _evaluate_student(raw, layout=None) -> Book:
    # the charts' hidden `paths` and `plotted` sheets (360 positions of the coordinates; the
    # plotted rows as numbers or #N/A) are not graded and nothing on the kinematics sheet
    # refers to them: leaving them out halves the work
    sheets = {n: sh for n, sh in raw.sheets.items() if n not in (PATHS_SHEET, PLOTTED_SHEET)}
    if layout is not None:        # cells no formula can read, outside the table: not evaluated
        sheets = without_unread(sheets, raw.names, layout, {SCENE_SHEET})
    return evaluate_sheets(raw.path, sheets, [n for n in raw.order if n in sheets], raw.names, strict=False)


# The reference of a variant is the workbook sheetkin generates for it, evaluated. Only the
# input block (column D of the input rows) differs between variants of one mechanism with
# the same number of positions: the generated sheet is kept per structure (its rows'
# names, kinds and formulas, and the positions), and each variant's reference is that
# sheet with the variant's inputs, evaluated (the evaluator keeps the parsed formulas).
# No workbook is rebuilt per variant; references are kept per variant (its inputs).
_TEMPLATE_SHEETS: dict = {}               # structure -> the generated Sheet, {input name: row}
_REFERENCES: dict = {}                    # (structure, inputs) -> Book, at most _KEEP of them
_KEEP = 64


def _reference(scene: Scene) -> Book:
    """The variant's reference: its generated workbook's first sheet, evaluated."""
    rows = sheet_rows(scene).rows
    structure = (scene.crank.positions, tuple((r.name, r.kind, r.formula, r.guard) for r in rows))
    inputs = tuple((r.name, r.value) for r in rows if r.kind == "input")
    key = (structure, inputs)
    book = _REFERENCES.get(key)
    if book is None:
        if structure not in _TEMPLATE_SHEETS:
            if len(_TEMPLATE_SHEETS) >= _KEEP:
                _TEMPLATE_SHEETS.clear()
            _TEMPLATE_SHEETS[structure] = _template_sheet(scene)
        sheet, input_rows = _TEMPLATE_SHEETS[structure]
        consts = dict(sheet.consts)
        for name, value in inputs:          # as the generated workbook writes them (ints as floats)
            if value is None:
                consts.pop((input_rows[name], 4), None)
            else:
                consts[(input_rows[name], 4)] = (float(value) if isinstance(value, int) and not isinstance(value, bool)
                                                 else value)
        variant = Sheet(sheet.name, sheet.state, consts=consts, formulas=sheet.formulas,
                        max_row=sheet.max_row, max_col=sheet.max_col)
        book = evaluate_sheets("<reference>", {variant.name: variant}, [variant.name], {}, strict=True)
        if len(_REFERENCES) >= _KEEP:
            del _REFERENCES[next(iter(_REFERENCES))]          # the oldest
        _REFERENCES[key] = book
    return book


def _template_sheet(scene: Scene) -> tuple[Sheet, dict[str, int]]:
    """The first sheet of the scene's generated workbook as the evaluator reads it, and the
    row of every input."""
    book = _build_reference(scene, evaluate=False)
    sheet = book[0]
    input_rows = {sheet.consts.get((r, 1)): r for r in range(5, sheet.max_row + 1)}
    # the sheet's own check rows, their status cells and the summary above are not graded
    # against a reference (the student's checks are read from the student's sheet): left
    # out, they would be half of each variant's evaluation (SUMPRODUCT, COUNT, IF per row)
    # (their cells per position stay: which check rows apply, not "н/д", is the reference's)
    checks = _check_rows(scene)              # once: sheet_rows costs ~3 ms a call
    unchecked = {r for n, r in input_rows.items() if n in checks}
    sheet.formulas = {(r, c): f for (r, c), f in sheet.formulas.items()
                      if r >= 5 and (r not in unchecked or c >= FIRST_COL)}
    return sheet, input_rows


def _check_rows(scene: Scene) -> set[str]:
    return {r.name for r in sheet_rows(scene).rows if r.kind in ("check", "fdcheck")}


def reference_book(scene: Scene) -> Book:
    """The variant's evaluated reference workbook (cached per structure and inputs): what copy
    detection compares another variant's typed numbers with."""
    return _reference(scene)


def _build_reference(scene: Scene, evaluate: bool = True):
    """The generated workbook of the scene: evaluated (a Book), or its first Sheet (and
    title) unevaluated. Building it takes ~0.1-0.3 s (openpyxl): done once per structure."""
    wb = build_workbook(scene, scene_text="", charts=False)
    sheets, order = {}, []
    for ws in wb.worksheets[:1]:
        sh = Sheet(ws.title, "visible")
        for row in ws.iter_rows():
            for c in row:
                v = c.value
                if v is None:
                    continue
                if isinstance(v, str) and v.startswith("="):
                    sh.formulas[(c.row, c.column)] = v[1:]
                else:
                    sh.consts[(c.row, c.column)] = (float(v) if isinstance(v, int) and not isinstance(v, bool)
                                                    else XlError(v) if c.data_type == "e" else v)
                sh.max_row, sh.max_col = max(sh.max_row, c.row), max(sh.max_col, c.column)
        sheets[ws.title] = sh
        order.append(ws.title)
    if not evaluate:
        return [sheets[order[0]]]
    return evaluate_sheets("<reference>", sheets, order, {}, strict=True)


def _cache_mismatches(book: Book, sheet: str, angle_rows: Set[int] = frozenset(), limit: int = 50,
                      columns: dict[int, int] | None = None) -> list[str]:
    """Formula cells whose value, as the spreadsheet last saved it, differs from what the
    formula gives now (stale values, or a number pasted over a formula's result). On the
    rows of link angles, in [0, 360), 359.99999999999994 and 0 are the same angle (MOD's
    last bit differs between spreadsheets)."""
    from sheetkin.xlsx.coords import get_column_letter
    out = []
    sh = book.sheets[sheet]
    for (r, c), cached in sorted(sh.cached.items()):
        now = book.value(sheet, r, c)
        if isinstance(cached, (int, float)) and not isinstance(cached, bool):
            cached = float(cached)
            if isinstance(now, bool):    # LibreOffice saves a logical result as 1 or 0 (.ods)
                now = float(now)
            if isinstance(now, float) and abs(now - cached) <= max(1e-9, 1e-9 * abs(cached)):
                continue
            if isinstance(now, float) and r in angle_rows and abs(abs(now - cached) - 360.0) <= 1e-9:
                continue
        elif (isinstance(cached, str) and (now == cached or (now is None and cached == ""))
              or isinstance(cached, bool) and now == cached):
            continue
        elif isinstance(cached, str) and isinstance(now, str) and now.startswith("#") and cached.startswith("#"):
            continue                                     # errors: LibreOffice and Excel name some differently
        out.append(f"{sheet}!{get_column_letter((columns or {}).get(c, c))}{r} (formula gives {now!r}, "
                   f"saved value {cached!r})")
        if len(out) >= limit:
            break
    return out
