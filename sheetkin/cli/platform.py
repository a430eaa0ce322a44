"""What the shell does on Linux and not on Windows, and the user's language.

cmd.exe and PowerShell hand `validate class/*-key.xlsx` to the program as it was typed
(a POSIX shell expands the pattern first): sheetkin expands such a pattern itself. The
teacher's language for the pages and messages that have one comes from --lang, else the
locale (LC_ALL, LC_MESSAGES, LANG: "ru_RU.UTF-8" is Russian), else English.
"""
from __future__ import annotations

import glob
import os
from pathlib import Path

LANGS = ("ru", "uk", "en")
_MAGIC = frozenset("*?[")


def expand_patterns(paths: list[str]) -> list[str]:
    """Each path that holds * ? or [ and names no existing file replaced by the files it
    matches, sorted (what bash would have passed); a pattern that matches nothing is kept
    as typed, so the command says "no such file" about it. An existing name stays itself
    (a file really called "a[1].xlsx")."""
    out: list[str] = []
    for p in paths:
        if _MAGIC & set(p) and not Path(p).exists():
            found = sorted(glob.glob(p, recursive=True))
            out.extend(found or [p])
        else:
            out.append(p)
    return out


def user_lang(explicit: str | None = None, environ=None) -> str | None:
    """ru, uk or en: `explicit` (--lang) if given, else the first locale variable set
    (LC_ALL, LC_MESSAGES, LANG, as gettext reads them) when it names one of them; None when
    neither says (the caller's default applies)."""
    if explicit:
        return explicit
    env = os.environ if environ is None else environ
    for var in ("LC_ALL", "LC_MESSAGES", "LANG"):
        value = env.get(var)
        if value:
            code = value.split(".")[0].split("_")[0].lower()
            return code if code in LANGS else None
    return None
