"""The words of the kinematics sheet that are not a row's description, one table a language
(ru, the course's default; uk; en): headers, the student's cells in rows 1-2, the
instruction block with the legend of the statuses, the chart titles and axes.

The instruction block is rows of the sheet (sections named guide_1 ...), written before
the given data, so that the exercise says on its first screen and its first printed page
what to fill, in which order, what not to change and what the checks' statuses mean.
Imports nothing from sheetkin.
"""
from __future__ import annotations

from typing import Any

SHEET: dict[str, dict[str, Any]] = {   # texts, and (text, text) pairs
    "ru": {"name": "имя", "unit": "ед.", "desc": "описание", "value": "значение / проверка",
           "checks": "проверки", "na": "н/д", "pos": "положение i",
           "student": ("студент", "фамилия, имя"), "group": ("группа", "учебная группа"),
           "variant": "вариант"},
    "uk": {"name": "ім'я", "unit": "од.", "desc": "опис", "value": "значення / перевірка",
           "checks": "перевірки", "na": "н/д", "pos": "положення i",
           "student": ("студент", "прізвище, ім'я"), "group": ("група", "навчальна група"),
           "variant": "варіант"},
    "en": {"name": "name", "unit": "unit", "desc": "description", "value": "value / check",
           "checks": "checks", "na": "n/a", "pos": "position i",
           "student": ("student", "family name, first name"), "group": ("group", "the student's group"),
           "variant": "variant"},
}

# the instruction block and the legend (one line a row; {positions}: E..last column)
GUIDE = {
    "ru": ("Как заполнять лист",
           "1. Впишите фамилию, имя в D1 и группу в D2 (строки 1-2).",
           "2. Исходные данные (жёлтые ячейки столбца D) заданы: не изменяйте их (изменённые данные - оценка 0).",
           "    Лист защищён без пароля, чтобы их нельзя было изменить случайно.",
           "3. Заполните сиреневые ячейки столбца D (Delta_Fi_rad, Alfa_A, Betta_A),",
           "    затем строки расчёта сверху вниз: формула в столбце E, её копия до последнего положения.",
           "4. Положения нумерует строка i (0, 1, 2, ...), как заголовки столбцов; строки i и phi_1 заполнены.",
           "Статусы проверок (столбец D строк chk_... и fd_...; итог - в D3):",
           "    0 (зелёный) - проверка выполнена;  1 (красный) - не выполнена: ищите ошибку в строках выше;",
           "    н/д (серый) - проверять нечего (шаг больше 3 град или группа не собирается);",
           "    не заполнено - строки, которые читает проверка, ещё пусты (её ячейки тоже пусты)."),
    "uk": ("Як заповнювати аркуш",
           "1. Впишіть прізвище, ім'я в D1 і групу в D2 (рядки 1-2).",
           "2. Вихідні дані (жовті клітинки стовпця D) задані: не змінюйте їх (змінені дані - оцінка 0).",
           "    Аркуш захищений без пароля, щоб їх не можна було змінити випадково.",
           "3. Заповніть бузкові клітинки стовпця D (Delta_Fi_rad, Alfa_A, Betta_A),",
           "    потім рядки розрахунку згори донизу: формула в стовпці E, її копія до останнього положення.",
           "4. Положення нумерує рядок i (0, 1, 2, ...), як заголовки стовпців; рядки i та phi_1 заповнені.",
           "Статуси перевірок (стовпець D рядків chk_... та fd_...; підсумок - у D3):",
           "    0 (зелений) - перевірку виконано;  1 (червоний) - не виконано: шукайте помилку в рядках вище;",
           "    н/д (сірий) - перевіряти нічого (крок більший за 3 град або група не збирається);",
           "    не заповнено - рядки, які читає перевірка, ще порожні (її клітинки теж порожні)."),
    "en": ("How to fill in the sheet",
           "1. Type your family name and first name in D1 and your group in D2 (rows 1-2).",
           "2. The given data (the yellow cells of column D) are given: do not change them (changed: score 0).",
           "    The sheet is protected without a password, so that a slip cannot change them.",
           "3. Fill in the lilac cells of column D (Delta_Fi_rad, Alfa_A, Betta_A),",
           "    then the rows below from the top: a formula in column E, copied to the last position.",
           "4. Row i numbers the positions (0, 1, 2, ...), as the column headers do; rows i and phi_1 are filled.",
           "The checks' statuses (column D of the rows chk_... and fd_...; all of them summed up in D3):",
           "    0 (green) - the check passes;  1 (red) - it fails: look for the mistake in the rows above;",
           "    n/a (grey) - nothing to check (a step over 3 deg, or the group does not assemble);",
           "    not filled in - the rows the check reads are still empty (so are its cells)."),
}

CHARTS = {
    "ru": {"speeds": "Скорости точек", "accs": "Ускорения точек", "omegas": "Угловые скорости звеньев",
           "power": "Уравновешивающий момент и мощности", "reactions": "Реакции в кинематических парах",
           "phi": "phi_1, град", "v": "v, м/с", "a": "a, м/с²", "w": "omega, рад/с", "pw": "Н·м, Вт",
           "r": "R, Н"},
    "uk": {"speeds": "Швидкості точок", "accs": "Прискорення точок", "omegas": "Кутові швидкості ланок",
           "power": "Зрівноважувальний момент і потужності", "reactions": "Реакції в кінематичних парах",
           "phi": "phi_1, град", "v": "v, м/с", "a": "a, м/с²", "w": "omega, рад/с", "pw": "Н·м, Вт",
           "r": "R, Н"},
    "en": {"speeds": "Speeds of points", "accs": "Accelerations of points", "omegas": "Angular velocities of links",
           "power": "Balancing moment and powers", "reactions": "Joint reactions",
           "phi": "phi_1, deg", "v": "v, m/s", "a": "a, m/s²", "w": "omega, rad/s", "pw": "N·m, W",
           "r": "R, N"},
}


def guide_line(name: str, lang: str) -> str | None:
    """The text of an instruction row (guide_1 ...) in `lang`; None for any other row."""
    if not name.startswith("guide_"):
        return None
    return GUIDE[lang][int(name.split("_")[1]) - 1]
