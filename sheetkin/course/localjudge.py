"""Each row judged on its own inputs: which wrong rows are mistakes, and which only inherit one
(issue 13, item 3).

The validator compares every row of a student's sheet with the reference (the generated
workbook of the variant, evaluated). A row can be wrong there and still be computed right:
its formula is the lecture's, only a row it reads is wrong. Worse, a number typed with few
digits (omega_2 typed -2.54 where the formula gives -2.54251) passes to its digits, and every
formula below it is then wrong by ~1e-4, while each of them is right. So here each row is
judged *locally*: the row's reference formula is evaluated over the student's own values of
the cells it refers to (the reference sheet's layout, every named row holding the student's
numbers: rows are mapped by their name in column A, as the validator maps them; the
formulas are the generated sheet's, parsed once per structure and never rebuilt):

* a formula cell is locally right when it equals that value up to rounding (RTOL, ATOL:
  the validator's precision);
* a typed cell (a number where the reference has a formula) is locally right within half a
  unit of its last typed digit, plus what the typed digits of the numbers it is computed
  from carry into it (each typed row above is moved by its half unit once, and the change
  of the rows that read it is added: a hand calculation from rounded numbers is not a
  mistake); a typed cell that differs from its inputs' value by more than formula
  precision but within its digits is *rounded*.

The likely causes (name_causes), in sheet order:
* a row with a cell wrong both against the reference and on its own inputs: a mistake;
* a row whose other flagged cells (a rounded typed number; a number right against the
  reference but not on the student's inputs; a derived value of column D) differ from the
  reference, and so carry an error down, when a wrong cell below (same position) depends on
  it that no cause above accounts for (omega_2 typed -3.23 and f1_g1 typed to 6 digits from
  the unrounded omega_2: omega_2 is named, f1_g1 is not).
A row that is right given its inputs is never a cause: it is wrong because of the causes
among its ancestors (because_of), or because of given data that differ from the reference's
(the issued variant's, when the validator grades against it). A row that reads a missing or
empty row is not judged (local ""): it keeps the old rule (wrong because of the missing row).
A number typed over a formula with all its digits is not a cause: it equals its formula.
"""
from __future__ import annotations

import re
from collections.abc import Set
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from sheetkin.messages import message
from sheetkin.sheet.workbook import FIRST_COL
from sheetkin.xlsx.coords import get_column_letter
from sheetkin.xlsx.evaluator import BOOL, EMPTY, NUM, TEXT, Book, Run, evaluate_runs, parse_rows, store_value
from sheetkin.xlsx.functions import ERROR_TEXT, NAME

from .caches import Kept
from .layout import VALUE_COL
from .report_model import LocalJudgement
from .tolerance import ATOL, RTOL

# a full turn in a row's unit: angles are compared modulo it (an angle taken MOD 2*PI() or
# MOD 360, or one turn more, is the same angle)
TURN = {"deg": 360.0, "rad": 2.0 * np.pi}


def angle_difference(d, period: float | None):
    """|a - b| (d) of two angles as the shorter way round a full turn `period`; d itself
    when the row is not an angle (period None)."""
    if not period:
        return d
    m = np.mod(d, period)
    return np.minimum(m, period - m)


def typed_tolerance(x: float) -> float:
    """A number typed by hand is right to half a unit of its last typed digit."""
    text = repr(float(x))
    if "e" in text or "E" in text:
        mant, exp = text.lower().split("e")
        decimals = len(mant.split(".")[1]) if "." in mant else 0
        return 0.5 * 10.0 ** (int(exp) - decimals)
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0 ** -decimals if text.split(".")[1] != "0" else 0.5


def typed_digits(x: float) -> int:
    """Significant digits of a typed number as its shortest repr writes it (-2.54: 3)."""
    mant = repr(abs(float(x))).lower().split("e")[0]
    if mant.endswith(".0"):
        mant = mant[:-2]
    digits = mant.replace(".", "").lstrip("0")
    if "." not in mant:
        digits = digits.rstrip("0")
    return max(len(digits), 1)


def typed_text(x: float) -> str:
    """A typed number as the student typed it: -2.54, 0.14, 3."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def magnitude(x: float) -> str:
    """A relative difference to one digit, as a teacher reads it: 1e-4, 3e-2, 0.5."""
    if not np.isfinite(x):
        return "a non-number"
    if x == 0:
        return "0"
    if x >= 0.1:
        return f"{x:.1g}"
    return re.sub(r"e([+-])0*(\d)", r"e\1\2", f"{x:.0e}").replace("e+", "e")


# --------------------------------------------------------------------------- the plan
@dataclass
class _Plan:
    """What one generated sheet (one structure) gives every judgement: kept per template."""
    formulas: dict                                           # the template's (its identity)
    rows: dict[str, int]                                     # name -> the reference's row
    runs: dict[str, list[Run]]                               # name -> its formula's runs
    cols: dict[str, np.ndarray]                              # name -> columns of its formulas
    reads: dict[str, set[str]]                               # name -> the rows its formula reads


_PLANS = Kept(64)


def _plan(sheet, judged: tuple[str, ...]) -> _Plan:
    key = (id(sheet.formulas), judged)
    hit = _PLANS.get(key)
    if hit is not None and hit.formulas is sheet.formulas:
        return hit
    rows: dict[str, int] = {}
    for r in range(5, sheet.max_row + 1):
        v = sheet.consts.get((r, 1))
        if isinstance(v, str) and v and v not in rows:
            rows[v] = r
    name_at = {r: n for n, r in rows.items()}
    wanted = {rows[n]: n for n in judged if n in rows}
    runs: dict[str, list[Run]] = {}
    reads: dict[str, set[str]] = {}
    for run in parse_rows(sheet, set(wanted)):
        n = wanted[run.row]
        runs.setdefault(n, []).append(run)
        got = reads.setdefault(n, set())
        for ref in cast(list, run.refs):   # parse_rows returns only parsed runs: refs is set
            if ref.sheet not in (None, sheet.name):
                continue
            r1 = ref.r1 if ref.r1_abs else run.row + ref.r1
            r2 = ref.r2 if ref.r2_abs else run.row + ref.r2
            got |= {name_at[r] for r in range(min(r1, r2), max(r1, r2) + 1) if r in name_at}
        got.discard(n)
    cols = {n: np.unique(np.concatenate([run.cols for run in rs])) for n, rs in runs.items()}
    plan = _Plan(sheet.formulas, rows, runs, cols, reads)
    return _PLANS.keep(key, plan)


# --------------------------------------------------------------------------- judging
# A judged cell's state (Judgement.state, _compare): right on its own inputs; a typed number
# off by more than rounding but within its digits; wrong.
CELL_RIGHT, CELL_ROUNDED, CELL_WRONG = 0, 1, 2


@dataclass
class Judgement:
    """One row judged on its own inputs: per judged column (cols) 0 right, 1 rounded (a
    typed number off its inputs' value by more than rounding but within its digits), 2
    wrong; local is "right", "wrong", or "" (not judged: it reads a missing or empty row)."""
    name: str
    local: LocalJudgement = ""
    cols: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    state: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int8))
    typed: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))

    def flagged(self, states=(CELL_ROUNDED, CELL_WRONG)) -> list[int]:
        """Columns whose state is one of states."""
        return [int(c) for c, s in zip(self.cols, self.state, strict=False) if s in states]


@dataclass
class Local:
    """The student's values in the reference's layout, every judged row's reference formula
    over them, and the judgements; the reference's own values for the downstream errors."""
    plan: _Plan
    student_rows: dict[str, int]
    num: np.ndarray                  # the student's values (reference layout)
    tag: np.ndarray
    txt: np.ndarray
    lnum: np.ndarray                 # the reference formulas over them
    ltag: np.ndarray
    rnum: np.ndarray                 # the reference
    rtag: np.ndarray
    rtxt: np.ndarray
    judgements: dict[str, Judgement] = field(default_factory=dict)
    same: np.ndarray | None = None   # per cell: the student's value equals the reference's
    periods: dict[str, float] = field(default_factory=dict)    # angle rows: name -> a full turn
    columns: dict[int, int] = field(default_factory=dict)      # issued column -> the student's (layout)

    def carried(self, name: str, cols: list[int]) -> set[int]:
        """Positions (from 1) among columns `cols` where a row differs from the reference:
        the error it passes down; every position for a value of column D."""
        r = self.plan.rows[name]
        same = cast(np.ndarray, self.same)   # judge sets it before name_causes asks
        off = [int(c) for c in cols if not same[r, c]]
        if off and off[0] == VALUE_COL:
            return set(range(1, self.num.shape[1] - FIRST_COL + 1))
        return {c - FIRST_COL + 1 for c in off}

    def value(self, name: str, col: int, which: str = "student"):
        """A cell as Book.value gives it, from the student's values or the reference's."""
        r = self.plan.rows[name]
        num, tag, txt = (self.num, self.tag, self.txt) if which == "student" else (self.rnum, self.rtag, self.rtxt)
        return _py(num, tag, txt, r, col)

    def local_value(self, name: str, col: int):
        r = self.plan.rows[name]
        return _py(self.lnum, self.ltag, None, r, col)

    def cell(self, name: str, col: int) -> str:
        """The student's cell of a row: G72."""
        return f"{get_column_letter(self.columns.get(col, col))}{self.student_rows[name]}"

    def changed(self, name: str) -> bool:
        """Whether the student's value of an input (column D) differs from the reference's."""
        if name not in self.plan.rows or name not in self.student_rows:
            return False
        return self.value(name, VALUE_COL) != self.value(name, VALUE_COL, "reference")

    def row_error(self, name: str, at: list[int] | None = None) -> float:
        """Largest difference of a row from the reference (in columns `at`, default all),
        relative to the row's size."""
        r = self.plan.rows.get(name)
        cols = self.plan.cols.get(name)
        if r is None or cols is None:
            return 0.0
        scale_cols = cols
        if at is not None:
            cols = np.intersect1d(cols, at)
        rs = self.rnum[r, scale_cols][self.rtag[r, scale_cols] == NUM]
        scale = float(np.abs(rs).max()) if rs.size else 0.0
        s, st, ref, rt = self.num[r, cols], self.tag[r, cols], self.rnum[r, cols], self.rtag[r, cols]
        if ((rt == NUM) != (st == NUM)).any():
            return np.inf
        both = (rt == NUM) & (st == NUM)
        if not both.any():
            return 0.0
        d = angle_difference(np.abs(s[both] - ref[both]), self.periods.get(name))
        return float(d.max() / scale) if scale > 0 else float(d.max())


def _py(num, tag, txt, r: int, c: int):
    t = int(tag[r, c])
    if t == NUM:
        return float(num[r, c])
    if t == BOOL:
        return bool(num[r, c])
    if t == TEXT:
        return None if txt is None else txt[r, c]
    if t == EMPTY:
        return None
    return ERROR_TEXT[t]


def _student_store(reference: Book, student: Book, sheet: str, plan: _Plan, names: dict[str, int]):
    """The reference's value stores with every named row the student has replaced by the
    student's values (from column D on; a formula we cannot evaluate: its cached value)."""
    rs = reference.order[0]
    num, tag, txt = reference.num[rs].copy(), reference.tag[rs].copy(), reference.txt[rs].copy()
    s_num, s_tag, s_txt = student.num[sheet], student.tag[sheet], student.txt[sheet]
    pairs = [(plan.rows[n], names[n]) for n in plan.rows if n in names]
    if not pairs:
        return num, tag, txt
    rr = np.array([p[0] for p in pairs])
    sr = np.array([p[1] for p in pairs])
    nc = num.shape[1]
    w = min(nc, s_num.shape[1])
    tag[rr, VALUE_COL:] = EMPTY
    num[rr, VALUE_COL:] = 0.0
    inside = sr < s_num.shape[0]
    if w > VALUE_COL and inside.any():
        a, b = rr[inside][:, None], sr[inside][:, None]
        cs = np.arange(VALUE_COL, w)[None, :]
        num[a, cs], tag[a, cs], txt[a, cs] = s_num[b, cs], s_tag[b, cs], s_txt[b, cs]
        cached = student.sheets[sheet].cached
        for i, j in zip(*np.nonzero(tag[a, cs] == NAME), strict=False):
            r_ref, r_st, c = int(a[i, 0]), int(b[i, 0]), int(cs[0, j])
            if (r_st, c) in cached:
                store_value(num, tag, txt, r_ref, c, cached[(r_st, c)])   # as the validator grades it
    return num, tag, txt


def _compare(name: str, s, st, lv, lt, typed, tol, period: float | None = None) -> np.ndarray:
    """Per cell 0 right, 1 rounded, 2 wrong: the student's values (s, st) against the
    reference formula's over them (lv, lt); typed cells within tol (their digits)."""
    out = np.full(len(s), CELL_WRONG, np.int8)
    both = (st == NUM) & (lt == NUM)
    d = angle_difference(np.abs(s - lv), period)      # angles: 0 and 360 agree
    with np.errstate(invalid="ignore"):
        tight = d <= np.maximum(ATOL, RTOL * np.abs(lv))
        out[both & tight] = CELL_RIGHT
        out[both & ~tight & typed & (d <= tol)] = CELL_ROUNDED
    out[(lt == BOOL) & (st == BOOL) & (s == lv)] = CELL_RIGHT
    out[(lt != NUM) & (lt != BOOL) & (st != NUM)] = CELL_RIGHT   # a marker or an error: any non-number
    return out


def judge(reference: Book, student: Book, sheet: str, names: dict[str, int], judged: list[str],
          unavailable: Set[str] = frozenset(), periods: dict[str, float] | None = None,
          columns: dict[int, int] | None = None) -> Local:
    """Each of the rows `judged` (names, in sheet order) judged on the student's own values.
    reference: the evaluated reference (its first sheet is the generated sheet, formulas
    and all); student: the student's evaluated workbook, `sheet` its graded sheet, `names`
    its rows by name (column A); unavailable: rows missing or empty in the student's sheet;
    periods: the angle rows' full turn (TURN by unit), compared modulo it; columns: where
    the student's columns are (sheetkin/course/layout.py), to name their cells."""
    ref_sheet = reference.sheets[reference.order[0]]
    plan = _plan(ref_sheet, tuple(judged))
    num, tag, txt = _student_store(reference, student, sheet, plan, names)
    rs = reference.order[0]
    local = Local(plan, names, num, tag, txt, np.zeros_like(num), np.full(tag.shape, EMPTY, np.int8),
                  reference.num[rs], reference.tag[rs], reference.txt[rs], periods=dict(periods or {}),
                  columns=dict(columns or {}))
    missing = set(unavailable) | {n for n in plan.rows if n not in names}
    todo = [n for n in judged if n in plan.runs and n in names and n not in missing
            and not (plan.reads[n] & missing)]
    # a row equal to the reference, reading only rows equal to the reference, is right on
    # its inputs without evaluating it (most rows of most books: the cost stays small)
    local.same = _same_cells(local)
    exact = cast(np.ndarray, local.same.all(axis=1))   # a 2-D array reduced along one axis
    for n in todo:
        if exact[plan.rows[n]] and all(exact[plan.rows[x]] for x in plan.reads[n]):
            cols = plan.cols[n]
            z = np.zeros(len(cols), np.int8)
            local.judgements[n] = Judgement(n, "right", cols, z, z.astype(bool))
    todo = [n for n in todo if n not in local.judgements]
    _evaluate_into(local, [run for n in todo for run in plan.runs[n]], local.lnum, local.ltag)
    st_sheet = student.sheets[sheet]
    tols: dict[str, np.ndarray] = {}
    for n in todo:
        r, sr, cols = plan.rows[n], names[n], plan.cols[n]
        s, st = num[r, cols], tag[r, cols]
        # typed: a value without a formula (an empty cell is judged, but is not a number typed)
        typed = np.array([not st_sheet.computed(sr, int(c)) for c in cols]) & (st != EMPTY)
        tol = np.zeros(len(cols))
        for i in np.flatnonzero(typed & (st == NUM)):
            tol[i] = typed_tolerance(float(s[i]))
        tols[n] = tol
        local.judgements[n] = Judgement(n, "", cols, np.zeros(len(cols), np.int8), typed)
    prop = _propagated(local, todo, tols)
    for n in todo:
        j, r = local.judgements[n], plan.rows[n]
        j.state = _compare(n, num[r, j.cols], tag[r, j.cols], local.lnum[r, j.cols], local.ltag[r, j.cols],
                           j.typed, tols[n] + prop.get(n, 0.0), local.periods.get(n))
        j.local = "wrong" if (j.state == CELL_WRONG).any() else "right"
    for n in judged:
        local.judgements.setdefault(n, Judgement(n))
    return local


def _same_cells(local: Local) -> np.ndarray:
    """Per cell of the reference's layout: whether the student's value equals the
    reference's (numbers to RTOL, ATOL; booleans exactly; any two non-numbers); columns
    before D are not compared (True)."""
    s, st, r, rt = local.num, local.tag, local.rnum, local.rtag
    with np.errstate(invalid="ignore"):
        close = np.abs(s - r) <= np.maximum(ATOL, RTOL * np.abs(r))
    same = np.where(rt == NUM, (st == NUM) & close,
                    np.where(rt == BOOL, (st == BOOL) & (s == r), (st != NUM) & (st != BOOL)))
    same[:, :VALUE_COL] = True
    return same


def _evaluate_into(local: Local, runs: list[Run], lnum: np.ndarray, ltag: np.ndarray) -> None:
    for run, n, t in evaluate_runs(runs, *_stores(local, runs)):
        lnum[run.row, run.cols] = n
        ltag[run.row, run.cols] = t


def _stores(local: Local, runs: list[Run]):
    name = runs[0].sheet if runs else ""
    return {name: local.num}, {name: local.tag}, {name: local.txt}


def _propagated(local: Local, todo: list[str], tols: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """What the typed digits of the rows above carry into each typed cell: every row whose
    typed numbers are coarser than formula precision is moved by their half units once, and
    the change of the typed cells of the rows reading it is added up (|d row/d input| x
    half unit, summed over inputs: a bound to first order)."""
    plan = local.plan
    out: dict[str, np.ndarray] = {}
    typed_rows = [n for n in todo if local.judgements[n].typed.any()]
    for x in todo:
        r, cols, tol = plan.rows[x], plan.cols[x], tols[x]
        coarse = tol > np.maximum(ATOL, RTOL * np.abs(local.num[r, cols]))
        if not coarse.any():
            continue
        users = [y for y in typed_rows if x in plan.reads[y]]
        if not users:
            continue
        saved = local.num[r, cols].copy()
        local.num[r, cols] = saved + np.where(coarse, tol, 0.0)
        moved_num, moved_tag = np.zeros_like(local.lnum), np.full(local.ltag.shape, EMPTY, np.int8)
        _evaluate_into(local, [run for y in users for run in plan.runs[y]], moved_num, moved_tag)
        local.num[r, cols] = saved
        for y in users:
            ry, cy = plan.rows[y], plan.cols[y]
            ok = (moved_tag[ry, cy] == NUM) & (local.ltag[ry, cy] == NUM)
            change = np.where(ok, np.abs(moved_num[ry, cy] - local.lnum[ry, cy]), 0.0)
            out[y] = out.get(y, 0.0) + np.nan_to_num(change, nan=0.0, posinf=0.0)
    return out


# --------------------------------------------------------------------------- causes
def typed_note(local: Local, name: str, dependents: list[str]) -> str:
    """One line for a typed number that is a cause: its cell, the number, its digits, what
    its inputs give when it is off by more than its digits, and the largest relative
    difference from the reference of the rows that depend on it."""
    j = local.judgements[name]
    flagged = [c for c, s, t in zip(j.cols, j.state, j.typed, strict=False) if s in (CELL_ROUNDED, CELL_WRONG) and t]
    c = int(flagged[0])
    got = local.value(name, c)
    what = (message("typed_digits", v=typed_text(got), d=typed_digits(got)) if isinstance(got, float)
            else f"typed {got!r}")
    if j.state[list(j.cols).index(c)] == CELL_WRONG:
        lv = local.local_value(name, c)
        what += " " + message("inputs_give", v=f"{lv:.6g}") if isinstance(lv, float) else ""
    more = message("and_more_typed_cells", n=len(flagged) - 1) if len(flagged) > 1 else ""
    at = None if c == VALUE_COL else flagged          # a derived value: every position
    if not dependents:
        below = message("no_row_depends_on")
    else:
        below = message("downstream_rows_differ_up", v=magnitude(max(local.row_error(d, at) for d in dependents)))
    return f"{local.cell(name, c)} {name} {what}{more}: {below}"


def name_causes(rows: list, local: Local, ancestors: dict[str, set[str]], inputs: set[str], new_row) -> None:
    """Set local, cause, note and because_of of the validator's rows (RowReport: name,
    status, cause, ...), the causes as the module's docstring says; a cause whose
    comparison with the reference passed becomes wrong at its flagged cells. A derived
    value (column D) that is a cause gets a row of its own, new_row(name, column) -> row,
    appended. The other wrong rows are wrong because of the causes above them, or of given
    data (inputs) that differ from the reference's."""
    by = {r.name: r for r in rows}
    wrong = {r.name: set(r.wrong_cells) for r in rows if r.status == "wrong"}
    below: dict[str, list[str]] = {}
    for r in rows:
        if r.status in ("correct", "wrong"):
            for a in ancestors.get(r.name, ()):
                below.setdefault(a, []).append(r.name)
    causes = _find_causes(rows, by, local, wrong, below, new_row)
    _note_typed_causes(by, local, causes, below, ancestors)
    _name_because_of(rows, local, causes, ancestors, inputs)


def _find_causes(rows: list, by: dict, local: Local, wrong: dict[str, set[int]],
                 below: dict[str, list[str]], new_row) -> list[str]:
    """The causes, in the judged rows' order: each row's local judgement set on its report;
    a cause marked (cause, local "wrong"; wrong at its flagged cells if its comparison with
    the reference passed; a derived value's new row appended to rows)."""
    causes: list[str] = []
    explained: set[tuple[str, int]] = set()
    for n, j in local.judgements.items():
        rep = by.get(n)
        if rep is not None:
            rep.local = j.local
        if not j.local:
            continue
        wrong_below = [d for d in below.get(n, ()) if d in wrong]
        off = {c - FIRST_COL + 1 for c in j.flagged((CELL_WRONG,))}
        if rep is not None and rep.status == "wrong" and off & wrong[n]:
            named = True                       # a cell wrong, and wrong on its own inputs: a mistake
            explained |= {(d, k) for d in wrong_below for k in wrong[d] if k in wrong[n]}
        elif j.local == "wrong" or (j.state == CELL_ROUNDED).any():
            # a cell right to its digits, or right but not on the student's inputs, or a
            # derived value: a cause where the error it carries down (its flagged cells
            # that differ from the reference) makes a cell below it wrong that nothing
            # above accounts for
            carried = local.carried(n, j.flagged())
            cells = {(d, k) for d in wrong_below for k in wrong[d] if k in carried}
            named = bool(cells - explained)
            explained |= cells
        else:
            continue
        if not named:
            continue
        if rep is None:
            rep = by[n] = new_row(n, int(j.cols[0]))
            rows.append(rep)
        rep.cause = True
        rep.local = j.local = "wrong"          # a rounded number is not right to formula precision
        causes.append(n)
        if rep.status != "wrong":
            _mark_wrong(rep, local, j)
    return causes


def _note_typed_causes(by: dict, local: Local, causes: list[str], below: dict[str, list[str]],
                       ancestors: dict[str, set[str]]) -> None:
    """The error a typed number carries: in the rows below it alone (the cause's note)."""
    for n in causes:
        j = local.judgements[n]
        if any(s in (CELL_ROUNDED, CELL_WRONG) and t for s, t in zip(j.state, j.typed, strict=False)):
            mine = [d for d in below.get(n, ()) if not any(c in ancestors.get(d, ()) for c in causes if c != n)]
            by[n].note = typed_note(local, n, mine or below.get(n, []))


def _name_because_of(rows: list, local: Local, causes: list[str], ancestors: dict[str, set[str]],
                     inputs: set[str]) -> None:
    """The other wrong rows: wrong because of the causes above them, or of given data that
    differ from the reference's; a row not judged, because of what is wrong above it."""
    changed = [n for n in inputs if local.changed(n)]
    bad = {r.name for r in rows if r.status in ("wrong", "missing", "empty")}
    for rep in rows:
        if rep.status != "wrong" or rep.cause:
            continue
        anc = ancestors.get(rep.name, set())
        rep.because_of = [c for c in causes if c in anc] + [c for c in changed if c in anc]
        if not rep.because_of:     # a row not judged: what is missing, empty or wrong above it
            rep.because_of = [n for n in (x.name for x in rows) if n in anc & bad
                              and not (ancestors.get(n, set()) & bad)]
        if not rep.because_of and not rep.local:
            rep.cause = True       # not judged, nothing above it wrong: the old rule


def _mark_wrong(rep, local: Local, j: Judgement) -> None:
    """A cause the comparison with the reference passed (a number right to its digits, a
    derived value) is wrong: at its flagged cells (positions counted from 1; a derived
    value in column D has none)."""
    flagged = j.flagged()
    positions = [c - FIRST_COL + 1 for c in flagged if c >= FIRST_COL]
    rep.status = "wrong"
    rep.wrong_cells = sorted(set(rep.wrong_cells) | set(positions))
    rep.first_wrong = rep.wrong_cells[0] if rep.wrong_cells else None
    c = flagged[0] if not positions else FIRST_COL + rep.first_wrong - 1
    rep.expected, rep.got = local.value(rep.name, c, "reference"), local.value(rep.name, c)
