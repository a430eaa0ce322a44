"""The rows' texts are data: each module that writes rows keeps its templates in a TEXTS
table per language (ru, uk, en), and the rows ask for them by key (sheetkin.groups.rows.Texts).

  * every key of every table is in all three languages, with the same format fields (a key
    missing from one language, or a field spelt differently, fails here, not in a student's
    Ukrainian book);
  * the Ukrainian tables are Ukrainian (no Russian-only letters) and the English ones have no
    Cyrillic;
  * no row of a book goes through a Russian -> Ukrainian word table (there is none any
    more): every row the kinds, the helpers, the dynamics blocks and the workbook writer
    write carries its Ukrainian text, and a kind's TITLE is said in the three languages;
  * a Text field (a label such as "hinge B") is taken in each template's own language.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from helpers import toykind
from helpers.kinds import DYNAMICS
from helpers.russian_words import russian_words

import sheetkin
from sheetkin.groups import KINDS, kind_of, rows
from sheetkin.groups import lang as langs
from sheetkin.groups.rows import Builder, Text, Texts
from sheetkin.sheet import dynamics, texts
from sheetkin.sheet.workbook import sheet_rows

WB = Path(__file__).resolve().parents[2] / "workbooks"
RUSSIAN = russian_words()
MODULES = ({"rows": rows, "dynamics": dynamics, "workbook": texts, "toykind": toykind}
           | {k: kind_of(k) for k in KINDS})


def mismatches(tables) -> list[str]:
    """What is wrong with a TEXTS table: a language missing, a key missing from a language,
    a key whose format fields differ from the Russian template's."""
    t = Texts(tables)
    if set(tables) != {"ru", "uk", "en"}:
        return [f"languages {sorted(tables)}"]
    out = []
    for key in set().union(*(tables[lang] for lang in tables)):
        missing = [lang for lang in ("ru", "uk", "en") if key not in tables[lang]]
        if missing:
            out.append(f"{key}: missing in {', '.join(missing)}")
            continue
        fields = {lang: t.fields(lang, key) for lang in ("ru", "uk", "en")}
        if not fields["ru"] == fields["uk"] == fields["en"]:
            out.append(f"{key}: fields {fields}")
    return out


@pytest.mark.parametrize("name", sorted(MODULES))
def test_every_key_in_every_language_with_the_same_fields(name):
    assert MODULES[name].TEXTS["ru"], name
    assert mismatches(MODULES[name].TEXTS) == []


def test_a_missing_key_or_field_is_caught():
    """The check above fails where it should: a key dropped from one language, a field renamed."""
    good = {"ru": {"a": "звено {k}", "b": "x"}, "uk": {"a": "ланка {k}", "b": "x"}, "en": {"a": "link {k}", "b": "x"}}
    assert mismatches(good) == []
    dropped = {**good, "uk": {"a": "ланка {k}"}}
    assert mismatches(dropped) == ["b: missing in uk"]
    renamed = {**good, "en": {"a": "link {j}", "b": "x"}}
    assert len(mismatches(renamed)) == 1 and mismatches(renamed)[0].startswith("a: fields")
    with pytest.raises(KeyError):
        Texts(dropped)("b")


@pytest.mark.parametrize("name", sorted(MODULES))
def test_each_table_in_its_language(name):
    tables = MODULES[name].TEXTS
    russian_only = {k: v for k, v in tables["uk"].items() if re.search("[ЫыЭэЪъЁё]", v)}
    cyrillic_en = {k: v for k, v in tables["en"].items() if re.search("[А-Яа-яЁёІіЇїЄєҐґ]", v)}
    assert russian_only == {} and cyrillic_en == {}
    # no Russian word form left in the Ukrainian (tests/helpers/russian_words.py)
    russian = {k: w for k, v in tables["uk"].items() for w in re.findall("[А-Яа-яІіЇїЄєҐґ']+", v)
               if w.lower() in RUSSIAN}
    assert russian == {}


def test_a_text_field_is_said_in_each_language():
    t = Texts({"ru": {"x": "координата x {of}"}, "uk": {"x": "координата x {of}"}, "en": {"x": "x of {of}"}})
    label = Text("шарнира B", "шарніра B", "hinge B")
    assert t("x", of=label) == Text("координата x шарнира B", "координата x шарніра B", "x of hinge B")
    assert t("x", of="B").en == "x of B"


def _writers(frame) -> str:
    """The module that asked for a row: the first caller outside sheetkin.groups.rows."""
    while frame is not None and frame.f_globals.get("__name__") == rows.__name__:
        frame = frame.f_back
    return frame.f_globals.get("__name__", "?") if frame is not None else "?"


def test_no_row_goes_through_a_word_table(monkeypatch):
    """Every row of a book, whoever writes it (the kinds, the helpers, the dynamics blocks,
    the workbook writer's given data, crank block and [[point]] rows, the instruction lines),
    comes with its description in all three languages, as a Text: the builder takes nothing
    else, and the languages module has no translator left to call."""
    assert not {"ukrainian", "UK_WORDS", "text"} & set(vars(langs))
    assert not hasattr(Text, "of")
    add, writers, untranslated = Builder.add, set(), []

    def spy(self, name, unit, text, *args, **kw):
        if not isinstance(text, Text) or not (text.ru and text.uk and text.en):
            untranslated.append((name, text))
        writers.add(_writers(sys._getframe(1)))
        return add(self, name, unit, text, *args, **kw)

    monkeypatch.setattr(Builder, "add", spy)
    scenes = [sheetkin.load_scene(p) for p in sorted(WB.glob("*.toml"))]
    scenes += [sheetkin.parse_scene(text, f"{key}.toml") for key, (_, text) in DYNAMICS.items()]
    kinds_seen, n = set(), 0
    for scene in scenes:
        built = sheet_rows(scene).rows
        assert len(built) > 50
        n += len(built)
        assert all(r.uk for r in built)
        kinds_seen |= {g.type for g in scene.groups}
    assert kinds_seen == set(KINDS)
    assert untranslated == [] and n > 4000
    # every writer went through the spy: the kinds, the helpers' callers, the sheet's modules
    assert {"sheetkin.sheet.workbook", "sheetkin.sheet.dynamics"} | {kind_of(k).__name__ for k in KINDS} <= writers


def test_the_builder_refuses_a_bare_string():
    """A description given as a Russian string (the old b.add(name, unit, ru, en)) is not a
    Text: the row cannot be built, so it cannot reach a book untranslated."""
    b = Builder(sheetkin.load_scene(WB / "fourbar.toml"))
    with pytest.raises(AttributeError):
        b.add("x", "m", "угол звена 2")        # type: ignore[arg-type]
    with pytest.raises(TypeError):
        b.section("s", "Раздел", "Section")     # type: ignore[call-arg]


@pytest.mark.parametrize("name", sorted(KINDS) + ["toykind"])
def test_a_kinds_title_in_three_languages(name):
    title = toykind.TITLE if name == "toykind" else kind_of(name).TITLE
    assert isinstance(title, Text)
    assert title.ru and title.uk and title.en and len({title.ru, title.uk, title.en}) == 3
    assert not re.search("[ыэъёЫЭЪЁ]", title.uk) and not re.search("[іїєґІЇЄҐ']", title.ru)
    assert not re.search("[А-Яа-яЁёІіЇїЄєҐґ]", title.en)
    words = {w.lower() for w in re.findall("[А-Яа-яІіЇїЄєҐґ']+", title.uk)}
    assert not words & (RUSSIAN - {"по"}), words & RUSSIAN     # "по" is Ukrainian too
