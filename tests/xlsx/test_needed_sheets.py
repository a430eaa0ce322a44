"""read_book(needed_for=...) and `sheetkin evaluate`: only the printed sheet and the sheets
its formulas read are parsed and computed (issue 32, speed), with the same values as when
every sheet is; whenever the formulas' text cannot tell which sheets they read, every sheet
is read."""
from __future__ import annotations

from pathlib import Path

import pytest
from openpyxl import Workbook

from sheetkin.cli.commands import main
from sheetkin.xlsx.cells import read_book
from sheetkin.xlsx.evaluator import evaluate

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"


def book(tmp_path: Path, sheets: dict[str, dict[str, object]], names: dict[str, str] | None = None) -> Path:
    wb = Workbook()
    wb.remove(wb.active)
    for title, cells in sheets.items():
        ws = wb.create_sheet(title)
        for at, v in cells.items():
            ws[at] = v
    if names:
        from openpyxl.workbook.defined_name import DefinedName
        for n, text in names.items():
            wb.defined_names[n] = DefinedName(n, attr_text=text)
    path = tmp_path / "b.xlsx"
    wb.save(path)
    return path


def parsed(path: Path, needed_for) -> set[str]:
    """The sheets whose cells were read."""
    raw = read_book(path, needed_for=needed_for)
    assert raw.order == list(raw.sheets)
    return {n for n, sh in raw.sheets.items() if sh.formulas or sh.consts}


def test_only_the_sheets_read_through_the_formulas(tmp_path):
    p = book(tmp_path, {"Main": {"A1": "=Data!A1*2", "A2": 1},
                        "Data": {"A1": "='Более данных'!B2+1"},
                        "Более данных": {"B2": 5},
                        "Other": {"A1": 7, "A2": "=1/0"}})
    assert parsed(p, 0) == {"Main", "Data", "Более данных"}
    assert parsed(p, "Data") == {"Data", "Более данных"}
    assert parsed(p, "Other") == {"Other"}
    assert parsed(p, None) == {"Main", "Data", "Более данных", "Other"}
    assert parsed(p, "nope") == {"Main", "Data", "Более данных", "Other"}   # the caller says it is missing
    b = evaluate(p, needed_for=0, saved=False)
    assert b.value("Main", 1, 1) == 12.0 and b.order == ["Main", "Data", "Более данных", "Other"]


def test_sheet_names_in_another_case_or_quoted(tmp_path):
    p = book(tmp_path, {"Main": {"A1": "=data!A1+'МОЙ Лист'!A1+'it''s'!A1"},
                        "Data": {"A1": 1}, "Мой лист": {"A1": 2}, "it's": {"A1": 3}, "Other": {"A1": 4}})
    # read in any case (Excel's way; the evaluator itself wants the name as it is written)
    assert parsed(p, 0) == {"Main", "Data", "Мой лист", "it's"}
    p = book(tmp_path, {"Main": {"A1": "=Data!A1+'Мой лист'!A1+'it''s'!A1"},
                        "Data": {"A1": 1}, "Мой лист": {"A1": 2}, "it's": {"A1": 3}, "Other": {"A1": 4}})
    assert parsed(p, 0) == {"Main", "Data", "Мой лист", "it's"}
    assert evaluate(p, needed_for=0).value("Main", 1, 1) == 6.0


@pytest.mark.parametrize("formula", ['=INDIRECT("Other!A1")', "=SUM(A:A)", "=SUM(2:3)", "=SHEETS()",
                                     '=CELL("address",A2)', "=SUM(Data:Other!A1)", '=INFO ("directory")',
                                     "=SUM(Table1[x])", "=SUM(Data:'Other'!A1)", "=Sheet (A1)",
                                     "=indirect(A2)"])
def test_every_sheet_when_the_text_cannot_tell(tmp_path, formula):
    p = book(tmp_path, {"Main": {"A1": formula, "A2": 1}, "Data": {"A1": 1}, "Other": {"A1": 4, "A9": 5}})
    assert parsed(p, 0) == {"Main", "Data", "Other"}


def test_every_sheet_with_a_defined_name(tmp_path):
    p = book(tmp_path, {"Main": {"A1": "=x+1"}, "Other": {"A1": 4}}, names={"x": "Other!$A$1"})
    assert parsed(p, 0) == {"Main", "Other"}
    assert evaluate(p, needed_for=0).value("Main", 1, 1) == 5.0


def test_without_saved_values_the_same_values(tmp_path):
    for path in sorted(WORKBOOKS.glob("*.xlsx"))[:3]:
        full, lean = evaluate(path), evaluate(path, needed_for=0, saved=False)
        main_sheet = full.order[0]
        assert (full.num[main_sheet] == lean.num[main_sheet]).all()
        assert (full.tag[main_sheet] == lean.tag[main_sheet]).all()
        assert not lean.sheets[main_sheet].cached and full.sheets[main_sheet].cached


def test_the_command_prints_the_same_sheet(tmp_path, capsys):
    p = book(tmp_path, {"Main": {"A5": "x", "E5": "=Data!A1*2", "F5": 3},
                        "Data": {"A1": 2}, "Other": {"A5": "y", "E5": "=1+1"}})
    assert main(["evaluate", str(p), "--format", "csv"]) == 0
    assert capsys.readouterr().out == "name,1,2\nx,4.0,3.0\n"
    assert main(["evaluate", str(p), "--format", "csv", "--sheet", "Other"]) == 0
    assert capsys.readouterr().out == "name,1\ny,2.0\n"
    assert main(["evaluate", str(p), "--sheet", "nope"]) == 2
    assert "no sheet 'nope'; sheets: Main, Data, Other" in capsys.readouterr().err


def _with_first_sheet(path: Path, sheet_data: bytes) -> Path:
    """The book at `path` with its first sheet's <sheetData> replaced (Excel's shapes:
    shared formulas, references in the text)."""
    import re
    import zipfile
    out = path.with_name("crafted.xlsx")
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zout:
        for info in zin.infolist():
            data = zin.read(info.filename)
            if info.filename == "xl/worksheets/sheet1.xml":
                data = re.sub(rb"<sheetData>.*</sheetData>|<sheetData/>", lambda m: sheet_data, data, flags=re.S)
            zout.writestr(info.filename, data)
    return out


def _scans(monkeypatch) -> list:
    """(whether the scan read the reader's bytes, the sheets it named, the sheets the old
    scan of the decoded texts names) of each sheet-name scan from now on."""
    from sheetkin.xlsx import cells
    scans = []
    real = cells._sheets_named

    def spy(sh, sheet_names):
        held = sh.formula_bytes
        got = real(sh, sheet_names)
        sh.formula_bytes = None
        scans.append((held is not None, got, real(sh, sheet_names)))
        sh.formula_bytes = held
        return got
    monkeypatch.setattr(cells, "_sheets_named", spy)
    return scans


def test_the_scan_reads_the_text_the_file_holds(tmp_path, monkeypatch):
    """The sheet-name scan reads the fast path's own UTF-8 text of the formulas (issue 32),
    with references as the file spells them (a Cyrillic sheet name as &#...;, &gt;, &amp;):
    the same sheets as the scan of every formula's decoded text, the same values as reading
    every sheet."""
    p = book(tmp_path, {"Main": {"A1": 1}, "Data": {"A1": 2}, "Лист": {"A1": 5}, "Other": {"A1": 6}})
    name = "".join(f"&#{ord(ch)};" for ch in "Лист").encode()
    p = _with_first_sheet(p, b'<sheetData><row r="1"><c r="A1"><v>1</v></c><c r="B1"><f>Data!A1*2</f><v>4</v></c>'
                             b'<c r="C1" t="str"><f>IF(' + name + b'!A1&gt;4,"&#1076;&amp;"&amp;B1,"")</f><v></v></c>'
                             b"</row></sheetData>")
    scans = _scans(monkeypatch)
    assert parsed(p, 0) == {"Main", "Data", "Лист"}
    assert scans[0] == (True, ["Data", "Лист"], ["Data", "Лист"])          # Main's formulas
    assert scans[1:] == [(True, [], [])] * 2                                # Data's and Лист's: none
    lean, full = evaluate(p, needed_for=0, saved=False), evaluate(p)
    assert [lean.value("Main", 1, c) for c in range(1, 4)] == [1.0, 4.0, "д&4"]
    assert (lean.num["Main"] == full.num["Main"]).all() and (lean.tag["Main"] == full.tag["Main"]).all()


def _lower_case_shared(tmp_path: Path) -> Path:
    """Main!E5:E6 one shared formula, Q1!a1 (lower case, as only a hand-edited file has it)."""
    p = book(tmp_path, {"Main": {"A5": "r5"}, "Q1": {"A1": 10, "A2": 15}, "Q2": {"A1": 20}, "Other": {"A1": 6}})
    return _with_first_sheet(p, b'<sheetData><row r="5"><c r="A5" t="inlineStr"><is><t>r5</t></is></c>'
                                b'<c r="E5"><f t="shared" ref="E5:E6" si="0">Q1!a1</f><v>10</v></c></row>'
                                b'<row r="6"><c r="A6" t="inlineStr"><is><t>r6</t></is></c>'
                                b'<c r="E6"><f t="shared" si="0"/><v>20</v></c></row></sheetData>')


def test_a_shared_formula_in_lower_case_as_libreoffice_computes(soffice, tmp_path):
    """LibreOffice's recalculation of that book: E6 is Q1!A2 (15), as sheetkin reads it."""
    from helpers.libreoffice import recalculate

    from sheetkin.xlsx.libreoffice import read_values
    p = _lower_case_shared(tmp_path)
    out = recalculate([p], tmp_path / "lo")
    lo = read_values(next(iter(out.values())), "Main")
    assert (lo["E5"], lo["E6"]) == (10, 15)
    assert [evaluate(p, needed_for=0, saved=False).value("Main", r, 5) for r in (5, 6)] == [10.0, 15.0]


def test_a_shared_formula_scans_every_cells_text(tmp_path, monkeypatch):
    """A shared formula's other cells are its text shifted: a sheet that has one is scanned
    through every cell's text, not the file's (Q1!a1, a lower-case reference only a
    hand-edited file has, was once shifted down to Q2!a1, a sheet its first cell does not
    name: found by a fresh-eyes review of issue 32's change). Down a row it is Q1!A2, as in
    Excel; the sheets read and the values are those of reading every sheet."""
    p = _lower_case_shared(tmp_path)
    scans = _scans(monkeypatch)
    assert parsed(p, 0) == {"Main", "Q1"}
    assert scans[0] == (False, ["Q1"], ["Q1"])
    lean, full = evaluate(p, needed_for=0, saved=False), evaluate(p)
    assert lean.sheets["Main"].formulas[(6, 5)] == "Q1!A2"
    assert lean.value("Main", 6, 5) == full.value("Main", 6, 5) == 15.0
