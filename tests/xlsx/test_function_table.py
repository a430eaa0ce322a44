"""The function table (sheetkin/xlsx/table.py): the docs list it, every entry is exercised by
the generated book of tests/helpers/function_book.py, and that book's values equal LibreOffice's
recalculation and Gnumeric's (where Gnumeric has the function) to 1e-12 relative, errors as
errors of the same kind."""
from __future__ import annotations

import math
from pathlib import Path

import openpyxl
import pytest
from helpers.function_book import ARRAYS, CASES, EXCEL_DIFFERS, GNUMERIC_DIFFERS, NUM_AS_VALUE, SYNTAX, write_book
from helpers.libreoffice import recalculate

from sheetkin.xlsx import table
from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.functions import XlError
from sheetkin.xlsx.parse import function_name, parse_formula

ROOT = Path(__file__).resolve().parents[2]


def test_the_docs_list_the_table():
    page = (ROOT / "docs" / "evaluator.md").read_text(encoding="utf-8")
    start = page.index("<!-- functions:start")
    listed = page[page.index("-->", start) + 4:page.index("<!-- functions:end -->")]
    assert listed == table.markdown(), "docs/evaluator.md: regenerate with python -m sheetkin.xlsx.table"
    counts = {c: len(n) for c, n in table.by_category().items()}
    assert f"{sum(counts.values())} functions" in listed
    for category, n in counts.items():
        assert f"**{category}** ({n})" in listed


def test_every_entry_is_exercised_by_the_book():
    assert set(CASES) == set(table.SUPPORTED) - SYNTAX
    for name, formulas in CASES.items():
        assert any(function_name(f.split("(")[0]) == name or f"{name}(" in f.upper() for f in formulas), name


def test_every_documented_difference_is_a_case_of_the_book():
    written = {f for fs in CASES.values() for f in fs}
    assert set(EXCEL_DIFFERS) <= written and set(GNUMERIC_DIFFERS) <= written
    page = (ROOT / "docs" / "evaluator.md").read_text(encoding="utf-8")
    for f in [*EXCEL_DIFFERS, *GNUMERIC_DIFFERS]:
        if EXCEL_DIFFERS.get(f, "").startswith("LibreOffice's booleans"):
            continue
        assert f"`={f}`" in page, f


def test_the_kernels_named_in_the_table_exist():
    """The table names kernels of modules loaded on first call: each resolves."""
    import importlib
    for f in table.FUNCTIONS.values():
        for k in [f.kernel, *(c.cell_contents for c in (getattr(f.kernel, "__closure__", None) or ()))]:
            if isinstance(k, table.LazyKernel):
                obj = getattr(importlib.import_module(f"sheetkin.xlsx.{k.module}"), k.attr)
                assert callable(obj[k.key] if k.key is not None else obj), (f.name, k.attr, k.key)


def test_excel_storage_prefixes_are_read():
    for text in ("_xlfn.IFS(1,2)", "_xlfn._xlws.SORT(A1)", "_xlws.FILTER(A1)", "_XLFN.ACOT(1)"):
        tree = parse_formula("=" + text, 1, 1, {})
        assert "." not in tree[1] or tree[1] in table.SUPPORTED, tree
    assert function_name("_xlfn.ACOT") == "ACOT" and function_name("_xlfn._xlws.SORT") == "SORT"


def test_arity_comes_from_the_table():
    assert table.arity_problem(parse_formula("=SWITCH(1,2)", 1, 1, {})) == "SWITCH takes 3 to 255 arguments, not 2"
    assert table.arity_problem(parse_formula("=ROUNDUP(1)", 1, 1, {})) == "ROUNDUP takes 2 arguments, not 1"
    assert table.arity_problem(parse_formula("=NOSUCH(1,2,3)", 1, 1, {})) is None


@pytest.fixture(scope="module")
def book(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("functions")
    path = tmp / "functions.xlsx"
    cells = write_book(path)
    wb = openpyxl.load_workbook(path)
    for anchor, ref, _ in ARRAYS:            # every cell of an array formula's range is compared
        for row in wb["F"][ref]:
            for c in row:
                cells.setdefault(c.coordinate, f"{{{anchor}}}")
    return path, cells


def _ours(path: Path, cells) -> dict[str, object]:
    from openpyxl.utils.cell import column_index_from_string, coordinate_from_string
    b = evaluate(path)
    out = {}
    for a in cells:
        col, row = coordinate_from_string(a)
        out[a] = b.value("F", row, column_index_from_string(col))
    return out


def _theirs(path: Path, cells) -> dict[str, object]:
    wb = openpyxl.load_workbook(path, data_only=True)
    return {a: wb["F"][a].value for a in cells}


def _agree(ours, theirs) -> bool:
    if ours == NUM_AS_VALUE and theirs == "#VALUE!":
        return True
    if isinstance(ours, XlError) or (isinstance(theirs, str) and theirs.startswith("#")):
        return str(ours) == str(theirs)
    if ours in ("", None) and theirs in ("", None):
        return True
    if isinstance(ours, bool) or isinstance(theirs, bool):
        return ours is theirs or (isinstance(theirs, int) and not isinstance(theirs, bool) and ours == theirs)
    if isinstance(ours, float) and isinstance(theirs, (int, float)):
        return math.isclose(ours, theirs, rel_tol=1e-12, abs_tol=1e-300)
    return ours == theirs


def _differences(path: Path, cells, recalculated: Path) -> list[str]:
    ours, theirs = _ours(path, cells), _theirs(recalculated, cells)
    return [f"F!{a} ={cells[a]}: sheetkin {ours[a]!r}, other {theirs[a]!r}" for a in cells
            if cells[a] not in EXCEL_DIFFERS and not _agree(ours[a], theirs[a])]


def test_every_function_agrees_with_libreoffice(book, tmp_path, soffice):
    path, cells = book
    out = recalculate([path], tmp_path / "lo")[path.resolve()]
    diffs = _differences(path, cells, out)
    assert not diffs, f"{len(diffs)} cells differ:\n" + "\n".join(diffs)


def test_every_function_agrees_with_gnumeric(book, tmp_path, ssconvert):
    """Gnumeric where it has the function (a function it lacks is its #NAME?)."""
    from helpers.engines import gnumeric_recalc
    path, cells = book
    out = gnumeric_recalc(path, tmp_path / "gnumeric")
    theirs = _theirs(out, cells)
    lacking = {a for a, v in theirs.items() if v == "#NAME?"}
    diffs = _differences(path, {a: f for a, f in cells.items() if a not in lacking and f not in GNUMERIC_DIFFERS}, out)
    assert not diffs, f"{len(diffs)} cells differ:\n" + "\n".join(diffs)

