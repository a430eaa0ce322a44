"""The kinematics sheet prints readably: LibreOffice's PDF of a workbook has the title rows
and columns A-D on every page, six positions per page, every description whole."""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest
from libreoffice import render_pdf

import sheetkin
from sheetkin.sheet.printing import POSITIONS_PER_PAGE
from sheetkin.sheet.workbook import sheet_rows, write_workbook

WB = Path(__file__).resolve().parents[2] / "workbooks"


@pytest.fixture(scope="module")
def pages(soffice, tmp_path_factory):
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext not found: run `bash tests/setup.sh` (poppler-utils)")
    tmp = tmp_path_factory.mktemp("print")
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    book = tmp / "fourbar.xlsx"
    write_workbook(scene, book)
    pdf = render_pdf(book, tmp)
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout
    return scene, [p for p in text.split("\f") if p.strip()]


def test_every_page_repeats_titles_and_a_to_d(pages):
    scene, texts = pages
    sheet = [t for t in texts if "описание" in t]
    assert len(sheet) >= 3
    groups = set()
    for t in sheet:
        assert scene.title in t and "значение /" in t and "проверка" in t
        header = next(line for line in t.splitlines() if line.lstrip().startswith("имя"))
        numbers = [int(x) for x in re.findall(r"\b\d+\b", header)]
        first = numbers[0]
        assert (first - 1) % POSITIONS_PER_PAGE == 0
        assert numbers == list(range(first, min(first + POSITIONS_PER_PAGE, 14)))
        groups.add(first)
    assert groups == {1, 7, 13}                                  # 13 positions: 6 + 6 + 1
    assert texts[-1].lstrip().startswith("положение i =")       # the charts page comes last


def test_descriptions_print_whole(pages):
    """Every word of every description and row name is on the pages (none cut at the
    column's edge); wrapped rows were given the height of their lines."""
    scene, texts = pages
    words = set(" ".join(texts).split())
    for row in sheet_rows(scene).rows:
        for w in (row.ru.split() if row.kind != "section" else []):
            assert w in words, (row.name, w)
