"""Issue 22: the reports in the teacher's language (ru, uk, en; `validate --lang`, by
default the books' own), the student shown as the author, <html lang> set."""
from __future__ import annotations

import html
import re

import pytest
from helpers.classbooks import fill, flip_sign
from helpers.clirun import run
from helpers.scenes import FOURBAR

import sheetkin
from sheetkin.course.report import html_report, summary_table, text_report
from sheetkin.course.report_texts import WORDS, class_lang
from sheetkin.course.validator import validate
from sheetkin.sheet.workbook import write_workbook

ENGLISH = {"likely", "cause", "wrong", "rows", "correct", "missing", "expected", "got", "largest", "error",
           "positions", "position", "student", "group", "file", "result", "mistakes", "depend", "deg", "the",
           "score", "check", "fail", "books", "share"}


@pytest.fixture(scope="module")
def books(tmp_path_factory):
    d = tmp_path_factory.mktemp("lang")
    out = {}
    for lang in ("ru", "uk", "en"):
        scene = sheetkin.parse_scene(FOURBAR, "fourbar.toml")
        ex, key = d / f"ex-{lang}.xlsx", d / f"key-{lang}.xlsx"
        write_workbook(scene, ex, exercise=True, scene_text=FOURBAR, lang=lang)
        write_workbook(scene, key, scene_text=FOURBAR, lang=lang)
        out[lang] = fill(ex, key, d / f"sidorov-{lang}.xlsx", student="Сидоров А.", group="ГИ-21",
                         change=flip_sign("omega_3"))
    return out


@pytest.fixture(scope="module")
def reports(books):
    return {lang: validate(path) for lang, path in books.items()}


def _words(text: str) -> set[str]:
    return {w.lower() for w in re.findall(r"[A-Za-z]+(?:_[A-Za-z0-9]+)*", text)}


def test_every_language_has_every_word():
    assert WORDS["ru"].keys() == WORDS["uk"].keys() == WORDS["en"].keys()


def test_every_word_the_reports_use_is_in_the_table():
    """Each `t["key"]` of the modules that look words up (t = words(lang)) names a word of
    WORDS: a misspelt or removed key would be a KeyError in one language's report only
    where that line is reached; read from the sources, independently of any report."""
    import re
    from pathlib import Path

    import sheetkin.course
    folder = Path(sheetkin.course.__file__).parent
    used = set()
    for module in ("report.py", "report_html.py"):
        text = (folder / module).read_text(encoding="utf-8")
        assert "= words(" in text
        used |= set(re.findall(r"\bt\[[\"']([a-z_0-9]+)[\"']\]", text))
    assert len(used) > 40 and "unusable" in used          # the scan found the lookups
    assert used - WORDS["en"].keys() == set()


def test_the_books_language_is_the_reports_default(reports, books, capsys):
    assert {lang: rep.lang for lang, rep in reports.items()} == {"ru": "ru", "uk": "uk", "en": "en"}
    assert class_lang(list(reports.values())) in ("ru", "uk", "en")
    code, out, _ = run(capsys, "validate", books["uk"], "--progress", "never")
    assert code == 1 and "ймовірна причина: omega_3" in out
    code, out, _ = run(capsys, "validate", books["uk"], "--lang", "ru", "--progress", "never")
    assert code == 1 and "вероятная причина: omega_3" in out


@pytest.mark.parametrize("lang", ["ru", "uk"])
def test_text_and_html_reports_speak_one_language(reports, lang):
    rep = reports[lang]
    text = text_report(rep, lang) + summary_table([rep, reports["en"]], lang)
    assert not _words(text) & ENGLISH, sorted(_words(text) & ENGLISH)
    page = html_report([rep], lang=lang)
    assert f"<html lang='{lang}'>" in page
    visible = html.unescape(re.sub(r"<script>.*?</script>|<style>.*?</style>|<[^>]+>", " ", page, flags=re.S))
    assert not _words(visible) & ENGLISH, sorted(_words(visible) & ENGLISH)
    if lang == "uk":
        assert not re.search("[ыэъё]", text + visible)


def test_english_reports_have_no_cyrillic_but_the_students_own(reports):
    rep = reports["en"]
    text = text_report(rep, "en").replace("Сидоров А.", "").replace("ГИ-21", "").replace(rep.title, "")
    assert not re.search("[А-Яа-яЁёІіЇїЄє]", text)
    assert "<html lang='en'>" in html_report([rep], lang="en")


def test_the_author_shown_is_the_student(reports):
    rep = reports["ru"]
    assert (rep.student, rep.group) == ("Сидоров А.", "ГИ-21")
    first = text_report(rep, "ru").splitlines()[0]
    assert "Сидоров А." in first and (rep.author or "sheetkin") not in first
    page = html_report([rep], lang="ru")
    assert "Сидоров А.: " in page and "sheetkin example" not in page
