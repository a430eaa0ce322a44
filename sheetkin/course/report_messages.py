"""The validator's own messages in the teacher's language (ru, uk; English as it is).

The messages are made in English where they arise (the workbook reader, the validator,
the seal, identities, copies: `--json` and the tests keep one set of words) and said in
Russian or Ukrainian where a teacher reads them: the text report, the HTML page and
grades.csv (`say(text, lang)`). Two tables, one a language:

* TEMPLATES: messages built with values, an English regular expression whose named
  groups are the values, and a format template per language (`{name}` the value);
* PHRASES: fixed English phrases and their translations, applied after the templates
  (longest first; also inside the templates' values: "password-protected (an encrypted
  Excel workbook)").

grades.csv's column headers are in COLUMN_NAMES, except the identifier column: it keeps
the name Moodle's export gave it (`Email address`, `ID number`, `Username`), the name
Moodle's import matches. A message no table knows stays English (a rare reason a file is
unusable, an internal error). Imports nothing from sheetkin.
"""
from __future__ import annotations

import re
from functools import cache

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

# (English pattern, {lang: template}); the values are the named groups
TEMPLATES: tuple[tuple[str, dict[str, str]], ...] = (
    # the given data and the seal (sheetkin.course.issued)
    (r"given data changed: (?P<list>.+?)(?= \(|$)", {"ru": "исходные данные изменены: {list}",
                                                     "uk": "вихідні дані змінено: {list}"}),
    (r"scene sheet edited: its seal \(scene!C2\) is missing",
     {"ru": "лист сцены изменён: его печати (scene!C2) нет",
      "uk": "аркуш сцени змінено: його печатки (scene!C2) немає"}),
    (r"scene sheet edited: the seal does not match the embedded scene, variant id and student under the "
     r"teacher's key \(or the key is another class's\)",
     {"ru": "лист сцены изменён: печать не совпадает со встроенной сценой, номером варианта и студентом "
            "по ключу преподавателя (или ключ от другой группы)",
      "uk": "аркуш сцени змінено: печатка не збігається з вбудованою сценою, номером варіанта й студентом "
            "за ключем викладача (або ключ від іншої групи)"}),
    (r"the book names no variant", {"ru": "в книге не указан вариант", "uk": "у книзі не зазначено варіант"}),
    (r"variant '(?P<v>[^']*)' is not in (?P<roster>.+?): checked against the embedded scene",
     {"ru": "варианта '{v}' нет в {roster}: проверено по встроенной сцене",
      "uk": "варіанта '{v}' немає в {roster}: перевірено за вбудованою сценою"}),
    (r"(?P<roster>\S+) has no column for (?P<names>.+?): those are checked against the embedded scene",
     {"ru": "в {roster} нет столбца для {names}: они проверены по встроенной сцене",
      "uk": "у {roster} немає стовпця для {names}: їх перевірено за вбудованою сценою"}),
    # the validator's notes (sheetkin.course.validator, layout)
    (r"check status typed over its formula \(column D; counted as failing, its share of the grade lost\): "
     r"(?P<names>.+)", {"ru": "статус проверки введён поверх её формулы (столбец D; считается невыполненной, её доля "
                              "оценки потеряна): {names}",
                        "uk": "статус перевірки введено поверх її формули (стовпець D; вважається невиконаною, її "
                              "частку оцінки втрачено): {names}"}),
    (r"check rows deleted \(counted as failing, their share of the grade lost\): (?P<names>.+)",
     {"ru": "строки проверки удалены (считаются невыполненными, их доля оценки потеряна): {names}",
      "uk": "рядки перевірки видалено (вважаються невиконаними, їхню частку оцінки втрачено): {names}"}),
    (r"(?P<n>\d+) cell\(s\) outside the issued table ignored \(notes, scratch cells, dragged formulas\): "
     r"(?P<cells>.+)", {"ru": "ячеек вне выданной таблицы (не оцениваются: заметки, черновые ячейки, протянутые "
                              "формулы): {n}: {cells}",
                        "uk": "клітинок поза виданою таблицею (не оцінюються: нотатки, чернеткові клітинки, "
                              "протягнуті формули): {n}: {cells}"}),
    (r"graded sheet: '(?P<sheet>[^']*)' \(found by its row names; tab (?P<k>\d+) of (?P<n>\d+)\)",
     {"ru": "оценённый лист: '{sheet}' (найден по именам строк; вкладка {k} из {n})",
      "uk": "оцінений аркуш: '{sheet}' (знайдено за назвами рядків; вкладка {k} з {n})"}),
    (r"columns found by their headers: (?P<list>.+)",
     {"ru": "столбцы найдены по заголовкам: {list}", "uk": "стовпці знайдено за заголовками: {list}"}),
    (r"\(formula gives (?P<now>.+?), saved value (?P<saved>.+?)\)",
     {"ru": "(формула даёт {now}, сохранено {saved})", "uk": "(формула дає {now}, збережено {saved})"}),
    # a typed number named as a cause (sheetkin.course.localjudge.typed_note)
    (r"typed (?P<v>\S+), (?P<d>\d+) digits", {"ru": "введено {v}, цифр: {d}", "uk": "введено {v}, цифр: {d}"}),
    (r"\(its inputs give (?P<v>[^)]+)\)", {"ru": "(по её входным данным {v})", "uk": "(за її вхідними даними {v})"}),
    (r", and (?P<n>\d+) more typed cells", {"ru": " и ещё введённых ячеек: {n}", "uk": " і ще введених клітинок: {n}"}),
    (r"downstream rows differ by up to (?P<v>\S+)", {"ru": "зависимые строки отличаются до {v}",
                                                     "uk": "залежні рядки відрізняються до {v}"}),
    # who handed a book in (sheetkin.course.identity)
    (r"found in the folder of (?P<a>.+?), but (?P<b>.+?)'s name is typed in it",
     {"ru": "найдена в папке {a}, но в ней введено имя {b}",
      "uk": "знайдено в теці {a}, але в ній введено ім'я {b}"}),
    (r"issued to (?P<a>.+?), handed in by (?P<b>.+)",
     {"ru": "выдана {a}, сдал(а) {b}", "uk": "видано {a}, здав(ла) {b}"}),
    (r"\(Moodle participant (?P<n>\d+)\)", {"ru": "(участник Moodle {n})", "uk": "(учасник Moodle {n})"}),
    # a typed name against the class list (sheetkin.course.identity: the name as Python's repr)
    (r"the folder (?P<f>'[^']*'): no one in the class list is named (?P<n>'[^']*'|\"[^\"]*\")",
     {"ru": "папка {f}: в списке группы нет никого с именем {n}",
      "uk": "тека {f}: у списку групи немає нікого з ім'ям {n}"}),
    (r"the folder (?P<f>'[^']*'): (?P<n>'[^']*'|\"[^\"]*\") can be (?P<who>[^;]+)",
     {"ru": "папка {f}: {n} - это может быть {who}", "uk": "тека {f}: {n} - це може бути {who}"}),
    (r"no one in the class list is named (?P<n>'[^']*'|\"[^\"]*\")",
     {"ru": "в списке группы нет никого с именем {n}", "uk": "у списку групи немає нікого з ім'ям {n}"}),
    (r"(?P<n>'[^']*'|\"[^\"]*\") can be (?P<who>[^;]+)",
     {"ru": "{n} - это может быть {who}", "uk": "{n} - це може бути {who}"}),
    (r"\bparticipant (?P<n>\d+)", {"ru": "участник {n}", "uk": "учасник {n}"}),
    (r"not graded: (?P<who>.+?) handed in (?P<file>.+?) too, which is newer",
     {"ru": "не оценена: {who} сдал(а) и {file}, она новее", "uk": "не оцінено: {who} здав(ла) і {file}, він новіший"}),
    (r"not graded: (?P<who>.+?) handed in (?P<file>.+?) too, their own book \(this one is not\)",
     {"ru": "не оценена: {who} сдал(а) и {file}, свою книгу (эта - не своя)",
      "uk": "не оцінено: {who} здав(ла) і {file}, свою книгу (ця - не своя)"}),
    (r"not graded: (?P<who>.+?) handed in (?P<file>.+?) too, which is usable \(this one is not\)",
     {"ru": "не оценена: {who} сдал(а) и {file}, она проверяется (эта - нет)",
      "uk": "не оцінено: {who} здав(ла) і {file}, він перевіряється (цей - ні)"}),
    (r"graded; older files of this student not graded: (?P<files>.+)",
     {"ru": "оценена; более старые файлы этого студента не оценены: {files}",
      "uk": "оцінено; старіші файли цього студента не оцінено: {files}"}),
    (r"graded; other files of this student not graded: (?P<files>.+)",
     {"ru": "оценена; другие файлы этого студента не оценены: {files}",
      "uk": "оцінено; інші файли цього студента не оцінено: {files}"}),
    # why sheetkin cannot compute a cell (sheetkin.xlsx: the evaluator's problems)
    (r"unsupported functions (?P<f>\S+(?:, \S+)*)", {"ru": "неподдерживаемые функции {f}",
                                                     "uk": "непідтримувані функції {f}"}),
    (r"unsupported function (?P<f>\S+)", {"ru": "неподдерживаемая функция {f}", "uk": "непідтримувана функція {f}"}),
    (r"cannot read the formula (?P<f>=.+): ", {"ru": "не читается формула {f}: ", "uk": "не читається формула {f}: "}),
    (r"the name (?P<n>\S+) is not a formula \(", {"ru": "имя {n} - не формула (", "uk": "ім'я {n} - не формула ("}),
    (r"unexpected (?P<t>'[^']*'|\"[^\"]*\") in (?P<f>\S+)\(\.\.\.\)",
     {"ru": "неожиданный символ {t} в {f}(...)", "uk": "неочікуваний символ {t} у {f}(...)"}),
    (r"unexpected (?P<t>'[^']*'|\"[^\"]*\")", {"ru": "неожиданный символ {t}", "uk": "неочікуваний символ {t}"}),
    (r"(?P<f>\S+)\( is not closed", {"ru": "{f}( не закрыта", "uk": "{f}( не закрито"}),
    (r"circular reference among (?P<cells>.+?) and (?P<n>\d+) more cells",
     {"ru": "циклическая ссылка, ячейки: {cells} и ещё {n}", "uk": "циклічне посилання, клітинки: {cells} і ще {n}"}),
    (r"circular reference among ", {"ru": "циклическая ссылка, ячейки: ", "uk": "циклічне посилання, клітинки: "}),
    # possible copies (sheetkin.course.copies)
    (r"one issued book \(variant (?P<v>.+?), issued to one student\) handed in by (?P<n>\d+) students",
     {"ru": "одна выданная книга (вариант {v}, выдан одному студенту) сдана студентами: {n}",
      "uk": "одну видану книгу (варіант {v}, видано одному студентові) здали студенти: {n}"}),
    (r"one issued book \(variant (?P<v>.+?), issued to (?P<to>.+?)\) handed in by (?P<n>\d+) students",
     {"ru": "одна выданная книга (вариант {v}, выдан {to}) сдана студентами: {n}",
      "uk": "одну видану книгу (варіант {v}, видано {to}) здали студенти: {n}"}),
    (r"the same variant (?P<v>.+?) from (?P<n>\d+) students \(no assignment: `variants --class-list` gives each "
     r"student their own\)",
     {"ru": "один вариант {v} у студентов: {n} (без назначения: `variants --class-list` даёт каждому свой)",
      "uk": "один варіант {v} у студентів: {n} (без призначення: `variants --class-list` дає кожному свій)"}),
    (r"the same issued variant (?P<v>.+?), its given data changed in one",
     {"ru": "один выданный вариант {v}, в одной из книг изменены исходные данные",
      "uk": "один виданий варіант {v}, в одній із книг змінено вихідні дані"}),
    (r"(?P<n>\d+) typed numbers equal to variant (?P<v>\S+)'s computed values \((?P<what>[^)]*\)?)\)",
     {"ru": "введённых чисел, равных вычисленным значениям варианта {v} ({what}): {n}",
      "uk": "введених чисел, рівних обчисленим значенням варіанта {v} ({what}): {n}"}),
    (r"(?P<n>\d+) identical typed numbers, wrong for one variant at least",
     {"ru": "одинаковых введённых чисел, неверных хотя бы для одного варианта: {n}",
      "uk": "однакових введених чисел, неправильних хоча б для одного варіанта: {n}"}),
    (r"(?P<n>\d+) typed numbers equal to what (?P<who>.+?) computed",
     {"ru": "введённых чисел, равных вычисленному в {who}: {n}",
      "uk": "введених чисел, рівних обчисленому в {who}: {n}"}),
    (r"the same wrong formula in (?P<name>\S+)", {"ru": "одна и та же неверная формула в {name}",
                                                  "uk": "та сама неправильна формула в {name}"}),
    (r"\(key (?P<path>[^,)]+), issued to (?P<who>[^)]+)\)", {"ru": "(ключ {path}, выдан {who})",
                                                             "uk": "(ключ {path}, видано {who})"}),
    (r"\(key (?P<path>[^,)]+)\)", {"ru": "(ключ {path})", "uk": "(ключ {path})"}),
    (r"possible copy: (?P<n>\d+) files ", {"ru": "возможно, списано: файлов {n}: ",
                                           "uk": "можливо, списано: файлів {n}: "}),
    (r" and (?P<n>\d+) more(?=\W|$)", {"ru": " и ещё {n}", "uk": " і ще {n}"}),
    # why a file is unusable (sheetkin.xlsx: package, cells; sheetkin.course.validator)
    (r"password-protected \((?P<what>[^)]*)\)", {"ru": "защищена паролем ({what})", "uk": "захищено паролем ({what})"}),
    (r"LibreOffice's conversion to \.xlsx (?P<how>failed|timed out)",
     {"ru": "преобразование LibreOffice в .xlsx {how}", "uk": "перетворення LibreOffice на .xlsx {how}"}),
    (r"not an \.xlsx file \((?P<what>.+?)\)(?=;|$)", {"ru": "не файл .xlsx ({what})", "uk": "не файл .xlsx ({what})"}),
    (r"corrupt or truncated zip archive \((?P<what>.+?)\)(?=;|$)",
     {"ru": "zip-архив повреждён или обрезан ({what})", "uk": "zip-архів пошкоджений або обрізаний ({what})"}),
    (r"file is more than (?P<size>[^;]+)", {"ru": "файл больше {size}", "uk": "файл більший за {size}"}),
    (r"file is (?P<size>[^;]+)", {"ru": "файл размером {size}", "uk": "файл розміром {size}"}),
    (r"expected at most (?P<size>.+?) \(sheetkin's limit for a workbook\)",
     {"ru": "ожидалось не более {size} (предел sheetkin для книги)",
      "uk": "очікувалося не більше {size} (межа sheetkin для книги)"}),
    (r"more than (?P<size>\S+ \S+) uncompressed in all", {"ru": "больше {size} в распакованном виде всего",
                                                          "uk": "більше {size} у розпакованому вигляді загалом"}),
    (r"more than (?P<size>\S+ \S+) uncompressed", {"ru": "больше {size} в распакованном виде",
                                                   "uk": "більше {size} у розпакованому вигляді"}),
    (r"contains macros(?: or is macro-enabled)? \((?P<what>[^)]*)\)",
     {"ru": "содержит макросы ({what})", "uk": "містить макроси ({what})"}),
    (r"links to other files \((?P<what>.+?)\)(?=;|$)", {"ru": "ссылается на другие файлы ({what})",
                                                        "uk": "посилається на інші файли ({what})"}),
    (r"no embedded scene \(hidden sheet '(?P<sheet>[^']*)'\); expected a workbook made by `sheetkin workbook`",
     {"ru": "нет встроенной сцены (скрытый лист '{sheet}'); ожидалась книга, сделанная `sheetkin workbook`",
      "uk": "немає вбудованої сцени (прихований аркуш '{sheet}'); очікувалася книга, зроблена `sheetkin workbook`"}),
    (r"no sheet holds the rows of the issued table \(names such as (?P<names>.+?)\.\.\. in a column\)",
     {"ru": "ни один лист не содержит строк выданной таблицы (имён вроде {names}... в столбце)",
      "uk": "жоден аркуш не містить рядків виданої таблиці (назв на зразок {names}... у стовпці)"}),
    (r"(?P<what>.+?); and it no longer reads: ", {"ru": "{what}; и она больше не читается: ",
                                                  "uk": "{what}; і вона більше не читається: "}),
    (r"internal error while validating \((?P<what>.+)\); this is a bug in sheetkin (?P<v>\S+): please report it "
     r"with this file", {"ru": "внутренняя ошибка при проверке ({what}); это ошибка sheetkin {v}: сообщите о ней, "
                               "приложив этот файл",
                         "uk": "внутрішня помилка під час перевірки ({what}); це помилка sheetkin {v}: повідомте "
                               "про неї, доклавши цей файл"}),
)

# fixed phrases (longest first when applied)
PHRASES: dict[str, dict[str, str]] = {
    "ru": {
        "an encrypted Excel workbook": "зашифрованная книга Excel", "an encrypted .xls workbook":
        "зашифрованная книга .xls", "an encrypted OpenDocument spreadsheet": "зашифрованная таблица OpenDocument",
        "a password-protected, encrypted workbook": "защищённая паролем, зашифрованная книга",
        "a workbook saved without a password (File > Save As, untick the password)":
        "нужна книга, сохранённая без пароля (Файл > Сохранить как, снять пароль)",
        "expected .xlsx: save it as Excel Workbook (.xlsx) without a password":
        "ожидался .xlsx: сохраните как книгу Excel (.xlsx) без пароля",
        "expected an Excel workbook saved as .xlsx": "ожидалась книга Excel, сохранённая как .xlsx",
        "expected a complete .xlsx file: save or copy it again": "ожидался целый файл .xlsx: сохраните или "
        "скопируйте его заново",
        "expected .xlsx: in LibreOffice, File > Save As > Excel 2007-365 (.xlsx)":
        "ожидался .xlsx: в LibreOffice Файл > Сохранить как > Excel 2007-365 (.xlsx)",
        "expected an .xlsx workbook": "ожидалась книга .xlsx", "expected an .xlsx file": "ожидался файл .xlsx",
        "expected an unencrypted .xlsx file": "ожидался незашифрованный файл .xlsx",
        "is encrypted (password-protected zip entries)": "зашифрован (части zip защищены паролем)",
        "an OpenDocument spreadsheet, .ods": "таблица OpenDocument, .ods", "an Excel binary workbook, .xlsb":
        "двоичная книга Excel, .xlsb", "empty file (0 bytes)": "пустой файл (0 байт)",
        "no such file": "нет такого файла", "is a directory": "это папка", "not a spreadsheet": "не таблица",
        "plain text": "простой текст", "not a zip archive": "не zip-архив",
        "its end is missing": "нет его конца", "failed": "не удалось",
        "timed out": "не завершилось вовремя", "(embedded scene)": "(встроенная сцена)",
        "an old binary Excel .xls file, or another OLE compound file":
        "старая двоичная книга Excel .xls или другой составной файл OLE", "XML or HTML": "XML или HTML",
        "no row depends on it": "от неё не зависит ни одна строка", "a non-number": "не число",
        "issued to one student": "выдан одному студенту", "byte-identical files": "файлы совпадают побайтно",
        "the same student name": "одно и то же имя студента",
        "Check rows deleted": "Удалённые строки проверки",
        "Check statuses typed over their formulas": "Статусы проверок, введённые поверх формул",
        "Notes": "Примечания", "identity: ": "кто сдал: ", "unusable: ": "не проверяется: ",
        "no name typed": "имя не введено", "empty": "пусто",
        "the formula ends too early": "формула обрывается", "unbalanced parentheses": "непарные скобки",
    },
    "uk": {
        "an encrypted Excel workbook": "зашифрована книга Excel", "an encrypted .xls workbook":
        "зашифрована книга .xls", "an encrypted OpenDocument spreadsheet": "зашифрована таблиця OpenDocument",
        "a password-protected, encrypted workbook": "захищена паролем, зашифрована книга",
        "a workbook saved without a password (File > Save As, untick the password)":
        "потрібна книга, збережена без пароля (Файл > Зберегти як, зняти пароль)",
        "expected .xlsx: save it as Excel Workbook (.xlsx) without a password":
        "очікувався .xlsx: збережіть як книгу Excel (.xlsx) без пароля",
        "expected an Excel workbook saved as .xlsx": "очікувалася книга Excel, збережена як .xlsx",
        "expected a complete .xlsx file: save or copy it again": "очікувався цілий файл .xlsx: збережіть або "
        "скопіюйте його знову",
        "expected .xlsx: in LibreOffice, File > Save As > Excel 2007-365 (.xlsx)":
        "очікувався .xlsx: у LibreOffice Файл > Зберегти як > Excel 2007-365 (.xlsx)",
        "expected an .xlsx workbook": "очікувалася книга .xlsx", "expected an .xlsx file": "очікувався файл .xlsx",
        "expected an unencrypted .xlsx file": "очікувався незашифрований файл .xlsx",
        "is encrypted (password-protected zip entries)": "зашифрований (частини zip захищено паролем)",
        "an OpenDocument spreadsheet, .ods": "таблиця OpenDocument, .ods", "an Excel binary workbook, .xlsb":
        "двійкова книга Excel, .xlsb", "empty file (0 bytes)": "порожній файл (0 байтів)",
        "no such file": "немає такого файлу", "is a directory": "це тека", "not a spreadsheet": "не таблиця",
        "plain text": "звичайний текст", "not a zip archive": "не zip-архів",
        "its end is missing": "немає його кінця", "failed": "не вдалося", "timed out": "не завершилося вчасно",
        "(embedded scene)": "(вбудована сцена)",
        "an old binary Excel .xls file, or another OLE compound file":
        "стара двійкова книга Excel .xls або інший складений файл OLE", "XML or HTML": "XML або HTML",
        "no row depends on it": "від неї не залежить жоден рядок", "a non-number": "не число",
        "issued to one student": "видано одному студентові", "byte-identical files": "файли збігаються побайтово",
        "the same student name": "те саме ім'я студента",
        "Check rows deleted": "Видалені рядки перевірки",
        "Check statuses typed over their formulas": "Статуси перевірок, введені поверх формул",
        "Notes": "Примітки", "identity: ": "хто здав: ", "unusable: ": "не перевіряється: ",
        "no name typed": "ім'я не введено", "empty": "порожньо",
        "the formula ends too early": "формула обривається", "unbalanced parentheses": "непарні дужки",
    },
}


@cache
def _compiled(lang: str):
    templates = [(re.compile(p), t[lang]) for p, t in TEMPLATES]
    phrases = sorted(PHRASES[lang].items(), key=lambda kv: -len(kv[0]))
    return templates, [(re.compile(_bounded(en)), said) for en, said in phrases]


def _bounded(en: str) -> str:
    """A phrase as a whole phrase: not part of a word or of a file name ("failed.xlsx")."""
    head = r"(?<![\w/.-])" if en[0].isalnum() else ""
    tail = r"(?![\w/-]|\.\w)" if en[-1].isalnum() else ""
    return head + re.escape(en) + tail


def say(text: str, lang: str) -> str:
    """A message of the validator (a reason, a note, a seal, an identity flag, a copy's
    reason) in `lang`; English, or a language without tables, as it is."""
    if not text or lang not in PHRASES:
        return text
    templates, phrases = _compiled(lang)
    for pattern, template in templates:
        text = pattern.sub(lambda m, t=template: t.format(**m.groupdict()), text)
    for pattern, said in phrases:
        text = pattern.sub(lambda m, s=said: s, text)
    return text


def column_name(column: str, lang: str) -> str:
    """A grades.csv header (or its yes / no) in `lang`."""
    return COLUMN_NAMES.get(lang, {}).get(column, column)


# issue 31: the behavioural check's notes (sheetkin.course.behaviour), given data typed as
# text (sheetkin.course.validator), a book of another class (sheetkin.course.issued)
TEMPLATES = (
    (r"check rows not judged: check by hand \((?P<n>\d+); sheetkin cannot evaluate their status\): (?P<names>.+)",
     {"ru": "строки проверки не оценены: проверьте вручную ({n}; sheetkin не может вычислить их статус): {names}",
      "uk": "рядки перевірки не оцінено: перевірте вручну ({n}; sheetkin не може обчислити їхній статус): {names}"}),
    (r"not judged: check by hand \((?P<n>\d+); sheetkin cannot evaluate their formulas, they are left out of the "
     r"score\): (?P<names>.+)",
     {"ru": "не оценено: проверьте вручную ({n}; sheetkin не может вычислить их формулы, они не входят в "
            "оценку): {names}",
      "uk": "не оцінено: перевірте вручну ({n}; sheetkin не може обчислити їхні формули, вони не входять до "
            "оцінки): {names}"}),
    (r"does not follow the given data \((?P<n>\d+); right for the issued data, wrong when they change; they earn "
     r"nothing\): (?P<list>.+)",
     {"ru": "не следует за исходными данными ({n}; верно для выданных данных, неверно при их изменении; баллов не "
            "приносят): {list}",
      "uk": "не слідує за вихідними даними ({n}; правильно для виданих даних, неправильно при їх зміні; балів не "
            "приносять): {list}"}),
    (r"check rows that do not check \((?P<n>\d+); they still pass when the given data change and the rows they "
     r"check do not; counted as failing\): (?P<list>.+)",
     {"ru": "строки проверки, которые ничего не проверяют ({n}; они выполняются и тогда, когда исходные данные "
            "изменены, а проверяемые строки нет; считаются невыполненными): {list}",
      "uk": "рядки перевірки, які нічого не перевіряють ({n}; вони виконуються й тоді, коли вихідні дані "
            "змінено, а рядки, що перевіряються, ні; вважаються невиконаними): {list}"}),
    (r"\(row (?P<r>\d+)(?P<rest>[,:)])", {"ru": "(строка {r}{rest}", "uk": "(рядок {r}{rest}"}),
    (r"\bempty at i = ", {"ru": "пусто при i = ", "uk": "порожньо при i = "}),
    (r"given (?P<name>\S+) \((?P<cell>[^)]+)\) is the text (?P<text>'[^']*'|\"[^\"]*\"), not a number: read as "
     r"(?P<x>\S+), as a spreadsheet reads it \(type it as a number\)",
     {"ru": "исходное {name} ({cell}) - текст {text}, а не число: прочитано как {x}, как его читает электронная "
            "таблица (введите его числом)",
      "uk": "вихідне {name} ({cell}) - текст {text}, а не число: прочитано як {x}, як його читає електронна "
            "таблиця (введіть його числом)"}),
    (r"this book is of another scheme, not of the class issued with (?P<roster>.+?) \(its given data "
     r"(?P<names>.+?) are not the roster's\)",
     {"ru": "эта книга другой схемы, а не группы, выданной с {roster} (её исходных данных {names} нет в списке "
            "вариантов)",
      "uk": "ця книга іншої схеми, а не групи, виданої з {roster} (її вихідних даних {names} немає в списку "
            "варіантів)"}),
    (r"this book is of a class issued with another roster, not (?P<roster>.+?) \(variant (?P<v>\S+?)"
     r"(?:'s given data differ from its row| is not in it)\)",
     {"ru": "эта книга группы, выданной с другим списком вариантов, а не {roster} (вариант {v} в нём другой "
            "или его нет)",
      "uk": "ця книга групи, виданої з іншим списком варіантів, а не {roster} (варіант {v} у ньому інший "
            "або його немає)"}),
    *TEMPLATES,
)
