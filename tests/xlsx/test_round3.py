"""Issue 23, item 4: the evaluator as Excel where it was silently wrong: TRUNC past the
double's range, ISERROR/IFERROR on Excel 365's newer errors, text capped at 32,767
characters (#VALUE! past it: a text doubled 40 times by `&` reached 2 GB), phonetic guides
left out of the text, duplicate sheet names refused. The expected values are Excel's
documented behaviour (support.microsoft.com: TRUNC, ISERROR, IFERROR, "Excel specifications
and limits": 32,767 characters in a cell)."""
from __future__ import annotations

import zipfile
from pathlib import Path

import openpyxl
import pytest

from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.functions import ERRORS
from sheetkin.xlsx.package import UnusableWorkbook
from sheetkin.xlsx.values import MAX_TEXT


def _book(tmp_path: Path, cells: dict[str, object]) -> tuple:
    wb = openpyxl.Workbook()
    ws = wb.active
    for ref, v in cells.items():
        ws[ref] = v
    path = tmp_path / "b.xlsx"
    wb.save(path)
    book = evaluate(path)
    sheet = book.order[0]
    return book, sheet


def _value(book, sheet, ref):
    from openpyxl.utils.cell import column_index_from_string, coordinate_from_string
    col, row = coordinate_from_string(ref)
    return book.value(sheet, row, column_index_from_string(col))


@pytest.mark.parametrize("formula, expected", [
    ("=TRUNC(1E308,2)", 1e308), ("=TRUNC(-1E308,5)", -1e308), ("=TRUNC(2^60+0.5,3)", 2.0 ** 60),
    ("=TRUNC(3.14159,2)", 3.14), ("=TRUNC(-3.14159,3)", -3.141), ("=TRUNC(1234.5,-2)", 1200.0),
    ("=TRUNC(1E300,-400)", 0.0), ("=TRUNC(8.9)", 8.0), ("=TRUNC(1E-300,400)", 1e-300),
])
def test_trunc(tmp_path, formula, expected):
    book, sheet = _book(tmp_path, {"A1": formula})
    assert _value(book, sheet, "A1") == expected


@pytest.mark.parametrize("code", ["#SPILL!", "#CALC!", "#GETTING_DATA", "#N/A", "#DIV/0!"])
def test_iserror_and_iferror_see_every_error(tmp_path, code):
    book, sheet = _book(tmp_path, {"A1": f"=ISERROR({code})", "A2": f"=IFERROR({code},7)",
                                   "A3": f"=IFERROR(1,{code})"})
    assert _value(book, sheet, "A1") is True
    assert _value(book, sheet, "A2") == 7
    assert _value(book, sheet, "A3") == 1


def test_saved_spill_error_is_an_error(tmp_path):
    """A cell whose saved value is #SPILL! (t="e"), as Excel 365 writes a blocked spill."""
    path = tmp_path / "spill.xlsx"
    wb = openpyxl.Workbook()
    wb.active["B1"] = "=ISERROR(A1)"
    wb.save(path)
    patched = tmp_path / "spill2.xlsx"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(patched, "w") as zout:
        for info in zin.infolist():
            data = zin.read(info)
            if info.filename == "xl/worksheets/sheet1.xml":
                data = data.replace(b'<c r="B1"', b'<c r="A1" t="e"><v>#SPILL!</v></c><c r="B1"')
            zout.writestr(info, data)
    book = evaluate(patched)
    assert book.value(book.order[0], 1, 2) is True
    assert ERRORS["#SPILL!"] >= 10


def test_text_capped_at_excels_limit(tmp_path):
    cells = {"A1": '="ab"'} | {f"A{r}": f"=A{r - 1}&A{r - 1}" for r in range(2, 42)}   # 40 doublings
    cells["B1"] = '=A14&"x"'                                   # 2**14 + 1 characters: fits
    book, sheet = _book(tmp_path, cells)
    # A15 holds 2**15 = 32,768 characters: one past the limit
    assert len(_value(book, sheet, "A14")) == 16_384
    assert _value(book, sheet, "A15") == "#VALUE!"
    assert _value(book, sheet, "A41") == "#VALUE!"       # the error propagates, no 2 GB text
    assert len(_value(book, sheet, "B1")) == 16_385
    assert MAX_TEXT == 32_767


def test_text_of_exactly_the_limit_fits(tmp_path):
    book, sheet = _book(tmp_path, {"A1": "x" * 32_000, "A2": f'=A1&"{"y" * 200}"', "A3": "=A2&A1",
                                   "A4": f'=A1&"{"y" * 255}"&"{"z" * 255}"&"{"w" * 257}"'})
    assert len(_value(book, sheet, "A2")) == 32_200
    assert _value(book, sheet, "A3") == "#VALUE!"
    assert len(_value(book, sheet, "A4")) == 32_767              # exactly the limit


def _shared_strings_book(tmp_path, si_xml: bytes) -> Path:
    """A book whose A1 is shared string 0, `si_xml` (openpyxl writes inline strings)."""
    path = tmp_path / "ss.xlsx"
    wb = openpyxl.Workbook()
    wb.active["A1"] = "placeholder"
    wb.active["B1"] = '=A1&"!"'
    wb.save(path)
    out = tmp_path / "phonetic.xlsx"
    main = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(out, "w") as zout:
        for info in zin.infolist():
            data = zin.read(info)
            if info.filename == "xl/worksheets/sheet1.xml":
                data = data.replace(b'<c r="A1" t="inlineStr"><is><t>placeholder</t></is></c>',
                                    b'<c r="A1" t="s"><v>0</v></c>')
            elif info.filename == "[Content_Types].xml":
                data = data.replace(b"</Types>", b'<Override PartName="/xl/sharedStrings.xml" ContentType='
                                    b'"application/vnd.openxmlformats-officedocument.spreadsheetml.sharedStrings'
                                    b'+xml"/></Types>')
            zout.writestr(info, data)
        zout.writestr("xl/sharedStrings.xml", f'<sst xmlns="{main}" count="1" uniqueCount="1">'.encode()
                      + si_xml + b"</sst>")
    return out


def test_phonetic_runs_are_not_part_of_the_text(tmp_path):
    """<rPh>: the furigana Excel shows above 東京 (トウキョウ) is not in the cell's text."""
    si = ("<si><r><t>東</t></r><r><rPr><b/></rPr><t>京</t></r>"
          '<rPh sb="0" eb="2"><t>トウキョウ</t></rPh><phoneticPr fontId="1"/></si>').encode()
    book = evaluate(_shared_strings_book(tmp_path, si))
    sheet = book.order[0]
    assert book.value(sheet, 1, 1) == "東京"
    assert book.value(sheet, 1, 2) == "東京!"
    plain = ('<si><t>日本</t><rPh sb="0" eb="2"><t>ニホン</t></rPh></si>').encode()
    book = evaluate(_shared_strings_book(tmp_path, plain))
    assert book.value(book.order[0], 1, 1) == "日本"


@pytest.mark.parametrize("second", ["Sheet", "SHEET", "sheet"])
def test_duplicate_sheet_names_are_refused(tmp_path, second):
    path = tmp_path / "two.xlsx"
    wb = openpyxl.Workbook()
    wb.create_sheet("Other")
    wb.save(path)
    patched = tmp_path / "dup.xlsx"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(patched, "w") as zout:
        for info in zin.infolist():
            data = zin.read(info)
            if info.filename == "xl/workbook.xml":
                data = data.replace(b'name="Other"', f'name="{second}"'.encode())
            zout.writestr(info, data)
    with pytest.raises(UnusableWorkbook, match="two sheets named"):
        evaluate(patched)
