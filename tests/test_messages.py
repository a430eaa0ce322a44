"""Issue 29: sheetkin's messages through keys in one catalogue (sheetkin.messages).

Every key has its English, Russian and Ukrainian templates with the same fields; every
English template, rendered with values, is said back as its Russian and Ukrainian ones
(the patterns `say` uses are derived from the English templates, so a reworded template
keeps its translation); and no module of sheetkin writes one of the messages out as an
English literal instead of building it through its key."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from sheetkin import messages
from sheetkin.messages import CATALOGUE, DOMAINS, LANGS, Msg, fields_of, message, pattern, say

PACKAGE = Path(__file__).resolve().parents[1] / "sheetkin"
# a value for each field: the first of these its pattern takes whole
SAMPLES = ("7", "'L1'", "L1", ",", "=A1", "--class-list", "5 MB", "failed", "a.xlsx")


def domain_of(key: str) -> str:
    return next(d for d, sections in DOMAINS.items() for section, _ in sections if key in section)


def sample_values(entry: Msg) -> dict[str, str]:
    values = {}
    for field in fields_of(entry.en):
        found = re.compile(entry.fields.get(field, messages.DEFAULT_FIELD))
        values[field] = next(s for s in SAMPLES if found.fullmatch(s))
    return values


def field_problems(catalogue: dict[str, Msg]) -> list[str]:
    """The keys whose languages are missing or name other fields than the English."""
    out = []
    for key, entry in catalogue.items():
        en = fields_of(entry.en)
        for lang in LANGS:
            said = getattr(entry, lang)
            if not said.strip() or said == entry.en:
                out.append(f"{key}: no {lang}")
            elif fields_of(said) != en:
                out.append(f"{key}: {lang} names {sorted(fields_of(said))}, English {sorted(en)}")
        if set(entry.fields) - en:
            out.append(f"{key}: a pattern for no field: {sorted(set(entry.fields) - en)}")
    return out


def test_every_key_has_its_three_languages_with_the_same_fields():
    assert len(CATALOGUE) > 150
    assert len(CATALOGUE) == sum(len(s) for sections in DOMAINS.values() for s, _ in sections)   # keys unique
    assert field_problems(CATALOGUE) == []


@pytest.mark.parametrize(("broken", "problem"), [
    (Msg("given data changed: {list}", ru="исходные данные изменены: {list}", uk=""), "no uk"),
    (Msg("given data changed: {list}", ru="исходные данные изменены", uk="вихідні дані змінено: {list}"),
     "ru names []"),
    (Msg("{n} cells", ru="{n} ячеек", uk="{n} клітинок {m}"), "uk names ['m', 'n']"),
    (Msg("{n} cells", ru="{n} ячеек", uk="{n} клітинок", fields={"m": r"\d+"}), "a pattern for no field"),
])
def test_a_dropped_language_or_field_is_found(broken, problem):
    found = field_problems({"given_data_changed": broken})
    assert len(found) == 1 and problem in found[0], found


@pytest.mark.parametrize("key", list(CATALOGUE))
def test_each_english_template_is_said_in_russian_and_ukrainian(key):
    """The English message rendered with values and said in its domain is its ru and uk
    templates rendered with the same values (the values themselves said as any text is)."""
    entry, domain = CATALOGUE[key], domain_of(key)
    values = sample_values(entry)
    english = message(key, **values)
    assert re.search(pattern(entry), english), (pattern(entry), english)
    for lang in LANGS:
        want = say(messages._FORMAT.vformat(getattr(entry, lang), (), values), lang, domain)
        assert say(english, lang, domain) == want, (lang, english)
    assert say(english, "en", domain) == english


def test_a_pattern_is_derived_from_its_english_template():
    entry = CATALOGUE["graded_sheet_found_row"]
    assert entry.en == "graded sheet: '{sheet}' (found by its row names; tab {k} of {n})"
    assert pattern(entry) == (r"graded\ sheet:\ '(?P<sheet>[^']*)'\ \(found\ by\ its\ row\ names;\ tab\ "
                              r"(?P<k>\d+)\ of\ (?P<n>\d+)\)")
    # a field named twice repeats what it matched
    assert "(?P=seed)" in pattern(CATALOGUE["variants_written"])


def test_a_reworded_template_keeps_its_translation(monkeypatch):
    """The English changes in one place, and what `say` looks for changes with it."""
    old = CATALOGUE["check_rows_deleted_counted"]
    new = old._replace(en="check rows removed (counted as failing, their share of the grade lost): {names}")
    monkeypatch.setitem(messages.REPORT, "check_rows_deleted_counted", new)
    monkeypatch.setitem(CATALOGUE, "check_rows_deleted_counted", new)
    messages._compiled.cache_clear()
    try:
        text = message("check_rows_deleted_counted", names="chk_Fi")
        assert text.startswith("check rows removed") and say(text, "ru") == old.ru.format(names="chk_Fi")
    finally:
        messages._compiled.cache_clear()


def test_plural_forms():
    said = say("1 check row failing; 3 of 21 check rows; 5 typed, not computed", "ru", "grading")
    assert said == "1 строка проверки не выполнена; 3 из 21 строки проверки; 5 введены числами"
    with pytest.raises(TypeError):
        message("n_check_rows_failing", m=1)        # a value for another field


def _literals(path: Path) -> list[tuple[int, str]]:
    """The string literals of a module (the fixed parts of f-strings too), docstrings left out."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
            and n.body and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    return [(n.lineno, n.value) for n in ast.walk(tree)
            if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs]


def english_copies(paths) -> list[str]:
    """Where a module of sheetkin writes a catalogue's message as an English literal, not
    through its key: a literal holding the longest fixed part (15 characters or more) of a
    message's template, or a literal that is one of the validator's fixed phrases (15
    characters or more). The grading vocabulary's words ("wrong", "typed, not computed") and
    the counts of them are data too (verdicts, columns) and stay literal where they are.)"""
    chunks, phrases = {}, {e.en: k for k, e in messages.REPORT_PHRASES.items() if len(e.en) >= 15}
    for key, entry in CATALOGUE.items():
        longest = max((lit for lit, *_ in messages.string.Formatter().parse(entry.en)), key=len).strip()
        vocabulary = key in messages.REPORT_PHRASES or key in messages.GRADING and (
            not fields_of(entry.en) or entry.en.startswith("{"))        # a word, or a count of one
        if len(longest) >= 15 and not vocabulary:
            chunks[longest] = key
    out = []
    for path in paths:
        for line, text in _literals(path):
            out += [f"{path.name}:{line}: {key}" for chunk, key in chunks.items() if chunk in text]
            out += [f"{path.name}:{line}: {phrases[text]}"] if text in phrases else []
    return sorted(o for o in set(out) if (o.split(":")[0], o.split(": ")[-1]) not in ELSEWHERE)


# other texts that share the words of a catalogue's message: (module, key) -> what they are
ELSEWHERE: dict[tuple[str, str], str] = {
    ("convert.py", "at_most_limit"): "an OpenDocument file's limit: 'at most N bytes (sheetkin's limit ...)'",
    ("package.py", "uncompressed_all"): "'N MB uncompressed in all', the size found (no 'more than')",
    ("issued.py", "not_utf8_csv"): "the roster's 'not UTF-8 (nor Windows-1251) text; expected roster.csv ...'",
    ("identity.py", "found_folder_but_name"): "'found in the folder of X, but the name typed in it is Y'",
    ("grades.py", "given_data_changed"): "the score explained, in the grading vocabulary",
    ("rpr.py", "cannot_assemble"): "a row's description: '(< 0: cannot assemble)'",
    ("rrp.py", "cannot_assemble"): "a row's description",
    ("rrr.py", "cannot_assemble"): "a row's description",
}


def test_no_module_writes_a_catalogue_message_in_english():
    paths = [p for p in PACKAGE.rglob("*.py") if p.name != "messages.py"]
    assert english_copies(paths) == []


def test_an_english_copy_is_found(tmp_path):
    fake = tmp_path / "issued.py"
    fake.write_text('"""scene sheet edited: its seal (scene!C2) is missing"""\n'      # a docstring: fine
                    'def f(names):\n    return f"check rows deleted (counted as failing, their share of the grade '
                    'lost): {names}"\n')
    assert english_copies([fake]) == ["issued.py:3: check_rows_deleted_counted"]
