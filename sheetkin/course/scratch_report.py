"""The mapping of a from-scratch book (sheetkin/course/scratch.py) in the text report: for each
quantity of the lecture, the cells found (sheet, row or column, the student's label, unit).
A leaf: reads the report's `mapping` and `given_found` (absent on an issued book's report)."""
from __future__ import annotations

import html

from .scratch import ScratchReport

_KEYS = ("head", "given", "found", "nearest", "not found", "check row", "departs", "also", "required", "helper",
         "checks", "quantity", "grade", "cells", "label", "unit", "correct", "typed", "wrong", "missing")
_WORDS = {lang: dict(zip(_KEYS, texts, strict=True)) for lang, texts in {
    "en": ("the student's table (found by value)", "given data found", "found", "nearest", "not found", "check row",
           "departs at position", "also", "required", "not required", "check rows (not graded)", "quantity",
           "grade", "cells", "the student's label", "unit", "correct", "typed", "wrong", "missing"),
    "ru": ("таблица студента (найдена по значениям)", "исходные данные найдены", "найдено", "ближайшая",
           "не найдено", "строка проверки", "расходится с положения", "также", "обязательная", "необязательная",
           "строки проверки (не оцениваются)", "величина", "оценка", "ячейки", "подпись студента", "единицы",
           "верно", "набрано числами", "неверно", "нет"),
    "uk": ("таблиця студента (знайдена за значеннями)", "вихідні дані знайдено", "знайдено", "найближча",
           "не знайдено", "рядок перевірки", "розходиться з положення", "також", "обов'язкова", "необов'язкова",
           "рядки перевірки (не оцінюються)", "величина", "оцінка", "клітинки", "підпис студента", "одиниці",
           "вірно", "набрано числами", "невірно", "немає"),
}.items()}


def mapping_lines(rep, lang: str = "en") -> list[str]:
    """Lines for text_report: the given data found, then one line per quantity ([] for a
    report without a mapping: an issued book's)."""
    mapping = rep.mapping if isinstance(rep, ScratchReport) else None
    if not mapping:
        return []
    t = _WORDS.get(lang, _WORDS["en"])
    out = [f"  {t['head']}:"]
    given = rep.given_found
    if given:
        out.append(f"    {t['given']}: " + ", ".join(
            f"{g['name']} {g['cell']}" + (f" «{g['label']}»" if g.get("label") else "") for g in given))
    checks = [m for m in mapping if m["status"] == "check row"]
    for m in mapping:
        if m["status"] == "check row":
            continue
        if not m.get("required", True) and m["status"] != "found":
            continue                      # an intermediate of sheetkin's method the student did another way
        name = m["quantity"] or t["check row"]
        text = f"    {name}: {t[m['status']]}"
        if "cells" in m:
            text += f" {m['cells']}" + (f" «{m['label']}»" if m.get("label") else "")
            if m.get("unit"):
                text += f" ({m['unit']})"
        if m.get("departs_at"):
            text += f", {t['departs']} {m['departs_at']}"
        if m.get("also"):
            text += f"; {t['also']} {', '.join(m['also'])}"
        if m["quantity"] and not m.get("required", True):
            text += f" [{t['helper']}]"
        elif m.get("grade") and m["grade"] != "correct":
            text += f" -> {t.get(m['grade'], m['grade'])}"
        out.append(text)
    if checks:
        out.append(f"    {t['checks']} ({len(checks)}): " + ", ".join(
            m["cells"] + (f" «{m['label']}»" if m.get("label") else "") for m in checks))
    return out


def mapping_table(rep, lang: str = "en") -> list[str]:
    """The mapping as an HTML table for the report page: each quantity, its grade, the cells
    found and the student's own label beside them ([] without a mapping)."""
    mapping = rep.mapping if isinstance(rep, ScratchReport) else None
    if not mapping:
        return []
    e, t = html.escape, _WORDS.get(lang, _WORDS["en"])
    out = [f"<table class='cells mapping'><caption class='note'>{e(t['head'])}</caption><tr><th>{t['quantity']}</th>"
           f"<th>{t['grade']}</th><th>{t['cells']}</th><th>{e(t['label'])}</th><th>{t['unit']}</th></tr>"]
    for m in mapping:
        if m["status"] == "check row" or (not m.get("required", True) and m["status"] != "found"):
            continue
        grade = m.get("grade") or t["helper"]
        where = m.get("cells", "") + (f" ({t['departs']} {m['departs_at']})" if m.get("departs_at") else "")
        cls = "" if grade in ("correct", t["helper"]) else " class='wrong'"
        out.append(f"<tr><td>{e(m['quantity'])}</td><td{cls}>{e(t.get(grade, grade))}</td><td>{e(where)}</td>"
                   f"<td>{e(m.get('label', ''))}</td><td>{e(m.get('unit', ''))}</td></tr>")
    checks = [m for m in mapping if m["status"] == "check row"]
    if checks:
        out.append(f"<tr><td colspan='5' class='note'>{e(t['checks'])}: "
                   + e(", ".join(m["cells"] + (f" «{m['label']}»" if m.get("label") else "") for m in checks))
                   + "</td></tr>")
    out.append("</table>")
    return out
