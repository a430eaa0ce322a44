"""A workbook the student built from scratch (issue 33): its table found by value, graded.

The lecture's step 7 has the student program the task themselves, row by row; many teachers
hand out only the scheme and its given data. Such a book has no embedded scene and none of
sheetkin's row names, so nothing of the issued layout can be assumed. Knowing the variant
(`--scene FILE`, or the roster and the class assignment naming the student's variant), this
module:

1. evaluates every sheet of the book and indexes its numbers by value (one sorted array:
   a look-up is a binary search, so a book of 100k cells costs a sort, not a search per cell);
2. finds the crank positions (phi_1 in degrees or radians, a row or a column), and each
   quantity of the lecture (the reference of the variant, sheetkin's own workbook evaluated)
   as a row or a column of cells equal to the reference at every position, in the units a
   student uses (m or mm, rad or degrees; angles modulo a turn): the quantity's largest
   reference value is looked up, and only the lines through the cells holding it are compared;
3. finds the given data by value (typed numbers, or Russian texts "0,144") and label;
4. confirms each match by behaviour: the located given data are nudged (each length by its
   own small factor, the crank speed too; every typed cell holding the value, so whichever
   copy the formulas read moves), the book is evaluated again, and each matched line
   must follow the reference of the nudged variant (a private re-evaluation here,
   `_reevaluate_nudged`, to be unified with sheetkin/course/behaviour.py at merge); a line
   the nudge does not move (Fi, cos_1 ...) must be formulas reaching the given data
   (sheetkin.xlsx.precedents), as the validator asks of an issued book;
5. grades the lecture's required quantities (`required`): computed right, typed (or formulas
   that do not follow the given data), wrong (the nearest line on the table's axis named, with
   the position where it departs), missing. Intermediate rows (P, Q, D, cos, psi+-...) and
   check rows (residuals near zero) are recognised where they exist, not required.

The result is the validator's Report (ScratchReport adds the mapping), so the text, JSON, HTML
and grades.csv outputs work unchanged.
"""
from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import numpy as np

from sheetkin.kinematics.scene import Scene, SceneError, load_scene
from sheetkin.sheet.charts import PATHS_SHEET, PLOTTED_SHEET
from sheetkin.sheet.workbook import FIRST_COL, SCENE_SHEET, prefilled_in_exercise
from sheetkin.xlsx.cells import RawBook
from sheetkin.xlsx.coords import get_column_letter
from sheetkin.xlsx.evaluator import Book, evaluate_sheets
from sheetkin.xlsx.precedents import reaching
from sheetkin.xlsx.values import NUM, TEXT

from . import issued
from .book import UnusableInput
from .caches import scene_rows
from .reference import reference_book, variant_scene
from .report_model import Report, RowReport

RTOL, ATOL = 1e-6, 1e-9        # a student's own formulas agree with the solver far closer than this
NUDGE = 0.01                   # the given data are changed by about 1 % (each by its own factor)
MAX_CANDIDATES = 200           # cells holding a quantity's anchor value that are tried, at most

# the lecture's required quantities (its step 7: crank block, joints, groups' angles and their
# derivatives, sliders, points); the rest of sheetkin's rows are one method's intermediates
_REQUIRED = re.compile(r"^(Fi|Fi_t|Fi_tt|(x|y|vx|vy|v|ax|ay|a)_[A-Z]\w*|(phi|omega|eps)_\d+|"
                       r"(s|vs|as|s2|vs2|as2)_[A-Z]\w*)$")
_KINEMATIC_UNITS = {"", "m", "m/s", "m/s^2", "m^2", "rad", "deg", "rad/s", "rad/s^2"}
# the units a student writes a quantity in: (label, factor from the reference's unit, turn)
_UNITS: dict[str, list[tuple[str, float, float | None]]] = {
    "m": [("m", 1.0, None), ("mm", 1000.0, None)],
    "m/s": [("m/s", 1.0, None), ("mm/s", 1000.0, None)],
    "m/s^2": [("m/s^2", 1.0, None), ("mm/s^2", 1000.0, None)],
    "rad": [("rad", 1.0, 2 * math.pi), ("deg", 180 / math.pi, 360.0)],
    "deg": [("deg", 1.0, 360.0), ("rad", math.pi / 180, 2 * math.pi)],
}
_NUDGED_UNITS = {"m": (1.0, 1000.0), "rad/s": (1.0,), "rad/s^2": (1.0,)}
_COMMA_NUMBER = re.compile(r"^\s*[-+]?\d+,\d+\s*$")


@dataclass(frozen=True)
class ScratchOptions(issued.Options):
    """issued.Options with what grading a from-scratch book needs: the variant's scene
    (--scene FILE), or the class assignment that names each student's variant (with the
    roster: its scene files lie beside roster.csv)."""
    scene: Scene | None = None
    assignment: object = None          # sheetkin.course.identity.Assignment


@dataclass
class ScratchReport(Report):
    """The validator's Report of a from-scratch book, with the mapping: for each quantity
    the cells found (sheet, row or column, the student's label, the unit)."""
    mapping: list[dict] = field(default_factory=list)
    given_found: list[dict] = field(default_factory=list)


@dataclass
class Line:
    """n cells of one sheet: a row (axis "row": row `line`, columns start..) or a column."""
    sheet: str
    axis: str
    line: int
    start: int
    n: int

    def cells(self) -> list[tuple[int, int]]:
        return ([(self.line, self.start + k) for k in range(self.n)] if self.axis == "row"
                else [(self.start + k, self.line) for k in range(self.n)])

    def where(self) -> str:
        (r0, c0), (r1, c1) = self.cells()[0], self.cells()[-1]
        return f"{self.sheet}!{get_column_letter(c0)}{r0}:{get_column_letter(c1)}{r1}"


@dataclass
class Found:
    line: Line
    unit: str
    scale: float
    turn: float | None
    label: str = ""


# --------------------------------------------------------------------------- the quantities
@dataclass
class Quantity:
    name: str
    unit: str
    required: bool
    ref: np.ndarray                 # the reference at every position, in the sheet's unit


def quantities(scene: Scene, ref: Book) -> list[Quantity]:
    """The rows of positions sheetkin's workbook has for the scene (its reference), minus
    the check rows and those the exercise gives filled in; each marked required or not."""
    sheet = ref.order[0]
    rows = {ref.sheets[sheet].consts.get((r, 1)): r for r in range(5, ref.sheets[sheet].max_row + 1)}
    n = scene.crank.positions
    out = []
    for r in scene_rows(scene):
        if r.kind not in ("calc", "accepted") or prefilled_in_exercise(r.name, r.kind) or r.name not in rows:
            continue
        if r.unit not in _KINEMATIC_UNITS:
            continue                    # dynamics (forces, energies): not the lecture's step 7
        vals = [ref.value(sheet, rows[r.name], FIRST_COL + k) for k in range(n)]
        v = np.array([x if isinstance(x, float) else np.nan for x in vals])
        out.append(Quantity(r.name, r.unit, bool(_REQUIRED.match(r.name)), v))
    return out


def _positions_ref(scene: Scene) -> np.ndarray:
    return np.asarray(scene.crank_angles_deg(), dtype=float)


# --------------------------------------------------------------------------- the book's numbers
@dataclass
class _Index:
    """Every number of the evaluated book, sorted: a look-up is a binary search."""
    values: np.ndarray
    sheet: np.ndarray
    row: np.ndarray
    col: np.ndarray
    names: list[str]

    @classmethod
    def of(cls, book: Book, skip: frozenset[str] = frozenset()) -> _Index:
        vs, ss, rs, cs = [], [], [], []
        names = [n for n in book.order if n not in skip]
        for k, s in enumerate(names):
            rr, cc = np.nonzero(book.tag[s] == NUM)
            vs.append(book.num[s][rr, cc])
            ss.append(np.full(len(rr), k, np.int32))
            rs.append(rr)
            cs.append(cc)
        v = np.concatenate(vs) if vs else np.zeros(0)
        order = np.argsort(v, kind="stable")

        def cat(parts):
            return np.concatenate(parts)[order] if parts else np.zeros(0, np.int64)
        return cls(v[order], cat(ss), cat(rs), cat(cs), names)

    def near(self, x: float, tol: float) -> range:
        lo = int(np.searchsorted(self.values, x - tol, "left"))
        hi = int(np.searchsorted(self.values, x + tol, "right"))
        return range(lo, hi)


def _tol(x: np.ndarray | float) -> np.ndarray:
    return np.maximum(ATOL, RTOL * np.abs(x))


def _agree(got: np.ndarray, exp: np.ndarray, turn: float | None) -> np.ndarray:
    """Cell by cell: the student's number equals the reference (angles modulo a turn);
    where the reference is not a number (cannot assemble), anything but a number does."""
    d = np.abs(got - exp)
    if turn:
        d = np.abs((got - exp + turn / 2) % turn - turn / 2)
    ok = d <= _tol(exp)
    return np.where(np.isnan(exp), np.isnan(got), ok & ~np.isnan(got))


def _line_values(book: Book, ln: Line) -> np.ndarray:
    num, tag = book.num[ln.sheet], book.tag[ln.sheet]
    out = np.full(ln.n, np.nan)
    for k, (r, c) in enumerate(ln.cells()):
        if r < num.shape[0] and c < num.shape[1] and tag[r, c] == NUM:
            out[k] = num[r, c]
    return out


def _label(book: Book, ln: Line) -> str:
    """The student's label of a line: the texts before its first cell (left of a row, above
    a column), nearest last, at most three."""
    txt, tag = book.txt[ln.sheet], book.tag[ln.sheet]
    texts = []
    if ln.axis == "row":
        spots = [(ln.line, c) for c in range(ln.start - 1, 0, -1)]
    else:
        spots = [(r, ln.line) for r in range(ln.start - 1, 0, -1)]
    for r, c in spots:
        if r < tag.shape[0] and c < tag.shape[1] and tag[r, c] == TEXT and str(txt[r, c]).strip():
            texts.append(" ".join(str(txt[r, c]).split())[:40])
            if len(texts) == 3:
                break
    return " | ".join(reversed(texts))


_GREEK = {"φ": "phi", "ф": "phi", "ψ": "psi", "ω": "omega", "ε": "eps", "ξ": "xi", "θ": "theta", "η": "eta"}


def _key(text: str) -> str:
    t = text.split(",")[0].split("|")[-1].strip().lower()
    for g, w in _GREEK.items():
        t = t.replace(g, w)
    return re.sub(r"[^a-z0-9]", "", t.replace("fi", "phi").replace("phiphi", "phi"))


def _name_keys(name: str) -> set[str]:
    aliases = {"Fi": {"phi1", "phi"}, "Fi_t": {"omega1", "phit"}, "Fi_tt": {"eps1", "phitt"}}
    return {_key(name)} | aliases.get(name, set())


# --------------------------------------------------------------------------- locating
@dataclass
class Located:
    positions: Found | None = None
    found: dict[str, list[Found]] = field(default_factory=dict)     # name -> full matches, best first
    # name -> the nearest line, the position (from 0) where it departs, expected, got there,
    # every position (from 1) where it differs
    nearest: dict[str, tuple[Found, int, float, float, list[int]]] = field(default_factory=dict)
    given: dict[str, tuple[str, int, int, float, str]] = field(default_factory=dict)   # name -> cell, scale, label
    # name -> every typed cell holding its value (all are changed by the behavioural check:
    # whichever copy the student's formulas read, they move)
    given_cells: dict[str, list[tuple[str, int, int]]] = field(default_factory=dict)
    checks: list[Line] = field(default_factory=list)
    cells_indexed: int = 0


def _full_matches(book: Book, idx: _Index, ref: np.ndarray, units, axis_hint: Line | None) -> list[Found]:
    """Every row or column of the book equal to `ref` at every position, in one of `units`."""
    n = len(ref)
    finite = np.where(np.isfinite(ref), np.abs(ref), -1.0)
    k = int(np.argmax(finite))
    if finite[k] < 1e-6:
        return []                          # a row of zeros: cannot be told from empty cells
    out: list[Found] = []
    seen: set[tuple] = set()
    for unit, scale, turn in units:
        exp = ref * scale
        x = exp[k]
        targets = [x + m * turn for m in (-2, -1, 0, 1, 2)] if turn else [x]
        for t in targets:
            hits = idx.near(t, float(_tol(t)))
            for h in list(hits)[:MAX_CANDIDATES]:
                s, r, c = idx.names[idx.sheet[h]], int(idx.row[h]), int(idx.col[h])
                for axis, line, start in (("row", r, c - k), ("col", c, r - k)):
                    if start < 1 or (s, axis, line, start) in seen:
                        continue
                    seen.add((s, axis, line, start))
                    ln = Line(s, axis, line, start, n)
                    if bool(_agree(_line_values(book, ln), exp, turn).all()):
                        out.append(Found(ln, unit, scale, turn))
    if axis_hint is not None:
        out.sort(key=lambda f: (f.line.sheet, f.line.axis, f.line.start) != (axis_hint.sheet, axis_hint.axis,
                                                                              axis_hint.start))
    return out


def _is_formula_line(raw: RawBook, ln: Line) -> bool:
    sh = raw.sheets.get(ln.sheet)
    return sh is not None and any(sh.computed(r, c) for r, c in ln.cells())


def locate(raw: RawBook, book: Book, scene: Scene, qs: list[Quantity], skip: frozenset[str] = frozenset()) -> Located:
    """The positions, every quantity's lines, the nearest line of those not found, the given
    data and the check rows (the module's docstring, steps 1-3); no line on the sheets `skip`
    (the issued sheet, when the student's own table is looked for elsewhere)."""
    idx = _Index.of(book, skip)
    out = Located(cells_indexed=len(idx.values))
    n = scene.crank.positions
    pos = _full_matches(book, idx, _positions_ref(scene), _UNITS["deg"], None)
    pos_lines = [p.line for p in pos]
    for q in qs:
        ms = _full_matches(book, idx, q.ref, _UNITS.get(q.unit, [(q.unit, 1.0, None)]), None)
        # a positions line of typed numbers is not a computed quantity (Fi in degrees is phi_1)
        ms = [m for m in ms if not (m.line in pos_lines and not _is_formula_line(raw, m.line))]
        if ms:
            out.found[q.name] = ms
    # the table: the sheet, orientation and first position most quantities share (a book may
    # hold the issued sheet's prefilled positions and the student's own table elsewhere)
    votes: dict[tuple, int] = {}
    for ms in out.found.values():
        for key in {_table_key(m.line) for m in ms}:
            votes[key] = votes.get(key, 0) + 1
    table = max(votes, key=lambda k: votes[k]) if votes else None
    if pos:
        pos.sort(key=lambda p: _table_key(p.line) != table)
        out.positions = pos[0]
    for q in qs:
        found = out.found.get(q.name)
        if not found:
            continue
        ms = found
        for m in ms:
            m.label = _label(book, m.line)
        keys = _name_keys(q.name)
        # formulas before typed numbers, then the table's lines, then the label naming it
        ms.sort(key=lambda m: (not _is_formula_line(raw, m.line), _table_key(m.line) != table,
                               _key(m.label) not in keys))
    axis = out.positions.line if out.positions else None
    if axis is None and table is not None:
        axis = next(m.line for ms in out.found.values() for m in ms if _table_key(m.line) == table)
    taken = {(m.line.sheet, m.line.axis, m.line.line) for ms in out.found.values() for m in ms[:1]}
    if axis is not None:
        _nearest(book, axis, qs, out, taken)
        _check_rows(raw, book, axis, n, out, taken)
    out.given, out.given_cells = _given(raw, book, scene, out)
    return out


def _table_key(ln: Line) -> tuple[str, str, int]:
    return (ln.sheet, ln.axis, ln.start)


def _block(book: Book, axis: Line) -> tuple[np.ndarray, int]:
    """The table's lines on the axis's sheet, orientation and positions: lines x n values."""
    num, tag = book.num[axis.sheet], book.tag[axis.sheet]
    vals = np.where(tag == NUM, num, np.nan)
    if axis.axis == "col":
        vals = vals.T
    block = np.full((vals.shape[0], axis.n), np.nan)
    width = max(0, min(axis.n, vals.shape[1] - axis.start))
    block[:, :width] = vals[:, axis.start:axis.start + width]
    return block, vals.shape[0]


def _nearest(book: Book, axis: Line, qs: list[Quantity], out: Located, taken: set) -> None:
    """For each required quantity: the line on the table's axis whose label names it, else
    (not found) the line that agrees at the most positions; where it departs from the
    reference. For a found quantity it is kept in case the full matches are another quantity
    of equal values that does not follow the given data (v_A = 1 m/s beside omega = 1 rad/s)."""
    block, lines = _block(book, axis)
    labels: dict[int, str] = {}
    units_of = {q.name: _UNITS.get(q.unit, [(q.unit, 1.0, None)]) for q in qs}
    for q in qs:
        if not q.required:
            continue
        found = out.found.get(q.name)
        keys = _name_keys(q.name)
        named: int | None = None
        for ln in range(1, lines):
            if ln == axis.line or np.isnan(block[ln]).all():
                continue
            if ln not in labels:
                labels[ln] = _label(book, Line(axis.sheet, axis.axis, ln, axis.start, axis.n))
            if _key(labels[ln]) in keys:
                named = int(ln)                              # the student's own name for it
                break
        if found and (named is None or any(m.line.axis == axis.axis and m.line.line == named for m in found)):
            continue
        best = None
        for unit, scale, turn in units_of[q.name]:
            agree = _agree(block, (q.ref * scale)[None, :], turn) & ~np.isnan(block)
            score = agree.sum(axis=1)
            if named is not None:
                cand = (int(score[named]), unit, scale, turn, named)
                best = cand if best is None or cand[0] > best[0] else best
                continue
            for j in np.nonzero(score)[0]:
                if (axis.sheet, axis.axis, int(j)) in taken or j == axis.line:
                    continue
                cand = (int(score[j]), unit, scale, turn, int(j))
                if best is None or cand[0] > best[0]:
                    best = cand
        if best is None:
            continue
        _, unit, scale, turn, ln = best
        line = Line(axis.sheet, axis.axis, ln, axis.start, axis.n)
        exp = q.ref * scale
        got = block[ln]
        bad = np.nonzero(~_agree(got, exp, turn))[0]
        if not len(bad):
            if not found:      # a row of zeros (Fi_tt at a constant speed) the label names: found
                out.found[q.name] = [Found(line, unit, scale, turn, labels.get(ln, ""))]
                taken.add((axis.sheet, axis.axis, ln))
            continue
        k = int(bad[0])
        out.nearest[q.name] = (Found(line, unit, scale, turn, _label(book, line)), k, float(exp[k]), float(got[k]),
                               [int(j) + 1 for j in bad])


def _check_rows(raw: RawBook, book: Book, axis: Line, n: int, out: Located, taken: set) -> None:
    """Lines of formulas on the table's axis whose every number is near zero: the student's
    check rows (residuals of a constraint), recognised, not graded."""
    block, lines = _block(book, axis)
    for ln in range(1, lines):
        v = block[ln]
        if (axis.sheet, axis.axis, ln) in taken or np.isnan(v).sum() > n // 2:
            continue
        if np.nanmax(np.abs(v)) <= 1e-6:
            line = Line(axis.sheet, axis.axis, ln, axis.start, n)
            if _is_formula_line(raw, line):
                out.checks.append(line)


def _in_table(loc: Located, s: str, r: int, c: int) -> bool:
    """Whether a cell lies across the table's positions (a typed position number i = 10 is
    not the crank speed 10 rad/s)."""
    p = loc.positions.line if loc.positions else None
    if p is None or p.sheet != s:
        return False
    k = c if p.axis == "row" else r
    return p.start <= k < p.start + p.n


def _given(raw: RawBook, book: Book, scene: Scene, loc: Located) -> tuple[dict, dict]:
    """The cells holding the variant's given data: typed numbers (or Russian texts "0,144")
    equal to a given value in m or mm (rad/s for the crank speed), outside the matched lines;
    among several, the one whose label names it, else the first in reading order."""
    units = {r.name: r.unit for r in scene_rows(scene) if r.kind == "input"}
    inside = {(m.line.sheet, rc) for ms in loc.found.values() for m in ms for rc in m.line.cells()}
    if loc.positions:
        inside |= {(loc.positions.line.sheet, rc) for rc in loc.positions.line.cells()}
    typed: list[tuple[str, int, int, float]] = []
    for s in book.order:
        sh = raw.sheets.get(s)
        if sh is None:
            continue
        for (r, c), v in sh.consts.items():
            if (s, (r, c)) in inside or _in_table(loc, s, r, c):
                continue
            if isinstance(v, float):
                typed.append((s, r, c, v))
            elif isinstance(v, str) and _COMMA_NUMBER.match(v):
                typed.append((s, r, c, float(v.replace(",", "."))))
    # sorted by value: each given value is a binary search, not a pass over the book
    vals = np.array([t[3] for t in typed])
    order = np.argsort(vals, kind="stable")
    vals = vals[order]
    sheet_at = {s: k for k, s in enumerate(book.order)}
    out, every = {}, {}
    table = loc.positions.line.sheet if loc.positions else ""
    for name, value in issued.given_values(scene).items():
        if name not in ("Fi0", "Delta_Fi") and (units.get(name) not in _NUDGED_UNITS or value == 0):
            continue
        if value == 0:
            continue
        scales = _NUDGED_UNITS.get(units.get(name, ""), (1.0, math.pi / 180))
        hits = []
        for sc in scales:
            x, tol = value * sc, 1e-9 * abs(value * sc)
            lo, hi = np.searchsorted(vals, x - tol, "left"), np.searchsorted(vals, x + tol, "right")
            hits += [(*typed[int(order[j])][:3], sc) for j in range(int(lo), int(hi))]
        hits.sort(key=lambda h: (sheet_at.get(h[0], 0), h[1], h[2]))          # reading order
        if not hits:
            continue
        def named(h, name=name):
            ln = Line(h[0], "row", h[1], h[2], 1)
            return _key(_label(book, ln)) != _key(name)
        hits.sort(key=lambda h: (named(h), h[0] != table))     # its label, then the table's sheet
        s, r, c, sc = hits[0]
        out[name] = (s, r, c, sc, _label(book, Line(s, "row", r, c, 1)))
        every[name] = [(h[0], h[1], h[2]) for h in hits]
    return out, every


# --------------------------------------------------------------------------- the behaviour
def _evaluate(raw: RawBook, replace: Mapping[tuple[str, int, int], object] | None = None) -> Book:
    """The book's sheets evaluated (sheetkin's hidden sheets left out), with some typed cells
    replaced."""
    sheets = {n: sh for n, sh in raw.sheets.items() if n not in (PATHS_SHEET, PLOTTED_SHEET, SCENE_SHEET)}
    for (s, r, c), v in (replace or {}).items():
        sh = sheets[s]
        consts = dict(sh.consts)
        consts[(r, c)] = v
        sheets[s] = dataclasses.replace(sh, consts=consts)
    return evaluate_sheets(raw.path, sheets, [n for n in raw.order if n in sheets], raw.names, strict=False)


def _reevaluate_nudged(raw: RawBook, scene: Scene, loc: Located) -> tuple[Book, Book, dict] | None:
    """Private re-evaluation (to be unified with sheetkin/course/behaviour.py at merge):
    each located given cell changed by its own small factor, the book evaluated again, and
    the reference of the nudged variant; None when nothing could be nudged or the nudged
    mechanism does not assemble as the variant does at every position."""
    given = issued.given_values(scene)
    units = {r.name: r.unit for r in scene_rows(scene) if r.kind == "input"}
    # one factor per given value (names of equal value share their cells, so their factor)
    values: dict[float, list[str]] = {}
    for name in loc.given:
        if units.get(name) in _NUDGED_UNITS:
            values.setdefault(given[name], []).append(name)
    if not values:
        return None
    base = reference_book(scene)
    for size in (NUDGE, NUDGE / 4, NUDGE / 16):
        by_value = {v: 1 + size * (1 + 0.37 * j) * (-1) ** j for j, v in enumerate(values)}
        inputs = {n: given[n] * by_value[v] for v, names in values.items() for n in names}
        factors = {cell: by_value[v] for v, names in values.items() for n in names for cell in loc.given_cells[n]}
        try:
            nudged = variant_scene(scene, inputs, scene.crank.positions, {})
            ref = reference_book(nudged)
        except (SceneError, UnusableInput, ValueError):
            continue
        if _same_assembly(base, ref):
            replace = {}
            for (s, r, c), f in factors.items():
                v = raw.sheets[s].consts[(r, c)]
                if isinstance(v, str):
                    replace[(s, r, c)] = repr(float(v.replace(",", ".")) * f).replace(".", ",")
                else:
                    replace[(s, r, c)] = float(v) * f
            return _evaluate(raw, replace), ref, {k: v for k, v in factors.items()}
    return None


def _same_assembly(a: Book, b: Book) -> bool:
    """The nudged reference has numbers where the variant's has, and its link angles moved
    by less than 20 degrees (the same branch)."""
    sa, sb = a.order[0], b.order[0]
    na, nb = a.num[sa], b.num[sb]
    if na.shape != nb.shape or not np.array_equal(a.tag[sa] == NUM, b.tag[sb] == NUM):
        return False
    sheet = a.sheets[sa]
    for r in range(5, sheet.max_row + 1):
        name = sheet.consts.get((r, 1))
        if isinstance(name, str) and re.match(r"^phi_\d+$", name):
            d = np.abs((nb[r] - na[r] + 180) % 360 - 180)
            if np.nanmax(d[FIRST_COL:], initial=0) > 20:
                return False
    return True


# --------------------------------------------------------------------------- grading
def scene_for(path: str, options) -> tuple[Scene | None, str]:
    """The variant a from-scratch book is graded against, and its name: --scene, else the
    roster and the class assignment naming the student (their Moodle folder)."""
    scene = getattr(options, "scene", None)
    if scene is not None:
        return scene, Path(scene.source or "").stem if scene.source else ""
    assignment, roster = getattr(options, "assignment", None), getattr(options, "roster", None)
    if assignment is None or roster is None:
        return None, ""
    from .batch import unpacked_as
    from .classlist import moodle_submitter
    sub = moodle_submitter(unpacked_as(path))      # a book from a zip: its entry's Moodle folder
    if sub is None:
        return None, ""
    people = assignment.as_class_list().match(sub.name)
    idents = {p.ident for p in people}
    if len(idents) != 1:
        return None, ""
    _, vid, _ = assignment.people[idents.pop()]
    files = roster.files.get(vid)
    if not files:
        return None, ""
    p = Path(roster.path).parent / files["scene"]
    if not p.is_file():
        raise UnusableInput(f"{path}: the variant {vid} of its student: no scene file {p}")
    return load_scene(str(p)), vid


def scratch_options(options: issued.Options, scene_path: str | None, roster_path: str | None) -> issued.Options:
    """`validate --scene FILE`, or --roster with the class assignment beside it: the options
    grade_book needs (the CLI's one call); the options unchanged otherwise."""
    from .identity import find_assignment
    scene = load_scene(scene_path) if scene_path else None
    assignment = find_assignment(roster_path) if roster_path and scene is None else None
    if scene is None and assignment is None:
        return options
    fields = {f.name: getattr(options, f.name) for f in dataclasses.fields(issued.Options)}
    return ScratchOptions(**fields, scene=scene, assignment=assignment)


def own_table(raw: RawBook, path: str, options, report: Report) -> Report:
    """An issued book whose issued sheet is left empty: the student's own table on another
    sheet, found and graded against the issued variant (its identity and seal kept); the
    issued report when no table is found or the issued sheet holds work."""
    scene = report.variant_scene
    from .grades import graded_rows  # the rows the exercise gives filled in are not work
    if report.error or scene is None or any(r.status not in ("missing", "empty") for r in graded_rows(report)):
        return report
    layout = report.layout
    try:        # the issued sheet (its given data, its prefilled positions) is not the student's table
        mine = grade_book(raw, path, options, scene=scene, skip=frozenset({layout.sheet}) if layout else frozenset())
    except (UnusableInput, SceneError):
        return report
    if all(r.status == "missing" for r in mine.rows):
        return report
    for name in ("student", "group", "variant", "given_changed", "seal", "accepted_changes", "issued_to"):
        setattr(mine, name, getattr(report, name))
    table = next((m["cells"].split("!")[0] for m in mine.mapping if m.get("status") == "found"), "?")
    mine.notes = ([f"the issued sheet {layout.sheet if layout else ''} is empty: the student's own table on "
                   f"sheet {table} is graded (found by value)"] + report.notes + mine.notes)
    mine.lang = report.lang or "ru"
    return mine


def applies(options) -> bool:
    """Whether a book without sheetkin's embedded scene can be graded from scratch."""
    return getattr(options, "scene", None) is not None or (
        getattr(options, "assignment", None) is not None and getattr(options, "roster", None) is not None)


def grade_book(raw: RawBook, path: str, options, scene: Scene | None = None,
               skip: frozenset[str] = frozenset()) -> ScratchReport:
    """The Report of a book built from scratch (the module's docstring); its table is not
    looked for on the sheets `skip`."""
    vid = ""
    if scene is None:
        scene, vid = scene_for(path, options)
    if scene is None:
        raise UnusableInput(f"{path}: no embedded scene, and no variant known for it (--scene FILE, or --roster "
                            "with assignment.csv and the book in its student's Moodle folder)")
    book = _evaluate(raw)
    ref = reference_book(scene)
    qs = quantities(scene, ref)
    loc = locate(raw, book, scene, qs, skip)
    notes = []
    turn = _positions_ref(scene)
    if loc.positions is None and len(turn) > 2 and abs(abs(turn[-1] - turn[0]) - 360.0) < 1e-9:
        # the last position is the first one turned by 360 degrees: many students stop before it
        # (0 ... 330); their table, one position short, is graded on the positions it has
        short = dataclasses.replace(scene, crank=dataclasses.replace(scene.crank, positions=len(turn) - 1))
        short_ref = reference_book(short)
        short_qs = quantities(short, short_ref)
        short_loc = locate(raw, book, short, short_qs, skip)
        if short_loc.positions is not None:
            scene, ref, qs, loc = short, short_ref, short_qs, short_loc
            notes.append(f"the table stops one position before the full turn ({len(turn) - 1} positions; the last "
                         f"issued one, {turn[-1]:g} deg, repeats {turn[0]:g} deg): graded on those")
    if loc.positions is None and not loc.found:
        raise UnusableInput(f"{path}: no embedded scene, and no table of the variant{' ' + vid if vid else ''} found "
                            "by value (no row or column of its crank positions or of any quantity)")
    n = scene.crank.positions
    rep = ScratchReport(path, author="", title="", positions=n, problems=list(book.problems)[:20], variant=vid)
    rep.lang, rep.variant_scene, rep.roster_differs = "ru", scene, False
    rep.notes += notes
    for attr in ("checks_total", "checks_apply", "checks_passing", "checks_na", "checks_unfilled"):
        setattr(rep, attr, 0)
    rep.position_names = [(float(k), float(a)) for k, a in enumerate(_positions_ref(scene))]
    nudged = _reevaluate_nudged(raw, scene, loc)
    if nudged is None:
        rep.notes.append("the behavioural check could not run (no given data found by value to change): "
                         "formulas reaching the positions count as computed")
    sources: dict[str, list[tuple[int, int]]] = {}
    for s, r, c, _, _ in loc.given.values():
        sources.setdefault(s, []).append((r, c))
    if loc.positions:
        sources.setdefault(loc.positions.line.sheet, []).extend(loc.positions.line.cells())
    for s, cells in _given_block(raw, loc).items():
        sources.setdefault(s, []).extend(cells)
    reach = reaching(book, cast(dict[str, Iterable[tuple[int, int]]], sources))
    ref_sheet = ref.order[0]
    ref_rows = {ref.sheets[ref_sheet].consts.get((r, 1)): r for r in range(5, ref.sheets[ref_sheet].max_row + 1)}
    qref2 = {}
    if nudged is not None:
        _, ref2, _ = nudged
        s2 = ref2.order[0]
        for q in qs:
            vals = [ref2.value(s2, ref_rows[q.name], FIRST_COL + k) for k in range(n)]
            qref2[q.name] = np.array([x if isinstance(x, float) else np.nan for x in vals])
    for q in qs:
        ms = loc.found.get(q.name)
        graded = None
        # zero at every position (the slider's angle, Fi_tt at a constant speed): such a line
        # cannot be told from empty cells by value, so it is graded only where found by its label
        if q.required and not ms and q.name not in loc.nearest and bool(np.nanmax(np.abs(q.ref), initial=0) < 1e-6):
            rep.mapping.append({"quantity": q.name, "required": False, "status": "not found"})
            continue
        if q.required:
            row, graded = _grade_quantity(q, ms, loc, raw, nudged, qref2.get(q.name), reach)
            rep.rows.append(row)
            if ms and graded is None:
                ms = None                 # its full matches are another quantity's: the nearest line
            elif ms and graded is not None:
                ms = [graded] + [m for m in ms if m is not graded]
        rep.mapping.append(_mapped(q, ms, loc))
        if q.required:
            from .grades import row_verdict
            rep.mapping[-1]["grade"] = row_verdict(rep.rows[-1])
    rep.mapping += [{"quantity": "", "status": "check row", "cells": ln.where(), "label": _label(book, ln),
                     "unit": ""} for ln in loc.checks]
    rep.given_found = [{"name": k, "cell": f"{s}!{get_column_letter(c)}{r}", "label": lab,
                        "unit": "mm" if sc == 1000 else ""} for k, (s, r, c, sc, lab) in loc.given.items()]
    if loc.positions:
        rep.notes.append(f"crank positions: {loc.positions.line.where()} ({loc.positions.unit})")
    else:
        rep.notes.append("crank positions not found (a row or column of the crank's angles in degrees or radians)")
    return rep


def _given_block(raw: RawBook, loc: Located) -> dict[str, list[tuple[int, int]]]:
    """The typed numbers beside the given data found by value (the same column, within five
    rows of them): the given values a search by value cannot find (zeros: x_O, Fi_tt0 = 0)."""
    out: dict[str, list[tuple[int, int]]] = {}
    spans: dict[tuple[str, int], list[int]] = {}
    for s, r, c, _, _ in loc.given.values():
        spans.setdefault((s, c), []).append(r)
    for (s, c), rows in spans.items():
        lo, hi = min(rows) - 5, max(rows) + 5
        out.setdefault(s, []).extend((r, c) for r in range(max(1, lo), hi + 1)
                                     if isinstance(raw.sheets[s].consts.get((r, c)), float))
    return out


def _grade_quantity(q: Quantity, ms: list[Found] | None, loc: Located, raw: RawBook, nudged, ref2,
                    reach) -> tuple[RowReport, Found | None]:
    """The quantity's row report, and the line graded: the first full match that computes
    (follows the nudged given data, or reaches them), else the line its label names."""
    tried = [_grade_line(q, m, raw, nudged, ref2, reach) for m in (ms or [])[:4]]
    for rep, m in zip(tried, ms or [], strict=False):
        if not rep.typed_cells:
            return rep, m
    near = loc.nearest.get(q.name)
    if near is not None and not any(m.line == near[0].line for m in ms or []):
        return _wrong(q, near), None
    if tried:
        keys = _name_keys(q.name)
        k = next((j for j, m in enumerate((ms or [])[:4]) if _key(m.label) in keys), 0)
        return tried[k], (ms or [])[k]
    return RowReport(q.name, None, "missing", kind="calc"), None


def _wrong(q: Quantity, near) -> RowReport:
    f, k, exp, got, wrong = near
    rep = RowReport(q.name, f.line.line, "wrong", kind="calc", first_wrong=k + 1, expected=exp,
                    got=None if math.isnan(got) else got, cause=True, max_error=math.inf)
    rep.wrong_cells = wrong
    rep.note = (f"nearest line {f.line.where()}" + (f" «{f.label}»" if f.label else "")
                + f" ({f.unit}) departs at position {k + 1}: expected {exp:.6g}, got "
                + ("empty" if math.isnan(got) else f"{got:.6g}"))
    return rep


def _grade_line(q: Quantity, m: Found, raw: RawBook, nudged, ref2, reach) -> RowReport:
    """A full match: computed where its formulas follow the nudged given data (or, for a
    line the nudge does not move, reach them); typed elsewhere."""
    rep = RowReport(q.name, m.line.line, "correct", kind="calc")
    sh = raw.sheets[m.line.sheet]
    moved = ref2 is not None and not bool(_agree(ref2, q.ref, None).all())
    follows = None
    if nudged is not None and moved:
        got2 = _line_values(nudged[0], m.line)
        follows = _agree(got2, ref2 * m.scale, m.turn)
    for k, (r, c) in enumerate(m.line.cells()):
        # a formula of constants (=0.5236) neither follows the nudge nor reaches the given data
        if sh.computed(r, c):
            ok = bool(follows[k]) if follows is not None else bool(reach[m.line.sheet][r, c])
            if ok:
                rep.formula_cells += 1
                continue
            rep.reads_typed.append(k + 1)
        rep.typed_cells.append(k + 1)
    if rep.typed_cells:
        rep.source = "typed"
    return rep


def _mapped(q: Quantity, ms: list[Found] | None, loc: Located) -> dict:
    if ms:
        m = ms[0]
        return {"quantity": q.name, "required": q.required, "status": "found", "cells": m.line.where(),
                "axis": m.line.axis, "line": m.line.line, "label": m.label, "unit": m.unit,
                "also": [x.line.where() for x in ms[1:4]]}
    near = loc.nearest.get(q.name)
    if near:
        f, k, _, _, _ = near
        return {"quantity": q.name, "required": q.required, "status": "nearest", "cells": f.line.where(),
                "axis": f.line.axis, "line": f.line.line, "label": f.label, "unit": f.unit, "departs_at": k + 1}
    return {"quantity": q.name, "required": q.required, "status": "not found"}
