"""The kinematics sheet prints readably: LibreOffice's PDF of a workbook has the title rows,
columns A-D and the summary on every page, the positions and rows spread evenly over the
pages (no page of a few rows), every description whole."""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest
from helpers.libreoffice import render_pdf
from openpyxl.utils import get_column_letter

import sheetkin
from sheetkin.sheet.printing import PAGE_WIDTH_MM, POSITION_WIDTH, POSITIONS_PER_PAGE, UNIT_MM, column_strips
from sheetkin.sheet.workbook import build_workbook, prefilled_in_exercise, sheet_rows, write_workbook

WB = Path(__file__).resolve().parents[2] / "workbooks"


def _pdf_pages(book: Path, tmp: Path) -> list[str]:
    pdf = render_pdf(book, tmp)
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout
    return [p for p in text.split("\f") if p.strip()]


@pytest.fixture(scope="module")
def pages(soffice, tmp_path_factory):
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext not found: run `bash tests/setup.sh` (poppler-utils)")
    tmp = tmp_path_factory.mktemp("print")
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    book = tmp / "fourbar.xlsx"
    write_workbook(scene, book)
    return scene, _pdf_pages(book, tmp)


def test_every_page_repeats_titles_and_a_to_d(pages):
    """Every page: the scheme's title (the page header), the headers, columns A-D and the
    summary D3 whole; the positions spread evenly across (13: 7 + 6), numbered as row i."""
    scene, texts = pages
    sheet = [t for t in texts if "описание" in t]
    groups = set()
    for t in sheet:
        assert scene.title in t and "значение /" in t and "проверка" in t
        assert "все проверки выполнены" in t                    # D3, not cut at the page's edge
        header = next(line for line in t.splitlines() if line.lstrip().startswith("имя"))
        numbers = [int(x) for x in re.findall(r"\b\d+\b", header)]
        first = numbers[0]
        assert numbers == list(range(first, first + len(numbers))) and len(numbers) <= POSITIONS_PER_PAGE
        groups.add((first, len(numbers)))
    ends = column_strips(scene.crank.positions)
    assert groups == {(a, b - a) for a, b in zip([0] + ends, ends, strict=False)} == {(0, 7), (7, 6)}
    assert texts[-1].lstrip().startswith("положение i =")       # the charts page comes last


@pytest.fixture(scope="module")
def exercises(soffice, tmp_path_factory):
    """The bundled exercises printed by LibreOffice, with their row breaks."""
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext not found: run `bash tests/setup.sh` (poppler-utils)")
    tmp = tmp_path_factory.mktemp("print_all")
    out = {}
    for stem in ("fourbar", "shaper_dynamics", "slotted_lever", "three_group_chain"):
        scene = sheetkin.load_scene(WB / f"{stem}.toml")
        wb = build_workbook(scene, exercise=True)
        ws = wb.worksheets[0]
        wb.save(tmp / f"{stem}.xlsx")
        across = len(ws.col_breaks.brk) + 1
        down = len(ws.row_breaks.brk) + 1
        out[stem] = (across, down, [t for t in _pdf_pages(tmp / f"{stem}.xlsx", tmp) if "описание" in t])
    return out


@pytest.mark.parametrize("stem", ["fourbar", "shaper_dynamics", "slotted_lever", "three_group_chain"])
def test_no_page_holds_only_a_few_rows(exercises, stem):
    """The pages are the ones sheetkin planned (LibreOffice added no break of its own: the
    rows fit), and each holds at least 3/4 of the lines of the fullest page (the four-bar
    once printed 3 pages of three "н/д" rows)."""
    across, down, sheet = exercises[stem]
    assert len(sheet) == across * down
    lines = [sum(1 for ln in t.splitlines() if ln.strip()) for t in sheet]
    assert min(lines) >= 0.75 * max(lines), lines


def test_descriptions_print_whole(pages):
    """Every word of every description and row name is on the pages (none cut at the
    column's edge); wrapped rows were given the height of their lines."""
    scene, texts = pages
    words = set(" ".join(texts).split())
    for row in sheet_rows(scene).rows:
        for w in (row.ru.split() if row.kind != "section" else []):
            assert w in words, (row.name, w)


def test_readme_gives_each_bundled_books_pages():
    """The README's page counts are the ones sheetkin plans (kinematics pages across x down,
    which the LibreOffice tests above find printed, plus the charts page), for every bundled
    book: a change of layout that moves a count fails here until the README says it."""
    text = " ".join((WB.parent / "README.md").read_text(encoding="utf8").split())
    said = dict(re.findall(r"(\w+) (\d+)(?:,| pages)", text[text.index("On paper ("):]))
    planned = {}
    for toml in sorted(WB.glob("*.toml")):
        ws = build_workbook(sheetkin.load_scene(toml)).worksheets[0]
        planned[toml.stem] = str((len(ws.col_breaks.brk) + 1) * (len(ws.row_breaks.brk) + 1) + 1)
    assert {k: said.get(k) for k in planned} == planned


def _fill(cell) -> str:
    return cell.fill.fgColor.rgb[-6:] if cell.fill.fill_type == "solid" else ""


def test_exercise_colours_say_what_to_change():
    """One colour says "do not change" (the given data, locked), another "fill in" (D1, D2,
    the derived values, the computed rows' empty cells): never the same; the accepted
    values' names are blue in the exercise as in the key (the guide says so)."""
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    built = sheet_rows(scene)
    for exercise in (True, False):
        ws = build_workbook(scene, exercise=exercise, charts=False).worksheets[0]
        where = {ws.cell(r, 1).value: r for r in range(5, ws.max_row + 1)}
        given = {_fill(ws.cell(where[row.name], 4)) for row in built.rows if row.kind == "input"}
        fill_in = {_fill(ws["D1"]), _fill(ws["D2"])}
        if exercise:                 # the key has their formulas
            fill_in |= {_fill(ws.cell(where[row.name], 4)) for row in built.rows if row.kind == "derived"}
        assert len(given) == 1 and len(fill_in) == 1 and given != fill_in and "" not in given | fill_in
        assert ws["D1"].protection.locked is False
        accepted = [row.name for row in built.rows if row.kind == "accepted"]
        assert accepted and {_fill(ws.cell(where[n], 1)) for n in accepted} == {"DDEBF7"}
        if exercise:                 # the empty rows the student computes: the "fill in" colour
            empty = [row.name for row in built.rows if row.kind in ("calc", "accepted")
                     and not prefilled_in_exercise(row.name, row.kind)]
            assert empty
            for n in empty:
                cells = [ws.cell(where[n], 5 + k) for k in range(scene.crank.positions)]
                assert all(c.value is None for c in cells), n
                assert {_fill(c) for c in cells} == fill_in, n


@pytest.mark.parametrize("stem", ["fourbar", "slotted_lever", "three_group_chain"])
def test_print_settings_fill_the_page(stem):
    """The scale makes A-D and the widest page's positions fill landscape A4's width (not
    more: LibreOffice would add a break of its own; not a position's width less); the
    first page is the widest and E1's title is merged over exactly its positions."""
    scene = sheetkin.load_scene(WB / f"{stem}.toml")
    ws = build_workbook(scene, exercise=True, charts=False).worksheets[0]
    ends = column_strips(scene.crank.positions)
    sizes = [b - a for a, b in zip([0] + ends, ends, strict=False)]
    assert sizes[0] == max(sizes) <= POSITIONS_PER_PAGE and max(sizes) - min(sizes) <= 1
    units = sum(ws.column_dimensions[c].width for c in "ABCD") + sizes[0] * POSITION_WIDTH
    printed = units * UNIT_MM * ws.page_setup.scale / 100
    assert PAGE_WIDTH_MM - POSITION_WIDTH * UNIT_MM * ws.page_setup.scale / 100 < printed <= PAGE_WIDTH_MM
    assert ws.page_setup.orientation == "landscape" and not ws.sheet_properties.pageSetUpPr.fitToPage
    assert [str(r) for r in ws.merged_cells.ranges] == [f"E1:{get_column_letter(4 + sizes[0])}1"]
    assert ws["E1"].alignment.wrap_text
    # the header has room above row 1 (at 0.4 in top and 0.3 in header margins it printed
    # over row 1)
    assert ws.page_margins.top - ws.page_margins.header >= 0.3


def test_a_long_title_prints_whole(soffice, tmp_path):
    """A variant's long title wraps in E1 at word breaks over the first page's positions:
    every word of it is whole on the PDF's first page (it was cut at "(вар" on every page
    of the first positions), and the counts of row 2 are there too."""
    import dataclasses
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext not found: run `bash tests/setup.sh` (poppler-utils)")
    scene = sheetkin.load_scene(WB / "shaper.toml")
    scene = dataclasses.replace(scene, title=scene.title + " с длинным названием для проверки переноса (вариант 17)")
    book = tmp_path / "long.xlsx"
    build_workbook(scene, exercise=True).save(book)
    texts = _pdf_pages(book, tmp_path)
    first = texts[0]
    head = first[:first.index("описание")]
    words = head.split()
    for w in scene.title.split():
        assert words.count(w) >= 2, w               # the page header's and E1's, each whole
    for label in ("заполнено:", "выполнено:", "н/д:"):
        assert label in head
