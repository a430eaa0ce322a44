"""The mapping of a from-scratch book (sheetkin/course/scratch.py) in the text report: for each
quantity of the lecture, the cells found (sheet, row or column, the student's label, unit).
A leaf: reads the report's `mapping` and `given_found` (absent on an issued book's report)."""
from __future__ import annotations

_WORDS = {
    "en": {"head": "the student's table (found by value)", "given": "given data found", "found": "found",
           "nearest": "nearest", "not found": "not found", "check row": "check row", "departs": "departs at position",
           "also": "also", "required": "required", "helper": "not required",
           "checks": "check rows (not graded)", "typed": "typed", "wrong": "wrong", "missing": "missing"},
    "ru": {"head": "таблица студента (найдена по значениям)", "given": "исходные данные найдены", "found": "найдено",
           "nearest": "ближайшая", "not found": "не найдено", "check row": "строка проверки",
           "departs": "расходится с положения", "also": "также", "required": "обязательная",
           "helper": "необязательная", "checks": "строки проверки (не оцениваются)", "typed": "набрано числами",
           "wrong": "неверно", "missing": "нет"},
    "uk": {"head": "таблиця студента (знайдена за значеннями)", "given": "вихідні дані знайдено",
           "found": "знайдено", "nearest": "найближча", "not found": "не знайдено", "check row": "рядок перевірки",
           "departs": "розходиться з положення", "also": "також", "required": "обов'язкова",
           "helper": "необов'язкова", "checks": "рядки перевірки (не оцінюються)", "typed": "набрано числами",
           "wrong": "невірно", "missing": "немає"},
}


def mapping_lines(rep, lang: str = "en") -> list[str]:
    """Lines for text_report: the given data found, then one line per quantity ([] for a
    report without a mapping: an issued book's)."""
    mapping = getattr(rep, "mapping", None)
    if not mapping:
        return []
    t = _WORDS.get(lang, _WORDS["en"])
    out = [f"  {t['head']}:"]
    given = getattr(rep, "given_found", []) or []
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
