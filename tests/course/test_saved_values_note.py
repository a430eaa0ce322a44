"""The text report's "(the saved values were used)" after a cell sheetkin cannot compute:
said only where the validator did take the value the spreadsheet saved (a book written by
openpyxl saves none; a name that does not read gives #VALUE!, which is never replaced), and
the evaluator's note itself in the teacher's language."""
from __future__ import annotations

import math
import re
import zipfile
from pathlib import Path

import openpyxl

from sheetkin.course.report import text_report
from sheetkin.course.report_model import Report, RowReport
from sheetkin.course.validator import validate

ROOT = Path(__file__).resolve().parents[2]
SAVED = {"en": "(the saved values were used)", "ru": "(взяты сохранённые значения)"}


def _book(tmp_path: Path, saved: str | None) -> Path:
    """The bundled fourbar book, row Fi computed by a function sheetkin does not know;
    saved: the value written as the spreadsheet's saved value of each of its cells (None:
    none, as openpyxl writes)."""
    wb = openpyxl.load_workbook(ROOT / "workbooks" / "fourbar.xlsx")
    ws = wb.worksheets[0]
    r = next(r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value == "Fi")
    for c in range(5, 5 + 13):
        ws.cell(r, c).value = f"=NOSUCHFUNCTION({ws.cell(r - 1, c).coordinate})"
    dst = tmp_path / f"book-{saved}.xlsx"
    wb.save(dst)
    if saved is not None:
        src = zipfile.ZipFile(dst).infolist(), dst.read_bytes()
        out = tmp_path / f"saved-{saved}.xlsx"
        with zipfile.ZipFile(dst) as zin, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zout:
            for item in src[0]:
                data = zin.read(item.filename)
                if item.filename == "xl/worksheets/sheet1.xml":
                    data, n = re.subn(rb"(<f>NOSUCHFUNCTION\([^<]*\)</f>)<v\s*(?:/>|></v>)",
                                      rb"\1<v>" + saved.encode() + rb"</v>", data)
                    assert n == 13
                zout.writestr(item, data)
        dst = out
    return dst


def test_no_saved_values_no_note(tmp_path):
    rep = validate(_book(tmp_path, None))
    assert any("unsupported function NOSUCHFUNCTION" in p for p in rep.problems)
    fi = next(r for r in rep.rows if r.name == "Fi")
    assert fi.source == "formula" and fi.status == "wrong"
    for lang, note in SAVED.items():
        text = text_report(rep, lang)
        assert note not in text
    text = text_report(rep, "ru")
    assert "неподдерживаемая функция NOSUCHFUNCTION" in text and "unsupported" not in text


def test_saved_values_used_are_said(tmp_path):
    rep = validate(_book(tmp_path, "0"))
    fi = next(r for r in rep.rows if r.name == "Fi")
    assert fi.source == "cached"
    line = next(ln for ln in text_report(rep, "ru").splitlines() if "NOSUCHFUNCTION" in ln)
    assert line.startswith("  не вычисляется: ") and line.endswith(SAVED["ru"])


def test_note_only_on_the_problems_whose_rows_took_saved_values():
    rows = [RowReport("Fi", 42, "correct", source="cached"), RowReport("dFi", 43, "wrong", source="formula",
                                                                        first_wrong=1, expected=1.0, got=math.nan)]
    rep = Report("a.xlsx", rows=rows, positions=13,
                 problems=["Кинематика!E42:Q42: unsupported function COLUMN",
                           "Кинематика!E43:Q43: the name arr_43 is not a formula (={0,1}: unexpected '{')",
                           "Черновик!E42: unsupported function ROW",
                           "Кинематика!E50: circular reference among Кинематика!E50, Кинематика!E51: #VALUE!"])

    class Layout:
        sheet = "Кинематика"
    rep.layout = Layout()        # type: ignore[assignment]
    lines = [ln for ln in text_report(rep, "ru").splitlines() if ln.startswith("  не вычисляется: ")]
    assert [ln.endswith(SAVED["ru"]) for ln in lines] == [True, False, False, False]
    assert lines[1] == ("  не вычисляется: Кинематика!E43:Q43: имя arr_43 - не формула (={0,1}: "
                        "неожиданный символ '{')")
    assert "циклическая ссылка, ячейки: Кинематика!E50, Кинематика!E51" in lines[3]
    assert not any(w in " ".join(lines) for w in ("unsupported", "circular", "not a formula", "unexpected"))
