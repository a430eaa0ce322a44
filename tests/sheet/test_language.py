"""Issue 22: one language per book. Every word a student reads (descriptions, units,
section titles, headers, statuses, instructions, chart titles and axes, the drawing's
labels) is in the book's language: the books are scanned for words of the other two.
The scene's own text (its title, typed by the teacher) and the row names of column A
(the lecture's identifiers: phi_1, omega_3, chk_v_B ...) are not the book's words."""
from __future__ import annotations

import io
import re
import zipfile
from pathlib import Path

import pytest
from helpers.russian_words import russian_words

import sheetkin
from sheetkin.sheet.workbook import TITLE_CELL, build_workbook, sheet_rows

WB = Path(__file__).resolve().parents[2] / "workbooks"
# every kind, the dynamics blocks, a [[point]] on a slider
STEMS = ("fourbar", "shaper_dynamics", "three_group_chain", "slider_on_coupler", "two_rockers_slotted",
         "kulisa_moving_axis", "scotch_yoke")
ENGLISH = {"check", "checks", "velocity", "acceleration", "link", "links", "position", "positions", "variant",
           "seed", "deg", "rad", "cannot", "assemble", "assembles", "branch", "group", "point", "hinge", "length",
           "angle", "speed", "speeds", "input", "given", "the", "of", "and", "residual", "step", "crank", "slider",
           "guide", "frame", "block", "slot", "fill", "filled", "pass", "fail", "name", "unit", "value",
           "description", "accepted", "values", "free", "through", "m/s", "kg", "right", "side", "system"}
RUSSIAN = russian_words() | {"проверки", "выполнены", "заполнено", "изменять", "значение", "описание"}


def _texts(stem: str, lang: str, exercise: bool) -> list[str]:
    """The words a student reads in a book: its cells' texts (no formulas, no row names of
    computed rows, not the scene's title), its charts' titles, axes and series labels, the
    status words the formulas can show."""
    scene = sheetkin.load_scene(WB / f"{stem}.toml")
    wb = build_workbook(scene, lang=lang, exercise=exercise)
    names = {r.name for r in sheet_rows(scene).rows}
    out = [ws.title for ws in wb.worksheets if ws.sheet_state == "visible"]
    for ws in wb.worksheets:
        if ws.sheet_state != "visible":
            continue
        for row in ws.iter_rows():
            for c in row:
                v = c.value
                if not isinstance(v, str) or (ws is wb.worksheets[0] and c.coordinate == TITLE_CELL):
                    continue
                if v.startswith("="):
                    out += re.findall(r'"([^"]*)"', v)              # the words a formula can show
                elif not (c.column == 1 and v in names):
                    out.append(v)
                fmt = c.number_format or ""
                out += re.findall(r'"([^"]*)"', fmt)               # "заполнено: "0
    buf = io.BytesIO()
    wb.save(buf)
    with zipfile.ZipFile(buf) as z:
        for n in z.namelist():
            if n.startswith("xl/charts/chart"):
                xml = z.read(n).decode("utf-8")
                out += re.findall(r"<a:t>([^<]*)</a:t>", xml) + re.findall(r"<c:v>([^<]*)</c:v>", xml)
    return out


def _words(texts: list[str]) -> set[str]:
    # an identifier (Delta_Fi_rad, chk_v_B) is one word, not "rad"
    return {w.lower() for t in texts for w in re.findall(r"[A-Za-zА-Яа-яЁёІіЇїЄєҐґ'/_0-9]+", t)}


@pytest.mark.parametrize("stem", STEMS)
@pytest.mark.parametrize("exercise", [False, True])
def test_russian_book_has_no_english_or_ukrainian(stem, exercise):
    texts = _texts(stem, "ru", exercise)
    words = _words(texts)
    assert not words & ENGLISH, sorted(words & ENGLISH)
    # the axes' units ("x, m" once stayed English): м, м/с, Н, Вт
    assert not [t for t in texts if re.search(r",\s*(m|m/s|m/s²|rad/s|deg|N|W|N·m)(,|$)", t)]
    assert not [w for w in words if re.search("[іїєґ]", w)]
    assert {"м", "рад/с", "проверка:"} & words or "м" in words


@pytest.mark.parametrize("stem", STEMS)
def test_ukrainian_book_has_no_russian_or_english(stem):
    words = _words(_texts(stem, "uk", True))
    assert not words & ENGLISH, sorted(words & ENGLISH)
    assert not [w for w in words if re.search("[ыэъё]", w)], [w for w in words if re.search("[ыэъё]", w)]
    assert not words & RUSSIAN, sorted(words & RUSSIAN)
    assert {"перевірка", "швидкість", "прискорення"} <= words


@pytest.mark.parametrize("stem", STEMS)
def test_english_book_has_no_cyrillic(stem):
    texts = _texts(stem, "en", True)
    assert not [t for t in texts if re.search("[А-Яа-яЁёІіЇїЄєҐґ]", t)]


def test_units_said_in_the_books_language():
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    units = {lang: {c.value for c in build_workbook(scene, lang=lang, charts=False).worksheets[0]["B"]
                    if c.value} for lang in ("ru", "uk", "en")}
    assert {"м", "град", "рад/с", "м/с", "м/с²"} <= units["ru"] == units["uk"] - {"од."} | {"ед."}
    assert {"m", "deg", "rad/s", "m/s", "m/s²"} <= units["en"]
    assert not {"m", "deg", "rad", "m/s^2"} & units["ru"]


def test_ukrainian_rows_hold_no_russian_word():
    """Each row of every bundled book says its Ukrainian description with no Russian word
    form: the rows' Ukrainian tables, and the fields filled into them (a label that stayed
    Russian, a template taken from the wrong table, would show here)."""
    russian = set()
    for toml in sorted(WB.glob("*.toml")):
        for row in sheet_rows(sheetkin.load_scene(toml)).rows:
            assert row.uk, row.name
            for w in re.findall(r"[А-Яа-яЁёІіЇїЄєҐґ']+", row.say("uk")):
                if w.lower() in RUSSIAN or re.search("[ыэъё]", w.lower()):
                    russian.add((row.name, w))
    assert not russian


def test_variant_label_in_the_books_language():
    title = 'title  = "Кривошипно-коромысловый механизм'
    text = (WB / "fourbar.toml").read_text(encoding="utf-8").replace(title, title + ' (variant fourbar-01)')
    scene = sheetkin.parse_scene(text, "v.toml")
    got = {lang: build_workbook(scene, lang=lang, charts=False, scene_text=text).worksheets[0][TITLE_CELL].value
           for lang in ("ru", "uk", "en")}
    assert got["ru"].endswith("(вариант fourbar-01)") and got["uk"].endswith("(варіант fourbar-01)")
    assert got["en"].endswith("(variant fourbar-01)")


def test_bundled_titles_are_titles():
    for toml in WB.glob("*.toml"):
        title = sheetkin.load_scene(toml).title
        assert "seed" not in title and re.search("[А-Яа-я]", title), (toml.name, title)
