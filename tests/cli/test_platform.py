"""What a user on Windows or in another language would guess: sheetkin expands a file
pattern the shell left as typed (cmd.exe, PowerShell), `docs student-guide` picks the
guide in the user's language, `examples` without DIR writes into the current folder."""
from __future__ import annotations

import shutil
from pathlib import Path

from helpers.clirun import run

from sheetkin.cli.platform import expand_patterns, user_lang

ROOT = Path(__file__).resolve().parents[2]
WORKBOOKS = ROOT / "workbooks"


def test_a_pattern_the_shell_left_is_expanded_sorted(tmp_path):
    for name in ("b-key.xlsx", "a-key.xlsx", "c-exercise.xlsx"):
        (tmp_path / name).write_bytes(b"")
    odd = tmp_path / "x[1].xlsx"                      # a real file whose name looks like a pattern
    odd.write_bytes(b"")
    got = expand_patterns([str(tmp_path / "*-key.xlsx"), str(odd), str(tmp_path / "none-*.xlsx")])
    assert got == [str(tmp_path / "a-key.xlsx"), str(tmp_path / "b-key.xlsx"), str(odd),
                   str(tmp_path / "none-*.xlsx")]


def test_validate_takes_a_quoted_pattern(tmp_path, capsys):
    """`sheetkin validate 'class/*.xlsx'` as Windows passes it: both books are validated (it
    said "no such file" about the pattern)."""
    for stem in ("fourbar", "slotted_lever"):
        shutil.copy(WORKBOOKS / f"{stem}.xlsx", tmp_path / f"{stem}.xlsx")
    code, out, err = run(capsys, "validate", "--jobs", "1", str(tmp_path / "*.xlsx"))
    assert code == 0, err
    assert "no such file" not in err and "fourbar.xlsx" in out and "slotted_lever.xlsx" in out
    code, out, err = run(capsys, "validate", "--jobs", "1", str(tmp_path / "nothing-*.xlsx"))
    assert code == 2 and "nothing-*.xlsx" in out + err      # the pattern named, as typed


def test_the_language_comes_from_lang_then_the_locale():
    assert user_lang("uk", {"LANG": "ru_RU.UTF-8"}) == "uk"
    assert user_lang(None, {"LANG": "ru_RU.UTF-8"}) == "ru"
    assert user_lang(None, {"LC_ALL": "uk_UA.UTF-8", "LANG": "en_US.UTF-8"}) == "uk"
    assert user_lang(None, {"LANG": "C.UTF-8"}) is None
    assert user_lang(None, {}) is None


def test_docs_student_guide_in_the_users_language(capsys, monkeypatch):
    # this checkout's pages (an editable install elsewhere would serve its own docs/)
    monkeypatch.setattr("sheetkin.cli.commands._docs_folder", lambda: ROOT / "docs")
    for var in ("LC_ALL", "LC_MESSAGES", "LANG"):
        monkeypatch.delenv(var, raising=False)
    page = {lang: (ROOT / "docs" / f"student-guide.{lang}.md").read_text(encoding="utf-8") for lang in ("ru", "uk")}
    assert page["ru"] != page["uk"]
    assert run(capsys, "docs", "student-guide")[1] == page["ru"]              # the course's language
    assert run(capsys, "docs", "student-guide", "--lang", "uk")[1] == page["uk"]
    monkeypatch.setenv("LANG", "uk_UA.UTF-8")
    assert run(capsys, "docs", "student-guide")[1] == page["uk"]
    assert run(capsys, "docs", "student-guide.ru")[1] == page["ru"]           # as named
    monkeypatch.setenv("LANG", "en_GB.UTF-8")                                   # no English guide
    assert run(capsys, "docs", "student-guide")[1] == page["ru"]


def test_examples_without_dir_writes_here(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "examples")
    assert code == 0, err
    assert (tmp_path / "fourbar.toml").is_file() and "fourbar.toml" in out
