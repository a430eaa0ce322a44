"""Hostile formulas and names (issue 11, items 2 and 3): a malformed formula or name is its
cell's problem, never the process's; resources are bounded by what the file holds, not by
what it names.

Every hostile cell must get an Excel error (the one Excel or LibreOffice gives, where
one applies) and exactly the note that names it; the cells around it are computed;
`evaluate` (strict) refuses the file with one line naming file, cell and problem;
`sheetkin evaluate` exits 2 with that line; the validator goes on. The notes' error codes
follow LibreOffice 7.4 where it has one (checked by hand: =SIN(1,2) and =IF() are #VALUE!,
names in a circle #N/A, a circular reference #VALUE!, its Err:522 saved to .xlsx).
"""
from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from openpyxl.utils import get_column_letter
from openpyxl.workbook.defined_name import DefinedName

from sheetkin.cli.commands import main
from sheetkin.xlsx import cells as xlsxread
from sheetkin.xlsx import evaluator, table
from sheetkin.xlsx import limits as evaluator_limits
from sheetkin.xlsx.evaluator import EvaluationError, evaluate
from sheetkin.xlsx.limits import MAX_EVAL_DEPTH
from sheetkin.xlsx.package import Limits, UnusableWorkbook
from sheetkin.xlsx.parse import MAX_FORMULA_CHARS, MAX_NESTING

ROOT = Path(__file__).resolve().parents[2]

# (formula, the cell's value, a piece of its note); A1 holds 2, Data!A1 3 and Data!C5 4
HOSTILE = [
    ("=IF()", "#VALUE!", "IF takes 1 to 3 arguments, not 0"),
    ("=SUM()", "#VALUE!", "SUM takes 1 to 255 arguments, not 0"),
    ("=SIN(1,2)", "#VALUE!", "SIN takes 1 argument, not 2"),
    ("=PI(1)", "#VALUE!", "PI takes 0 arguments, not 1"),
    ("=IFERROR(1)", "#VALUE!", "IFERROR takes 2 arguments, not 1"),
    ("=SUM(" + ",".join(["1"] * 256) + ")", "#VALUE!", "not 256"),
    ("=ROUND(SIN(1,2),1)", "#VALUE!", "SIN takes 1 argument"),
    ("=(1+2", "#NAME?", "unbalanced parentheses"),
    ("=1+)", "#NAME?", "not a formula"),
    ("=SUM(1,2", "#NAME?", "SUM( is not closed"),
    ("=1 ~ 2", "#NAME?", "unexpected '~'"),
    ("=1**2", "#NAME?", "unexpected '*'"),
    ('="abc', "#NAME?", "not a formula"),
    ("=#FOO!+1", "#NAME?", "not a formula"),
    ("=A1 B1", "#NAME?", "unexpected 'B1'"),
    ("=FOO(1)", "#NAME?", "unsupported function FOO"),
    ("=" + "+".join(["A1"] * 10000), "#VALUE!", f"longer than {MAX_FORMULA_CHARS} characters"),
    ("=" + "(" * 10000 + "1" + ")" * 10000, "#VALUE!", f"longer than {MAX_FORMULA_CHARS} characters"),
    ("=" + "(" * 3000 + "1" + ")" * 3000, "#VALUE!", f"nesting deeper than {MAX_NESTING} levels"),
    ("=" + "SIN(" * 65 + "1" + ")" * 65, "#VALUE!", f"nesting deeper than {MAX_NESTING} levels"),
    ("=" + "-" * 5000 + "1", "#VALUE!", f"nesting deeper than {MAX_NESTING} levels"),
    ("=1" + "%" * 5000, "#VALUE!", f"nesting deeper than {MAX_NESTING} levels"),
    ("=Nope!A1+1", "#REF!", "refers to the sheet 'Nope', which does not exist"),
    ("='No such'!A1:B2", "#REF!", "refers to the sheet 'No such'"),
    ("=cyc_a", "#N/A", "circle (CYC_A -> CYC_B -> CYC_A)"),
    ("=cyc_b+1", "#N/A", "circle"),
    ("=self_n*2", "#N/A", "circle (SELF_N -> SELF_N)"),
    ("=bad_n", "#VALUE!", "the name bad_n is not a formula"),
    ("=fn_n", "#VALUE!", "the name FN_N: SIN takes 1 argument, not 2"),
    ("=unknown_n", "#NAME?", "the name UNKNOWN_N: unsupported function NOPE"),
    ("=chain_0", "#VALUE!", f"nested deeper than {MAX_EVAL_DEPTH} levels"),
]

# formulas at (not past) the limits, and references far outside the used range: computed
# (the chains also go through every walk of the tree: names, whole columns)
COMPUTED = [
    ("=" + "+".join(["1"] * 4000), 4000.0),                  # 7999 characters: a chain 4000 deep
    ("=" + "+".join(["A1"] * 2700), 5400.0),
    ("=" + "-".join(["A1"] * 2700), 2 - 2 * 2699.0),
    ("=" + "(" * 60 + "A1" + ")" * 60, 2.0),
    ("=" + "SIN(" * 63 + "0" + ")" * 63, 0.0),
    ("=" + "-" * 60 + "A1", 2.0),
    ("=short_chain", 5.0),                                    # 150 names, each naming the next
    ("=" + "+".join(["short_150"] * 700), 3500.0),            # a chain of names 700 deep
    ("=" + "+".join(["SUM(Data!A:A)"] * 500), 1500.0),        # whole columns in a chain 500 deep
    ("=$XFD$1048576+1", 1.0),
    ("=XFD1048576", 0.0),
    ("=SUM(Data!$A$1:$XFD$1048576)", 7.0),
    ("=COUNT(Data!A1:XFD1048576)", 2.0),
    ("=MAX(Data!$A$1:$XFD$1048576)+MIN(Data!B1:XFD1048576)", 8.0),
    ("=AVERAGE(Data!A1:XFD1048576)", 3.5),
    ("=SUM(Data!B2:B1048576)", 0.0),
    ("=SUMPRODUCT(Data!A1:A3,Data!Z1:Z3)", 0.0),              # Z is past Data's used range: empty
    ("=SUMPRODUCT(Data!A1:C5,Data!A1:C5)", 25.0),
    ("=Sheet1!#REF!", "#REF!"),
    ("=A1:B2+A1:C3", "#VALUE!"),
]


def _names() -> dict[str, str]:
    names = {"cyc_a": "cyc_b", "cyc_b": "cyc_a", "self_n": "self_n+1", "bad_n": "1+)",
             "fn_n": "SIN(1,2)", "unknown_n": "NOPE(1)"}
    for i in range(5000):                                     # a chain past the evaluation limit
        names[f"chain_{i}"] = f"chain_{i + 1}"
    names["chain_5000"] = "5"
    for i in range(150):
        names[f"short_{i}"] = f"short_{i + 1}"
    names["short_chain"], names["short_150"] = "short_0", "5"
    return names


def _book(path: Path, formulas: list[str], names: dict[str, str] | None = None) -> Path:
    """Calc!A1 = 2, the formulas in row 3 from column B; Data!A1 = 3, Data!C5 = 4."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    ws["A1"] = 2
    for j, f in enumerate(formulas):
        ws.cell(3, 2 + j, f)
    data = wb.create_sheet("Data")
    data["A1"], data["C5"] = 3, 4
    for n, text in (names or {}).items():
        wb.defined_names[n] = DefinedName(n, attr_text=text)
    wb.save(path)
    return path


@pytest.fixture(scope="module")
def hostile(tmp_path_factory) -> tuple[Path, evaluator.Book]:
    path = _book(tmp_path_factory.mktemp("hostile") / "hostile.xlsx",
                 [f for f, _, _ in HOSTILE] + [f for f, _ in COMPUTED], _names())
    return path, evaluate(path, strict=False)


@pytest.mark.parametrize("j", range(len(HOSTILE)), ids=[f[:24] for f, _, _ in HOSTILE])
def test_a_hostile_cell_gets_an_error_and_one_note(hostile, j):
    path, book = hostile
    formula, value, note = HOSTILE[j]
    cell = f"Calc!{get_column_letter(2 + j)}3"
    assert book.value("Calc", 3, 2 + j) == value
    mine = [n for n in book.notes if n.startswith(cell + ":")]
    assert len(mine) == 1 and note in mine[0], mine
    assert "\n" not in mine[0] and len(mine[0]) < 400


@pytest.mark.parametrize("j", range(len(COMPUTED)), ids=[f[:24] for f, _ in COMPUTED])
def test_formulas_at_the_limits_and_far_references_are_computed(hostile, j):
    path, book = hostile
    col = 2 + len(HOSTILE) + j
    assert book.value("Calc", 3, col) == COMPUTED[j][1]
    assert not [n for n in book.notes if n.startswith(f"Calc!{get_column_letter(col)}3:")]


def test_every_note_is_a_hostile_cell(hostile):
    path, book = hostile
    assert len(book.notes) == len(HOSTILE)
    assert book.notes is book.problems


def test_strict_evaluation_refuses_with_one_line_naming_file_and_cells(hostile):
    path, _ = hostile
    with pytest.raises(EvaluationError) as exc:
        evaluate(path)
    msg = str(exc.value)
    assert msg.startswith(str(path)) and "\n" not in msg
    assert "Calc!B3: IF takes 1 to 3 arguments, not 0" in msg
    assert f"(and {len(HOSTILE) - 10} more)" in msg


def test_the_stores_are_the_used_range(hostile):
    _, book = hostile
    assert book.num["Data"].shape == (6, 4)           # Data!A1:C5, not the 1,048,576 rows it names
    assert book.num["Calc"].shape == (4, 2 + len(HOSTILE) + len(COMPUTED))


def test_sheetkin_evaluate_exits_2_with_one_line(hostile, capsys):
    path, _ = hostile
    assert main(["evaluate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith(f"sheetkin: error: {path}: Calc!B3: IF takes")


def test_sheetkin_evaluate_turns_an_internal_error_into_one_line(tmp_path, monkeypatch, capsys):
    path = _book(tmp_path / "ok.xlsx", ["=A1+1"])
    for exc in (RecursionError("maximum recursion depth exceeded"), MemoryError(), KeyError("x"), ValueError("np")):
        def boom(*a, exc=exc, **k):
            raise exc
        monkeypatch.setattr(evaluator, "evaluate_sheets", boom)
        assert main(["evaluate", str(path)]) == 2
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and err.startswith(f"sheetkin: error: {path}: cannot be evaluated")
        assert type(exc).__name__ in err


def test_an_evaluator_bug_in_one_cell_is_that_cells_problem(tmp_path, monkeypatch):
    path = _book(tmp_path / "bug.xlsx", ["=SUM(A1,1)", "=A1*3"])

    def broken(args, ranges):
        raise IndexError("a bug")
    monkeypatch.setitem(table.FUNCTIONS, "SUM", dataclasses.replace(table.FUNCTIONS["SUM"], kernel=broken))
    book = evaluate(path, strict=False)
    assert book.value("Calc", 3, 2) == "#VALUE!" and book.value("Calc", 3, 3) == 6.0
    assert len(book.notes) == 1 and book.notes[0].startswith("Calc!B3: internal error of the evaluator (IndexError")
    with pytest.raises(EvaluationError, match="Calc!B3: internal error"):
        evaluate(path)


def test_no_recursion_limit_is_reachable(tmp_path):
    """The hostile book evaluated with a low recursion limit: every walk is iterative or
    bounded far below it (MAX_NESTING, MAX_EVAL_DEPTH)."""
    path = _book(tmp_path / "deep.xlsx", [f for f, _, _ in HOSTILE] + [f for f, _ in COMPUTED], _names())
    code = ("import sys; sys.setrecursionlimit(600); from sheetkin.xlsx.evaluator import evaluate; "
            f"b = evaluate({str(path)!r}, strict=False); print(len(b.notes))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == str(len(HOSTILE))


# --------------------------------------------------------------------------- circular
def test_circular_references_lenient_are_the_cells_problem(tmp_path):
    path = _book(tmp_path / "circle.xlsx", ["=C3+1", "=B3*2", "=A1+1", "=SUM(A1:E3)"])
    book = evaluate(path, strict=False)
    assert [book.value("Calc", 3, c) for c in (2, 3, 4, 5)] == ["#VALUE!", "#VALUE!", 3.0, "#VALUE!"]
    assert len(book.notes) == 1
    note = book.notes[0]
    assert "circular reference among" in note and "Calc!B3" in note and "Calc!C3" in note
    assert "Calc!E3" in note and "D3" not in note     # E3 sums itself


# --------------------------------------------------------------------------- shared formulas
SHEET = ('<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n'
         '<worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>{}</sheetData></worksheet>')


def _crafted(tmp_path: Path, name: str, rows: str) -> Path:
    base = tmp_path / "base.xlsx"
    if not base.exists():
        wb = openpyxl.Workbook()
        wb.active.title = "Calc"
        wb.save(base)
    path = tmp_path / name
    with zipfile.ZipFile(base) as zin, zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zout:
        for info in zin.infolist():
            data = zin.read(info.filename)
            if info.filename == "xl/worksheets/sheet1.xml":
                data = SHEET.format(rows).encode()
            zout.writestr(info.filename, data)
    return path


DANGLING = ('<row r="1"><c r="A1"><v>2</v></c>'
            '<c r="B1"><f t="shared" si="7"/><v>99</v></c>'                 # no master anywhere
            '<c r="C1"><f t="shared" si="3"/><v>5</v></c>'                  # master later in the file
            '<c r="D1"><f>B1+1</f><v>100</v></c></row>'
            '<row r="2"><c r="B2"><f t="shared" ref="B2:C2" si="3">A1*2</f><v>4</v></c></row>')


@pytest.mark.parametrize("fast", [True, False], ids=["regex path", "element tree"])
def test_a_dangling_shared_formula_is_na_with_a_note(tmp_path, monkeypatch, fast):
    if not fast:
        monkeypatch.setattr(xlsxread, "_read_fast", lambda *a, **k: None)
    path = _crafted(tmp_path, "dangling.xlsx", DANGLING)
    book = evaluate(path, strict=False)
    assert book.value("Calc", 1, 2) == "#N/A"                 # never the cached 99
    assert book.value("Calc", 1, 4) == "#N/A"                 # propagates
    assert (1, 3) in book.sheets["Calc"].formulas             # its master comes later: found
    assert book.sheets["Calc"].cached[(1, 2)] == 99.0
    assert len(book.notes) == 1
    assert book.notes[0].startswith("Calc!B1: a shared formula (si=7) without its first cell")
    with pytest.raises(EvaluationError, match=r"dangling.xlsx: Calc!B1: a shared formula \(si=7\)"):
        evaluate(path)


# --------------------------------------------------------------------------- resources
def _run_limited(code: str, limit_bytes: int) -> subprocess.CompletedProcess:
    """Python code in a subprocess whose address space is capped (RLIMIT_AS)."""
    pre = f"import resource; resource.setrlimit(resource.RLIMIT_AS, ({limit_bytes}, {limit_bytes}))\n"
    return subprocess.run([sys.executable, "-c", pre + code], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"})


def test_a_small_file_naming_the_whole_grid_stays_small(tmp_path):
    """Before: =$XFD$1048576+1 made the stores 1,048,577 x 16,385 (a 128 GiB allocation)."""
    path = _book(tmp_path / "grid.xlsx", ["=$XFD$1048576+1", "=SUM(Data!$A$1:$XFD$1048576)",
                                          "=XFD1048576*2",
                                          "=COUNT(Data!$A$1:$XFD$1048576)"])
    assert path.stat().st_size < 34_000
    out = _run_limited("from sheetkin.xlsx.evaluator import evaluate\n"
                       f"b = evaluate({str(path)!r})\n"
                       "print([b.value('Calc', 3, c) for c in range(2, 6)])\n"
                       "import resource; print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)", 2_000_000_000)
    assert out.returncode == 0, out.stderr[-2000:]
    values, rss_kb = out.stdout.strip().splitlines()
    assert values == "[1.0, 7.0, 0.0, 2.0]"


def test_stray_cells_far_apart_are_refused_with_one_line(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    ws["A1"], ws["ES100000"], ws["B1"] = 1, 2, "=A1+1"
    wb.save(tmp_path / "spread.xlsx")
    with pytest.raises(UnusableWorkbook) as exc:
        evaluate(tmp_path / "spread.xlsx", strict=False)
    msg = str(exc.value)
    assert "sheet 'Calc' A1:ES100000, 14,900,000" in msg and "10,000,000" in msg and "\n" not in msg
    book = evaluate(tmp_path / "spread.xlsx", limits=Limits(max_used_cells=20_000_000))
    assert book.value("Calc", 1, 2) == 2.0


def test_formulas_reading_too_much_are_refused_with_one_line(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    for r in range(1, 1001):
        ws.cell(r, 1, r)
    for c in range(2, 202):                      # 200 cells, each reading A1:A1000 (relative)
        ws.cell(1, c, f"=SUM({get_column_letter(c - 1)}1:{get_column_letter(c - 1)}1000)")
    wb.save(tmp_path / "reads.xlsx")
    assert evaluate(tmp_path / "reads.xlsx").value("Calc", 1, 2) == 500500.0
    with pytest.raises(UnusableWorkbook, match=r"its formulas read more than 100,000 cells in all \(at Calc!"):
        evaluate(tmp_path / "reads.xlsx", limits=Limits(max_reads=100_000))


def test_a_run_read_in_pieces_equals_the_run_at_once(tmp_path, monkeypatch):
    """Relative ranges of a long run are read a piece at a time (CHUNK_READS): same values."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    rng = np.random.default_rng(1)
    for r in range(1, 41):
        for c in range(1, 61):
            ws.cell(r, c, float(rng.normal()))
    for c in range(1, 50):
        L, M = get_column_letter(c), get_column_letter(c + 10)
        ws.cell(42, c, f"=SUM({L}1:{M}40)+MAX({L}2:{L}30)-AVERAGE($A$1:$BH$40,{L}1)+COUNT({L}1:{M}3)")
        ws.cell(43, c, f"=SUMPRODUCT({L}1:{M}40,{L}1:{M}40)+MIN($B$1:$Z$9,{L}5)")
    wb.save(tmp_path / "runs.xlsx")
    whole = evaluate(tmp_path / "runs.xlsx")
    assert whole.runs == 2
    monkeypatch.setattr(evaluator_limits, "CHUNK_READS", 500)
    pieces = evaluate(tmp_path / "runs.xlsx")
    a = np.array([[whole.value("Calc", r, c) for c in range(1, 50)] for r in (42, 43)])
    b = np.array([[pieces.value("Calc", r, c) for c in range(1, 50)] for r in (42, 43)])
    assert np.allclose(a, b, rtol=1e-13, atol=1e-13)
    x = np.array([[ws.cell(r, c).value for c in range(1, 61)] for r in range(1, 41)])
    for j in (0, 17, 48):
        expect = (x[:, j:j + 11].sum() + x[1:30, j].max() - (x.sum() + x[0, j]) / (x.size + 1) + 33
                  + (x[:, j:j + 11] ** 2).sum() + min(x[:9, 1:26].min(), x[4, j]))
        assert a[0, j] + a[1, j] == pytest.approx(expect, rel=1e-12)


# --------------------------------------------------------------------------- the validator goes on
def test_validate_reports_the_rest_of_a_workbook_with_hostile_cells(tmp_path):
    import sheetkin
    from sheetkin.course.validator import validate
    from sheetkin.sheet.workbook import write_workbook
    text = (ROOT / "workbooks" / "fourbar.toml").read_text(encoding="utf-8")
    path = tmp_path / "fourbar.xlsx"
    write_workbook(sheetkin.parse_scene(text, "fourbar.toml"), path, scene_text=text)
    wb = openpyxl.load_workbook(path)
    ws = wb.worksheets[0]
    rows = {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value}
    ws.cell(rows["F_g1"], 6).value = "=SIN(1,2)"
    ws.cell(rows["F_g1"], 7).value = "=" + "(" * 100 + "1" + ")" * 100
    ws.cell(rows["F_g1"], 8).value = f"=I{rows['F_g1']}+1"
    ws.cell(rows["F_g1"], 9).value = f"=H{rows['F_g1']}+1"
    wb.defined_names["loop_a"] = DefinedName("loop_a", attr_text="loop_a")
    ws.cell(rows["F_g1"], 10).value = "=loop_a"
    wb.save(path)
    rep = validate(path)
    assert rep.error is None
    wrong = {r.name for r in rep.rows if r.status == "wrong"}
    assert "F_g1" in wrong and rep.rows and len([r for r in rep.rows if r.status == "correct"]) > 10
    notes = " | ".join(rep.problems)
    for piece in ("SIN takes 1 argument", f"nesting deeper than {MAX_NESTING}", "circular reference",
                  "LOOP_A -> LOOP_A"):
        assert piece in notes, notes


def _column_filled_down(path: Path, rows: int = 300) -> Path:
    """A column of =A1*2 filled down (LibreOffice writes it as one shared formula) and numbers."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Calc"
    for r in range(1, rows + 1):
        ws.cell(r, 1, r * 0.5)
        ws.cell(r, 3, "text" if r % 7 == 0 else r)
    wb.save(path)
    # the shared block B1:B{rows}, master in B1, as Excel and LibreOffice write it
    cells = "".join(f'<row r="{r}"><c r="A{r}"><v>{r * 0.5}</v></c><c r="B{r}"><f t="shared" si="0"'
                    + (f' ref="B1:B{rows}">A1*2</f>' if r == 1 else "/>") + "</c></row>" for r in range(1, rows + 1))
    return _crafted(path.parent, "filled.xlsx", cells)


def test_a_sheet_read_in_pieces_equals_it_read_at_once(tmp_path, monkeypatch):
    path = _column_filled_down(tmp_path / "base_filled.xlsx")
    whole = xlsxread.read_book(path)
    monkeypatch.setattr(xlsxread, "_PIECE", 300)              # a few rows a piece: the block spans pieces
    pieces = xlsxread.read_book(path)
    a, b = whole.sheets["Calc"], pieces.sheets["Calc"]
    assert (a.consts, a.formulas, a.cached, a.dangling, a.max_row, a.max_col) == \
           (b.consts, b.formulas, b.cached, b.dangling, b.max_row, b.max_col)
    assert b.formulas[(300, 2)] == "A300*2" and not b.dangling
    book = evaluate(path)
    assert book.value("Calc", 300, 2) == 300.0


def test_too_many_cells_are_refused_while_reading(tmp_path, monkeypatch):
    path = _column_filled_down(tmp_path / "base_filled.xlsx")
    for fast in (True, False):
        if not fast:
            monkeypatch.setattr(xlsxread, "_read_fast", lambda *a, **k: None)
        with pytest.raises(UnusableWorkbook,
                           match=r"more than 500 cells hold a value or a formula \(counted up to sheet 'Calc'\)"):
            xlsxread.read_book(path, Limits(max_cells=500))
        assert len(xlsxread.read_book(path, Limits(max_cells=600)).sheets["Calc"].formulas) == 300


def test_too_much_formula_text_is_refused_with_one_line(tmp_path):
    path = _book(tmp_path / "text.xlsx", [f"=A1*{i}+SIN(A1)" for i in range(100)])
    assert evaluate(path).value("Calc", 3, 3) == pytest.approx(2 + np.sin(2))
    with pytest.raises(UnusableWorkbook, match=r"its formulas hold 1,\d{3} characters of text to read"):
        evaluate(path, limits=Limits(max_formula_chars=1000))
