"""Books a student builds from scratch (issue 33): a new file, their own layout and Russian
labels, the given data in B5.., the table a row per quantity (positions across C..) or a
column per quantity (positions down), angles in degrees or radians, typed in LibreOffice
through UNO (tests/helpers/studentbooks_uno.py, one soffice for all the books).

The student's formulas are the lecture's (sheetkin's own workbook for the scene, whose rows
follow the lecture's step 7), moved cell by cell into the student's layout: every reference
re-pointed, no formula copied by sheetkin's column letters. In a radians book the link
angles (phi_1, phi_k) are kept in radians: their formulas wrapped in RADIANS(), and each
formula reading them reads DEGREES(cell). Check rows without ranges are kept (the student's
own checks); the numeric-derivative checks (ranges) are left out.

Mutations name a row: wrong (its formula times 1.05 from position 4 on), typed (its values
pasted as numbers), missing (the row left out, and the check rows reading it).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import openpyxl

from sheetkin.course.reference import build_reference, reference_book
from sheetkin.kinematics.scene import Scene
from sheetkin.sheet.workbook import FIRST_COL, sheet_rows

_REF = re.compile(r"(?<![A-Za-z_\"])\$?([A-Z]{1,3})\$?(\d+)(?![\d(A-Za-z_])")
_UNITS_RU = {"m": "м", "m/s": "м/с", "m/s^2": "м/с²", "rad": "рад", "deg": "град", "rad/s": "рад/с",
             "rad/s^2": "рад/с²", "m^2": "м²"}
GIVEN_ROW = 5          # B5..: the given data, labels in A
TABLE_AT = 30          # the table's first line


def _col(letters: str) -> int:
    n = 0
    for ch in letters:
        n = n * 26 + ord(ch) - 64
    return n


def _letters(c: int) -> str:
    s = ""
    while c:
        c, rem = divmod(c - 1, 26)
        s = chr(65 + rem) + s
    return s


def label_ru(name: str, unit: str) -> str:
    """The student's own label: "x B, м", "ω2, рад/с", "φ2, град"."""
    m = re.match(r"^(phi|omega|eps)_(\d+)$", name)
    greek = {"phi": "φ", "omega": "ω", "eps": "ε"}
    text = (greek[m.group(1)] + m.group(2)) if m else {"Fi": "φ1", "Fi_t": "ω1", "Fi_tt": "ε1"}.get(
        name, name.replace("_", " "))
    u = _UNITS_RU.get(unit, "")
    return f"{text}, {u}" if u else text


@dataclass
class StudentBook:
    """A from-scratch book: cells to type (sheet -> [(row, col, value or "=formula")])."""
    cells: dict[str, list[list]] = field(default_factory=dict)
    where: dict[str, tuple[int, int]] = field(default_factory=dict)     # quantity -> its first cell
    exercise: str = ""              # the file LibreOffice opens (a blank book)
    gnumeric: bool = False

    @property
    def ops(self) -> list:
        out: list = []
        for sheet, cells in self.cells.items():
            if sheet != "main":
                out.append(["insert_sheet", sheet, 1])
            values = [c for c in cells if not (isinstance(c[2], str) and c[2].startswith("="))]
            formulas = [c for c in cells if isinstance(c[2], str) and c[2].startswith("=")]
            out += [["formula_lines", sheet, _lines(formulas)], ["values", sheet, values]]
        return out


def _lines(formulas: list[list]) -> list[list]:
    """Formulas grouped into runs of neighbouring cells of one row or one column."""
    out: list[list] = []
    for r, c, f in sorted(formulas, key=lambda x: (x[0], x[1])):
        last = out[-1] if out else None
        if last and last[0] == last[2] == r and c == last[3] + 1:
            last[3] = c
            last[4].append(f)
        else:
            out.append([r, c, r, c, [f]])
    if len(out) > len(formulas) // 2:                   # columns: group down instead
        out = []
        for r, c, f in sorted(formulas, key=lambda x: (x[1], x[0])):
            last = out[-1] if out else None
            if last and last[1] == last[3] == c and r == last[2] + 1:
                last[2] = r
                last[4].append(f)
            else:
                out.append([r, c, r, c, [f]])
    return out


def student_book(scene: Scene, orientation: str = "row", angles: str = "deg", sheet: str = "main",
                 wrong: str = "", typed: str = "", missing: str = "", student: str = "Иванов Иван") -> StudentBook:
    """The book a student builds for `scene` (the module's docstring)."""
    gen = build_reference(scene, evaluate=False)[0]
    ref = reference_book(scene)
    rs = ref.order[0]
    rows = sheet_rows(scene).rows
    by_row = {}
    for r in range(5, gen.max_row + 1):
        name = gen.consts.get((r, 1))
        if isinstance(name, str):
            by_row[r] = name
    n = scene.crank.positions
    inputs = [r for r in rows if r.kind == "input" and r.name not in ("Tol", "Tol_FD")]
    derived = [r for r in rows if r.kind == "derived"]
    keep = []
    for r in rows:
        if r.kind in ("index", "calc", "accepted", "guard", "check") and r.name not in (missing,):
            keep.append(r)
    name_row = {v: k for k, v in by_row.items()}
    # check rows with ranges (the numeric derivatives) or reading a missing row: left out
    def reads(name: str) -> set[str]:
        f = gen.formulas.get((name_row[name], FIRST_COL)) or gen.formulas.get((name_row[name], 4)) or ""
        return {by_row.get(int(m.group(2)), "") for m in _REF.finditer(f)}
    def ranged(name: str) -> bool:
        return ":" in (gen.formulas.get((name_row[name], FIRST_COL)) or "")
    table = [r for r in keep if not (r.kind == "check" and (ranged(r.name) or missing in reads(r.name)))]
    table = [r for r in table if r.name in name_row]
    radians = ({"phi_1"} | {r.name for r in rows if r.unit == "deg" and r.name.startswith("phi_")}
               if angles == "rad" else set())
    # where each sheetkin cell goes: inputs and derived values -> B5..; table -> rows or columns
    place: dict[tuple[int, int], tuple[int, int]] = {}
    cells: list[list] = [[1, 1, "Студент"], [1, 2, student], [2, 1, "Группа"], [2, 2, "МТ-21"],
                         [4, 1, "Исходные данные"]]
    for k, r in enumerate(inputs + derived):
        at = GIVEN_ROW + k
        place[(name_row[r.name], 4)] = (at, 2)
        cells.append([at, 1, label_ru(r.name, r.unit) + (" (вычислить)" if r.kind == "derived" else "")])
    top = max(TABLE_AT, GIVEN_ROW + len(inputs) + len(derived) + 2)    # below the given data
    for k, r in enumerate(table):
        g = name_row[r.name]
        for p in range(n):
            if orientation == "row":
                place[(g, FIRST_COL + p)] = (top + k, 3 + p)
            else:
                place[(g, FIRST_COL + p)] = (top + 1 + p, 2 + k)
        unit = "rad" if r.name in radians else r.unit
        cells.append([top + k, 1, label_ru(r.name, unit)] if orientation == "row"
                     else [top, 2 + k, label_ru(r.name, unit)])
    book = StudentBook()

    def moved(formula: str, at_row: int) -> str:
        def sub(m):
            key = (int(m.group(2)), _col(m.group(1)))
            if key not in place:
                raise KeyError(f"{m.group(0)} of {formula} (row {at_row}) has no place")
            r, c = place[key]
            # the given data absolute ($B$5), the table relative: a student types the first
            # cell and drags it along the positions
            cell = f"${_letters(c)}${r}" if key[1] == 4 else f"{_letters(c)}{r}"
            return f"DEGREES({cell})" if by_row.get(key[0]) in radians else cell
        return "=" + _REF.sub(sub, formula)

    for k, r in enumerate(inputs):
        at = GIVEN_ROW + k
        v = r.value
        cells.append([at, 2, float(v) if isinstance(v, (int, float)) else v])
        book.where[r.name] = (at, 2)
    for r in derived:
        g = name_row[r.name]
        cells.append([place[(g, 4)][0], 2, moved(gen.formulas[(g, 4)], g)])
    for r in table:
        g = name_row[r.name]
        for p in range(n):
            at = place[(g, FIRST_COL + p)]
            if r.name == "i":
                cells.append([at[0], at[1], float(p)])
                continue
            f = gen.formulas.get((g, FIRST_COL + p))
            if f is None:
                continue
            text = moved(f, g)
            if r.name in radians:
                text = f"=RADIANS({text[1:]})"
            if r.name == wrong and p >= 3:
                text = f"=({text[1:]})*1.05"
            if r.name == typed:
                v = ref.value(rs, g, FIRST_COL + p)
                text = v if not isinstance(v, bool) else ("TRUE" if v else "FALSE")
            cells.append([at[0], at[1], text])
        book.where[r.name] = place[(g, FIRST_COL)]
    book.cells[sheet] = cells
    return book


def leaf_rows(scene: Scene) -> list[str]:
    """Required rows no computed row reads (only check rows): safe to break one alone."""
    from sheetkin.course.scratch import _REQUIRED
    gen = build_reference(scene, evaluate=False)[0]
    by_row = {r: gen.consts.get((r, 1)) for r in range(5, gen.max_row + 1)}
    kinds = {r.name: r.kind for r in sheet_rows(scene).rows}
    read: set[str] = set()
    for (r, c), f in gen.formulas.items():
        if c == FIRST_COL and kinds.get(by_row.get(r)) in ("calc", "accepted", "guard"):
            read |= {by_row.get(int(m.group(2))) for m in _REF.finditer(f)}
    return [r.name for r in sheet_rows(scene).rows if r.kind in ("calc", "accepted") and _REQUIRED.match(r.name)
            and r.name not in read]


def blank_book(path: Path, sheet: str = "Лист1") -> Path:
    """An empty workbook, as File > New gives one (the student types everything)."""
    wb = openpyxl.Workbook()
    wb.active.title = sheet
    wb.save(path)
    return path


def write_openpyxl(book: StudentBook, path: Path) -> Path:
    """The same book written by openpyxl (no LibreOffice): fast, for the benchmarks."""
    wb = openpyxl.Workbook()
    wb.active.title = "Лист1"
    for name, cells in book.cells.items():
        ws = wb.active if name == "main" else wb.create_sheet(name)
        for r, c, v in cells:
            ws.cell(r, c, v)
    wb.save(path)
    return path


def with_draft_sheet(path: Path, rows: int = 2000, cols: int = 50) -> Path:
    """The book at `path` with a sheet "Черновик" of rows x cols numbers that are none of the
    lecture's (a student's draft): what the from-scratch search must look through."""
    wb = openpyxl.load_workbook(path)
    ws = wb.create_sheet("Черновик")
    for r in range(1, rows + 1):
        for c in range(1, cols + 1):
            ws.cell(r, c, ((r * 7919 + c * 104729) % 1000003) / 1000.0)
    wb.save(path)
    return path


def distinct_leaves(scene: Scene) -> list[str]:
    """Leaf rows (leaf_rows) whose values no other required quantity has in any unit, and
    that vary: a mutation of one of them can only be named as that row."""
    from sheetkin.course.scratch import _UNITS, _agree, quantities
    qs = [q for q in quantities(scene, reference_book(scene)) if q.required]
    out = []
    for name in leaf_rows(scene):
        q = next(x for x in qs if x.name == name)
        if q.ref.size == 0 or float(q.ref.max() - q.ref.min()) < 1e-6:
            continue
        twins = [o for o in qs if o.name != name and any(
            bool(_agree(o.ref * sc, q.ref, None).all()) for _, sc, _ in _UNITS.get(o.unit, [("", 1.0, None)]))]
        if not twins:
            out.append(name)
    return out
