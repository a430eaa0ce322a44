"""The reference of a variant: the scene with the student's input block, the workbook
sheetkin generates for it evaluated (cached per structure and inputs), and the dependency
graph of its rows."""
from __future__ import annotations

import dataclasses
import math
import re
from typing import cast

from sheetkin.groups import kind_of
from sheetkin.groups.group import Group
from sheetkin.kinematics.scene import Point, Scene
from sheetkin.sheet.workbook import (
    FIRST_COL,
    build_workbook,
)
from sheetkin.xlsx.cells import Sheet
from sheetkin.xlsx.evaluator import Book, evaluate_sheets
from sheetkin.xlsx.functions import XlError

from .book import UnusableInput
from .caches import Kept, scene_rows
from .layout import VALUE_COL


# --------------------------------------------------------------------------- the variant
def input_values(book: Book, sheet: str, names: dict[str, int]) -> dict[str, object]:
    return {n: book.value(sheet, r, VALUE_COL) for n, r in names.items()}


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
    rows = scene_rows(scene)
    ref = re.compile(r"\{(?:scale:)?([^{}@:]+)(?:@(?:prev|next))?\}")
    direct = {r.name: set(ref.findall(r.formula)) | ({r.guard} if r.guard else set()) for r in rows}
    out: dict[str, set[str]] = {}
    for r in rows:                                   # rows come after what they use
        acc = set()
        for d in direct[r.name]:
            acc |= {d} | out.get(d, set())
        out[r.name] = acc - {r.name}
    return out


# The reference of a variant is the workbook sheetkin generates for it, evaluated. Only the
# input block (column D of the input rows) differs between variants of one mechanism with
# the same number of positions: the generated sheet is kept per structure (its rows'
# names, kinds and formulas, and the positions), and each variant's reference is that
# sheet with the variant's inputs, evaluated (the evaluator keeps the parsed formulas).
# No workbook is rebuilt per variant; references are kept per variant (its inputs).
_TEMPLATE_SHEETS = Kept(64)               # structure -> the generated Sheet, {input name: row}, {row: status}
_REFERENCES = Kept(64)                    # (structure, inputs) -> Book


def kept_structures() -> int:
    """How many generated sheets are kept (one per structure, however many variants):
    what a test or a long-running process can see of the cache."""
    return len(_TEMPLATE_SHEETS)


def reference_book(scene: Scene) -> Book:
    """The variant's reference: its generated workbook's first sheet, evaluated (cached per
    structure and inputs); also what copy detection compares another variant's typed numbers
    with."""
    rows = scene_rows(scene)
    structure = _structure(scene, rows)
    inputs = tuple((r.name, r.value) for r in rows if r.kind == "input")
    key = (structure, inputs)
    book = _REFERENCES.get(key)
    if book is None:
        sheet, input_rows, _ = _template(scene, structure)
        consts = dict(sheet.consts)
        for name, value in inputs:          # as the generated workbook writes them (ints as floats)
            if value is None:
                consts.pop((input_rows[name], VALUE_COL), None)
            else:
                number = isinstance(value, int) and not isinstance(value, bool)
                consts[(input_rows[name], VALUE_COL)] = float(value) if number else value
        variant = Sheet(sheet.name, sheet.state, consts=consts, formulas=sheet.formulas,
                        max_row=sheet.max_row, max_col=sheet.max_col)
        book = evaluate_sheets("<reference>", {variant.name: variant}, [variant.name], {}, strict=True)
        _REFERENCES.keep(key, book)
    return book


def _structure(scene: Scene, rows) -> tuple:
    return scene.crank.positions, tuple((r.name, r.kind, r.formula, r.guard) for r in rows)


def _template(scene: Scene, structure: tuple) -> tuple[Sheet, dict[str, int], dict[int, str]]:
    if structure not in _TEMPLATE_SHEETS:
        _TEMPLATE_SHEETS.keep(structure, template_sheet(scene))
    return _TEMPLATE_SHEETS[structure]


def issued_statuses(scene: Scene) -> dict[int, str]:
    """The status formula (column D, without "=") of each of the sheet's own check rows, by
    row, as the scene's generated workbook issues it (kept with the template sheet, which
    drops them): the behavioural check evaluates a student's status formula again only
    where it is not the issued one (behaviour._held_checks)."""
    return _template(scene, _structure(scene, scene_rows(scene)))[2]


def template_sheet(scene: Scene) -> tuple[Sheet, dict[str, int], dict[int, str]]:
    """The first sheet of the scene's generated workbook as the evaluator reads it, the row
    of every input, and the status formulas of the check rows it leaves out (by row)."""
    book = build_reference(scene, evaluate=False)
    sheet = book[0]
    input_rows = {sheet.consts.get((r, 1)): r for r in range(5, sheet.max_row + 1)}
    # the sheet's own check rows, their status cells and the summary above are not graded
    # against a reference (the student's checks are read from the student's sheet): left
    # out, they would be half of each variant's evaluation (SUMPRODUCT, COUNT, IF per row)
    # (their cells per position stay: which check rows apply, not "н/д", is the reference's)
    checks = check_row_names(scene)              # once: sheet_rows costs ~3 ms a call
    unchecked = {r for n, r in input_rows.items() if n in checks}
    statuses = {r: f for (r, c), f in sheet.formulas.items() if r in unchecked and c == VALUE_COL}
    sheet.formulas = {(r, c): f for (r, c), f in sheet.formulas.items()
                      if r >= 5 and (r not in unchecked or c >= FIRST_COL)}
    return sheet, input_rows, statuses


def check_row_names(scene: Scene) -> set[str]:
    """The names of the sheet's own check rows (kinds check and fdcheck): graded from the
    student's sheet, not against the reference."""
    return {r.name for r in scene_rows(scene) if r.kind in ("check", "fdcheck")}


def build_reference(scene: Scene, evaluate: bool = True):
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
