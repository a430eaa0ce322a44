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

from sheetkin.xlsx.cells import read_book
from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.functions import ERRORS, XlError
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


# ---------------------------------------------------------------- errors are not text
# A text that spells an error ("#N/A" typed, a shared or inline string, a formula's text
# result, a literal "#N/A" in a formula) is text: Excel, LibreOffice and Gnumeric say
# =ISERROR("#N/A") is FALSE. Expected values: those engines (the three-engine test below
# recalculates the same book in LibreOffice and Gnumeric).
TEXT_AS_ERROR = {
    "B1": ('=ISERROR("#N/A")', False), "B2": ('=ISERR("#DIV/0!")', False),
    "B3": ('=IFERROR("#N/A",1)', "#N/A"), "B4": ('=ISTEXT("#N/A")', True),
    "B5": ('=ERROR.TYPE("#N/A")', "an error"), "B6": ('="#N/A"=NA()', "an error"),
    "B7": ("=ISERROR(A1)", False), "B8": ("=ISTEXT(A1)", True), "B9": ("=IFERROR(A1,1)", "#N/A"),
    "B10": ("=ISERROR(A2)", False), "B11": ("=ISERR(A2)", False), "B12": ('=A1&""', "#N/A"),
    "B13": ("=ERROR.TYPE(NA())", 7), "B14": ("=ERROR.TYPE(1/0)", 2), "B15": ("=ISNA(NA())", True),
    "B16": ("=ISERR(NA())", False), "B17": ('=ISNA("#N/A")', False), "B18": ('=IF(A1="#N/A",1,2)', 1),
    "B19": ('="#N/A"="#n/a"', True), "B20": ("=ISERROR(B12)", False), "B21": ("=ISTEXT(B12)", True),
    "B22": ('=REPT("ab",3)', "ababab"), "B23": ('=CONCATENATE("a",1,"#N/A")', "a1#N/A"),
    "B24": ("=ISERROR(A3)", True), "B25": ("=ISTEXT(A3)", False), "B26": ("=ERROR.TYPE(A3)", 7),
    "B27": ("=ISERR(A4)", True), "B28": ('=IFERROR(A4,"x")', "x"), "B29": ("=ISERROR(A5)", False),
    "B30": ("=ERROR.TYPE(A4)", 2), "B31": ("=ISERR(#N/A)", False),
}


def _texts_and_errors_book(tmp_path: Path) -> Path:
    """A1 "#N/A" and A2 "#DIV/0!" typed as text, A5 "#VALUE!" a shared string; A3 the error
    #N/A and A4 #DIV/0! saved as errors (t="e"); column B the formulas of TEXT_AS_ERROR."""
    wb = openpyxl.Workbook()
    ws = wb.active
    for ref, text in (("A1", "#N/A"), ("A2", "#DIV/0!")):
        ws[ref] = text
        ws[ref].data_type = "s"             # openpyxl would take it for an error
    ws["A3"], ws["A4"], ws["A5"] = "#N/A", "#DIV/0!", "placeholder"     # errors (openpyxl: t="e")
    for ref, (formula, _) in TEXT_AS_ERROR.items():
        ws[ref] = formula
    path = tmp_path / "texts.xlsx"
    wb.save(path)
    return _with_shared_string(path, tmp_path / "texts-ss.xlsx", "A5", "#VALUE!")


def _with_shared_string(path: Path, out: Path, ref: str, text: str) -> Path:
    """The book with cell `ref` (an inline string) holding shared string 0, `text`."""
    main = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(out, "w") as zout:
        for info in zin.infolist():
            data = zin.read(info)
            if info.filename == "xl/worksheets/sheet1.xml":
                start = data.index(f'<c r="{ref}" t="inlineStr">'.encode())
                end = data.index(b"</c>", start) + 4
                data = data[:start] + f'<c r="{ref}" t="s"><v>0</v></c>'.encode() + data[end:]
            elif info.filename == "[Content_Types].xml" and b"sharedStrings" not in data:
                data = data.replace(b"</Types>", b'<Override PartName="/xl/sharedStrings.xml" ContentType='
                                    b'"application/vnd.openxmlformats-officedocument.spreadsheetml.sharedStrings'
                                    b'+xml"/></Types>')
            zout.writestr(info, data)
        zout.writestr("xl/sharedStrings.xml", f'<sst xmlns="{main}" count="1" uniqueCount="1"><si><t>'
                      f"{text}</t></si></sst>".encode())
    return out


def _kind(v):
    """A value as the engines are compared: an error is "an error", whatever its code."""
    return "an error" if isinstance(v, XlError) else v


def test_text_that_spells_an_error_is_text(tmp_path):
    path = _texts_and_errors_book(tmp_path)
    raw = read_book(path)
    consts = raw.sheets[raw.order[0]].consts
    assert type(consts[(1, 1)]) is str and type(consts[(5, 1)]) is str      # typed text, shared string
    assert type(consts[(3, 1)]) is XlError and consts[(3, 1)] == "#N/A"     # a saved error
    book = evaluate(path)
    sheet = book.order[0]
    got = {ref: _kind(_value(book, sheet, ref)) for ref in TEXT_AS_ERROR}
    assert got == {ref: want for ref, (_, want) in TEXT_AS_ERROR.items()}
    assert type(_value(book, sheet, "A1")) is str and type(_value(book, sheet, "B12")) is str
    assert isinstance(_value(book, sheet, "B6"), XlError) and _value(book, sheet, "B6") == "#N/A"


def test_text_that_spells_an_error_three_engines(tmp_path, soffice, ssconvert):
    """The same book recalculated by LibreOffice and Gnumeric: every cell of column B the
    same kind of value (an error, a text, a number, a boolean) as sheetkin's; their saved
    text results (t="str", "#N/A") are read back as text, their errors (t="e") as errors."""
    from helpers.engines import gnumeric_recalc
    from helpers.libreoffice import recalculate
    path = _texts_and_errors_book(tmp_path)
    book = evaluate(path)
    ours = {ref: _kind(_value(book, book.order[0], ref)) for ref in TEXT_AS_ERROR}
    lo = recalculate([path], tmp_path / "lo")[path.resolve()]
    for engine, out in (("libreoffice", lo), ("gnumeric", gnumeric_recalc(path, tmp_path / "gn"))):
        raw = read_book(out)
        sh = raw.sheets[raw.order[0]]
        theirs = {}
        for ref in TEXT_AS_ERROR:
            v = sh.cached.get((int(ref[1:]), 2))
            # a boolean may be saved as a number (t="n"): compared as the boolean
            theirs[ref] = bool(v) if isinstance(ours[ref], bool) and isinstance(v, float) else _kind(v)
        assert theirs == ours, engine
        assert type(sh.cached[(12, 2)]) is str                   # "#N/A" saved as a text result


# ---------------------------------------------------------------- text of at most 32,767 characters
@pytest.mark.parametrize("how", ["shared", "inline", "cached"])
@pytest.mark.parametrize("length, ok", [(MAX_TEXT, True), (MAX_TEXT + 1, False), (200_000, False)])
def test_long_text_read_from_a_file_is_value_error(tmp_path, how, length, ok):
    """A text longer than a cell may hold, read from the file (a shared string, an inline
    string, a formula's saved text): #VALUE! in that cell, as a formula making it gives."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws["A1"] = "placeholder"
    ws["B1"] = "=ISERROR(A1)"
    ws["C1"] = '=A1&""'
    path = tmp_path / "long.xlsx"
    wb.save(path)
    text = "x" * length
    if how == "shared":
        path = _with_shared_string(path, tmp_path / "long-ss.xlsx", "A1", text)
    else:
        patched = tmp_path / "long2.xlsx"
        with zipfile.ZipFile(path) as zin, zipfile.ZipFile(patched, "w") as zout:
            for info in zin.infolist():
                data = zin.read(info)
                if info.filename == "xl/worksheets/sheet1.xml":
                    data = data.replace(b"<t>placeholder</t>", f"<t>{text}</t>".encode())
                    if how == "cached":
                        data = data.replace(b"<f>A1&amp;\"\"</f><v></v>", b"<f>A1&amp;\"\"</f>")
                        data = data.replace(b"<f>A1&amp;\"\"</f>", f"<f>A1&amp;\"\"</f><v>{text}</v>".encode())
                        data = data.replace(b'<c r="C1"', b'<c r="C1" t="str"')
                zout.writestr(info, data)
        path = patched
    raw = read_book(path)
    sh = raw.sheets[raw.order[0]]
    if how == "cached":
        assert sh.cached[(1, 3)] == (text if ok else "#VALUE!")
        assert isinstance(sh.cached[(1, 3)], XlError) is not ok
    else:
        assert sh.consts[(1, 1)] == (text if ok else "#VALUE!")
        assert isinstance(sh.consts[(1, 1)], XlError) is not ok
        book = evaluate(path)
        assert book.value(book.order[0], 1, 2) is (not ok)
        assert book.value(book.order[0], 1, 3) == (text if ok else "#VALUE!")


@pytest.mark.parametrize("formula, length", [
    ('=REPT("ab",16383)', 32_766), ('=REPT("abc",10922)', 32_766), ('=REPT("x",32767)', 32_767),
    ('=REPT("x",32768)', None), ('=REPT("ab",16384)', None), ('=REPT("x",1E15)', None),
    ('=REPT("x",-1)', None), ('=REPT("",1E300)', 0), ('=REPT("x",2.9)', 2),
    ('=CONCATENATE(REPT("x",20000),REPT("y",12767))', 32_767),
    ('=CONCATENATE(REPT("x",20000),REPT("y",12768))', None),
    ('=CONCATENATE(REPT("x",30000),REPT("y",30000),REPT("z",30000))', None),
])
def test_text_functions_capped(tmp_path, formula, length):
    """REPT and CONCATENATE: #VALUE! past 32,767 characters, known from the lengths before
    any text is built (REPT("x",1E15) would be a petabyte)."""
    import time
    t0 = time.perf_counter()
    book, sheet = _book(tmp_path, {"A1": formula, "B1": "=ISERROR(A1)"})
    assert time.perf_counter() - t0 < 10
    v = _value(book, sheet, "A1")
    if length is None:
        assert v == "#VALUE!" and isinstance(v, XlError)
        assert _value(book, sheet, "B1") is True
    else:
        assert type(v) is str and len(v) == length
        assert _value(book, sheet, "B1") is False


# ---------------------------------------------------------------- where a cell is: ROW, COLUMN, N, VALUE
# An honest student numbers positions with COLUMN() or ROW() (Fi =(COLUMN()-5)*PI()/6), or
# coerces with N and VALUE: the evaluator computes them as Excel, LibreOffice and Gnumeric do.
POSITIONAL = {
    "A3": ("=ROW()", 3), "B3": ("=COLUMN()", 2), "C3": ("=ROW(E7)", 7), "D3": ("=COLUMN(E7)", 5),
    "E3": ("=ROWS(A1:B4)", 4), "F3": ("=COLUMNS(A1:D1)", 4), "G3": ("=N(A1)", 5), "H3": ("=N(B1)", 0),
    "I3": ("=N(C1)", 1), "J3": ("=VALUE(B1)", 3.5), "K3": ("=VALUE(D1)", "an error"), "M3": ("=N(1/0)", "an error"),
    "N3": ("=COLUMN($C$1:$E$2)", 3), "O3": ("=ROW(A$9)+COLUMN(B1)", 11), "P3": ("=(COLUMN()-5)*30", 330),
}


def _positional_book(tmp_path: Path) -> Path:
    wb = openpyxl.Workbook()
    ws = wb.active
    ws["A1"], ws["B1"], ws["C1"], ws["D1"] = 5, "3.5", True, "abc"
    for ref, (formula, _) in POSITIONAL.items():
        ws[ref] = formula
    path = tmp_path / "positional.xlsx"
    wb.save(path)
    return path


def test_row_column_n_value(tmp_path):
    book = evaluate(_positional_book(tmp_path))
    got = {ref: _kind(_value(book, book.order[0], ref)) for ref in POSITIONAL}
    assert got == {ref: want for ref, (_, want) in POSITIONAL.items()}


def test_row_column_n_value_three_engines(tmp_path, soffice, ssconvert):
    from helpers.engines import gnumeric_recalc
    from helpers.libreoffice import recalculate
    path = _positional_book(tmp_path)
    book = evaluate(path)
    ours = {ref: _kind(_value(book, book.order[0], ref)) for ref in POSITIONAL}
    lo = recalculate([path], tmp_path / "lo")[path.resolve()]
    for engine, out in (("libreoffice", lo), ("gnumeric", gnumeric_recalc(path, tmp_path / "gn"))):
        sh = read_book(out).sheets[read_book(out).order[0]]
        theirs = {ref: _kind(sh.cached.get((int(ref[1:]), openpyxl.utils.column_index_from_string(ref[0]))))
                  for ref in POSITIONAL}
        if engine == "gnumeric":        # Gnumeric's N("3.5") is 3.5; Excel's documented N of text is 0
            assert theirs.pop("H3") == 3.5 and ours.get("H3") == 0
            theirs["H3"] = 0
        assert theirs == ours, engine
