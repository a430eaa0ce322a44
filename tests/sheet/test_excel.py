"""Workbooks true to Excel (issue 20): colours Excel paints, cached values, schema-valid parts,
Excel's limits on formulas, charts that never plot text, bounded work.

Excel cannot run here; what it would do is checked three ways: its documented rules (the
conditional formats' bgColor, 8,192 characters, 64 levels, 255 arguments, #N/A left out of a
chart), the ISO/IEC 29500 Transitional schemas (tests/helpers/ooxml.py), and the values against
sheetkin's solver, LibreOffice and the readers that do not recalculate (openpyxl's
data_only, pandas.read_excel).
"""
from __future__ import annotations

import importlib.util
import re
import zipfile
from pathlib import Path

import numpy as np
import openpyxl
import pandas as pd
import pytest
from helpers.clirun import run
from helpers.libreoffice import is_error, recalculate
from helpers.ooxml import schema_errors

import sheetkin
from sheetkin.sheet.workbook import (
    MAX_FORMULA_CHARS,
    WORKBOOK_MAX_CELLS,
    WORKBOOK_MAX_ROWS,
    WorkbookTooLarge,
    build_workbook,
    sheet_rows,
    write_workbook,
)
from sheetkin.xlsx.parse import ParseError, parse_formula

ROOT = Path(__file__).resolve().parents[2]
WORKBOOKS = ROOT / "workbooks"
BUNDLED = sorted(p.stem for p in WORKBOOKS.glob("*.toml"))
TOL = 1e-9
# a four-bar whose coupler is too short for part of the revolution (as in test_workbook.py)
GAPS = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8").replace(
    "lengths = [0.5, 0.34]", "lengths = [0.45, 0.2]").replace("O1 = [0.0, -0.53]", "O1 = [0.0, -0.6]")
NS = {"m": "http://schemas.openxmlformats.org/spreadsheetml/2006/main"}


def _scale():
    spec = importlib.util.spec_from_file_location("sheetkin_benchmarks_scale", ROOT / "benchmarks" / "scale.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _write(tmp_path, stem: str, text: str | None = None, **kw) -> tuple[Path, sheetkin.Scene]:
    text = text if text is not None else (WORKBOOKS / f"{stem}.toml").read_text(encoding="utf-8")
    scene = sheetkin.parse_scene(text, f"{stem}.toml")
    path = tmp_path / f"{stem}{'-exercise' if kw.get('exercise') else ''}.xlsx"
    write_workbook(scene, path, scene_text=text, **kw)
    return path, scene


def _formula_cells(path) -> dict[str, dict[str, str]]:
    """sheet title -> {cell: formula} of every formula cell."""
    wb = openpyxl.load_workbook(path)
    return {ws.title: {c.coordinate: c.value for row in ws.iter_rows() for c in row
                       if isinstance(c.value, str) and c.data_type == "f"} for ws in wb.worksheets}


def _same(a, b) -> bool:
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return abs(a - b) <= TOL * max(1.0, abs(a), abs(b))
    if is_error(a) or is_error(b):
        return is_error(a) and is_error(b)
    return a == b


# --------------------------------------------------------------------------- colours
def test_conditional_fills_carry_bg_and_fg_colour(tmp_path):
    """Excel paints a conditional format's solid fill with bgColor, LibreOffice and Gnumeric
    with fgColor: every dxf fill has both, the same colour."""
    path, _ = _write(tmp_path, "fourbar")
    for book in (path,):
        with zipfile.ZipFile(book) as z:
            styles = z.read("xl/styles.xml").decode()
        dxfs = re.findall(r"<dxf>.*?</dxf>", styles, re.S)
        assert len(dxfs) >= 3
        for d in dxfs:
            fg = re.search(r'<fgColor rgb="([0-9A-F]+)"', d)
            bg = re.search(r'<bgColor rgb="([0-9A-F]+)"', d)
            assert fg and bg and fg.group(1) == bg.group(1), d


# --------------------------------------------------------------------------- cached values
@pytest.mark.parametrize("stem", BUNDLED)
def test_cached_values_equal_compute(tmp_path, stem):
    """A fresh book read with no recalculation (openpyxl data_only, pandas.read_excel):
    every contract row equals compute(), every check status passes or is n/a, and the
    summary says all checks pass."""
    path, scene = _write(tmp_path, stem)
    df = sheetkin.compute(scene)
    ws = openpyxl.load_workbook(path, data_only=True).worksheets[0]
    rows = {ws.cell(r, 1).value: r for r in range(5, ws.max_row + 1) if ws.cell(r, 1).value}
    frame = pd.read_excel(path, sheet_name=0, header=None, index_col=0)
    frame = frame[~frame.index.duplicated()]
    n = len(df)
    for name in sheetkin.column_names(scene):
        got = np.array([ws.cell(rows[name], 5 + k).value for k in range(n)], dtype=float)
        via_pandas = frame.loc[name].iloc[3:3 + n].to_numpy(dtype=float)
        ref = df[name].to_numpy()
        for values in (got, via_pandas):
            d = np.abs(values - ref)
            if name.startswith("phi_"):
                d = np.minimum(d, 360.0 - d)
            assert np.all(d <= TOL * np.maximum(1.0, np.abs(ref))), name
    statuses = [ws.cell(r, 4).value for name, r in rows.items() if str(name).startswith(("chk_", "fd_"))]
    assert statuses and all(s == 0 or s == "н/д" for s in statuses)
    assert ws["D3"].value.startswith("все проверки выполнены")
    assert ws["F2"].value == sum(1 for s in statuses if s == 0)


def test_exercise_caches_what_its_formulas_give_on_the_empty_book(tmp_path):
    """No answers in an exercise's cached values: the computed rows are empty, the checks
    say "not filled in", the summary "not all rows filled in"."""
    path, scene = _write(tmp_path, "fourbar", exercise=True)
    ws = openpyxl.load_workbook(path, data_only=True).worksheets[0]
    rows = {ws.cell(r, 1).value: r for r in range(5, ws.max_row + 1) if ws.cell(r, 1).value}
    assert all(ws.cell(rows["x_B"], 5 + k).value is None for k in range(scene.crank.positions))
    statuses = [ws.cell(r, 4).value for name, r in rows.items() if str(name).startswith("chk_")]
    assert "не заполнено" in statuses and 0 not in statuses
    assert ws["D3"].value.startswith("заполнены не все строки")


def test_full_recalculation_on_load(tmp_path):
    path, _ = _write(tmp_path, "fourbar")
    with zipfile.ZipFile(path) as z:
        assert re.search(r'<calcPr[^>]*fullCalcOnLoad="1"', z.read("xl/workbook.xml").decode())


def test_cached_values_equal_libreoffice(soffice, tmp_path):
    """Every formula cell of every sheet (statuses, summaries, chart helpers, the plotted
    and paths sheets): the value cached by sheetkin equals LibreOffice's recalculation, in a
    key, an exercise, and a mechanism that cannot assemble over part of the revolution."""
    books = [_write(tmp_path, "fourbar")[0], _write(tmp_path, "fourbar", exercise=True)[0],
             _write(tmp_path, "gaps", GAPS)[0], _write(tmp_path, "shaper_dynamics")[0]]
    out = recalculate(books, tmp_path / "lo")
    for book in books:
        formulas = _formula_cells(book)
        cached = openpyxl.load_workbook(book, data_only=True)
        lo = openpyxl.load_workbook(out[book.resolve()], data_only=True)
        checked = 0
        for title, cells in formulas.items():
            for ref in cells:
                a, b = cached[title][ref].value, lo[title][ref].value
                assert _same(a, b), f"{book.name} {title}!{ref}: cached {a!r}, LibreOffice {b!r}"
                checked += 1
        assert checked > 300


# --------------------------------------------------------------------------- charts
def _chart_refs(path) -> list[tuple[str, str]]:
    with zipfile.ZipFile(path) as z:
        xml = "".join(z.read(n).decode() for n in z.namelist() if n.startswith("xl/charts/chart"))
    refs = []
    for f in re.findall(r"<(?:c:)?f>([^<]*)</(?:c:)?f>", xml):
        m = re.fullmatch(r"'?(.*?)'?!\$?([A-Z]+)\$?(\d+)(?::\$?([A-Z]+)\$?(\d+))?", f)
        if m and m.group(4):
            refs.append((m.group(1).replace("''", "'"), f"{m.group(2)}{m.group(3)}:{m.group(4)}{m.group(5)}"))
    return refs


def test_charts_never_plot_text(tmp_path):
    """The charts of a mechanism that cannot assemble over part of the revolution read
    numbers or #N/A only (Excel plots text and other errors as 0)."""
    path, _ = _write(tmp_path, "gaps", GAPS)
    wb = openpyxl.load_workbook(path, data_only=True)
    refs = _chart_refs(path)
    assert len(refs) > 20
    na = 0
    for sheet, rng in refs:
        for row in wb[sheet][rng]:
            for c in row:
                assert isinstance(c.value, (int, float)) or c.value == "#N/A", (sheet, c.coordinate, c.value)
                na += c.value == "#N/A"
    assert na > 0            # the gap is there, left out


# --------------------------------------------------------------------------- schema
def _allowed(errors: list[str]) -> list[str]:
    # [MS-OI29500] 2.1.678: Excel writes xml:space on <t> (the standard does not mention it);
    # openpyxl writes it where a text keeps leading or trailing spaces (the embedded scene)
    return [e for e in errors if "}t', attribute '{http://www.w3.org/XML/1998/namespace}space'" not in e]


@pytest.mark.parametrize("stem", BUNDLED)
def test_bundled_books_are_schema_valid(tmp_path, capsys, stem):
    """The book `sheetkin workbook` writes (the synthesis sheet where the scene has one)."""
    out = tmp_path / f"{stem}.xlsx"
    code, _, err = run(capsys, "workbook", WORKBOOKS / f"{stem}.toml", "-o", out)
    assert code == 0, err
    assert _allowed(schema_errors(out)) == []


def test_exercise_variants_synthesis_and_english_books_are_schema_valid(tmp_path, capsys):
    books = [_write(tmp_path, "shaper_dynamics", exercise=True)[0],
             _write(tmp_path, "gaps", GAPS, lang="en")[0]]
    code, _, err = run(capsys, "variants", WORKBOOKS / "fourbar.toml", "-n", "2", "--seed", "1",
                       "--out", tmp_path / "v")
    assert code == 0, err
    books += sorted((tmp_path / "v").glob("*.xlsx"))
    synth = tmp_path / "synth.xlsx"
    code, _, err = run(capsys, "synth", "crank-rocker", "--kw", "1.4", "--l3", "0.3", "--yd", "-0.1",
                           "--gamma1-deg", "30", "--gamma2-deg", "80", "--workbook", synth)
    assert code == 0, err
    books.append(synth)
    assert len(books) == 7
    for book in books:
        assert _allowed(schema_errors(book)) == [], book.name


def test_the_schema_check_finds_a_missing_scatter_style(tmp_path):
    path, _ = _write(tmp_path, "fourbar")
    bad = tmp_path / "bad.xlsx"
    with zipfile.ZipFile(path) as src, zipfile.ZipFile(bad, "w") as dst:
        for n in src.namelist():
            data = src.read(n)
            if n.startswith("xl/charts/"):
                data = re.sub(rb"<(c:)?scatterStyle [^>]*/>", b"", data)
            dst.writestr(n, data)
    assert any("scatterStyle" in e for e in schema_errors(bad))


# --------------------------------------------------------------------------- Excel's limits, caps
def test_largest_chain_the_caps_allow_is_within_excel_limits(tmp_path):
    """The longest chain of benchmarks/scale.py within WORKBOOK_MAX_ROWS: every formula of
    its book within 8,192 characters, and parsed by sheetkin's parser, which refuses more
    than 64 levels of nesting and 255 arguments (Excel's limits); one group more is refused."""
    scale = _scale()
    n = 35
    while True:                      # the rows grow with the groups: find the last that fits
        try:
            sheet_rows(sheetkin.parse_scene(scale.chain_scene_text(n + 1)))
        except WorkbookTooLarge:
            break
        n += 1
    assert n >= 40                   # the 40-group book Excel could not load before issue 20
    text = scale.chain_scene_text(n)
    scene = sheetkin.parse_scene(text)
    path = tmp_path / "chain.xlsx"
    write_workbook(scene, path, scene_text=text)      # evaluated strictly while saved
    longest = 0
    seen = set()
    for cells in _formula_cells(path).values():
        for ref, f in cells.items():
            longest = max(longest, len(f) - 1)
            shape = re.sub(r"[A-Z]+\d+", "R", f)
            if shape in seen:
                continue
            seen.add(shape)
            try:
                parse_formula(f, 1, 1, {})
            except ParseError as e:
                pytest.fail(f"{ref}: {e}")
    assert longest <= MAX_FORMULA_CHARS
    ws = openpyxl.load_workbook(path, data_only=True).worksheets[0]
    assert ws["D3"].value.startswith("все проверки выполнены"), ws["D3"].value


def test_twenty_thousand_points_are_refused_in_one_line(tmp_path, capsys):
    base = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    scene = tmp_path / "many.toml"
    scene.write_text(base + "".join(f'[[point]]\nname = "P{i}"\nlink = 2\nfrom = "A"\nalong = 1e-5\n'
                                    for i in range(20_000)), encoding="utf-8")
    code, out, err = run(capsys, "workbook", scene, "-o", tmp_path / "many.xlsx")
    assert code == 2 and err.count("\n") == 1 and f"{WORKBOOK_MAX_ROWS:,} rows" in err, err
    assert str(scene) in err and not (tmp_path / "many.xlsx").exists()


def test_too_many_cells_are_refused_in_one_line(tmp_path, capsys):
    rows = len(sheet_rows(sheetkin.parse_scene((WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8"))).rows)
    n = WORKBOOK_MAX_CELLS // rows + 1
    code, out, err = run(capsys, "workbook", WORKBOOKS / "fourbar.toml", "--positions", n, "--step-deg", "0.01",
                             "-o", tmp_path / "big.xlsx")
    assert code == 2 and err.count("\n") == 1 and f"{WORKBOOK_MAX_CELLS:,} cells" in err, err
    with pytest.raises(WorkbookTooLarge):
        build_workbook(sheetkin.parse_scene((WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
                                            .replace("positions = 13", f"positions = {n}")), scene_text="")
