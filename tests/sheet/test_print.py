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

import sheetkin
from sheetkin.sheet.printing import POSITIONS_PER_PAGE, column_strips
from sheetkin.sheet.workbook import build_workbook, sheet_rows, write_workbook

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
    summary D3 whole; the positions spread evenly across (13: 4 + 5 + 4), numbered as row i."""
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
    assert groups == {(a, b - a) for a, b in zip([0] + ends, ends, strict=False)} == {(0, 4), (4, 5), (9, 4)}
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
