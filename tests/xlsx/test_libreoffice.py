"""The LibreOffice harness (sheetkin/xlsx/libreoffice.py) on tiny workbooks written here with openpyxl.

Also pins down what LibreOffice 7.4 does with the formulas sheetkin relies on. soffice starts
few times: every book of stage 1 is recalculated in one call, the books derived from its
outputs (stage 2) in a second one; the PDF and the failure check take one call each.
"""
from __future__ import annotations

import math
import re
import zipfile
from pathlib import Path

import openpyxl
import pytest
from helpers.libreoffice import is_error, pdf_to_png, read_values, recalculate, render_pdf
from openpyxl.formatting.rule import CellIsRule, ColorScaleRule, FormulaRule
from openpyxl.styles import PatternFill
from openpyxl.workbook.defined_name import DefinedName

# LibreOffice writes cached numbers with 15 significant digits.
approx = lambda x: pytest.approx(x, rel=1e-13, abs=1e-13)  # noqa: E731

BUILDERS = {}


def book(fn):
    """Register a stage-1 workbook builder; the book is named after the function."""
    BUILDERS[fn.__name__] = fn
    return fn


def _rows(ws, rows):
    for r, values in enumerate(rows, start=1):
        for c, v in enumerate(values, start=1):
            ws.cell(r, c, v)


@book
def arith():
    wb = openpyxl.Workbook()
    _rows(wb.active, [
        [2, "=A1*3"],
        [3.5, "=A1+A2*2-1"],
        [None, "=A2/A1"],
        [None, "=A1^10"],
        [None, "=SUM(A1:A2)"],
        [None, "=B1+B2"],  # formula on formulas, none of them with a cached value
    ])
    return wb


# (formula, expected); ATAN2 takes (x, y), Python's math.atan2 takes (y, x).
TRIG = [
    ("=ATAN2(1,0)", 0.0),
    ("=ATAN2(0,1)", math.pi / 2),
    ("=ATAN2(-1,0)", math.pi),
    ("=ATAN2(0,-1)", -math.pi / 2),
    ("=ATAN2(1,2)", math.atan2(2, 1)),
    ("=ATAN2(-1,-1)", -3 * math.pi / 4),
    ("=MOD(-30,360)", 330.0),
    ("=MOD(390,360)", 30.0),
    ("=MOD(-30.5,360)", 329.5),
    ("=MOD(DEGREES(ATAN2(-1,-1)),360)", 225.0),
    ("=DEGREES(PI())", 180.0),
    ("=DEGREES(1)", math.degrees(1)),
    ("=RADIANS(180)", math.pi),
    ("=RADIANS(-30)", math.radians(-30)),
    ("=COS(RADIANS(60))", 0.5),
]


@book
def trig():
    wb = openpyxl.Workbook()
    _rows(wb.active, [[f] for f, _ in TRIG])
    return wb


@book
def branches():
    wb = openpyxl.Workbook()
    _rows(wb.active, [
        [0.25, '=IF(A1<0,"cannot assemble",SQRT(A1))'],
        [-1, '=IF(A2<0,"cannot assemble",SQRT(A2))'],
        [-1, '=IF(A3>=0,SQRT(A3),"cannot assemble")'],
        [0.25, '=IF(A4>=0,SQRT(A4),"cannot assemble")'],
    ])
    return wb


@book
def errors():
    wb = openpyxl.Workbook()
    _rows(wb.active, [
        ["=SQRT(-1)"],          # Excel: #NUM!, LibreOffice 7.4: #VALUE!
        ["=1/0"],
        ["=ACOS(2)"],
        ["=NA()"],
        ["=LN(0)"],
        ["=A1+1"],              # errors propagate
        ["=ISERROR(SQRT(-1))"],
        ["=IFERROR(SQRT(-1),-1)"],
        ["=1>2"],
        ["=2>1"],
    ])
    return wb


@book
def maxmin():
    wb = openpyxl.Workbook()
    ws = wb.active
    _rows(ws, [
        [1.5, "=MAX(A1:A6)"],
        ["text", "=MIN(A1:A6)"],
        [-4, "=MAX(C1:C3)"],
        ["9", "=MIN(C1:C3)"],   # a number stored as text is text
        [None, "=COUNT(A1:A6)"],
        [7],
    ])
    # The sheetkin case: a column where some rows say "cannot assemble".
    for r, v in enumerate([4, -1, 1], start=1):
        ws.cell(r, 4, v)
        ws.cell(r, 3, f'=IF(D{r}<0,"cannot assemble",SQRT(D{r}))')
    return wb


@book
def xsheet():
    wb = openpyxl.Workbook()
    inp = wb.active
    inp.title = "Input"
    inp["A1"], inp["A2"] = 21, 10
    data = wb.create_sheet("Crank data")
    data["A1"] = 0.5
    calc = wb.create_sheet("Calc")
    calc["A1"] = "=Input!A1*2"
    calc["A2"] = "='Crank data'!A1+Input!$A$2"
    calc["A3"] = "=omega_1*3"
    calc["A4"] = "=SUM(Input!A1:A2)"
    wb.defined_names["omega_1"] = DefinedName("omega_1", attr_text="Input!$A$2")
    return wb


@book
def condfmt():
    wb = openpyxl.Workbook()
    ws = wb.active
    _rows(ws, [[v, f"=A{r}*2"] for r, v in enumerate([-2, 0, 3], start=1)])
    ws["B4"] = '=IF(A1<0,"cannot assemble",1)'
    red = PatternFill("solid", start_color="FFC7CE", end_color="FFC7CE")
    ws.conditional_formatting.add("B1:B3", CellIsRule(operator="lessThan", formula=["0"], fill=red))
    ws.conditional_formatting.add("B1:B4", FormulaRule(formula=['ISTEXT(B1)'], fill=red))
    ws.conditional_formatting.add("A1:A3", ColorScaleRule(start_type="min", start_color="FFFFFF",
                                                          end_type="max", end_color="63BE7B"))
    return wb


@book
def edited():
    """Recalculated in stage 1, then A1 is changed with openpyxl and it is recalculated again."""
    wb = openpyxl.Workbook()
    _rows(wb.active, [[2, "=A1*3", "=B1+A1"]])
    return wb


@pytest.fixture(scope="session")
def stage1(soffice, tmp_path_factory) -> dict[str, Path]:
    """All BUILDERS books, recalculated in one soffice call: name -> output path."""
    src = tmp_path_factory.mktemp("lo_in1")
    paths = {}
    for name, build in BUILDERS.items():
        paths[name] = src / f"{name}.xlsx"
        build().save(paths[name])
    out = recalculate(list(paths.values()), tmp_path_factory.mktemp("lo_out1"))
    return {name: out[p.resolve()] for name, p in paths.items()}


def _set_cached_input(src: Path, dst: Path, cell: str, value: str) -> None:
    """Copy an xlsx, changing the stored value of one constant cell but not the cached
    values of the formulas that depend on it (so those become stale)."""
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "xl/worksheets/sheet1.xml":
                data, n = re.subn(rf'(<c r="{cell}"[^>]*><v>)[^<]*(</v>)'.encode(),
                                  rb"\g<1>" + value.encode() + rb"\g<2>", data)
                assert n == 1, data[:2000]
            zout.writestr(item, data)


@pytest.fixture(scope="session")
def stage2(stage1, tmp_path_factory) -> dict[str, Path]:
    """Books made from stage-1 outputs, recalculated in a second soffice call."""
    src = tmp_path_factory.mktemp("lo_in2")
    # openpyxl edit: it drops the cached values of formulas when it saves.
    wb = openpyxl.load_workbook(stage1["edited"])
    wb.active["A1"] = 10
    wb.save(src / "reedited.xlsx")
    # Stale cached values, as in a LibreOffice-written file whose input was changed outside
    # a spreadsheet: only recalculated because our profile forces recalculation on load.
    _set_cached_input(stage1["edited"], src / "stale.xlsx", "A1", "10")
    assert read_values(src / "stale.xlsx") == {"A1": 10, "B1": 6, "C1": 8}
    paths = {n: src / f"{n}.xlsx" for n in ("reedited", "stale")}
    out = recalculate(list(paths.values()), tmp_path_factory.mktemp("lo_out2"))
    return {name: out[p.resolve()] for name, p in paths.items()}


def test_arithmetic(stage1):
    v = read_values(stage1["arith"])
    assert v["B1"] == 6 and v["B2"] == approx(8.0) and v["B3"] == approx(1.75)
    assert v["B4"] == 1024 and v["B5"] == approx(5.5) and v["B6"] == approx(14.0)
    assert isinstance(v["B1"], int)  # whole numbers come back as int through openpyxl


@pytest.mark.parametrize("row", range(1, len(TRIG) + 1), ids=[f for f, _ in TRIG])
def test_trig_mod_degrees(stage1, row):
    formula, expected = TRIG[row - 1]
    assert read_values(stage1["trig"])[f"A{row}"] == approx(expected)


def test_atan2_takes_x_first(stage1):
    v = read_values(stage1["trig"])
    assert v["A1"] == approx(0.0)            # ATAN2(1,0): x=1, y=0
    assert v["A2"] == approx(math.pi / 2)    # ATAN2(0,1): x=0, y=1


def test_if_text_branch_only_when_taken(stage1):
    v = read_values(stage1["branches"])
    assert v["B1"] == approx(0.5) and v["B4"] == approx(0.5)
    # The SQRT of the negative number sits in the branch not taken: no error.
    assert v["B2"] == "cannot assemble" and v["B3"] == "cannot assemble"


def test_errors(stage1):
    v = read_values(stage1["errors"])
    for cell in ("A1", "A2", "A3", "A4", "A5", "A6"):
        assert is_error(v[cell]), (cell, v[cell])
    assert v["A2"] == "#DIV/0!" and v["A4"] == "#N/A"
    assert v["A7"] is True and v["A8"] == -1  # ISERROR / IFERROR see the error
    assert v["A9"] is False and v["A10"] is True  # booleans come back as bool


def test_is_error():
    for e in ("#VALUE!", "#NUM!", "#DIV/0!", "#REF!", "#NAME?", "#N/A", "#NULL!", "Err:502", "Err:522"):
        assert is_error(e)
    for v in ("cannot assemble", "", "#", "Err:", "Err:50", "#value", 0, 1.5, None, True, float("nan")):
        assert not is_error(v)


def test_max_min_ignore_text(stage1):
    v = read_values(stage1["maxmin"])
    assert v["B1"] == 7 and v["B2"] == -4 and v["B5"] == 3
    assert v["C2"] == "cannot assemble"
    assert v["B3"] == approx(2.0) and v["B4"] == approx(1.0)


def test_cross_sheet_and_defined_name(stage1):
    v = read_values(stage1["xsheet"], sheet="Calc")
    assert v == {"A1": 42, "A2": approx(10.5), "A3": 30, "A4": 31}


def test_conditional_formatting_survives(stage1):
    v = read_values(stage1["condfmt"])
    assert [v["B1"], v["B2"], v["B3"], v["B4"]] == [-4, 0, 6, "cannot assemble"]
    ws = openpyxl.load_workbook(stage1["condfmt"]).active
    assert len(ws.conditional_formatting) >= 2


def test_recalculated_after_openpyxl_edit(stage1, stage2):
    assert read_values(stage1["edited"]) == {"A1": 2, "B1": 6, "C1": 8}
    assert read_values(stage2["reedited"]) == {"A1": 10, "B1": 30, "C1": 40}


def test_stale_cached_values_recalculated(stage2):
    assert read_values(stage2["stale"]) == {"A1": 10, "B1": 30, "C1": 40}


def test_formulas_kept(stage1):
    ws = openpyxl.load_workbook(stage1["branches"]).active
    assert ws["B2"].value == '=IF(A2<0,"cannot assemble",SQRT(A2))'


def test_missing_output_raises(soffice, tmp_path):
    bad = tmp_path / "bad.xlsx"
    bad.write_bytes(b"not a workbook\x00\x01")
    with pytest.raises(RuntimeError, match="no xlsx for") as exc:
        recalculate([bad], tmp_path / "out", timeout=120)
    assert "stderr" in str(exc.value)


def test_same_output_name_rejected(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    for d in "ab":
        (tmp_path / d / "x.xlsx").write_bytes(b"")
    with pytest.raises(ValueError):
        recalculate([tmp_path / "a" / "x.xlsx", tmp_path / "b" / "x.xlsx"], tmp_path / "out")


def test_render_pdf_and_png(soffice, pdftoppm, stage1, tmp_path):
    pdf = render_pdf(stage1["condfmt"], tmp_path)
    assert pdf.read_bytes()[:5] == b"%PDF-"
    pngs = pdf_to_png(pdf, tmp_path / "pics" / "condfmt", dpi=50)
    assert pngs == [tmp_path / "pics" / "condfmt-1.png"]
    assert pngs[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
