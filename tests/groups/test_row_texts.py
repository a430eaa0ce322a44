"""The rows' texts are data: each module that writes rows keeps its templates in a TEXTS
table per language (ru, uk, en), and the rows ask for them by key (sheetkin.groups.rows.Texts).

  * every key of every table is in all three languages, with the same format fields (a key
    missing from one language, or a field spelt differently, fails here, not in a student's
    Ukrainian book);
  * the Ukrainian tables are Ukrainian (no Russian-only letters) and the English ones have no
    Cyrillic;
  * no row a group kind or the dynamics blocks write goes through the Russian -> Ukrainian
    word table any more (every such row carries its Ukrainian text);
  * a Text field (a label such as "hinge B") is taken in each template's own language.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
import toykind
from kinds import DYNAMICS

import sheetkin
from sheetkin.groups import KINDS, kind_of, rows
from sheetkin.groups.lang import UK_WORDS
from sheetkin.groups.rows import Builder, Text, Texts
from sheetkin.sheet import dynamics
from sheetkin.sheet.workbook import sheet_rows

WB = Path(__file__).resolve().parents[2] / "workbooks"
MODULES = {"rows": rows, "dynamics": dynamics, "toykind": toykind} | {k: kind_of(k) for k in KINDS}


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
    # no Russian word form left in the Ukrainian (one the word table says differently)
    russian = {k: w for k, v in tables["uk"].items() for w in re.findall("[А-Яа-яІіЇїЄєҐґ']+", v)
               if UK_WORDS.get(w.lower(), w).lower() != w.lower()}
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


def test_no_kind_row_goes_through_the_word_table(monkeypatch):
    """Every row the kinds and the dynamics blocks write carries its Ukrainian text (None:
    the writer would make it from the Russian by groups.lang's word table)."""
    add, through_words = Builder.add, set()

    def spy(self, name, unit="", ru="", en="", kind="calc", formula="", value=None, guard=..., uk=None):
        if uk is None:
            through_words.add(_writers(sys._getframe(1)))
        return add(self, name, unit, ru, en, kind, formula, value, guard, uk)

    monkeypatch.setattr(Builder, "add", spy)
    scenes = [sheetkin.load_scene(p) for p in sorted(WB.glob("*.toml"))]
    scenes += [sheetkin.parse_scene(text, f"{key}.toml") for key, (_, text) in DYNAMICS.items()]
    kinds_seen = set()
    for scene in scenes:
        assert len(sheet_rows(scene).rows) > 50
        kinds_seen |= {g.type for g in scene.groups}
    assert kinds_seen == set(KINDS)
    assert through_words == {"sheetkin.sheet.workbook"}     # the writer's own rows (crank, inputs, points)
