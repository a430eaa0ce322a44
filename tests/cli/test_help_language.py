"""The help of the teacher's commands in the teacher's language: `validate` and `variants`
speak Russian or Ukrainian when --lang or the locale says so; the English help stays
exactly as it was."""
from __future__ import annotations

import argparse
import re

import pytest

from sheetkin.cli.args import build_parser
from sheetkin.cli.commands import main
from sheetkin.cli.help_texts import TABLES, help_lang

CYRILLIC = re.compile("[а-яіїєґА-ЯІЇЄҐ]")


def _command(parser: argparse.ArgumentParser, name: str) -> argparse.ArgumentParser:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[name]


@pytest.mark.parametrize("lang", ["ru", "uk"])
@pytest.mark.parametrize("command", sorted(TABLES))
def test_every_option_has_its_translation(lang, command):
    """No option of the two commands is left in English: a new option without its
    Russian and Ukrainian help fails here."""
    p = _command(build_parser(lang), command)
    english = _command(build_parser(), command)
    assert CYRILLIC.search(p.description) and p.description != english.description
    for mine, theirs in zip(p._actions, english._actions, strict=True):
        assert CYRILLIC.search(mine.help or ""), (command, mine.option_strings or mine.dest)
        assert mine.help != theirs.help
    p.format_help()                      # argparse's %-formatting of every help passes


def test_the_english_help_is_the_parsers_own():
    for command in TABLES:
        assert _command(build_parser("en"), command).format_help() == _command(build_parser(), command).format_help()


def test_the_language_is_lang_then_the_locale():
    assert help_lang(["validate", "--lang", "uk", "--help"], {"LANG": "ru_RU.UTF-8"}) == "uk"
    assert help_lang(["validate", "--lang=ru", "x.xlsx"], {}) == "ru"
    assert help_lang(["validate", "--help"], {"LANG": "ru_RU.UTF-8"}) == "ru"
    assert help_lang(["validate", "--lang", "en", "--help"], {"LANG": "ru_RU.UTF-8"}) is None
    assert help_lang(["validate", "--help"], {"LANG": "C.UTF-8"}) is None


def test_validate_help_in_russian_from_the_locale(capsys, monkeypatch):
    for var in ("LC_ALL", "LC_MESSAGES"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    with pytest.raises(SystemExit):
        main(["validate", "--help"])
    assert "вывести отчёты в формате JSON" in capsys.readouterr().out
    monkeypatch.setenv("LANG", "C.UTF-8")
    with pytest.raises(SystemExit):
        main(["variants", "--help"])
    assert "number of variants" in capsys.readouterr().out
