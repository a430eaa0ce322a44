"""Judging a sheet by what it computes (issue 31): the student's own formulas evaluated again
on nudged given data, against the reference of those data.

A computed cell right for the issued given data earns credit only when it is also right for
the nudged variants of the same scheme (sheetkin/course/nudge.py: lengths, offsets, masses,
forces and crank speed moved a little, the configuration kept). The student's book is
evaluated again with the input block (column D of the input rows) replaced by each nudged
variant's values: the same parsed formulas in the same order (sheetkin/xlsx/replay.py),
nothing parsed twice. A cell right on the issued data and wrong on a nudged one "does not
follow the given data": a number passed off as work (=E$41*0+0.5236, =IF(FALSE;..;Лист2!E42),
=CHOOSE(E$40+1; 13 typed numbers) ...). It earns nothing, as a typed number does, and the
report names the row, a cell and its formula.

The crank's own rows (Fi, cos_1 ...), which the nudged lengths leave unmoved, are judged on
the turned variant (nudge.turned_variant: Fi0 and Delta_Fi moved), which judges only such
cells and not a zero. A check row passing on the issued data must fail on a nudged variant's
given data with the rows it checks held, where the reference's does (judge_held_checks).

A cell whose right value does not move with any of them (a slider's fixed angle, a zero)
cannot be told apart this way; there the precedent tracing (sheetkin.xlsx.precedents: "reads no
given data") still decides, as before. Where the tracing and the nudges both apply they agree:
a formula reading none of the given data cannot follow them.

No penalty without evidence: a row whose formulas sheetkin cannot evaluate (a function the
evaluator lacks, a formula it cannot read: the cell is #NAME? here and a number in the saved
file) is "not judged: check by hand". It is left out of the rows graded and named in the
report; so is a check row whose status sheetkin cannot evaluate (it is not failing). When
LibreOffice computed such cells on the issued data (course/by_libreoffice.py), it computes
them on the nudged copies too (by_libreoffice.fill_copies) and they are judged there.

The validator calls, in order: prepare (after the variant's reference is known), judge_rows
(after the rows are graded against the reference), judge_checks (after the check rows are
read). Each leaves a report it cannot judge as it was.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

import numpy as np

from sheetkin.kinematics.scene import Scene
from sheetkin.messages import message
from sheetkin.sheet.workbook import FIRST_COL, prefilled_in_exercise
from sheetkin.xlsx.coords import column_index_from_string
from sheetkin.xlsx.evaluator import Book
from sheetkin.xlsx.functions import FIRST_ERROR
from sheetkin.xlsx.functions import NAME as NAME_ERROR  # a function it lacks, a formula it cannot read
from sheetkin.xlsx.replay import Replay
from sheetkin.xlsx.values import NUM

from . import by_libreoffice, nudge
from .caches import scene_rows
from .layout import VALUE_COL, standard_view
from .localjudge import CELL_RIGHT, TURN, angle_difference, judge
from .tolerance import ATOL, RTOL

HELD_FI0 = 1.0           # degrees Fi0 moves by when the check rows are judged with their rows held

if TYPE_CHECKING:
    from .report_model import Report, RowReport
    from .rows import Graded



@dataclass
class Held:
    """The check rows whose reference fails with the rows they check held (reacting), and
    the student's sheet with those check rows so evaluated (issued layout; None: none react)."""
    reacting: set[str]
    sheet: Book | None
    # reacting check rows whose issued status formula their residuals fail: not evaluated
    settled: set[str] = field(default_factory=set)


@dataclass
class Behaviour:
    """The nudged variants of one book and the student's sheet evaluated on each (views in
    the issued layout, as the validator's evaluated sheet)."""
    nudged: list[nudge.Nudged]
    sheets: list[Book]
    # the check rows alone evaluated again on a variant's given data, every other cell held
    # at its issued value (_held_checks)
    held: Held | None = None
    # the cells sheetkin cannot compute took LibreOffice's values in each of the sheets
    # (by_libreoffice.fill_copies): they are judged on the nudged data as the others are
    by_libreoffice: bool = False


def prepare(g: Graded, raw: Book, names: dict, scene_text: str, libreoffice: bool = True) -> Behaviour | None:
    """The book's nudged variants and its formulas evaluated on them; None when there is
    nothing to nudge or an input cell holds a formula (then the precedents decide, as before).
    The cells sheetkin cannot compute are LibreOffice's on the nudged data too, when it is
    installed and `libreoffice` (course/by_libreoffice.py: one soffice run for the copies)."""
    from .reference import variant_scene
    scene, ref_book = g.student_scene, g.ref_book
    if scene is None or ref_book is None:
        return None
    positions = scene.crank.positions
    if nudge.NUDGES <= 0:                        # switched off (benchmarks/per_book.py --behaviour-off)
        return None
    # a nudged variant's reference is the issued reference evaluated again with the nudged
    # input block (the same generated sheet: validator._reference evaluates it so), its
    # parsed formulas and their order shared
    ref_sheet = ref_book.order[0]
    ref_replay = Replay(ref_book, {}, skip={ref_sheet: {r for n, r in g.ref_names.items()
                                                       if isinstance(n, str) and n.startswith(("chk", "fd_"))}})

    def reference(s: Scene) -> Book:
        inputs = {r.name: r.value for r in scene_rows(s) if r.kind == "input" and r.value is not None}
        return ref_replay.run({ref_sheet: {
            (g.ref_names[n], 4): float(v) if isinstance(v, int) and not isinstance(v, bool) else v
            for n, v in inputs.items() if n in g.ref_names}})
    def vary(s: Scene, inputs: dict) -> Scene:
        return variant_scene(s, inputs, positions, {})
    seed = scene_text.encode("utf-8")
    variants = nudge.nudged_variants(scene, seed, ref_book, vary, reference, nudge.NUDGES)
    if not variants:
        return None
    # last, the turned variant (Fi0 and Delta_Fi moved): for the cells the others leave unmoved
    turned = nudge.turned_variant(scene, seed, ref_book, vary, reference) if nudge.TURNED else None
    if turned is not None:
        variants.append(turned)
    value_col = g.layout.columns[4]
    raw_sheet = raw.sheets[g.main]
    for v in variants:
        for name in v.inputs:
            r = g.names.get(name)
            if r is not None and (r, value_col) in raw_sheet.formulas:
                return None                      # a given value computed by a formula: not replayed
    # the sheet's own check rows and the summary above the table are not graded on the nudged
    # data (their status formulas are most of a book's evaluation): not evaluated again
    checks = {r for n, r in g.names.items() if n.startswith(("chk", "fd_"))} | set(range(1, 5))
    replay = Replay(raw, names, skip={g.main: checks})
    changes = [{(g.names[n], value_col): x for n, x in v.inputs.items() if n in g.names} for v in variants]
    books = [replay.run({g.main: ch}) for ch in changes]
    by_lo = by_libreoffice.fill_copies(books, g.path, g.main, changes, libreoffice)
    sheets = [standard_view(b, g.layout, g.sh)[0] for b in books]
    return Behaviour(variants, sheets, _held_checks(g, raw, names, ref_book, [v for v in variants if not v.turned]),
                     by_lo)


def _held_inputs(v: nudge.Nudged, ref_book: Book, ref_names: dict) -> dict[str, float]:
    """The given data the check rows are evaluated on with the rows they check held: the
    variant's nudged data, and Fi0 moved by HELD_FI0 degrees (no configuration to keep there:
    the rows are not computed again, so chk_Fi reacts too)."""
    out = dict(v.inputs)
    if "Fi0" in ref_names:
        fi0 = ref_book.value(ref_book.order[0], ref_names["Fi0"], 4)
        if isinstance(fi0, float) and not isinstance(fi0, bool):
            out["Fi0"] = fi0 + HELD_FI0
    return out


def _held_checks(g: Graded, raw: Book, names: dict, ref_book: Book, variants: list[nudge.Nudged]) -> Held | None:
    """The check rows evaluated alone on the first variant's given data (_held_inputs), every
    other cell kept at its issued value: first the reference's (its residuals), then the
    student's check rows whose reference reacts (fails so while it passes on the issued
    data). An honest check then fails where the reference's does (its rows no longer agree
    with the given data); one that still passes checks nothing. One variant, the reacting
    rows only: a check of constants passes on any (issue 31's cost: the status formulas are
    most of a book's evaluation)."""
    ref_sheet = ref_book.order[0]
    theirs = {n: r for n, r in g.ref_names.items() if isinstance(n, str) and n.startswith(("chk", "fd_"))}
    if not variants or not theirs or not any(n in g.names for n in theirs):
        return None
    value_col = g.layout.columns[4]
    inputs = _held_inputs(variants[0], ref_book, g.ref_names)
    if any((g.names[n], value_col) in raw.sheets[g.main].formulas for n in inputs if n in g.names):
        return None
    held_ref = Replay(ref_book, {}, only={ref_sheet: set(theirs.values())}).run(
        {ref_sheet: {(g.ref_names[n], 4): x for n, x in inputs.items() if n in g.ref_names}})
    tol = {p: ref_book.value(ref_sheet, g.ref_names[t], 4) if t in g.ref_names else None
           for p, t in (("chk", "Tol"), ("fd_", "Tol_FD"))}
    positions = g.student_scene.crank.positions if g.student_scene is not None else 0
    reacting = set()
    for n, rr in theirs.items():
        t = tol["fd_" if n.startswith("fd_") else "chk"]
        if n in g.names and _finite(t) and _reacts(ref_book, held_ref, rr, positions, cast(float, t)):
            reacting.add(n)
    if not reacting:
        return Held(reacting, None)
    # a status formula that is the issued one is not evaluated where the residuals it reads
    # already fail it (the status formulas are most of the cost): settled
    issued = _issued_statuses(g, raw, reacting)

    def status(run) -> bool:
        return (run.sheet, run.row) in issued and len(run.cols) == 1 and int(run.cols[0]) == VALUE_COL
    mine = Replay(raw, names, only={g.main: {g.names[n] for n in reacting}}, keep=lambda run: not status(run)).run(
        {g.main: {(g.names[n], value_col): x for n, x in inputs.items() if n in g.names}})
    settled = {n for n in reacting if (g.main, g.names[n]) in issued
               and _residuals_fail(mine, g.main, issued[(g.main, g.names[n])])}
    rest = {g.names[n] for n in reacting if (g.main, g.names[n]) in issued and n not in settled}
    if rest:                            # the residuals pass: the status formula decides
        mine = Replay(mine, names, only={g.main: rest}, keep=status).run({})
    return Held(reacting, standard_view(mine, g.layout, g.sh)[0], settled)


_STATUS_RESIDUALS = re.compile(r"ISERROR\(SUM\(([A-Z]+)(\d+):([A-Z]+)(\d+)\)\)")
_STATUS_TOL = re.compile(r"MAX\([A-Z]+\d+:[A-Z]+\d+\)<=\$D\$(\d+),")


def _issued_statuses(g: Graded, raw: Book, reacting: set[str]) -> dict[tuple[str, int], tuple[int, int, int, int]]:
    """The reacting check rows whose status formula is the issued one (the same text, in the
    issued row and columns, alone in its run), by (sheet, row): the residual cells it reads
    (row, first and last column) and the row of the tolerance it compares them with."""
    if g.layout.moved or g.student_scene is None:
        return {}
    from .reference import issued_statuses
    statuses = issued_statuses(g.student_scene)
    alone = {run.row for run in raw.schedule if run.sheet == g.main and len(run.cols) == 1 and run.cols[0] == VALUE_COL}
    out = {}
    formulas = raw.sheets[g.main].formulas
    for n in reacting:
        r = g.names[n]
        f = statuses.get(r)
        if r != g.ref_names.get(n) or r not in alone or f is None or formulas.get((r, VALUE_COL)) != f:
            continue
        sums, tol = _STATUS_RESIDUALS.search(f), _STATUS_TOL.search(f)
        if sums is None or tol is None or int(sums[2]) != r or int(sums[4]) != r:
            continue
        out[(g.main, r)] = (r, column_index_from_string(sums[1]), column_index_from_string(sums[3]), int(tol[1]))
    return out


def _residuals_fail(book: Book, sheet: str, where: tuple[int, int, int, int]) -> bool:
    """Whether the issued status formula fails on these residuals: one of them is an error
    (its SUM is), or a number beyond the tolerance (its MAX or MIN is); whatever else it
    looks at, it then is 1, "н/д" or "не заполнено", never 0 (passing)."""
    r, first, last, tol_row = where
    tol = book.value(sheet, tol_row, VALUE_COL)
    if not _finite(tol):
        return False
    tags, nums = book.tag[sheet][r, first:last + 1], book.num[sheet][r, first:last + 1]
    if (tags >= FIRST_ERROR).any():
        return True
    numbers = nums[tags == NUM]
    return bool((np.abs(numbers) > tol).any())


def _close(got, exp, period: float | None) -> bool:
    if not isinstance(exp, float):
        return not isinstance(got, float) if not isinstance(exp, bool) else got == exp
    if not isinstance(got, float) or isinstance(got, bool):
        return False
    d = float(angle_difference(abs(got - exp), period))
    return d <= max(ATOL, RTOL * abs(exp))


def _unevaluable(g: Graded, r: int, c: int) -> bool:
    """A formula cell sheetkin cannot evaluate while the spreadsheet could: #NAME? here, a
    value that is no error in the saved file."""
    if g.evaluated.tag[g.main][r, c] != NAME_ERROR or not g.sh.computed(r, c):
        return False
    saved = g.sh.cached.get((r, c))
    return saved is not None and not (isinstance(saved, str) and saved.startswith("#"))


def judge_rows(report: Report, g: Graded, beh: Behaviour | None) -> None:
    """Mark the graded rows sheetkin cannot evaluate as not judged, and the computed cells right
    on the issued data that do not follow the nudged data as not computed (typed)."""
    periods = {r.name: TURN[r.unit] for r in g.ref_rows if r.unit in TURN}
    ref_book = cast(Book, g.ref_book)
    ref_sheet = ref_book.order[0]
    unjudged: list[str] = []
    not_following: list[str] = []
    candidates = []
    for rep in report.rows:
        if rep.status not in ("correct", "wrong") or rep.row is None or prefilled_in_exercise(rep.name, rep.kind):
            continue
        r = rep.row
        cols = [4] if rep.kind == "derived" else [FIRST_COL + k for k in range(report.positions)]
        if any(_unevaluable(g, r, c) for c in cols):
            rep.not_judged = True
            unjudged.append(rep.name)
            continue
        if beh is not None and rep.name in g.ref_names:
            candidates.append((rep, cols))
    from .report_html import position_list  # it imports the validator, which imports this
    report.filled_share = _filled_share(report, g)
    _name_empty_cells(report, g, position_list)
    # each row is also judged on its own nudged inputs (sheetkin.course.localjudge): a row
    # right given what it reads follows the given data, even when a row above it does not
    # (an honest formula reading a cheated row is not a cheat of its own)
    locals_ = [] if beh is None else [
        judge(n.reference, sheet, g.main, g.names, [rep.name for rep, _ in candidates], frozenset(), periods,
              g.layout.columns) for n, sheet in zip(beh.nudged, beh.sheets, strict=True)]
    for rep, cols in candidates:
        r = cast(int, rep.row)
        rr, period = g.ref_names[rep.name], periods.get(rep.name)
        if _right_on_every_variant(cast(Behaviour, beh), g.main, r, rr, cols, period):
            continue                             # most rows: no cell to judge one by one
        bad = set(rep.wrong_cells) | set(rep.typed_cells)
        states = [dict(zip((int(c) for c in lo.judgements[rep.name].cols), lo.judgements[rep.name].state, strict=True))
                  if rep.name in lo.judgements and lo.judgements[rep.name].local else {} for lo in locals_]
        for k, c in enumerate(cols):
            if k + 1 in bad or (rep.kind == "derived" and (rep.status != "correct" or rep.source != "formula")):
                continue
            if not g.evaluated.computed(g.main, r, c) and not cast(Behaviour, beh).by_libreoffice:
                continue          # computed by LibreOffice on the issued data only (course/by_libreoffice.py)
            issued = ref_book.value(ref_sheet, rr, c)
            moved = False
            for n, sheet, state in zip(cast(Behaviour, beh).nudged, cast(Behaviour, beh).sheets, states, strict=True):
                if n.turned and (moved or _finite(issued) and abs(cast(float, issued)) <= ATOL):
                    # judged on the nudged lengths already; or zero here (x_A at 90 deg, omega_2 at a
                    # dead centre): a zero has no sign, and a sign chosen by hand there is honest
                    break
                exp = n.reference.value(n.reference.order[0], rr, c)
                if _close(exp, issued, period):
                    continue                     # the right value does not move: the precedents decide
                moved = True
                if sheet.tag[g.main][r, c] == NAME_ERROR:
                    break                        # sheetkin cannot evaluate it, nor LibreOffice on these data
                if not _close(sheet.value(g.main, r, c), exp, period) and state.get(c, CELL_RIGHT) != CELL_RIGHT:
                    rep.not_following.append(k + 1)
                    break
        if rep.not_following:
            if rep.kind == "derived":
                rep.source = "typed"
            else:
                rep.typed_cells = sorted(set(rep.typed_cells) | set(rep.not_following))
            k = rep.not_following[0]
            c = cols[k - 1]
            formula = g.sh.formulas.get((r, c), "")
            cell = g.layout.cell(r, c)
            where = "" if rep.kind == "derived" else f", {position_list(report, rep.not_following, 'en')}"
            not_following.append(f"{rep.name} (row {r}{where}: {cell} ={formula})")
    if not_following:
        report.notes.append(message("not_following_given", n=len(not_following), list="; ".join(not_following[:12])
                                    + (" ..." if len(not_following) > 12 else "")))
    if unjudged:
        report.notes.append(message("rows_not_judged", n=len(unjudged), names=", ".join(unjudged[:12])
                                    + (" ..." if len(unjudged) > 12 else "")))


def _right_on_every_variant(beh: Behaviour, main: str, r: int, rr: int, cols: list[int], period: float | None) -> bool:
    """Whether the student's row r equals the reference's row rr (numbers, within the
    validator's precision) at every cell `cols` on every variant: then no cell of it can fail
    to follow the given data (judge_rows judges the others cell by cell)."""
    for n, sheet in zip(beh.nudged, beh.sheets, strict=True):
        rs = n.reference.order[0]
        et, st = n.reference.tag[rs], sheet.tag[main]
        if rr >= et.shape[0] or r >= st.shape[0] or max(cols) >= min(et.shape[1], st.shape[1]):
            return False
        if not ((et[rr, cols] == NUM) & (st[r, cols] == NUM)).all():
            return False
        exp, got = n.reference.num[rs][rr, cols], sheet.num[main][r, cols]
        if not (angle_difference(np.abs(got - exp), period) <= np.maximum(ATOL, RTOL * np.abs(exp))).all():
            return False
    return True


def _name_empty_cells(report: Report, g: Graded, position_list) -> None:
    """An empty cell is empty, not typed (issue 31): a row of formulas with cells left empty
    is a row of formulas, and the report says where it is empty rather than "an error value
    or text" there."""
    for rep in report.rows:
        if rep.kind == "derived" or rep.row is None or rep.status != "wrong":
            continue
        empty = [k + 1 for k in range(report.positions)
                 if (rep.row, FIRST_COL + k) not in g.sh.formulas and (rep.row, FIRST_COL + k) not in g.sh.consts]
        if not empty:
            continue
        if rep.source == "typed" and not rep.typed_cells:
            rep.source = "formula" if rep.formula_cells else "empty"
        if set(rep.wrong_cells) <= set(empty) and not rep.note:
            rep.note = f"empty at {position_list(report, empty, 'en')}"


def _filled_share(report: Report, g: Graded) -> float:
    """The share of the graded rows' cells that hold something (a formula or a value): the
    share of an unfilled check row's credit it keeps (credit per position: a book with its
    last position left empty keeps 12/13 of its check rows' share)."""
    cells = filled = 0
    for rep in report.rows:
        if rep.kind == "derived" or prefilled_in_exercise(rep.name, rep.kind):
            continue
        cells += report.positions
        if rep.row is not None:
            filled += sum(1 for k in range(report.positions)
                          if (rep.row, FIRST_COL + k) in g.sh.formulas or (rep.row, FIRST_COL + k) in g.sh.consts)
    return filled / cells if cells else 0.0


def judge_checks(report: Report, g: Graded) -> None:
    """A check row whose status sheetkin cannot evaluate is not failing: not judged, named,
    out of the check rows that apply."""
    def unjudged_check(n: str) -> bool:
        # its status is #NAME? here, or it fails here only because the cells it reads are
        # (the sheet's own formula turns an error among them into 1) while the saved status passes
        r = g.names[n]
        if _unevaluable(g, r, 4):
            return True
        saved = g.sh.cached.get((r, 4))
        return (isinstance(saved, (int, float)) and not isinstance(saved, bool) and saved == 0
                and any(_unevaluable(g, r, FIRST_COL + k) for k in range(report.positions)))
    unjudged = [n for n in report.failing_checks if n in g.names and unjudged_check(n)]
    if not unjudged:
        return
    report.failing_checks = [n for n in report.failing_checks if n not in unjudged]
    report.checks_not_judged = unjudged
    report.checks_apply = max(0, (report.checks_apply or 0) - len(unjudged))
    report.notes.append(message("check_rows_not_judged", n=len(unjudged), names=", ".join(unjudged[:12]))
                        + (" ..." if len(unjudged) > 12 else ""))


def judge_held_checks(report: Report, g: Graded, beh: Behaviour | None) -> None:
    """A check row passing on the issued data must check (issue 31): evaluated on a nudged
    variant's given data with the rows it checks held at their issued values, the reference's
    check row fails there; the student's must fail too. One that still passes (a status
    `=0*$D$17`, residuals `=0*$D$17` or pasted) does not check: it counts as failing, named
    in the report with its status cell's formula. A check row whose reference does not react
    (it reads none of the given data the variants change: chk_mag_A) is judged as before."""
    if beh is None or beh.held is None or beh.held.sheet is None:
        return
    from sheetkin.sheet.checks import passing
    held = beh.held.sheet
    not_checking: list[str] = []
    for n in sorted(beh.held.reacting, key=lambda n: g.names[n]):
        r = g.names[n]
        if (n in report.failing_checks or n in report.checks_not_judged
                or not passing(g.evaluated.value(g.main, r, 4))):
            continue
        if n not in beh.held.settled and passing(held.value(g.main, r, 4)):
            formula = g.sh.formulas.get((r, 4), "")
            not_checking.append(f"{n} (row {r}: {g.layout.cell(r, 4)} ={formula})")
            report.failing_checks.append(n)
            report.checks_passing = max(0, (report.checks_passing or 0) - 1)
    if not_checking:
        report.notes.append(message("check_rows_not_checking", n=len(not_checking), list="; ".join(not_checking[:12])
                                    + (" ..." if len(not_checking) > 12 else "")))


def _reacts(issued: Book, held: Book, r: int, positions: int, tol: float) -> bool:
    """Whether the reference's check row r would fail held (its residuals within tol on the
    issued data, beyond it at some position on the held evaluation): the reference's status
    cells are not written, its residuals are."""
    sheet = issued.order[0]
    before = [issued.value(sheet, r, FIRST_COL + k) for k in range(positions)]
    after = [held.value(sheet, r, FIRST_COL + k) for k in range(positions)]
    if not all(_finite(x) and abs(x) <= tol for x, y in zip(before, after, strict=True) if _finite(y)):
        return False                    # fails, or is not evaluated, on the issued data
    return any(_finite(x) and abs(x) > tol for x in after)


def _finite(x) -> bool:
    return isinstance(x, float) and math.isfinite(x)


def row_share(row: RowReport, positions: int, accept_typed: bool) -> float:
    """The share of a graded row's credit it earns (issue 31: credit per position): its
    positions computed right over its positions; 1 or 0 for a derived value of column D."""
    if row.status in ("missing", "empty"):
        return 0.0
    if row.kind == "derived" or positions <= 0:
        typed = row.is_typed and not accept_typed
        return 1.0 if row.status == "correct" and not typed else 0.0
    bad = set(row.wrong_cells) | (set() if accept_typed else set(row.typed_cells)) | set(row.not_following)
    return max(0, positions - len({k for k in bad if 1 <= k <= positions})) / positions
