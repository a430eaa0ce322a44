"""The languages of the books: Russian (the course's, the default), Ukrainian and English.

Every text of a book is data, written in each of the three languages where it is used: a
row's description in its module's TEXTS table (one table a language, asked for by key
through sheetkin.groups.rows.Texts: the group kinds, the row helpers, the workbook writer's
own rows in sheetkin.sheet.texts, the dynamics blocks), a kind's TITLE as a rows.Text, the
headers, instructions and chart titles in sheetkin.sheet.texts. Nothing is translated at
run time: the Russian -> Ukrainian word table the rows once went through is gone (its
output for the rows of that time is kept, word for word, in the Ukrainian tables).
Units are written once, in SI symbols ("m/s^2"), and said in the book's language by UNITS.
A leaf module: the row builders, the workbook writer and the reports read it.
"""
from __future__ import annotations

LANGS = ("ru", "uk", "en")

_UNITS_CYR = {"m": "м", "deg": "град", "rad": "рад", "rad/s": "рад/с", "rad/s^2": "рад/с²", "m/s": "м/с",
              "m/s^2": "м/с²", "m^2": "м²", "m^2/s": "м²/с", "m^2/s^2": "м²/с²", "N": "Н", "N m": "Н·м",
              "W": "Вт", "kg": "кг", "kg m^2": "кг·м²", "J": "Дж", "s": "с"}
_UNITS_EN = {"m/s^2": "m/s²", "rad/s^2": "rad/s²", "m^2": "m²", "m^2/s": "m²/s", "m^2/s^2": "m²/s²",
             "kg m^2": "kg·m²", "N m": "N·m"}
UNITS = {"ru": _UNITS_CYR, "uk": _UNITS_CYR, "en": _UNITS_EN}


def unit(u: str, lang: str) -> str:
    """A unit written in SI symbols ("m/s^2") as the book's language writes it ("м/с²")."""
    return UNITS[lang].get(u, u)


def check_lang(lang: str) -> str:
    if lang not in LANGS:
        raise ValueError(f"lang must be one of {', '.join(LANGS)}, got {lang!r}")
    return lang
