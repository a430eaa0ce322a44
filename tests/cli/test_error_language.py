"""issue 34: the usage errors of `validate` and `variants` in the teacher's language, as
their help (--lang, else the locale): one line, the file and the option named, the values
kept; English without either, and the other commands' errors stay English."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from sheetkin.cli.commands import main
from sheetkin.cli.help_texts import ERROR_WORD, ERRORS, WARNING_WORD, WARNINGS, error_line, say_error, say_line

CYRILLIC = re.compile("[а-яіїєґА-ЯІЇЄҐ]")
SCENE = str(Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml")


@pytest.mark.parametrize("k", range(len(ERRORS) + len(WARNINGS)))
def test_each_error_in_three_languages(k):
    """Every entry (errors, then warnings and closing lines): its English example is the
    message it matches; ru and uk both say it, differently, with Cyrillic words and every
    value the English named."""
    table, say = (ERRORS, say_error) if k < len(ERRORS) else (WARNINGS, say_line)
    pattern, said, example = table[k if k < len(ERRORS) else k - len(ERRORS)]
    m = re.search(pattern, example)
    assert m, (pattern, example)
    assert set(said) == {"ru", "uk"} and all(said[lang].strip() for lang in said)
    out = {lang: say(example, lang) for lang in ("ru", "uk")}
    assert out["ru"] != example and out["uk"] != example and out["ru"] != out["uk"]
    for lang, text in out.items():
        assert CYRILLIC.search(text), (lang, text)
        for value in m.groupdict().values():
            assert value in text, (lang, value, text)
    assert say(example, "en") == example and say(example, None) == example


def test_the_error_line_names_its_word():
    assert error_line("x.csv: no such roster file", None) == "sheetkin: error: x.csv: no such roster file"
    assert error_line("x.csv: no such roster file", "en").startswith("sheetkin: error: ")
    for lang, word in ERROR_WORD.items():
        assert error_line("x.csv: no such roster file", lang).startswith(f"sheetkin: {word}: x.csv: ")


def _cases(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("foo,bar\n1,2\n", encoding="utf-8")
    binary = tmp_path / "class.xlsx"
    binary.write_bytes(b"PK\x03\x04\x00\xff\x00binary")
    afile = tmp_path / "a.txt"
    afile.write_text("x", encoding="utf-8")
    books = str(tmp_path)
    return {
        "missing argument": ["validate"],
        "bad choice": ["validate", books, "--copies", "x"],
        "bad number": ["validate", books, "--jobs", "0"],
        "unknown option": ["validate", books, "--bogus"],
        "no roster": ["validate", books, "--roster", str(tmp_path / "nope.csv")],
        "class list without grades": ["validate", books, "--class-list", str(bad)],
        "no class list": ["validate", books, "--grades", str(tmp_path / "g.csv"), "--class-list",
                          str(tmp_path / "nope.csv")],
        "class list columns": ["validate", books, "--grades", str(tmp_path / "g.csv"), "--class-list", str(bad)],
        "class list binary": ["validate", books, "--grades", str(tmp_path / "g.csv"), "--class-list", str(binary)],
        "out-of": ["validate", books, "--grades", str(tmp_path / "g.csv"), "--out-of", "0"],
        "no scene": ["variants", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")],
        "out not a folder": ["variants", SCENE, "--out", str(afile)],
        "variants class list": ["variants", SCENE, "--out", str(tmp_path / "o"), "--class-list", str(bad)],
        "vary": ["variants", SCENE, "--out", str(tmp_path / "o"), "--vary", "Q=1..2"],
    }


def _error(capsys, argv) -> tuple[int, str]:
    try:
        code = main(argv)
    except SystemExit as e:          # argparse's own mistakes exit through _Parser.error
        code = e.code
    err = capsys.readouterr().err.strip().splitlines()
    return code, err[-1] if err else ""


def test_validate_and_variants_errors_in_the_teachers_language(tmp_path, capsys, monkeypatch):
    for var in ("LC_ALL", "LC_MESSAGES"):
        monkeypatch.delenv(var, raising=False)
    for name, argv in _cases(tmp_path).items():
        monkeypatch.setenv("LANG", "C.UTF-8")
        code, english = _error(capsys, argv)
        assert code == 2 and english.startswith("sheetkin: error: "), (name, english)
        assert not CYRILLIC.search(english.split(": ", 2)[2].split("e.g.")[0]), (name, english)
        monkeypatch.setenv("LANG", "ru_RU.UTF-8")
        code, russian = _error(capsys, argv)
        assert code == 2 and russian.startswith("sheetkin: ошибка: "), (name, russian)
        assert russian == error_line(english[len("sheetkin: error: "):], "ru")
        assert russian != english.replace("error", "ошибка", 1), (name, "not translated", english)
        # --lang beats the locale
        code, ukrainian = _error(capsys, [*argv, "--lang", "uk"])
        assert code == 2 and ukrainian.startswith("sheetkin: помилка: ") and ukrainian != russian, (name, ukrainian)
        code, english_again = _error(capsys, [*argv, "--lang", "en"])
        assert english_again == english, name
        # the file the mistake is in stays named as given
        for path in (a for a in argv if a.startswith(str(tmp_path)) and a in english):
            assert path in russian and path in ukrainian, (name, path)


def test_other_commands_stay_english(tmp_path, capsys, monkeypatch):
    for var in ("LC_ALL", "LC_MESSAGES"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    code, line = _error(capsys, ["compute", str(tmp_path / "nope.toml")])
    assert code == 2 and line == f"sheetkin: error: {tmp_path / 'nope.toml'}: no such file"


def test_a_class_issued_and_graded_speaks_russian_throughout(tmp_path, capsys):
    """variants --class-list and validate --grades with --lang ru: the closing lines and
    every warning (copies held, students who handed nothing in, names not found) in Russian,
    their word too; with --lang en the same lines are English."""
    cl = tmp_path / "class.csv"
    cl.write_bytes("Фамилия;Имя;Адрес электронной почты\nИванов;Иван;iv@x.ru\nПетрова;Анна;pe@x.ru\n"
                   "Сидоров;Пётр;si@x.ru\n".encode("cp1251"))
    out = tmp_path / "cls"
    assert main(["variants", SCENE, "--class-list", str(cl), "-n", "2", "--out", str(out), "--seed", "1",
                 "--lang", "ru"]) == 0
    said = capsys.readouterr().err
    assert "variants of" not in said and "upload to Moodle" not in said and "stays with you" not in said, said
    assert "загрузите в Moodle" in said and str(out / "students") in said
    subs = tmp_path / "sub"
    subs.mkdir()
    key = next((out / "teacher").glob("*-01-key.xlsx")).read_bytes()
    (subs / "a.xlsx").write_bytes(key)
    (subs / "b.xlsx").write_bytes(key)           # a copy: held for review
    runs = {}
    for lang in ("ru", "en"):
        main(["validate", str(subs), "--roster", str(out / "teacher" / "roster.csv"), "--class-list", str(cl),
              "--grades", str(tmp_path / f"g-{lang}.csv"), "--progress", "never", "--lang", lang])
        runs[lang] = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    english = [line for line in runs["en"] if line.startswith("sheetkin: warning: ")]
    assert len(english) >= 3, runs["en"]          # not found, held, handed nothing in
    russian = [line for line in runs["ru"] if line.startswith("sheetkin: ")]
    assert len(russian) == len([line for line in runs["en"] if line.startswith("sheetkin: ")])
    for line in russian:
        assert line.startswith(f"sheetkin: {WARNING_WORD['ru']}: "), line
        text = line.split(": ", 2)[2]
        for english_word in ("submission", "student(s)", "held for review", "left empty", "not found"):
            assert english_word not in text, line
    assert any("оценено работ: 2" in line for line in runs["ru"]), runs["ru"]
