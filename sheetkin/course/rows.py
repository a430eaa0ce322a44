"""Judging the computed rows: each row's cells against the reference (correct, wrong,
missing, empty; typed or computed), then the likely causes (sheetkin.course.localjudge)
and the cells whose formula and saved value disagree."""
from __future__ import annotations

import math
from collections.abc import Sequence, Set
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from sheetkin.kinematics.scene import Scene
from sheetkin.messages import message
from sheetkin.sheet.workbook import (
    FIRST_COL,
    prefilled_in_exercise,
)
from sheetkin.xlsx.cells import Sheet
from sheetkin.xlsx.evaluator import Book
from sheetkin.xlsx.functions import NAME as NAME_ERROR
from sheetkin.xlsx.parse import ParseError, functions_of, names_of, parse_formula, refs_of
from sheetkin.xlsx.precedents import POSITIONAL, reaching

from .caches import Kept
from .copies import submission_marks  # the raw cells copy detection compares
from .layout import VALUE_COL, Layout
from .localjudge import TURN, angle_difference, judge, name_causes
from .localjudge import typed_tolerance as _typed_tolerance
from .reference import row_ancestors
from .report_model import Report, RowReport
from .tolerance import ATOL, RTOL


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


@dataclass
class Graded:
    """What grading one book shares between its steps: the student's sheet (a view in the
    issued layout), its rows by name, and (set by _new_report) the variant's reference."""
    path: str
    scene: Scene
    ref_rows: Sequence
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


def from_given(raw: Book, g: Graded, positions: int) -> np.ndarray:
    """The cells of the graded sheet, in the issued layout (view columns), that are the
    book's given data or formulas reading them through formulas (sheetkin.xlsx.precedents):
    the given data are the input block's values (column D of the input rows), the rows the
    exercise gives filled in (i, phi_1, the guards) and the header's position numbers."""
    cols = g.layout.columns
    given_rows = {r.name for r in g.ref_rows if prefilled_in_exercise(r.name, r.kind)}
    input_names = {x.name for x in g.ref_rows if x.kind == "input"}
    sources = [(r, cols[VALUE_COL]) for n, r in g.names.items() if n in input_names]
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


def grade_rows(report: Report, g: Graded) -> None:
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
        report.rows.append(_grade_row(row, g, ref_sheet, positions, periods.get(row.name)))
    _find_causes(report, g, ancestors, periods)
    report.cache_mismatch = _cache_mismatches(evaluated, main, {r for n, r in names.items() if n.startswith("phi_")},
                                              columns=g.layout.columns)


def _grade_row(row, g: Graded, ref_sheet: str, positions: int, period: float | None) -> RowReport:
    """One computed (or derived) row of the reference against the student's: missing, empty,
    right or wrong at its cells."""
    rep = RowReport(row.name, g.names.get(row.name), "correct", kind=row.kind)
    if rep.row is None:
        rep.status = "missing"
        return rep
    r, rr = rep.row, g.ref_names[row.name]
    if row.kind == "derived":             # its value in column D (Delta_Fi_rad, Alfa_A ...)
        _grade_derived(rep, g, ref_sheet, rr, period)
        return rep
    cells = [(r, FIRST_COL + k) for k in range(positions)]
    if not any(c in g.sh.formulas or c in g.sh.consts for c in cells):
        rep.status = "empty"
        return rep
    _compare_cells(rep, cells, g, ref_sheet, rr, period)
    if rep.wrong_cells:
        rep.status = "wrong"
    return rep


def _find_causes(report: Report, g: Graded, ancestors: dict[str, set[str]], periods: dict[str, float]) -> None:
    """The likely causes: each row judged on the student's own values of what it reads
    (sheetkin.course.localjudge); the wrong rows right on their inputs depend on a cause."""
    ref_rows, names, sh = g.ref_rows, g.names, g.sh
    graded = {r.name for r in report.rows if r.status in ("correct", "wrong")}
    judged = [r.name for r in ref_rows if r.name in graded or (r.kind == "derived" and r.name in names)]
    local = judge(cast(Book, g.ref_book), g.evaluated, g.main, names, judged,
                  {r.name for r in report.rows if r.status in ("missing", "empty")}, periods, g.layout.columns)
    input_names = {r.name for r in ref_rows if r.kind == "input"}

    def derived_row(name: str, col: int) -> RowReport:
        return RowReport(name, names[name], "correct", kind="derived",
                         source="formula" if sh.computed(names[name], col) else "typed")
    name_causes(report.rows, local, ancestors, input_names, derived_row)


def _grade_derived(rep: RowReport, g: Graded, ref_sheet: str, rr: int, period: float | None) -> None:
    """A derived value of the input block (column D: Delta_Fi_rad, Alfa_A, Betta_A), which the
    student computes, graded as a computed row is: right, wrong (first_wrong None: it has no
    positions), empty, or typed (a number, or a formula reading only typed numbers: it earns
    nothing)."""
    r = cast(int, rep.row)
    if (r, VALUE_COL) not in g.sh.formulas and (r, VALUE_COL) not in g.sh.consts:
        rep.status = "empty"
        return
    got = g.evaluated.value(g.main, r, VALUE_COL)
    typed = not computes(g.sh, r, VALUE_COL) or not g.reaches(r, VALUE_COL)
    if typed:
        rep.source = "typed"
        if computes(g.sh, r, VALUE_COL):
            rep.reads_typed = [1]
    else:
        rep.formula_cells = 1
        if g.evaluated.tag[g.main][r, VALUE_COL] == NAME_ERROR and (r, VALUE_COL) in g.sh.cached:
            got, rep.source = g.sh.cached[(r, VALUE_COL)], "cached"        # a formula we cannot evaluate
            got = float(got) if isinstance(got, (int, float)) and not isinstance(got, bool) else got
    exp = cast(Book, g.ref_book).value(ref_sheet, rr, VALUE_COL)
    ok, err = _close(got, exp, rep.name, typed, period)
    rep.max_error = err
    if not ok:
        rep.status, rep.expected, rep.got = "wrong", exp, got


def _compare_cells(rep: RowReport, cells: list[tuple[int, int]], g: Graded, ref_sheet: str, rr: int,
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
        if not typed and evaluated.tag[main][r, c] == NAME_ERROR and (r, c) in sh.cached:
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
    return formula_reads_something(text, r, c)                  # parsed once per formula text


_READS = Kept(100_000)        # formula text -> whether it reads something


def formula_reads_something(text: str, r: int, c: int) -> bool:
    """Whether a formula reads some cell or name, or a positional function (ROW, COLUMN): the
    validator's computes() for a formula cell. Kept per formula text: whether a formula reads
    anything does not depend on its cell, and a class's books share their formulas (parsing
    them again was 46% of a further book's CPU, issue 31)."""
    known = _READS.get(text)
    if known is None:
        try:
            tree = parse_formula("=" + text.lstrip("="), r, c, {})
            known = bool(refs_of(tree) or names_of(tree) or functions_of(tree) & POSITIONAL)
        except ParseError:
            known = True                                # its evaluation reports what is wrong
        _READS.keep(text, known)
    return known


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
        out.append(f"{sheet}!{get_column_letter((columns or {}).get(c, c))}{r} "
                   + message("formula_gives_saved_value", now=repr(now), saved=repr(cached)))
        if len(out) >= limit:
            break
    return out
