"""The words of the validation reports (text, HTML, the summary table), one table a
language: ru, uk, en. `validate --lang` picks one; by default the books' own language
(the title of their first sheet, sheetkin.course.validator.book_lang). The Python API
(text_report, html_report ...) speaks English unless told, as it always did.

grades.csv's column headers are in COLUMN_NAMES, except the identifier column: it keeps
the name Moodle's export gave it (`Email address`, `ID number`, `Username`), the name
Moodle's import matches. The messages of the validator and the grading vocabulary are said
through sheetkin.messages.
"""
from __future__ import annotations

from collections import Counter

from sheetkin.messages import message

WORDS: dict[str, dict[str, str]] = {
    "en": {
        "unusable": "UNUSABLE", "positions": "positions", "rows": "{c} rows correct, {w} wrong, {m} missing or empty",
        "all_correct": "all correct", "cause": "likely cause", "row": "row", "formula": "formula", "typed": "typed",
        "cached": "cached", "wrong_at": "wrong at", "wrong_from": "wrong from", "expected": "expected", "got": "got",
        "error_value": "an error value or text where a number belongs", "largest": "largest error",
        "depend": "wrong only because they depend on", "missing": "missing", "empty": "empty",
        "no_row": " (no row of that name in column A)", "own_checks": "the sheet's own check rows that fail",
        "disagree": "formula and saved value disagree at {n} cell(s)", "cannot": "cannot evaluate",
        "saved_used": "(the saved values were used)", "own_inputs": "graded against the student's own inputs "
        "(--accept-changed-inputs)", "fail_issued": "FAIL; graded against the issued variant",
        "student": "student", "group": "group", "variant": "variant", "seal_ok": "seal ok", "note": "note",
        "file": "file", "result": "result", "wrong": "wrong", "first_cause": "first cause", "correct": "correct",
        "data_changed": "data changed", "seal_broken": "seal broken", "mistakes": "mistakes", "position": "position",
        "deg": "deg", "i_eq": "i = ", "score": "score", "wrong_rows": "wrong rows", "likely_causes": "likely causes",
        "missing_rows": "missing rows", "copy_of": "possible copy of", "given_changed": "given data changed",
        "title": "sheetkin validation", "h1": "sheetkin: validation of {n} workbook(s)",
        "intro": "{c} all correct, {o} with mistakes or unusable. Click a column's header to sort, a name to "
        "open the student's details. Positions are named as in the sheet: its row i and the crank angle phi_1.",
        "unusable_p": "Unusable", "graded_against": "graded against", "seal": "seal",
        "score_p": "score {s} (docs: grading)", "rows_p": "{c} rows correct, {w} wrong, {m} missing or empty.",
        "cells_caption": "the rows that are not right, position by position (headers: the sheet's i and phi_1)",
        "status": "status", "right": "right", "first_at": "first at", "depends_on": "depends on",
        "failing_checks": "Check rows of the sheet that fail", "disagree_h": "Formula and saved value disagree",
        "cannot_h": "Cannot evaluate", "no_picture": "no picture",
        "class": "The class at a glance", "class_rows": "Which rows the class got wrong: each row's share of "
        "wrong books, in the lecture's order (usable books: {n})", "class_scores": "Scores ({n} books)",
        "books": "books", "share": "share wrong", "none_wrong": "no row is wrong in any book",
        "students": "Students", "class_checks": "The sheet's check rows that fail: each one's share of books",
        "check": "check", "held": "held for review",
        "class_counts": "Graded books: {n}; held for review as possible copies: {h} (their grade is left empty "
        "in grades.csv). An older file of a student is not counted.",
    },
    "ru": {
        "unusable": "НЕ ПРОВЕРЯЕТСЯ", "positions": "положений",
        "rows": "строк верно: {c}, неверно: {w}, нет или пусто: {m}", "all_correct": "всё верно",
        "cause": "вероятная причина", "row": "строка", "formula": "формула", "typed": "введено числом",
        "cached": "сохранённое значение", "wrong_at": "неверно при", "wrong_from": "неверно начиная с",
        "expected": "ожидалось", "got": "получено", "error_value": "ошибка или текст там, где должно быть число",
        "largest": "наибольшая ошибка", "depend": "неверны только потому, что зависят от", "missing": "нет строк",
        "empty": "пусто", "no_row": " (в столбце A нет строки с таким именем)",
        "own_checks": "не выполнены проверки листа", "disagree": "формула и сохранённое значение расходятся "
        "(ячеек: {n})", "cannot": "не вычисляется", "saved_used": "(взяты сохранённые значения)",
        "own_inputs": "проверено по собственным данным студента (--accept-changed-inputs)",
        "fail_issued": "НЕ ЗАЧТЕНО; проверено по выданному варианту", "student": "студент", "group": "группа",
        "variant": "вариант", "seal_ok": "печать цела", "note": "примечание", "file": "файл", "result": "итог",
        "wrong": "неверно", "first_cause": "первая причина", "correct": "верно", "data_changed": "данные изменены",
        "seal_broken": "печать нарушена", "mistakes": "есть ошибки", "position": "положение", "deg": "град",
        "i_eq": "i = ", "score": "балл", "wrong_rows": "неверных строк", "likely_causes": "вероятные причины",
        "missing_rows": "нет строк", "copy_of": "возможно, списано у", "given_changed": "исходные данные изменены",
        "title": "sheetkin: проверка", "h1": "sheetkin: проверка книг ({n})",
        "intro": "Всё верно: {c}; с ошибками или не проверяются: {o}. Щелчок по заголовку столбца сортирует, по "
        "имени - открывает подробности. Положения названы как на листе: строка i и угол кривошипа phi_1.",
        "unusable_p": "Не проверяется", "graded_against": "проверено по", "seal": "печать",
        "score_p": "балл {s} (docs: grading)", "rows_p": "Строк верно: {c}, неверно: {w}, нет или пусто: {m}.",
        "cells_caption": "неверные строки по положениям (заголовки: i и phi_1 листа)", "status": "статус",
        "right": "верно", "first_at": "впервые при", "depends_on": "зависит от",
        "failing_checks": "Невыполненные проверки листа", "disagree_h": "Формула и сохранённое значение расходятся",
        "cannot_h": "Не вычисляется", "no_picture": "нет рисунка",
        "class": "Группа одним взглядом", "class_rows": "Какие строки группа сделала неверно: доля книг с неверной "
        "строкой, в порядке лекции (проверено книг: {n})", "class_scores": "Баллы (книг: {n})", "books": "книг",
        "share": "доля неверных", "class_checks": "Проверки листа, которые не выполнены: доля книг",
        "check": "проверка", "none_wrong": "ни в одной книге нет неверных строк", "students": "Студенты",
        "held": "отложено для проверки",
        "class_counts": "Оценено книг: {n}; отложено для проверки как возможные копии: {h} (в grades.csv их "
        "оценка пуста). Более старый файл студента не считается.",
    },
    "uk": {
        "unusable": "НЕ ПЕРЕВІРЯЄТЬСЯ", "positions": "положень",
        "rows": "рядків правильно: {c}, неправильно: {w}, немає або порожньо: {m}", "all_correct": "усе правильно",
        "cause": "ймовірна причина", "row": "рядок", "formula": "формула", "typed": "введено числом",
        "cached": "збережене значення", "wrong_at": "неправильно при", "wrong_from": "неправильно починаючи з",
        "expected": "очікувалося", "got": "отримано", "error_value": "помилка або текст там, де має бути число",
        "largest": "найбільша помилка", "depend": "неправильні лише тому, що залежать від",
        "missing": "немає рядків", "empty": "порожньо", "no_row": " (у стовпці A немає рядка з такою назвою)",
        "own_checks": "не виконано перевірки аркуша", "disagree": "формула і збережене значення розходяться "
        "(клітинок: {n})", "cannot": "не обчислюється", "saved_used": "(узято збережені значення)",
        "own_inputs": "перевірено за власними даними студента (--accept-changed-inputs)",
        "fail_issued": "НЕ ЗАРАХОВАНО; перевірено за виданим варіантом", "student": "студент", "group": "група",
        "variant": "варіант", "seal_ok": "печатка ціла", "note": "примітка", "file": "файл", "result": "підсумок",
        "wrong": "неправильно", "first_cause": "перша причина", "correct": "правильно",
        "data_changed": "дані змінено", "seal_broken": "печатку порушено", "mistakes": "є помилки",
        "position": "положення", "deg": "град", "i_eq": "i = ", "score": "бал", "wrong_rows": "неправильних рядків",
        "likely_causes": "ймовірні причини", "missing_rows": "немає рядків", "copy_of": "можливо, списано в",
        "given_changed": "вихідні дані змінено", "title": "sheetkin: перевірка",
        "h1": "sheetkin: перевірка книг ({n})",
        "intro": "Усе правильно: {c}; з помилками або не перевіряються: {o}. Клацання на заголовку стовпця "
        "сортує, на імені - відкриває подробиці. Положення названо як на аркуші: рядок i і кут кривошипа phi_1.",
        "unusable_p": "Не перевіряється", "graded_against": "перевірено за", "seal": "печатка",
        "score_p": "бал {s} (docs: grading)", "rows_p": "Рядків правильно: {c}, неправильно: {w}, немає або "
        "порожньо: {m}.", "cells_caption": "неправильні рядки за положеннями (заголовки: i та phi_1 аркуша)",
        "status": "статус", "right": "правильно", "first_at": "уперше при", "depends_on": "залежить від",
        "failing_checks": "Невиконані перевірки аркуша", "disagree_h": "Формула і збережене значення розходяться",
        "cannot_h": "Не обчислюється", "no_picture": "немає рисунка",
        "class": "Група одним поглядом", "class_rows": "Які рядки група зробила неправильно: частка книг із "
        "неправильним рядком, у порядку лекції (перевірено книг: {n})", "class_scores": "Бали (книг: {n})",
        "books": "книг", "share": "частка неправильних", "none_wrong": "у жодній книзі немає неправильних рядків",
        "students": "Студенти", "class_checks": "Перевірки аркуша, які не виконано: частка книг",
        "check": "перевірка", "held": "відкладено для перевірки",
        "class_counts": "Оцінено книг: {n}; відкладено для перевірки як можливі копії: {h} (у grades.csv їхня "
        "оцінка порожня). Старіший файл студента не враховується.",
    },
}


def words(lang: str) -> dict[str, str]:
    """The report's words in `lang` (ru, uk, en)."""
    if lang not in WORDS:
        raise ValueError(f"lang must be one of {', '.join(WORDS)}, got {lang!r}")
    return WORDS[lang]


def class_lang(reports) -> str:
    """The language most of the books are in (their sheets' titles): the reports' default."""
    langs = Counter(r.lang for r in reports if r.lang)
    return langs.most_common(1)[0][0] if langs else "ru"


# the HTML summary's grading columns (sheetkin.course.report_html), in each language
WORDS["en"].update({"rows correct": "rows correct", "rows typed": "rows typed"})
WORDS["ru"].update({"rows correct": "строк верно", "rows typed": "введено числами"})
WORDS["uk"].update({"rows correct": "рядків правильно", "rows typed": "введено числами"})


# rows whose formulas read only typed numbers (a number pasted elsewhere, then "=Лист2!E5"):
# typed, not computed (sheetkin.xlsx.precedents)
READS_TYPED = message("g_formulas_reading_only_typed")


# who handed a book in (sheetkin.course.identity) and the groups of possible copies
# (sheetkin.course.copies), as the HTML page shows them
WORDS["en"].update({"identity": "who handed it in", "identity_h": "Who handed it in",
                    "copies_h": "Possible copies (one line per group of books)"})
WORDS["ru"].update({"identity": "кто сдал", "identity_h": "Кто сдал",
                    "copies_h": "Возможное списывание (одна строка на группу книг)"})
WORDS["uk"].update({"identity": "хто здав", "identity_h": "Хто здав",
                    "copies_h": "Можливе списування (один рядок на групу книг)"})


# grades.csv's columns (sheetkin.course.grades.COLUMNS) in each language
COLUMN_NAMES: dict[str, dict[str, str]] = {
    "ru": {"student": "студент", "group": "группа", "variant": "вариант", "file": "файл", "verdict": "итог",
           "rows correct": "строк верно", "rows typed": "строк введено числами", "rows total": "строк всего",
           "checks passing": "проверок выполнено", "checks total": "проверок всего",
           "given data changed": "исходные данные изменены", "likely causes": "вероятные причины",
           "possible copy of": "возможно, списано у", "score": "балл", "score explained": "как получен балл",
           "identity": "кто сдал", "not judged": "не проверено (проверьте вручную)", "yes": "да", "no": "нет",
           "status": "состояние", "graded": "оценено", "held for review: possible copy":
           "отложено для проверки: возможно, списано", "not handed in": "не сдано",
           "possible copy: 0 (--copies zero)": "возможно, списано: 0 (--copies zero)",
           "grade": "оценка", "mark": "оценка по шкале"},
    "uk": {"student": "студент", "group": "група", "variant": "варіант", "file": "файл", "verdict": "підсумок",
           "rows correct": "рядків правильно", "rows typed": "рядків введено числами", "rows total": "рядків усього",
           "checks passing": "перевірок виконано", "checks total": "перевірок усього",
           "given data changed": "вихідні дані змінено", "likely causes": "ймовірні причини",
           "possible copy of": "можливо, списано в", "score": "бал", "score explained": "як отримано бал",
           "identity": "хто здав", "not judged": "не перевірено (перевірте вручну)", "yes": "так", "no": "ні",
           "status": "стан", "graded": "оцінено", "held for review: possible copy":
           "відкладено для перевірки: можливо, списано", "not handed in": "не здано",
           "possible copy: 0 (--copies zero)": "можливо, списано: 0 (--copies zero)",
           "grade": "оцінка", "mark": "оцінка за шкалою"},
}

def column_name(column: str, lang: str) -> str:
    """A grades.csv header (or its yes / no) in `lang`."""
    return COLUMN_NAMES.get(lang, {}).get(column, column)
