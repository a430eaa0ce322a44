"""Students' books made the way students make them (issue 21): the exercise opened in
LibreOffice, the key's formulas typed into its empty computed cells, then ordinary habits
(a scratch sheet inserted before the main one, a notes column after C, the charts tab
dragged first, numbers typed, a note in T150, rows deleted, a named row range), saved by
LibreOffice; or re-saved by Gnumeric's ssconvert.

LibreOffice is driven through UNO by tests/helpers/studentbooks_uno.py, run by /usr/bin/python3
(Debian's python3-uno works with that Python only) with its own profile and socket. Build
all the books a test needs with one make_books() call: one soffice start for all of them.

    recipe = Recipe(exercise, key).honest().scratch_sheet_first().note("T150", "проверил")
    make_books({tmp / "a.xlsx": recipe, ...})
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import openpyxl
from openpyxl.utils import column_index_from_string, get_column_letter

HERE = Path(__file__).resolve().parent
UNO_PYTHON = "/usr/bin/python3"


def uno_available() -> bool:
    """Whether LibreOffice can be driven through UNO here (soffice and python3-uno)."""
    if not shutil.which("soffice") or not os.path.exists(UNO_PYTHON):
        return False
    return subprocess.run([UNO_PYTHON, "-c", "import uno"], capture_output=True).returncode == 0


def rows_by_name(ws) -> dict[str, int]:
    out: dict[str, int] = {}
    for r in range(1, ws.max_row + 1):
        v = ws.cell(r, 1).value
        if isinstance(v, str) and v not in out:
            out[v] = r
    return out


def key_formulas(exercise: Path, key: Path) -> list[list]:
    """[row, col, formula] of every cell the key computes and the exercise leaves empty (the
    formulas an honest student types), in the issued layout."""
    ex = openpyxl.load_workbook(exercise).worksheets[0]
    kws = openpyxl.load_workbook(key).worksheets[0]
    out = []
    for row in kws.iter_rows(min_row=5):
        for c in row:
            if c.column >= 4 and isinstance(c.value, str) and c.value.startswith("=") \
                    and ex.cell(c.row, c.column).value is None:
                out.append([c.row, c.column, c.value])
    return out


def key_values(key: Path, names: list[str], digits: int | None = None) -> dict[str, list[float]]:
    """The key's values of rows `names` at every position, by sheetkin's evaluator (rounded
    to `digits` significant digits when given): what a student would type or paste."""
    from sheetkin.xlsx.evaluator import evaluate
    b = evaluate(key)
    sheet = b.order[0]
    at = rows_by_name(openpyxl.load_workbook(key).worksheets[0])
    last = max(c for (r, c) in b.sheets[sheet].formulas if r == at["phi_1"])
    out = {}
    for n in names:
        vals = [b.value(sheet, at[n], c) for c in range(5, last + 1)]
        if digits is not None:
            vals = [float(f"{v:.{digits}g}") if isinstance(v, float) else v for v in vals]
        out[n] = vals
    return out


@dataclass
class Recipe:
    """What a student does to the exercise, in order; ops as tests/helpers/studentbooks_uno.py reads them."""
    exercise: Path
    key: Path | None = None
    ops: list = field(default_factory=list)
    gnumeric: bool = False            # re-saved by ssconvert after LibreOffice

    def _rows(self) -> dict[str, int]:
        return rows_by_name(openpyxl.load_workbook(self.exercise).worksheets[0])

    def honest(self, skip: tuple[str, ...] = ()) -> Recipe:
        """The key's formulas typed into the exercise (rows `skip` left empty)."""
        rows = self._rows()
        skipped = {rows[n] for n in skip}
        self.ops.append(["formulas", "main", [f for f in key_formulas(self.exercise, self.key)
                                              if f[0] not in skipped]])
        return self

    def identity(self, student: str, group: str = "") -> Recipe:
        # the student's own cells D1 (name) and D2 (group): the rows "student", "group" are gone
        self.ops.append(["values", "main", [[r, 4, v] for r, v in ((1, student), (2, group)) if v]])
        return self

    def type_values(self, values: dict[str, list]) -> Recipe:
        """Numbers typed over (or into) rows: {name: [value per position]}."""
        rows = self._rows()
        self.ops.append(["values", "main", [[rows[n], 5 + k, v] for n, vs in values.items()
                                            for k, v in enumerate(vs)]])
        return self

    def formula(self, name: str, template: str, col: int | None = None) -> Recipe:
        """Row `name`'s formula replaced by `template` in every position ({c}: the column's
        letter, {r}: the row), or in column `col` only."""
        rows = self._rows()
        r = rows[name]
        n = len(key_formulas(self.exercise, self.key)) and self._positions()
        cols = [col] if col else list(range(5, 5 + n))
        self.ops.append(["formulas", "main", [[r, c, template.format(c=get_column_letter(c), r=r)] for c in cols]])
        return self

    def wrap(self, name: str, template: str) -> Recipe:
        """Row `name`'s key formulas typed wrapped: template "=MOD({f},2*PI())" ({f}: the
        key's formula without "=")."""
        r = self._rows()[name]
        self.ops.append(["formulas", "main", [[rr, c, template.format(f=f[1:])]
                                              for rr, c, f in key_formulas(self.exercise, self.key) if rr == r]])
        return self

    def _positions(self) -> int:
        ws = openpyxl.load_workbook(self.exercise).worksheets[0]
        r = self._rows()["i"]
        return sum(1 for c in range(5, ws.max_column + 1) if ws.cell(r, c).value is not None)

    def note(self, cell: str, value) -> Recipe:
        """A note or scratch value in a cell of the main sheet ("T150", "проверил")."""
        letters = "".join(ch for ch in cell if ch.isalpha())
        row = int(cell[len(letters):])
        op = "formulas" if isinstance(value, str) and value.startswith("=") else "values"
        self.ops.append([op, "main", [[row, column_index_from_string(letters), value]]])
        return self

    def scratch_sheet_first(self, name: str = "Лист1") -> Recipe:
        self.ops.append(["insert_sheet", name, 0])
        self.ops.append(["values", name, [[1, 1, "черновик"], [2, 2, 3.14]]])
        return self

    def tab_first(self, name: str) -> Recipe:
        self.ops.append(["move_sheet", name, 0])
        return self

    def insert_column_after_c(self) -> Recipe:
        self.ops.append(["insert_columns", "main", 4, 1])
        self.ops.append(["values", "main", [[4, 4, "заметки"], [8, 4, "из задания"]]])
        return self

    def delete_rows(self, *names: str) -> Recipe:
        """Rows deleted by name, bottom first (so the others keep their numbers)."""
        rows = self._rows()
        for r in sorted((rows[n] for n in names), reverse=True):
            self.ops.append(["delete_rows", "main", r, 1])
        return self

    def name_range(self, name: str, row_name: str) -> Recipe:
        """A defined name for a whole row of positions (phi = $E$31:$Q$31)."""
        r = self._rows()[row_name]
        last = get_column_letter(4 + self._positions())
        self.ops.append(["name_range", name, "main", f"$E${r}:${last}${r}"])
        return self


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def make_books(books: dict[Path, Recipe], timeout: float = 600) -> None:
    """Every book made in one LibreOffice session (UNO); those with gnumeric=True then
    re-saved by ssconvert."""
    jobs = [{"src": str(Path(r.exercise).resolve()), "dst": str(Path(dst).resolve()), "ops": r.ops}
            for dst, r in books.items()]
    with tempfile.TemporaryDirectory(prefix="sheetkin-uno-") as tmp:
        spec = Path(tmp) / "jobs.json"
        spec.write_text(json.dumps(jobs, ensure_ascii=False), "utf-8")
        profile = Path(tmp) / "profile"
        proc = subprocess.Popen([UNO_PYTHON, str(HERE / "studentbooks_uno.py"), str(spec), str(_free_port()),
                                 str(profile)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                start_new_session=True)
        try:
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
        if proc.returncode != 0:
            raise RuntimeError(f"UNO script failed ({proc.returncode}):\n{out}\n{err}")
    for dst, r in books.items():
        if not Path(dst).is_file():
            raise RuntimeError(f"LibreOffice wrote no {dst}")
        if r.gnumeric:
            resave_gnumeric(Path(dst))


def resave_gnumeric(path: Path) -> None:
    """The book opened and saved by Gnumeric (ssconvert), in place."""
    tmp = path.with_name(path.stem + "-gnumeric" + path.suffix)
    subprocess.run(["ssconvert", "--recalc", str(path), str(tmp)], check=True, capture_output=True, timeout=300)
    tmp.replace(path)
