"""The help of the teacher's commands (`validate`, `variants`) in Russian and Ukrainian.

The English help is the parser's own (sheetkin/cli/args.py), untouched; for ru and uk,
`translate(parser, lang)` replaces the description and each option's help of these
commands by the texts below, keyed by the option's first flag (or the positional's
dest). The language is the one `--lang` names on the command line, else the locale's
(sheetkin/cli/platform.py), chosen before the arguments are parsed, so that
`sheetkin validate --help` in a Russian terminal reads Russian. A text missing here keeps
the English one (tests/cli/test_help_language.py holds that none is missing).
The figures in the texts ({band}, {tries} ...) are the parser's own values.
"""
from __future__ import annotations

import argparse
import os

from .platform import LANGS, user_lang

HELP_FLAG = {"ru": "показать эту справку и выйти", "uk": "показати цю довідку й вийти"}

VALIDATE = {
    "ru": {
        "description":
            "Проверка заполненных книг (созданных `sheetkin workbook` или `sheetkin variants`): "
            "исходные данные сверяются с выданным вариантом (по roster.csv или по схеме, хранящейся "
            "в книге; изменённые данные - работа не засчитана); каждая именованная строка "
            "сравнивается с эталонным расчётом и проверяется ещё и на собственных исходных "
            "величинах студента, а отчёт называет неверные строки, вероятные причины (строки, "
            "неверные сами по себе, округлённые введённые числа) и строки, неверные только из-за "
            "них. Код выхода 0 - всё верно, 1 - найдены ошибки, 2 - непригодный ввод.",
        "paths": "файлы .xlsx, .xlsm, .xls, .ods или .fods, папки (в них книги ищутся рекурсивно) "
                 "или zip-архив Moodle «Скачать все ответы»; файл, названный дважды, проверяется "
                 "один раз; шаблон вроде class/*.xlsx раскрывает сама sheetkin (Windows)",
        "--json": "вывести отчёты в формате JSON",
        "--html": "также записать удобочитаемую HTML-страницу",
        "--lang": "язык отчётов (текст, HTML, заголовки и слова grades.csv, примечания JSON), "
                  "включая сообщения проверки (по умолчанию - язык самих книг) и эту справку; "
                  "столбец идентификатора в grades.csv сохраняет название Moodle",
        "--grades": "также записать по строке на каждую сданную работу: студент, группа, вариант, "
                    "файл, верные строки, выполненные проверки, изменённые исходные данные, "
                    "вероятные причины, возможные копии и балл (см. `sheetkin docs class`); "
                    "CSV-файл, который импортирует журнал оценок Moodle",
        "--class-list": "вместе с --grades: список группы в том виде, в каком его выгружает Moodle "
                        "(Имя, Фамилия, Адрес электронной почты или Идентификационный номер); "
                        "заполняет столбец идентификатора grades.csv по папке Moodle, из которой "
                        "пришла книга, иначе по имени, которое ввёл студент (русские формы: "
                        "«Иванов И.», «Петрова Анна Сергеевна»); одна оценка на студента (по "
                        "самому новому файлу)",
        "--copies": "вместе с --grades: оценка возможной копии (обеих книг пары): hold (по умолчанию: "
                    "балл не ставится, состояние «отложено для проверки», решает преподаватель), keep "
                    "(её балл), zero (0)",
        "--worksheet": "вместе с --grades: ведомость оценивания задания из Moodle («Скачать ведомость "
                       "оценок»); --grades записывает её обратно с её же столбцами и оценкой каждого "
                       "участника (в пересчёте на максимальную оценку), чтобы загрузить как есть",
        "--out-of": "вместе с --grades: также оценка из N баллов (максимум элемента оценивания Moodle) "
                    "рядом с баллом 0..100",
        "--scale": "вместе с --grades: также оценка по шкале рядом с баллом; без значения - пятибалльная "
                   "(отлично от 85, хорошо от 70, удовлетворительно от 50, ниже - неудовлетворительно) "
                   "на языке отчёта; или свои пороги: "
                   "'отлично=90,хорошо=75,удовлетворительно=60,неудовлетворительно=0'",
        "--grades-format": "вместе с --grades: csv (по умолчанию: то, что читает импорт Moodle: ',' между "
                           "полями, '.' в числах, UTF-8), csv-excel (';' и ',' в числах, UTF-8 с BOM: русский "
                           "Excel открывает его двойным щелчком по столбцам) или xlsx (книга)",
        "--progress": "индикатор хода проверки в stderr для нескольких файлов (auto: когда stderr - "
                      "терминал)",
        "--jobs": "проверять в N процессах (по умолчанию - по одному на ядро, здесь {cpus}; не "
                  "больше {max_jobs}); 1 - в этом процессе. Отчёты идут в порядке файлов в любом "
                  "случае; процесс, который аварийно завершился (нехватка памяти), стоит только "
                  "своего файла",
        "--scene": "вариант книги, построенной студентом с нуля (без шаблона sheetkin): её таблица "
                   "находится по значениям на любом листе, по строкам или по столбцам, и оценивается по "
                   "величинам, которые требует лекция (см. `sheetkin docs grading`); с --roster вариант "
                   "каждого студента называет assignment.csv рядом с ним",
        "--roster": "выданные варианты (их пишет `sheetkin variants`): блок исходных данных каждой "
                    "книги сравнивается со строкой её варианта (найденного по номеру варианта в "
                    "книге); изменённое исходное значение сообщается первым, работа не "
                    "засчитывается, а её строки оцениваются по выданным значениям. Без --roster "
                    "книга проверяется по схеме, хранящейся в ней самой",
        "--key": "файл-ключ преподавателя (по умолчанию .sheetkin-key рядом с --roster): проверяет "
                 "печать каждой выданной книги, так что правка скрытого листа со схемой будет "
                 "замечена",
        "--accept-changed-inputs": "оценивать каждую книгу по исходным данным самого студента, даже "
                                   "если они отличаются от выданного варианта (это по-прежнему "
                                   "сообщается, но работа засчитывается)",
        "--accept-typed": "засчитывать число, введённое вместо формулы, если оно верно до последнего "
                          "знака (по умолчанию расчётная строка засчитывается только там, где она "
                          "вычисляется; в отчёте она всё равно отмечена как введённая, а не "
                          "вычисленная; см. `sheetkin docs grading`)",
        "--no-libreoffice": "не вычислять в LibreOffice ячейки, которые sheetkin вычислить не может "
                            "(функция, которой он не знает): то, что их читает, «не оценено: "
                            "проверьте вручную» (по умолчанию их пересчитывает soffice, если он "
                            "установлен)",
    },
    "uk": {
        "description":
            "Перевірка заповнених книг (створених `sheetkin workbook` або `sheetkin variants`): "
            "вихідні дані звіряються з виданим варіантом (за roster.csv або за схемою, що "
            "зберігається в книзі; змінені дані - роботу не зараховано); кожен іменований рядок "
            "порівнюється з еталонним розрахунком і перевіряється ще й на власних вихідних "
            "величинах студента, а звіт називає хибні рядки, ймовірні причини (рядки, хибні самі "
            "по собі, округлені введені числа) і рядки, хибні лише через них. Код виходу 0 - усе "
            "правильно, 1 - знайдено помилки, 2 - непридатні вхідні дані.",
        "paths": "файли .xlsx, .xlsm, .xls, .ods або .fods, теки (у них книги шукаються рекурсивно) "
                 "або zip-архів Moodle «Завантажити всі відповіді»; файл, названий двічі, "
                 "перевіряється один раз; шаблон на кшталт class/*.xlsx розкриває сама sheetkin "
                 "(Windows)",
        "--json": "вивести звіти у форматі JSON",
        "--html": "також записати зручну для читання HTML-сторінку",
        "--lang": "мова звітів (текст, HTML, заголовки й слова grades.csv, примітки JSON), "
                  "включно з повідомленнями перевірки (типово - мова самих книг) і цією довідкою; "
                  "стовпець ідентифікатора в grades.csv зберігає назву Moodle",
        "--grades": "також записати по рядку на кожну здану роботу: студент, група, варіант, файл, "
                    "правильні рядки, виконані перевірки, змінені вихідні дані, ймовірні причини, "
                    "можливі копії та бал (див. `sheetkin docs class`); CSV-файл, який імпортує "
                    "журнал оцінок Moodle",
        "--class-list": "разом із --grades: список групи в тому вигляді, у якому його вивантажує "
                        "Moodle (Ім'я, Прізвище, Адреса електронної пошти або Ідентифікаційний "
                        "номер); заповнює стовпець ідентифікатора grades.csv за текою Moodle, з якої "
                        "надійшла книга, інакше за іменем, яке ввів студент (російські форми: "
                        "«Иванов И.», «Петрова Анна Сергеевна»); одна оцінка на студента (за "
                        "найновішим файлом)",
        "--copies": "разом із --grades: оцінка можливої копії (обох книг пари): hold (типово: бал не "
                    "ставиться, стан «відкладено для перевірки», вирішує викладач), keep (її бал), "
                    "zero (0)",
        "--worksheet": "разом із --grades: відомість оцінювання завдання з Moodle («Завантажити відомість "
                       "оцінок»); --grades записує її назад з її ж стовпцями й оцінкою кожного учасника "
                       "(у перерахунку на максимальну оцінку), щоб завантажити як є",
        "--out-of": "разом із --grades: також оцінка з N балів (максимум елемента оцінювання Moodle) "
                    "поруч із балом 0..100",
        "--scale": "разом із --grades: також оцінка за шкалою поруч із балом; без значення - п'ятибальна "
                   "(відмінно від 85, добре від 70, задовільно від 50, нижче - незадовільно) мовою "
                   "звіту; або свої пороги: 'відмінно=90,добре=75,задовільно=60,незадовільно=0'",
        "--grades-format": "разом із --grades: csv (типово: те, що читає імпорт Moodle: ',' між полями, "
                           "'.' у числах, UTF-8), csv-excel (';' і ',' у числах, UTF-8 з BOM: Excel "
                           "відкриває його подвійним клацанням по стовпцях) або xlsx (книга)",
        "--progress": "індикатор перебігу перевірки в stderr для кількох файлів (auto: коли stderr - "
                      "термінал)",
        "--jobs": "перевіряти в N процесах (типово - по одному на ядро, тут {cpus}; не більше "
                  "{max_jobs}); 1 - у цьому процесі. Звіти йдуть у порядку файлів у будь-якому "
                  "разі; процес, що аварійно завершився (брак пам'яті), коштує лише свого файла",
        "--scene": "варіант книги, побудованої студентом з нуля (без шаблону sheetkin): її таблиця "
                   "знаходиться за значеннями на будь-якому аркуші, за рядками або стовпцями, і "
                   "оцінюється за величинами, яких вимагає лекція (див. `sheetkin docs grading`); з "
                   "--roster варіант кожного студента називає assignment.csv поруч із ним",
        "--roster": "видані варіанти (їх записує `sheetkin variants`): блок вихідних даних кожної "
                    "книги порівнюється з рядком її варіанта (знайденого за номером варіанта в "
                    "книзі); змінене вихідне значення повідомляється першим, роботу не "
                    "зараховано, а її рядки оцінюються за виданими значеннями. Без --roster книга "
                    "перевіряється за схемою, що зберігається в ній самій",
        "--key": "файл-ключ викладача (типово .sheetkin-key поруч із --roster): перевіряє печатку "
                 "кожної виданої книги, тож правку прихованого аркуша зі схемою буде помічено",
        "--accept-changed-inputs": "оцінювати кожну книгу за вихідними даними самого студента, навіть "
                                   "якщо вони відрізняються від виданого варіанта (про це, як і "
                                   "раніше, повідомляється, але роботу зараховано)",
        "--accept-typed": "зараховувати число, введене замість формули, якщо воно правильне до "
                          "останнього знака (типово розрахунковий рядок зараховується лише там, де "
                          "він обчислюється; у звіті його все одно позначено як введений, а не "
                          "обчислений; див. `sheetkin docs grading`)",
        "--no-libreoffice": "не обчислювати в LibreOffice клітинки, яких sheetkin обчислити не може "
                            "(функція, якої він не знає): те, що їх читає, «не оцінено: перевірте "
                            "вручну» (типово їх перераховує soffice, якщо його встановлено)",
    },
}

VARIANTS = {
    "ru": {
        "description":
            "Создать N вариантов схемы для N студентов. По умолчанию каждая длина, координата и "
            "смещение (строки исходных данных в метрах), значение которых в схеме не равно нулю, "
            "меняется в пределах +-{band} от него с округлением до миллиметра; --vary задаёт "
            "диапазон для любого исходного значения схемы. Вариант принимается, если каждая группа "
            "собирается во всех положениях листа и за полный оборот (через {revolution} град: "
            "кривошип проворачивается полностью), каждое звено сохраняет вид движения (вращается "
            "или качается: кривошипно-коромысловый механизм остаётся кривошипно-коромысловым), "
            "|det| каждой группы (мера близости к мёртвому положению) не меньше --min-det во всех "
            "этих положениях и вариант отличается от всех остальных каким-либо исходным значением "
            "на {margin} его диапазона (не меньше одного шага сетки). Записывает в DIR для каждого "
            "варианта ID: ID.toml (его схема), ID-exercise.xlsx (расчётные строки пусты, ячейки "
            "студента и группы не заполнены), ID-key.xlsx (книга-ответ); а также roster.csv "
            "(вариант, задание, ответ, схема, затем все исходные значения) и ключ преподавателя "
            ".sheetkin-key (никогда не помещается в книгу: по нему `validate --roster` проверяет "
            "печати книг). Отказывает одной строкой, если у схемы меньше N подходящих вариантов "
            "за {tries}*N попыток.",
        "scene": "файл схемы (scene .toml)",
        "-n": "число вариантов (по умолчанию - по одному на студента из --class-list, иначе 30)",
        "--class-list": "список группы в том виде, в каком его выгружает Moodle (Имя, Фамилия, Адрес "
                        "электронной почты или Идентификационный номер; запятая или точка с "
                        "запятой; UTF-8 или Windows-1251): k-й студент списка (с 0) получает "
                        "вариант k mod N, так что студентов может быть больше, чем вариантов; в "
                        "задании каждого студента ID-ИМЯ-exercise.xlsx его имя уже вписано, а "
                        "идентификатор скреплён печатью; assignment.csv говорит, кто что получил",
        "--out": "папка для вариантов (создаётся, если её нет)",
        "--seed": "начальное значение генератора случайных чисел: то же значение даёт побайтно те "
                  "же схемы и roster.csv (по умолчанию - случайное, оно печатается)",
        "--vary": "диапазон исходного значения, названного как в блоке исходных данных (L1, L2, "
                  "x_D, Fi_t0, gamma_g2 ...), вместо диапазона по умолчанию; можно повторять; "
                  "например --vary L2=0.45..0.55",
        "--min-det": "наименьший |det| каждой группы в каждом положении (по умолчанию {min_det}: у "
                     "группы RRR угол передачи остаётся больше 14.5 град)",
        "--lang": "язык книг (по умолчанию ru) и этой справки",
        "--force": "перезаписать книги, уже лежащие в DIR; выданные ранее roster.csv, .sheetkin-key "
                   "и assignment.csv сохраняются рядом с новыми, с датой в имени (validate "
                   "по-прежнему проверяет книги, скреплённые старым ключом)",
    },
    "uk": {
        "description":
            "Створити N варіантів схеми для N студентів. Типово кожна довжина, координата і "
            "зміщення (рядки вихідних даних у метрах), значення яких у схемі не дорівнює нулю, "
            "змінюється в межах +-{band} від нього з округленням до міліметра; --vary задає "
            "діапазон для будь-якого вихідного значення схеми. Варіант приймається, якщо кожна "
            "група збирається в усіх положеннях аркуша і за повний оберт (через {revolution} град: "
            "кривошип провертається повністю), кожна ланка зберігає вид руху (обертається або "
            "хитається: кривошипно-коромисловий механізм лишається кривошипно-коромисловим), "
            "|det| кожної групи (міра близькості до мертвого положення) не менший за --min-det в "
            "усіх цих положеннях і варіант відрізняється від усіх інших якимось вихідним "
            "значенням на {margin} його діапазону (не менше одного кроку сітки). Записує в DIR для "
            "кожного варіанта ID: ID.toml (його схема), ID-exercise.xlsx (розрахункові рядки "
            "порожні, клітинки студента й групи не заповнені), ID-key.xlsx (книга-відповідь); а "
            "також roster.csv (варіант, завдання, відповідь, схема, потім усі вихідні значення) і "
            "ключ викладача .sheetkin-key (ніколи не кладеться в книгу: за ним `validate --roster` "
            "перевіряє печатки книг). Відмовляє одним рядком, якщо схема має менше N придатних "
            "варіантів за {tries}*N спроб.",
        "scene": "файл схеми (scene .toml)",
        "-n": "кількість варіантів (типово - по одному на студента з --class-list, інакше 30)",
        "--class-list": "список групи в тому вигляді, у якому його вивантажує Moodle (Ім'я, Прізвище, "
                        "Адреса електронної пошти або Ідентифікаційний номер; кома або крапка з "
                        "комою; UTF-8 або Windows-1251): k-й студент списку (з 0) отримує варіант "
                        "k mod N, тож студентів може бути більше, ніж варіантів; у завданні кожного "
                        "студента ID-ІМ'Я-exercise.xlsx його ім'я вже вписано, а ідентифікатор "
                        "скріплено печаткою; assignment.csv каже, хто що отримав",
        "--out": "тека для варіантів (створюється, якщо її немає)",
        "--seed": "початкове значення генератора випадкових чисел: те саме значення дає побайтно ті "
                  "самі схеми й roster.csv (типово - випадкове, його буде надруковано)",
        "--vary": "діапазон вихідного значення, названого як у блоці вихідних даних (L1, L2, x_D, "
                  "Fi_t0, gamma_g2 ...), замість типового; можна повторювати; наприклад "
                  "--vary L2=0.45..0.55",
        "--min-det": "найменший |det| кожної групи в кожному положенні (типово {min_det}: у групи "
                     "RRR кут передачі лишається більшим за 14.5 град)",
        "--lang": "мова книг (типово ru) і цієї довідки",
        "--force": "перезаписати книги, що вже є в DIR; видані раніше roster.csv, .sheetkin-key і "
                   "assignment.csv зберігаються поруч із новими, з датою в імені (validate, як і "
                   "раніше, перевіряє книги, скріплені старим ключем)",
    },
}
TABLES = {"validate": VALIDATE, "variants": VARIANTS}


def help_lang(argv: list[str], environ=None) -> str | None:
    """The language of the help: `--lang X` (or --lang=X) on the command line, else the
    locale's; None for English (the parser's own texts)."""
    for k, a in enumerate(argv):
        if a == "--lang" and k + 1 < len(argv):
            chosen: str | None = argv[k + 1]
            break
        if a.startswith("--lang="):
            chosen = a.split("=", 1)[1]
            break
    else:
        chosen = user_lang(None, os.environ if environ is None else environ)
    return chosen if chosen in LANGS and chosen != "en" else None


def translate(parser: argparse.ArgumentParser, lang: str | None, values: dict[str, object]) -> None:
    """The help of `validate` and `variants` in `lang` (ru, uk); None or en: left as it is.
    values: the figures the texts name ({band}, {cpus} ...)."""
    if lang not in ("ru", "uk"):
        return
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for command, table in TABLES.items():
        texts, p = table[lang], sub.choices[command]
        p.description = texts["description"].format(**values)
        for action in p._actions:
            key = action.option_strings[0] if action.option_strings else action.dest
            if isinstance(action, argparse._HelpAction):
                action.help = HELP_FLAG[lang]
            elif key in texts:
                action.help = texts[key].format(**values)


# --------------------------------------------------------------------------- errors
# The usage errors of `validate` and `variants` in the teacher's language (issue 34): the
# same language as their help (help_lang: --lang, else the locale). Each entry: the English
# message as a regular expression (its named groups the values: file names, options), the
# ru and uk templates, and an example of the English message as sheetkin prints it (the
# tests hold that each example matches its pattern and is said in both languages). What no
# entry matches goes through the validator's phrases (report_messages.say: "no such
# file" ...) and otherwise stays English. The line keeps the form "sheetkin: error: ...",
# its word "error" said too (ERROR_WORD).
ERROR_WORD = {"ru": "ошибка", "uk": "помилка"}
ERROR_COMMANDS = ("validate", "variants")


def error_parsers(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    """The subparsers of ERROR_COMMANDS (their argparse errors are said in the language)."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return [sub.choices[c] for c in ERROR_COMMANDS]


ERRORS: tuple[tuple[str, dict[str, str], str], ...] = (
    # argparse's own (sheetkin/cli/args.py _Parser.error)
    (r"the following arguments are required: (?P<what>.+?)(?= \(see |$)",
     {"ru": "не указаны обязательные аргументы: {what}", "uk": "не вказано обов'язкові аргументи: {what}"},
     "the following arguments are required: FILE|FOLDER|ZIP (see 'sheetkin validate --help')"),
    (r"argument (?P<opt>\S+): invalid choice: (?P<v>'[^']*') \(choose from (?P<list>[^)]*)\)",
     {"ru": "аргумент {opt}: недопустимое значение {v} (допустимы: {list})",
      "uk": "аргумент {opt}: неприпустиме значення {v} (припустимі: {list})"},
     "argument --copies: invalid choice: 'x' (choose from 'hold', 'keep', 'zero') (see 'sheetkin validate --help')"),
    (r"argument (?P<opt>\S+): expected a whole number, got (?P<v>'[^']*'|\"[^\"]*\")",
     {"ru": "аргумент {opt}: ожидалось целое число, получено {v}",
      "uk": "аргумент {opt}: очікувалося ціле число, отримано {v}"},
     "argument --jobs: expected a whole number, got 'x' (see 'sheetkin validate --help')"),
    (r"argument (?P<opt>\S+): expected a number >= (?P<n>\d+), got (?P<v>'[^']*'|\"[^\"]*\")",
     {"ru": "аргумент {opt}: ожидалось число не меньше {n}, получено {v}",
      "uk": "аргумент {opt}: очікувалося число не менше {n}, отримано {v}"},
     "argument -n: expected a number >= 1, got '0' (see 'sheetkin variants --help')"),
    (r"argument (?P<opt>\S+): expected one argument",
     {"ru": "аргумент {opt}: ожидалось одно значение", "uk": "аргумент {opt}: очікувалося одне значення"},
     "argument --roster: expected one argument (see 'sheetkin validate --help')"),
    (r"unrecognized arguments: (?P<what>.+?)(?= \(see |$)",
     {"ru": "неизвестные аргументы: {what}", "uk": "невідомі аргументи: {what}"},
     "unrecognized arguments: --bogus (see 'sheetkin --help')"),
    (r"\(see '(?P<prog>[^']+) --help'\)$", {"ru": "(см. '{prog} --help')", "uk": "(див. '{prog} --help')"},
     "unrecognized arguments: --bogus (see 'sheetkin --help')"),
    # the roster and the key (sheetkin/course/issued.py)
    (r"^(?P<f>.+?): no such roster file; `variants --class-list` keeps it in (?P<moved>.+)$",
     {"ru": "{f}: нет такого файла roster; `variants --class-list` хранит его в {moved}",
      "uk": "{f}: немає такого файлу roster; `variants --class-list` зберігає його в {moved}"},
     "class-21/roster.csv: no such roster file; `variants --class-list` keeps it in class-21/teacher/roster.csv"),
    (r"^(?P<f>.+?): no such roster file$",
     {"ru": "{f}: нет такого файла roster (его пишет `sheetkin variants`)",
      "uk": "{f}: немає такого файлу roster (його пише `sheetkin variants`)"},
     "class-21/roster.csv: no such roster file"),
    (r"^(?P<f>.+?): no such key file \(`sheetkin variants` writes \.sheetkin-key in its --out folder\)$",
     {"ru": "{f}: нет такого файла-ключа (`sheetkin variants` пишет .sheetkin-key в свою папку --out)",
      "uk": "{f}: немає такого файлу-ключа (`sheetkin variants` пише .sheetkin-key у свою теку --out)"},
     "nope.key: no such key file (`sheetkin variants` writes .sheetkin-key in its --out folder)"),
    # the class list (sheetkin/course/classlist.py)
    (r"^(?P<f>.+?): (?P<opt>--class-list|--worksheet): no such file$",
     {"ru": "{f}: {opt}: нет такого файла", "uk": "{f}: {opt}: немає такого файлу"},
     "participants.csv: --class-list: no such file"),
    (r"^(?P<f>.+?):1: --class-list: expected columns 'First name' and 'Last name' \(or 'Full name'\) and one of "
     r"(?P<ids>.+?); got (?P<got>.*)$",
     {"ru": "{f}:1: --class-list: ожидались столбцы 'First name' и 'Last name' (или 'Full name') и один из "
            "{ids} (или их русские названия из Moodle); получено {got}",
      "uk": "{f}:1: --class-list: очікувалися стовпці 'First name' і 'Last name' (або 'Full name') та один із "
            "{ids} (або їхні російські назви з Moodle); отримано {got}"},
     "class.csv:1: --class-list: expected columns 'First name' and 'Last name' (or 'Full name') and one of "
     "'Email address', 'ID number', 'Username'; got 'foo', 'bar'"),
    (r"^(?P<f>.+?): (?P<opt>--class-list|--worksheet): not UTF-8 text but a binary file \(a workbook\?\); save it "
     r"as CSV UTF-8$",
     {"ru": "{f}: {opt}: не текст UTF-8, а двоичный файл (книга?); сохраните его как CSV UTF-8",
      "uk": "{f}: {opt}: не текст UTF-8, а двійковий файл (книга?); збережіть його як CSV UTF-8"},
     "class.xlsx: --class-list: not UTF-8 text but a binary file (a workbook?); save it as CSV UTF-8"),
    (r"^(?P<f>[^:]+):(?P<line>\d+): (?P<opt>--class-list|--worksheet): not UTF-8 \(nor Windows-1251\) text; ",
     {"ru": "{f}:{line}: {opt}: не текст UTF-8 (и не Windows-1251); ",
      "uk": "{f}:{line}: {opt}: не текст UTF-8 (і не Windows-1251); "},
     "class.csv:3: --class-list: not UTF-8 (nor Windows-1251) text; save it as CSV UTF-8"),
    (r"^(?P<f>.+?): --class-list: empty; expected a header and one line per student$",
     {"ru": "{f}: --class-list: файл пуст; ожидались заголовок и по строке на студента",
      "uk": "{f}: --class-list: файл порожній; очікувалися заголовок і по рядку на студента"},
     "class.csv: --class-list: empty; expected a header and one line per student"),
    (r"^(?P<f>[^:]+):(?P<line>\d+): --class-list: a line without a name or an? (?P<id>.+)$",
     {"ru": "{f}:{line}: --class-list: строка без имени или без {id}",
      "uk": "{f}:{line}: --class-list: рядок без імені або без {id}"},
     "class.csv:4: --class-list: a line without a name or a Email address"),
    (r"^(?P<f>.+?): --class-list names no student$",
     {"ru": "{f}: в --class-list нет ни одного студента", "uk": "{f}: у --class-list немає жодного студента"},
     "class.csv: --class-list names no student"),
    # validate's options (sheetkin/cli/commands.py)
    (r"^--class-list fills grades\.csv's identifier column: give --grades GRADES\.csv too$",
     {"ru": "--class-list заполняет столбец идентификатора grades.csv: укажите и --grades GRADES.csv",
      "uk": "--class-list заповнює стовпець ідентифікатора grades.csv: вкажіть і --grades GRADES.csv"},
     "--class-list fills grades.csv's identifier column: give --grades GRADES.csv too"),
    (r"^--out-of (?P<v>\S+): expected the grade item's maximum, more than 0$",
     {"ru": "--out-of {v}: ожидался максимум элемента оценивания, больше 0",
      "uk": "--out-of {v}: очікувався максимум елемента оцінювання, більше 0"},
     "--out-of 0: expected the grade item's maximum, more than 0"),
    (r"^--scale: (?P<v>'.*?'|\".*?\"): expected NAME=LEAST SCORE \(0\.\.100\), e\.g\. (?P<e>.+)$",
     {"ru": "--scale: {v}: ожидалось ИМЯ=НАИМЕНЬШИЙ БАЛЛ (0..100), например {e}",
      "uk": "--scale: {v}: очікувалося НАЗВА=НАЙМЕНШИЙ БАЛ (0..100), наприклад {e}"},
     "--scale: 'a=b': expected NAME=LEAST SCORE (0..100), e.g. 'отлично=85,хорошо=70'"),
    # variants' (sheetkin/course/variants.py)
    (r"^(?P<f>.+?): exists; refusing to overwrite it \(use --force: an issued roster and key are then kept "
     r"beside the new ones, dated; or another --out\)$",
     {"ru": "{f}: уже есть; не перезаписываю (--force: выданные roster и ключ тогда сохраняются рядом с "
            "новыми, с датой; или другая папка --out)",
      "uk": "{f}: уже є; не перезаписую (--force: видані roster і ключ тоді зберігаються поруч із новими, "
            "з датою; або інша тека --out)"},
     "class-21/teacher/roster.csv: exists; refusing to overwrite it (use --force: an issued roster and key are "
     "then kept beside the new ones, dated; or another --out)"),
    (r"^--out (?P<f>.+?): not a folder$", {"ru": "--out {f}: не папка", "uk": "--out {f}: не тека"},
     "--out class.csv: not a folder"),
    (r"^--vary (?P<v>\S+): no given value (?P<name>'[^']*') in this scene; valid: (?P<list>.+)$",
     {"ru": "--vary {v}: в этой схеме нет исходного значения {name}; допустимы: {list}",
      "uk": "--vary {v}: у цій схемі немає вихідного значення {name}; припустимі: {list}"},
     "--vary Q=1..2: no given value 'Q' in this scene; valid: L1, L2, L3"),
)


# The warnings and the closing lines of `validate` and `variants` in the same language (issue
# 34: a Russian teacher reads no English line): the same form as ERRORS.
WARNING_WORD = {"ru": "предупреждение", "uk": "попередження"}
WARNINGS: tuple[tuple[str, dict[str, str], str], ...] = (
    # grades.csv (sheetkin/course/grades.py grade_lines, fill_worksheet)
    (r"^(?P<f>.+?): (?P<n>\d+) submission\(s\) graded$",
     {"ru": "{f}: оценено работ: {n}", "uk": "{f}: оцінено робіт: {n}"},
     "grades.csv: 4 submission(s) graded"),
    (r"^(?P<f>.+?): Moodle's grading worksheet (?P<w>.+?) with (?P<n>\d+) submission\(s\) graded \(upload it: "
     r"Upload grading worksheet\)$",
     {"ru": "{f}: ведомость оценок Moodle {w}, оценено работ: {n} (загрузите её: «Загрузить ведомость оценок»)",
      "uk": "{f}: відомість оцінок Moodle {w}, оцінено робіт: {n} (завантажте її: «Завантажити відомість "
            "оцінок»)"},
     "grades.csv: Moodle's grading worksheet worksheet.csv with 4 submission(s) graded (upload it: Upload "
     "grading worksheet)"),
    (r"no --class-list: the column (?P<c>'[^']*') is empty; Moodle identifies a student by it, not by name \(fill "
     r"it in, or give Moodle's participants export as --class-list\)",
     {"ru": "нет --class-list: столбец {c} пуст; Moodle узнаёт студента по нему, а не по имени (заполните его "
            "или укажите экспорт участников Moodle как --class-list)",
      "uk": "немає --class-list: стовпець {c} порожній; Moodle впізнає студента за ним, а не за ім'ям "
            "(заповніть його або вкажіть експорт учасників Moodle як --class-list)"},
     "no --class-list: the column 'Email address' is empty; Moodle identifies a student by it, not by name "
     "(fill it in, or give Moodle's participants export as --class-list)"),
    (r"(?P<n>\d+) submission\(s\) not found \(or found twice\) in the class list, their (?P<c>'[^']*') left "
     r"empty: (?P<list>.+)",
     {"ru": "работ не найдено (или найдено дважды) в списке группы: {n}, их {c} оставлен пустым: {list}",
      "uk": "робіт не знайдено (або знайдено двічі) у списку групи: {n}, їхній {c} залишено порожнім: {list}"},
     "3 submission(s) not found (or found twice) in the class list, their 'Email address' left empty: "
     "sub/a.xlsx, sub/b.xlsx"),
    (r" \(newer: ", {"ru": " (новее: ", "uk": " (новіший: "}, "old.xlsx (newer: new.xlsx)"),
    (r"one grade per student: (?P<n>\d+) older file\(s\) not graded: (?P<list>.+)",
     {"ru": "одна оценка на студента: более старых файлов не оценено: {n}: {list}",
      "uk": "одна оцінка на студента: старіших файлів не оцінено: {n}: {list}"},
     "one grade per student: 1 older file(s) not graded: old.xlsx, older.xlsx"),
    (r"(?P<n>\d+) book\(s\) not handed in by their own student: (?P<list>.+)",
     {"ru": "книг, сданных не своим студентом: {n}: {list}", "uk": "книг, зданих не своїм студентом: {n}: {list}"},
     "1 book(s) not handed in by their own student: a.xlsx: found in the folder of Петров Пётр"),
    (r"(?P<n>\d+) possible cop\(ies\) held for review, their score left empty \(--copies keep: their score; "
     r"--copies zero: 0\): (?P<list>.+)",
     {"ru": "возможных копий отложено для проверки: {n}, их балл оставлен пустым (--copies keep: их балл; "
            "--copies zero: 0): {list}",
      "uk": "можливих копій відкладено для перевірки: {n}, їхній бал залишено порожнім (--copies keep: їхній "
            "бал; --copies zero: 0): {list}"},
     "2 possible cop(ies) held for review, their score left empty (--copies keep: their score; --copies zero: "
     "0): a.xlsx, b.xlsx"),
    (r"(?P<n>\d+) student\(s\) of the class list handed nothing in, their score left empty: (?P<list>.+)",
     {"ru": "студентов списка группы, ничего не сдавших: {n}, их балл оставлен пустым: {list}",
      "uk": "студентів списку групи, що нічого не здали: {n}, їхній бал залишено порожнім: {list}"},
     "3 student(s) of the class list handed nothing in, their score left empty: Иванов Иван"),
    (r"the worksheet has no line for participant\(s\) (?P<list>.+?): their grade is not in it",
     {"ru": "в ведомости нет строки для участников {list}: их оценки в ней нет",
      "uk": "у відомості немає рядка для учасників {list}: їхньої оцінки в ній немає"},
     "the worksheet has no line for participant(s) 501, 502: their grade is not in it"),
    # the class (sheetkin/course/class_grading.py)
    (r"^(?P<f>.+?) contradicts (?P<n>\d+) of the (?P<m>\d+) sealed books \(their seals check, the roster's given "
     r"data differ\): is it another class's roster, or re-written\? Each sealed book is graded against its "
     r"sealed data$",
     {"ru": "{f} противоречит {n} из {m} запечатанных книг (их печати верны, а исходные данные roster другие): "
            "это roster другой группы или переписанный? Каждая запечатанная книга оценена по своим данным",
      "uk": "{f} суперечить {n} із {m} запечатаних книг (їхні печатки правильні, а вихідні дані roster інші): "
            "це roster іншої групи чи переписаний? Кожну запечатану книгу оцінено за її даними"},
     "class/roster.csv contradicts 3 of the 4 sealed books (their seals check, the roster's given data differ): "
     "is it another class's roster, or re-written? Each sealed book is graded against its sealed data"),
    (r"^none of the (?P<n>\d+) issued books' seals matches the key: is the key \(or --roster's folder\) another "
     r"class's\?$",
     {"ru": "ни одна из {n} выданных книг не запечатана этим ключом: ключ (или папка --roster) от другой группы?",
      "uk": "жодну з {n} виданих книг не запечатано цим ключем: ключ (або тека --roster) від іншої групи?"},
     "none of the 4 issued books' seals matches the key: is the key (or --roster's folder) another class's?"),
    (r"^none of the (?P<n>\d+) books' variants is in (?P<f>.+?): is it another class's roster\?$",
     {"ru": "ни одного из вариантов {n} книг нет в {f}: это roster другой группы?",
      "uk": "жодного з варіантів {n} книг немає в {f}: це roster іншої групи?"},
     "none of the 4 books' variants is in class/roster.csv: is it another class's roster?"),
    # variants' closing lines (sheetkin/cli/commands.py cmd_variants)
    (r"^(?P<out>.+?): (?P<n>\d+) variants of (?P<scene>.+?) \(seed (?P<seed>\d+): --seed (?P=seed) makes the same "
     r"again\)(?P<who>.*?); (?P<roster>[^;]+); the key (?P<key>.+) stays with you$",
     {"ru": "{out}: вариантов схемы {scene}: {n} (seed {seed}: --seed {seed} даёт те же снова){who}; {roster}; "
            "ключ {key} остаётся у вас",
      "uk": "{out}: варіантів схеми {scene}: {n} (seed {seed}: --seed {seed} дає ті самі знову){who}; {roster}; "
            "ключ {key} залишається у вас"},
     "cls: 3 variants of fourbar.toml (seed 1: --seed 1 makes the same again); cls/roster.csv; the key "
     "cls/.sheetkin-key stays with you"),
    (r", assigned to the (?P<n>\d+) students of (?P<f>.+?) \((?P<a>[^()]+)\)",
     {"ru": ", выданных {n} студентам из {f} ({a})", "uk": ", виданих {n} студентам із {f} ({a})"},
     "cls: 3 variants of fourbar.toml (seed 1: --seed 1 makes the same again), assigned to the 4 students of "
     "class.csv (cls/teacher/assignment.csv); cls/teacher/roster.csv; the key cls/teacher/.sheetkin-key stays "
     "with you"),
    (r"^upload to Moodle (?P<s>.+?) \(one book per student, named by the student\); (?P<t>.+?) is yours \(keys, "
     r"roster, assignment\.csv, the key\): never upload it; grade with --roster (?P<r>.+)$",
     {"ru": "загрузите в Moodle {s} (по книге на студента, названной по студенту); {t} - ваша (ключи, roster, "
            "assignment.csv, ключ): никогда её не загружайте; оценивайте с --roster {r}",
      "uk": "завантажте в Moodle {s} (по книзі на студента, названій за студентом); {t} - ваша (ключі, roster, "
            "assignment.csv, ключ): ніколи її не завантажуйте; оцінюйте з --roster {r}"},
     "upload to Moodle cls/students (one book per student, named by the student); cls/teacher is yours (keys, "
     "roster, assignment.csv, the key): never upload it; grade with --roster cls/teacher/roster.csv"),
)


def say_line(text: str, lang: str | None) -> str:
    """A warning or a closing line of `validate` or `variants` in `lang` (WARNINGS, then the
    validator's phrases); None or en: as it is."""
    return _said(text, lang, WARNINGS)


def warning_line(text: str, lang: str | None) -> str:
    """'sheetkin: warning: TEXT' in `lang` (say_line)."""
    return f"sheetkin: {WARNING_WORD.get(lang or '', 'warning')}: {say_line(text, lang)}"


def say_error(text: str, lang: str | None) -> str:
    """A usage error of `validate` or `variants` in `lang` (ru, uk: ERRORS, then the
    validator's phrases); None or en: as it is."""
    return _said(text, lang, ERRORS)


def _said(text: str, lang: str | None, table: tuple[tuple[str, dict[str, str], str], ...]) -> str:
    if lang not in ERROR_WORD:
        return text
    import re

    from sheetkin.course.report_messages import say
    for pattern, said, _ in table:
        template = said[lang]

        def fill(m: re.Match, t: str = template) -> str:
            return t.format(**m.groupdict())
        text = re.sub(pattern, fill, text)
    return say(text, lang)


def error_line(text: str, lang: str | None) -> str:
    """'sheetkin: error: TEXT' in `lang` (say_error)."""
    return f"sheetkin: {ERROR_WORD.get(lang or '', 'error')}: {say_error(text, lang)}"
