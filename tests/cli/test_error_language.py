"""issue 34: the usage errors of `validate` and `variants` in the teacher's language, as
their help (--lang, else the locale): one line, the file and the option named, the values
kept; English without either, and the other commands' errors stay English."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from sheetkin.cli.commands import main
from sheetkin.cli.help_texts import ERROR_WORD, WARNING_WORD, error_line
from sheetkin.messages import DOMAINS, pattern, say

CYRILLIC = re.compile("[а-яіїєґА-ЯІЇЄҐ]")
SCENE = str(Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml")


# English messages as sheetkin prints them (argparse's own among them), the errors' and
# the warnings' entries of sheetkin.messages each met by one at least
EXAMPLES = [
    ('errors',
     "the following arguments are required: FILE|FOLDER|ZIP (see 'sheetkin validate --help')"),
    ('errors',
     "argument --copies: invalid choice: 'x' (choose from 'hold', 'keep', 'zero') (see 'sheetkin validate --help')"),
    ('errors',
     "argument --jobs: expected a whole number, got 'x' (see 'sheetkin validate --help')"),
    ('errors',
     "argument -n: expected a number >= 1, got '0' (see 'sheetkin variants --help')"),
    ('errors',
     "argument --roster: expected one argument (see 'sheetkin validate --help')"),
    ('errors',
     "unrecognized arguments: --bogus (see 'sheetkin --help')"),
    ('errors',
     'class-21/roster.csv: no such roster file; `variants --class-list` keeps it in class-21/teacher/roster.csv'),
    ('errors',
     'class-21/roster.csv: no such roster file'),
    ('errors',
     'nope.key: no such key file (`sheetkin variants` writes .sheetkin-key in its --out folder)'),
    ('errors',
     'participants.csv: --class-list: no such file'),
    ('errors',
     "class.csv:1: --class-list: expected columns 'First name' and 'Last name' (or 'Full name') and one of 'Email "
     "address', 'ID number', 'Username'; got 'foo', 'bar'"),
    ('errors',
     'class.xlsx: --class-list: not UTF-8 text but a binary file (a workbook?); save it as CSV UTF-8'),
    ('errors',
     'class.csv:3: --class-list: not UTF-8 (nor Windows-1251) text; save it as CSV UTF-8'),
    ('errors',
     'class.csv: --class-list: empty; expected a header and one line per student'),
    ('errors',
     'class.csv:4: --class-list: a line without a name or a Email address'),
    ('errors',
     'class.csv: --class-list names no student'),
    ('errors',
     "--class-list fills grades.csv's identifier column: give --grades GRADES.csv too"),
    ('errors',
     "--out-of 0: expected the grade item's maximum, more than 0"),
    ('errors',
     "--scale: 'a=b': expected NAME=LEAST SCORE (0..100), e.g. 'отлично=85,хорошо=70'"),
    ('errors',
     'class-21/teacher/roster.csv: exists; refusing to overwrite it (use --force: an issued roster and key are then '
     'kept beside the new ones, dated; or another --out)'),
    ('errors',
     '--out class.csv: not a folder'),
    ('errors',
     "--vary Q=1..2: no given value 'Q' in this scene; valid: L1, L2, L3"),
    ('warnings',
     'grades.csv: 4 submission(s) graded'),
    ('warnings',
     "grades.csv: Moodle's grading worksheet worksheet.csv with 4 submission(s) graded (upload it: Upload grading "
     'worksheet)'),
    ('warnings',
     "no --class-list: the column 'Email address' is empty; Moodle identifies a student by it, not by name (fill it "
     "in, or give Moodle's participants export as --class-list)"),
    ('warnings',
     "3 submission(s) not found (or found twice) in the class list, their 'Email address' left empty: sub/a.xlsx, "
     'sub/b.xlsx'),
    ('warnings',
     'old.xlsx (newer: new.xlsx)'),
    ('warnings',
     'one grade per student: 1 older file(s) not graded: old.xlsx, older.xlsx'),
    ('warnings',
     '1 book(s) not handed in by their own student: a.xlsx: found in the folder of Петров Пётр'),
    ('warnings',
     '2 possible cop(ies) held for review, their score left empty (--copies keep: their score; --copies zero: 0): '
     'a.xlsx, b.xlsx'),
    ('warnings',
     '3 student(s) of the class list handed nothing in, their score left empty: Иванов Иван'),
    ('warnings',
     'the worksheet has no line for participant(s) 501, 502: their grade is not in it'),
    ('warnings',
     "class/roster.csv contradicts 3 of the 4 sealed books (their seals check, the roster's given data differ): is "
     "it another class's roster, or re-written? Each sealed book is graded against its sealed data"),
    ('warnings',
     "none of the 4 issued books' seals matches the key: is the key (or --roster's folder) another class's?"),
    ('warnings',
     "none of the 4 books' variants is in class/roster.csv: is it another class's roster?"),
    ('warnings',
     'cls: 3 variants of fourbar.toml (seed 1: --seed 1 makes the same again); cls/roster.csv; the key '
     'cls/.sheetkin-key stays with you'),
    ('warnings',
     'cls: 3 variants of fourbar.toml (seed 1: --seed 1 makes the same again), assigned to the 4 students of '
     'class.csv (cls/teacher/assignment.csv); cls/teacher/roster.csv; the key cls/teacher/.sheetkin-key stays with '
     'you'),
    ('warnings',
     'upload to Moodle cls/students (one book per student, named by the student); cls/teacher is yours (keys, '
     'roster, assignment.csv, the key): never upload it; grade with --roster cls/teacher/roster.csv'),
]


@pytest.mark.parametrize(("domain", "example"), EXAMPLES)
def test_each_error_in_three_languages(domain, example):
    """Every example (errors, then warnings and closing lines) is a message of its domain;
    ru and uk both say it, differently, with Cyrillic words and every value the English
    named."""
    found = [m for section, _ in DOMAINS[domain] for e in section.values() if (m := re.search(pattern(e), example))]
    assert found, example
    out = {lang: say(example, lang, domain, "report") for lang in ("ru", "uk")}
    assert out["ru"] != example and out["uk"] != example and out["ru"] != out["uk"]
    for lang, text in out.items():
        assert CYRILLIC.search(text), (lang, text)
        for m in found:             # a value holding another message ("{who}") is said too
            for value in m.groupdict().values():
                assert value in text or any(o.group(0) in value for o in found if o is not m), (lang, value, text)
    assert say(example, "en", domain) == example and say(example, None, domain) == example


def test_every_error_and_warning_has_an_example():
    for domain in ("errors", "warnings"):
        for key, entry in DOMAINS[domain][0][0].items():
            assert any(re.search(pattern(entry), e) for d, e in EXAMPLES if d == domain), key


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
