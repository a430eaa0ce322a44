"""The validator on workbooks made wrong on purpose: it names exactly the wrong rows, the
likely cause, and nothing else as a cause."""
from __future__ import annotations

import hashlib
import json
import re
import shutil
import zipfile
from pathlib import Path

import openpyxl
import pytest
from helpers.libreoffice import recalculate
from helpers.sheetrows import rows_of
from openpyxl.utils import get_column_letter

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.course.grades import all_correct
from sheetkin.course.issued import Options
from sheetkin.course.validator import validate
from sheetkin.sheet.workbook import write_workbook

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
BUNDLED = sorted(p.stem for p in WORKBOOKS.glob("*.toml"))


def edit(src: Path, dst: Path, change) -> Path:
    """Copy a workbook and change it with openpyxl as a student would (formulas kept)."""
    wb = openpyxl.load_workbook(src)
    ws = wb.worksheets[0]
    change(ws, rows_of(ws))
    wb.save(dst)
    return dst


def summary(rep):
    return ({r.name for r in rep.wrong}, {r.name for r in rep.causes}, {r.name for r in rep.missing})


@pytest.mark.parametrize("stem", BUNDLED)
def test_bundled_workbooks_are_correct(stem):
    rep = validate(WORKBOOKS / f"{stem}.xlsx")
    assert rep.error is None and all_correct(rep), [(r.name, r.status) for r in rep.rows if r.status != "correct"]
    assert len(rep.rows) > 30 and not rep.failing_checks and not rep.cache_mismatch


def test_sign_flipped(fourbar, tmp_path):
    def flip(ws, rows):
        for k in range(13):
            c = ws.cell(rows["omega_3"], 5 + k)
            c.value = "=-(" + c.value[1:] + ")"
    rep = validate(edit(fourbar, tmp_path / "w3.xlsx", flip))
    wrong, causes, missing = summary(rep)
    assert causes == {"omega_3"}
    assert wrong == {"omega_3", "vx_S3", "vy_S3"}          # S3's speed is on link 3; |v| and a unchanged
    assert all(r.because_of == ["omega_3"] for r in rep.wrong if not r.cause)
    assert not missing and "chk_vsys_g1" in rep.failing_checks


def test_formula_altered(fourbar, tmp_path):
    """One row's formula changed (the coupler's length used for the rocker's)."""
    def alter(ws, rows):
        for k in range(13):
            c = ws.cell(rows["F_g1"], 5 + k)
            old = f"-$D${rows['L3']}^2)"
            assert old in c.value
            c.value = c.value.replace(old, f"-$D${rows['L2']}^2)")
    rep = validate(edit(fourbar, tmp_path / "F.xlsx", alter))
    wrong, causes, _ = summary(rep)
    assert causes == {"F_g1"}
    assert {"phi_2", "phi_3", "x_B", "omega_2", "eps_3", "a_S3"} <= wrong
    assert all(r.because_of == ["F_g1"] for r in rep.wrong if r.name != "F_g1")


def test_row_copied_from_another_point(fourbar, tmp_path):
    """Seed 000's slip: S3's acceleration taken from S2's rows."""
    def copy(ws, rows):
        for q in ("ax", "ay"):
            for k in range(13):
                col = get_column_letter(5 + k)
                ws.cell(rows[f"{q}_S3"], 5 + k).value = f"={col}{rows[f'{q}_S2']}"
    rep = validate(edit(fourbar, tmp_path / "aS3.xlsx", copy))
    wrong, causes, _ = summary(rep)
    assert causes == {"ax_S3", "ay_S3"} and wrong == {"ax_S3", "ay_S3", "a_S3"}
    a = next(r for r in rep.rows if r.name == "a_S3")
    assert set(a.because_of) == {"ax_S3", "ay_S3"}


def test_number_typed_where_a_formula_belongs(fourbar, tmp_path):
    def typed(ws, rows):
        ws.cell(rows["x_B"], 7).value = -0.25                # position 3: wrong
        ws.cell(rows["y_A"], 8).value = 0.14                 # position 4: right (to its digits)
    rep = validate(edit(fourbar, tmp_path / "typed.xlsx", typed))
    wrong, causes, _ = summary(rep)
    assert causes == {"x_B"}
    xb = next(r for r in rep.rows if r.name == "x_B")
    assert xb.wrong_cells == [3] and xb.source == "typed"
    assert all(r.wrong_cells == [3] and r.because_of == ["x_B"] for r in rep.wrong if r.name != "x_B")
    assert "y_A" not in wrong


def test_a_row_missing(fourbar, tmp_path):
    def drop(ws, rows):
        ws.cell(rows["y_S2"], 1).value = None
    rep = validate(edit(fourbar, tmp_path / "missing.xlsx", drop))
    wrong, causes, missing = summary(rep)
    assert missing == {"y_S2"} and not wrong and not causes
    assert not all_correct(rep)


def test_half_filled_exercise(tmp_path, fourbar):
    """An exercise workbook with the crank block and hinge A filled in, the rest empty."""
    text = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    ex = tmp_path / "ex.xlsx"
    write_workbook(sheetkin.parse_scene(text, "fourbar.toml"), ex, scene_text=text, exercise=True)
    full = openpyxl.load_workbook(fourbar).worksheets[0]
    full_rows = rows_of(full)
    filled = ["Fi", "dFi", "Fi_t", "Fi_tt", "cos_1", "sin_1", "x_A", "y_A", "vx_A", "vy_A", "v_A"]

    def fill(ws, rows):
        for n in ["Delta_Fi_rad", "Alfa_A", "Betta_A"]:
            ws.cell(rows[n], 4).value = full.cell(full_rows[n], 4).value
        for n in filled:
            for k in range(13):
                ws.cell(rows[n], 5 + k).value = full.cell(full_rows[n], 5 + k).value
    rep = validate(edit(ex, tmp_path / "half.xlsx", fill))
    status = {r.name: r.status for r in rep.rows}
    assert all(status[n] == "correct" for n in filled)
    assert status["ax_A"] == "empty" and status["omega_3"] == "empty"
    assert not rep.wrong and not all_correct(rep)


def test_the_students_own_variant(fourbar, tmp_path):
    """A book made by `sheetkin workbook` (no variant id): its given data are the embedded
    scene. Changed inputs are named and fail, and the rows are graded against the embedded
    values (issue 13: "a student can change the given data and pass"); with
    --accept-changed-inputs the input block is the student's own variant: all correct."""
    def variant(ws, rows):
        ws.cell(rows["L1"], 4).value = 0.12
        ws.cell(rows["Fi_t0"], 4).value = -5.0
        ws.cell(rows["branch_g1"], 4).value = 1
    book = edit(fourbar, tmp_path / "variant.xlsx", variant)
    rep = validate(book)
    assert not all_correct(rep)
    assert {(c["name"], c["issued"], c["got"]) for c in rep.given_changed} == {
        ("L1", 0.14, 0.12), ("Fi_t0", 20.0, -5.0), ("branch_g1", -1.0, 1)}
    assert {r.name for r in rep.wrong} >= {"x_A", "Fi_t"}          # graded against 0.14 and 20
    rep = validate(book, options=Options(accept_changed=True))
    assert all_correct(rep) and rep.accepted_changes, [(r.name, r.status, r.expected, r.got) for r in rep.wrong][:3]


@pytest.fixture(scope="module")
def saved_by_libreoffice(soffice, tmp_path_factory, fourbar):
    """The four-bar as LibreOffice saves it: formulas with cached values; and a copy where
    one cached value was changed behind the formula's back."""
    out = recalculate([fourbar], tmp_path_factory.mktemp("lo"))[fourbar.resolve()]
    ws = openpyxl.load_workbook(out).worksheets[0]
    r = rows_of(ws)["omega_3"]
    stale = out.with_name("stale.xlsx")
    with zipfile.ZipFile(out) as zin, zipfile.ZipFile(stale, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "xl/worksheets/sheet1.xml":
                text = data.decode("utf-8")
                text, n = re.subn(rf'(<c r="F{r}"[^>]*>.*?<v>)([^<]*)(</v>)', r"\g<1>99.5\g<3>", text, count=1)
                assert n == 1
                data = text.encode("utf-8")
            zout.writestr(item, data)
    return out, stale


def test_libreoffice_saved_and_cached_values(saved_by_libreoffice, tmp_path):
    out, stale = saved_by_libreoffice
    rep = validate(out)
    assert all_correct(rep) and not rep.cache_mismatch
    rep = validate(stale)
    assert all_correct(rep)                                   # the formula is right ...
    assert len(rep.cache_mismatch) == 1 and "!F" in rep.cache_mismatch[0] and "99.5" in rep.cache_mismatch[0]


def test_only_values(saved_by_libreoffice, tmp_path):
    """Every formula replaced by the number LibreOffice computed (typed or pasted values)."""
    out, _ = saved_by_libreoffice
    values = openpyxl.load_workbook(out, data_only=True)
    wb = openpyxl.load_workbook(out)
    for ws, vs in zip(wb.worksheets, values.worksheets, strict=False):
        for row in ws.iter_rows():
            for c in row:
                if isinstance(c.value, str) and c.value.startswith("="):
                    c.value = vs.cell(c.row, c.column).value
    wb.save(tmp_path / "values.xlsx")
    rep = validate(tmp_path / "values.xlsx")
    # the values are right (to the digits LibreOffice saved) ...
    assert not rep.wrong, [(r.name, r.expected, r.got) for r in rep.wrong][:3]
    assert {r.source for r in rep.rows} == {"typed"}
    # ... but a computed row earns credit only when it computes (issue 21): no formula, at
    # most 10 of 100, and the book fails
    from sheetkin.course import grades
    assert not all_correct(rep) and grades.verdict(rep) == "typed, not computed"
    assert grades.score(rep) <= grades.NO_FORMULA_CAP and grades.counts(rep)["correct"] == 0


def test_unusable_inputs_in_a_batch(fourbar, tmp_path, capsys):
    folder = tmp_path / "submissions"
    folder.mkdir()
    shutil.copy(fourbar, folder / "good.xlsx")
    edit(fourbar, folder / "text_input.xlsx", lambda ws, rows: setattr(ws.cell(rows["L1"], 4), "value", "0.14 m"))
    (folder / "notes.xlsx").write_text("not a workbook")
    wb = openpyxl.Workbook()
    wb.active["A1"] = 1
    wb.save(folder / "foreign.xlsx")
    before = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.iterdir()}
    code = main(["validate", "--lang", "en", str(folder)])
    out = capsys.readouterr().out
    assert code == 2
    lines = {p: [ln for ln in out.splitlines() if p in ln] for p in before}
    assert any("all correct" in x or "correct" in x for x in out.splitlines() if "good.xlsx" in x)
    for bad, why in (("notes.xlsx", "not an .xlsx"), ("foreign.xlsx", "no embedded scene")):
        hit = [ln for ln in lines[bad] if "UNUSABLE" in ln]
        assert len(hit) == 1 and why in hit[0], (bad, lines[bad])
    # text typed over a given number is a change of the given data (graded against the
    # issued 0.14); only when the student's own inputs are graded is it unusable
    assert "given data changed: L1 0.14 -> '0.14 m'" in out
    assert main(["validate", "--lang", "en", str(folder / "text_input.xlsx"), "--accept-changed-inputs"]) == 2
    assert "UNUSABLE" in capsys.readouterr().out
    # the summary table; its student column is the student's own cells (blank here), not A2
    assert re.search(r"good\.xlsx\s+all correct", out) and "sheetkin example  " not in out
    after = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.iterdir()}
    assert before == after                                                    # never modified


def test_json_html_and_progress(fourbar, tmp_path, capsys):
    bad = edit(fourbar, tmp_path / "bad.xlsx",
               lambda ws, rows: [setattr(ws.cell(rows["omega_2"], 5 + k), "value", 1.0) for k in range(13)])
    html = tmp_path / "r.html"
    code = main(["validate", "--lang", "en", str(fourbar), str(bad), "--json", "--html", str(html),
                 "--progress", "always"])
    captured = capsys.readouterr()
    assert code == 1
    data = json.loads(captured.out)
    assert [r["ok"] for r in data["reports"]] == [True, False] and data["all_correct"] is False
    assert data["reports"][1]["summary"]["causes"] == ["omega_2"]
    assert "2/2" in captured.err and "#" in captured.err
    page = html.read_text(encoding="utf-8")
    assert "omega_2" in page and "class='wrong'" in page and "likely cause" in page


def test_a_cause_that_is_an_error_value_says_so(fourbar, tmp_path):
    """A formula giving #DIV/0! where a number belongs: the cause says what it is, not
    "largest error inf"."""
    from sheetkin.course.report import text_report

    def div0(ws, rows):
        for k in range(13):
            ws.cell(rows["omega_2"], 5 + k).value = "=1/0"
    rep = validate(edit(fourbar, tmp_path / "div0.xlsx", div0))
    assert [c.name for c in rep.causes] == ["omega_2"]
    text = text_report(rep)
    assert "an error value or text where a number belongs" in text and "largest error inf" not in text
