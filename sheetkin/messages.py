"""sheetkin's messages, each under a key, in English, Russian and Ukrainian: one catalogue
and one `say` (issue 29).

A message is built where it arises through its key, `message("given_data_changed",
list=...)`, which renders the English template of the catalogue: the English text lives
here only. It stays English where it is kept (the JSON, the tests, the reports' data) and is
said in the teacher's language where a teacher reads it (the text report, the HTML page,
grades.csv, the CLI's errors and warnings, the animation's page): `say(text, lang, *domains)`.
`say` finds the messages in an already-built (and often joined) English text by patterns
derived from the English templates themselves: each `{field}` a named group (the regex
`.+?` unless the entry's `fields` gives another; a field named twice must repeat), the rest
literal, with the entry's `start` and `end` as the zero-width context it needs (`^`, `$`,
`\\b`, a lookahead). Rewording an English template thus rewords what `say` looks for, and
tests/test_messages.py holds that every template renders and is said back in ru and uk.

The catalogue is in domains, each said in its order:

* report: the validator's messages (the workbook reader, the validator, the seal,
  identities, copies, the behavioural check), then REPORT_PHRASES, fixed phrases said
  after them, longest first and only as whole phrases (also inside the messages' values);
* grading: the grading vocabulary (verdicts, counts, the score explained), in order; a
  count's noun agrees with its number (`{n:строка|строки|строк}`: one, few, many). Its
  words ("wrong", "typed, not computed") are data too, verdicts and columns, written where
  they are decided (sheetkin.course.grades);
* errors, warnings: the CLI's usage errors and warnings of `validate` and `variants`
  (argparse's own errors among them: their English is argparse's);
* drawing: the captions and notes of a Picture (sheetkin.views.drawing, animate).

A text no entry matches stays English. Imports nothing from sheetkin.
"""
from __future__ import annotations

import re
import string
from collections.abc import Callable
from functools import cache
from typing import NamedTuple

LANGS = ("ru", "uk")        # the languages said; English is the messages' own
DEFAULT_FIELD = ".+?"       # a field's pattern unless its entry gives another


class Msg(NamedTuple):
    en: str                             # the English template, {field}s its values
    ru: str
    uk: str
    fields: dict[str, str] = {}         # field -> its pattern, where DEFAULT_FIELD does not fit
    start: str = ""                     # zero-width context before the message: ^, \b
    end: str = ""                       # ... after it: $, a lookahead


class _Plural(string.Formatter):
    """`{n:одна|две|пять}`: the form of a noun after the number n (1, 21: the first; 2-4,
    22-24: the second; 0, 5-20, 25: the third); other fields as str.format."""

    def format_field(self, value, format_spec: str) -> str:
        if "|" not in format_spec:
            return super().format_field(value, format_spec)
        one, few, many = format_spec.split("|")
        return plural(int(value), one, few, many)


_FORMAT = _Plural()


def plural(n: int, one: str, few: str, many: str) -> str:
    """The Russian or Ukrainian form of a noun after the number n: 1, 21 строка; 2-4, 22-24
    строки; 0, 5-20, 25 строк."""
    if n % 10 == 1 and n % 100 != 11:
        return one
    return few if 2 <= n % 10 <= 4 and not 12 <= n % 100 <= 14 else many


def fields_of(template: str) -> set[str]:
    """The {field}s a template names."""
    return {f for _, f, _, _ in string.Formatter().parse(template) if f is not None}


def message(key: str, /, **values: object) -> str:
    """The English message `key` with its values (each field of its template, no other)."""
    entry = CATALOGUE[key]
    if set(values) != fields_of(entry.en):
        raise TypeError(f"message {key!r} takes {sorted(fields_of(entry.en))}, got {sorted(values)}")
    return entry.en.format(**values)


def pattern(entry: Msg) -> str:
    """The regular expression that finds the entry's English message in a text, derived from
    its English template: the literal text escaped, each field a named group."""
    out, seen = [entry.start], set()
    for literal, field, _, _ in string.Formatter().parse(entry.en):
        out.append(re.escape(literal))
        if field is not None:
            out.append(f"(?P={field})" if field in seen else f"(?P<{field}>{entry.fields.get(field, DEFAULT_FIELD)})")
            seen.add(field)
    return "".join(out) + entry.end


def _whole(entry: Msg) -> str:
    """A fixed phrase as a whole phrase: not part of a word or of a file name ("failed.xlsx")."""
    en = entry.en
    head = r"(?<![\w/.-])" if en[0].isalnum() else ""
    tail = r"(?![\w/-]|\.\w)" if en[-1].isalnum() else ""
    return head + pattern(entry) + tail


@cache
def _compiled(domain: str, lang: str) -> list[tuple[re.Pattern, str]]:
    out = []
    for section, whole in DOMAINS[domain]:
        entries = sorted(section.values(), key=lambda e: -len(e.en)) if whole else list(section.values())
        out += [(re.compile(_whole(e) if whole else pattern(e)), getattr(e, lang)) for e in entries]
    return out


def say(text: str, lang: str | None, *domains: str) -> str:
    """An English text of sheetkin's messages (those of `domains`, in their order; the
    validator's, "report", if none is named) in `lang`; English, or another language, as it is."""
    if not text or lang not in LANGS:
        return text
    for domain in domains or ("report",):
        for found, template in _compiled(domain, lang):
            text = found.sub(_filled(template), text)
    return text


def _filled(template: str) -> Callable[[re.Match], str]:
    """A match's values written into `template`."""
    return lambda m: _FORMAT.vformat(template, (), m.groupdict())


# --------------------------------------------------------------------------- the catalogue
# the validator's messages (sheetkin.course: issued, validator, layout, checks, localjudge,
# identity, copies, behaviour; sheetkin.xlsx: the reader's refusals, the evaluator's problems)
ANOTHER_ROSTER = {"ru": "эта книга группы, выданной с другим списком вариантов, а не {roster} (вариант {v} в нём "
                        "другой или его нет)",
                  "uk": "ця книга групи, виданої з іншим списком варіантів, а не {roster} (варіант {v} у ньому "
                        "інший або його немає)"}
REPORT: dict[str, Msg] = {
    # the behavioural check's notes (sheetkin.course.behaviour), given data typed as text
    # (validator), a book of another class (issued)
    'check_rows_not_judged': Msg(
        'check rows not judged: check by hand ({n}; sheetkin cannot evaluate their status): {names}',
        ru='строки проверки не оценены: проверьте вручную ({n}; sheetkin не может вычислить их статус): {names}',
        uk='рядки перевірки не оцінено: перевірте вручну ({n}; sheetkin не може обчислити їхній статус): {names}',
        fields={'n': r'\d+', 'names': '.+'}),
    'rows_not_judged': Msg(
        'not judged: check by hand ({n}; sheetkin cannot evaluate their formulas, they are left out of the score): '
        '{names}',
        ru='не оценено: проверьте вручную ({n}; sheetkin не может вычислить их формулы, они не входят в оценку): '
           '{names}',
        uk='не оцінено: перевірте вручну ({n}; sheetkin не може обчислити їхні формули, вони не входять до оцінки): '
           '{names}',
        fields={'n': r'\d+', 'names': '.+'}),
    'not_following_given': Msg(
        'does not follow the given data ({n}; right for the issued data, wrong when they change; they earn nothing): '
        '{list}',
        ru='не следует за исходными данными ({n}; верно для выданных данных, неверно при их изменении; баллов не '
           'приносят): {list}',
        uk='не слідує за вихідними даними ({n}; правильно для виданих даних, неправильно при їх зміні; балів не '
           'приносять): {list}',
        fields={'n': r'\d+', 'list': '.+'}),
    'check_rows_not_checking': Msg(
        'check rows that do not check ({n}; they still pass when the given data change and the rows they check do '
        'not; counted as failing): {list}',
        ru='строки проверки, которые ничего не проверяют ({n}; они выполняются и тогда, когда исходные данные '
           'изменены, а проверяемые строки нет; считаются невыполненными): {list}',
        uk='рядки перевірки, які нічого не перевіряють ({n}; вони виконуються й тоді, коли вихідні дані змінено, а '
           'рядки, що перевіряються, ні; вважаються невиконаними): {list}',
        fields={'n': r'\d+', 'list': '.+'}),
    'row': Msg('(row {r}{rest}', ru='(строка {r}{rest}', uk='(рядок {r}{rest}', fields={'r': r'\d+', 'rest': r'[,:)]'}),
    'empty_at_i': Msg('empty at i = ', ru='пусто при i = ', uk='порожньо при i = ', start=r'\b'),
    'given_as_text': Msg(
        'given {name} ({cell}) is the text {text}, not a number: read as {x}, as a spreadsheet reads it (type it as '
        'a number)',
        ru='исходное {name} ({cell}) - текст {text}, а не число: прочитано как {x}, как его читает электронная '
           'таблица (введите его числом)',
        uk='вихідне {name} ({cell}) - текст {text}, а не число: прочитано як {x}, як його читає електронна таблиця '
           '(введіть його числом)',
        fields={'name': r'\S+', 'cell': '[^)]+', 'text': '\'[^\']*\'|\\"[^\\"]*\\"', 'x': r'\S+'}),
    'book_of_another_scheme': Msg(
        'this book is of another scheme, not of the class issued with {roster} (its given data {names} are not the '
        "roster's)",
        ru='эта книга другой схемы, а не группы, выданной с {roster} (её исходных данных {names} нет в списке '
           'вариантов)',
        uk='ця книга іншої схеми, а не групи, виданої з {roster} (її вихідних даних {names} немає в списку варіантів)'),
    'book_of_another_roster_row': Msg(
        "this book is of a class issued with another roster, not {roster} (variant {v}'s given data differ from its "
        'row)',
        ru=ANOTHER_ROSTER['ru'],
        uk=ANOTHER_ROSTER['uk'],
        fields={'v': r'\S+?'}),
    'book_of_another_roster_not_in': Msg(
        'this book is of a class issued with another roster, not {roster} (variant {v} is not in it)',
        ru=ANOTHER_ROSTER['ru'],
        uk=ANOTHER_ROSTER['uk'],
        fields={'v': r'\S+?'}),
    # the given data and the seal (sheetkin.course.issued)
    'given_data_changed': Msg(
        'given data changed: {list}',
        ru='исходные данные изменены: {list}',
        uk='вихідні дані змінено: {list}',
        end=r'(?= \(|$)'),
    'seal_missing': Msg(
        'scene sheet edited: its seal (scene!C2) is missing',
        ru='лист сцены изменён: его печати (scene!C2) нет',
        uk='аркуш сцени змінено: його печатки (scene!C2) немає'),
    'seal_mismatch': Msg(
        "scene sheet edited: the seal does not match the embedded scene, variant id and student under the teacher's "
        "key (or the key is another class's)",
        ru='лист сцены изменён: печать не совпадает со встроенной сценой, номером варианта и студентом по ключу '
           'преподавателя (или ключ от другой группы)',
        uk='аркуш сцени змінено: печатка не збігається з вбудованою сценою, номером варіанта й студентом за ключем '
           'викладача (або ключ від іншої групи)'),
    'book_names_no_variant': Msg(
        'the book names no variant',
        ru='в книге не указан вариант',
        uk='у книзі не зазначено варіант'),
    'variant_not_in_roster': Msg(
        "variant {v} is not in {roster}: checked against the embedded scene",
        ru="варианта {v} нет в {roster}: проверено по встроенной сцене",
        uk="варіанта {v} немає в {roster}: перевірено за вбудованою сценою",
        fields={'v': "'[^']*'"}),
    'has_no_column_for': Msg(
        '{roster} has no column for {names}: those are checked against the embedded scene',
        ru='в {roster} нет столбца для {names}: они проверены по встроенной сцене',
        uk='у {roster} немає стовпця для {names}: їх перевірено за вбудованою сценою',
        fields={'roster': r'\S+'}),
    # the validator's notes (sheetkin.course.checks, layout, rows)
    'check_status_typed_over': Msg(
        'check status typed over its formula (column D; counted as failing, its share of the grade lost): {names}',
        ru='статус проверки введён поверх её формулы (столбец D; считается невыполненной, её доля оценки потеряна): '
           '{names}',
        uk='статус перевірки введено поверх її формули (стовпець D; вважається невиконаною, її частку оцінки '
           'втрачено): {names}',
        fields={'names': '.+'}),
    'check_rows_deleted_counted': Msg(
        'check rows deleted (counted as failing, their share of the grade lost): {names}',
        ru='строки проверки удалены (считаются невыполненными, их доля оценки потеряна): {names}',
        uk='рядки перевірки видалено (вважаються невиконаними, їхню частку оцінки втрачено): {names}',
        fields={'names': '.+'}),
    'cell_outside_issued_table': Msg(
        '{n} cell(s) outside the issued table ignored (notes, scratch cells, dragged formulas): {cells}',
        ru='ячеек вне выданной таблицы (не оцениваются: заметки, черновые ячейки, протянутые формулы): {n}: {cells}',
        uk='клітинок поза виданою таблицею (не оцінюються: нотатки, чернеткові клітинки, протягнуті формули): {n}: '
           '{cells}',
        fields={'n': r'\d+', 'cells': '.+'}),
    'graded_sheet_found_row': Msg(
        "graded sheet: '{sheet}' (found by its row names; tab {k} of {n})",
        ru="оценённый лист: '{sheet}' (найден по именам строк; вкладка {k} из {n})",
        uk="оцінений аркуш: '{sheet}' (знайдено за назвами рядків; вкладка {k} з {n})",
        fields={'sheet': "[^']*", 'k': r'\d+', 'n': r'\d+'}),
    'columns_found_their_headers': Msg(
        'columns found by their headers: {list}',
        ru='столбцы найдены по заголовкам: {list}',
        uk='стовпці знайдено за заголовками: {list}',
        fields={'list': '.+'}),
    'formula_gives_saved_value': Msg(
        '(formula gives {now}, saved value {saved})',
        ru='(формула даёт {now}, сохранено {saved})',
        uk='(формула дає {now}, збережено {saved})'),
    # a typed number named as a cause (sheetkin.course.localjudge)
    'typed_digits': Msg(
        'typed {v}, {d} digits',
        ru='введено {v}, цифр: {d}',
        uk='введено {v}, цифр: {d}',
        fields={'v': r'\S+', 'd': r'\d+'}),
    'inputs_give': Msg(
        '(its inputs give {v})',
        ru='(по её входным данным {v})',
        uk='(за її вхідними даними {v})',
        fields={'v': '[^)]+'}),
    'and_more_typed_cells': Msg(
        ', and {n} more typed cells',
        ru=' и ещё введённых ячеек: {n}',
        uk=' і ще введених клітинок: {n}',
        fields={'n': r'\d+'}),
    'downstream_rows_differ_up': Msg(
        'downstream rows differ by up to {v}',
        ru='зависимые строки отличаются до {v}',
        uk='залежні рядки відрізняються до {v}',
        fields={'v': r'\S+'}),
    # who handed a book in (sheetkin.course.identity)
    'found_folder_but_name': Msg(
        "found in the folder of {a}, but {b}'s name is typed in it",
        ru='найдена в папке {a}, но в ней введено имя {b}',
        uk="знайдено в теці {a}, але в ній введено ім'я {b}"),
    'found_folder_typed_other': Msg(
        "found in the folder of {a}, but the name typed in it is {b}",
        ru='найдена в папке {a}, но в ней введено имя {b}',
        uk="знайдено в теці {a}, але в ній введено ім'я {b}",
        fields={'b': "'[^']*'|\"[^\"]*\""}),
    'claimed_twice': Msg(
        '{ident} is claimed by {a} and by {b}: not graded under it',
        ru='{ident} заявлен(а) {a} и {b}: под этим именем не оценено',
        uk='{ident} заявлено {a} і {b}: під цим іменем не оцінено',
        fields={'ident': '\\S+'}),
    'issued_handed': Msg(
        'issued to {a}, handed in by {b}',
        ru='выдана {a}, сдал(а) {b}',
        uk='видано {a}, здав(ла) {b}',
        fields={'b': '.+'}),
    'moodle_participant': Msg(
        '(Moodle participant {n})',
        ru='(участник Moodle {n})',
        uk='(учасник Moodle {n})',
        fields={'n': r'\d+'}),
    'folder_no_one_class': Msg(
        'the folder {f}: no one in the class list is named {n}',
        ru='папка {f}: в списке группы нет никого с именем {n}',
        uk="тека {f}: у списку групи немає нікого з ім'ям {n}",
        fields={'f': "'[^']*'", 'n': '\'[^\']*\'|\\"[^\\"]*\\"'}),
    'folder_can_be': Msg(
        'the folder {f}: {n} can be {who}',
        ru='папка {f}: {n} - это может быть {who}',
        uk='тека {f}: {n} - це може бути {who}',
        fields={'f': "'[^']*'", 'n': '\'[^\']*\'|\\"[^\\"]*\\"', 'who': '[^;]+'}),
    'no_one_class_list': Msg(
        'no one in the class list is named {n}',
        ru='в списке группы нет никого с именем {n}',
        uk="у списку групи немає нікого з ім'ям {n}",
        fields={'n': '\'[^\']*\'|\\"[^\\"]*\\"'}),
    'can_be': Msg(
        '{n} can be {who}',
        ru='{n} - это может быть {who}',
        uk='{n} - це може бути {who}',
        fields={'n': '\'[^\']*\'|\\"[^\\"]*\\"', 'who': '[^;]+'}),
    'participant': Msg('participant {n}', ru='участник {n}', uk='учасник {n}', fields={'n': r'\d+'}, start=r'\b'),
    'not_graded_newer': Msg(
        'not graded: {who} handed in {file} too, which is newer',
        ru='не оценена: {who} сдал(а) и {file}, она новее',
        uk='не оцінено: {who} здав(ла) і {file}, він новіший'),
    'not_graded_own_book': Msg(
        'not graded: {who} handed in {file} too, their own book (this one is not)',
        ru='не оценена: {who} сдал(а) и {file}, свою книгу (эта - не своя)',
        uk='не оцінено: {who} здав(ла) і {file}, свою книгу (ця - не своя)'),
    'not_graded_usable': Msg(
        'not graded: {who} handed in {file} too, which is usable (this one is not)',
        ru='не оценена: {who} сдал(а) и {file}, она проверяется (эта - нет)',
        uk='не оцінено: {who} здав(ла) і {file}, він перевіряється (цей - ні)'),
    'graded_older_files': Msg(
        'graded; older files of this student not graded: {files}',
        ru='оценена; более старые файлы этого студента не оценены: {files}',
        uk='оцінено; старіші файли цього студента не оцінено: {files}',
        fields={'files': '.+'}),
    'graded_other_files': Msg(
        'graded; other files of this student not graded: {files}',
        ru='оценена; другие файлы этого студента не оценены: {files}',
        uk='оцінено; інші файли цього студента не оцінено: {files}',
        fields={'files': '.+'}),
    # why sheetkin cannot compute a cell (sheetkin.xlsx: evaluator, parse, limits)
    'unsupported_functions': Msg(
        'unsupported functions {f}',
        ru='неподдерживаемые функции {f}',
        uk='непідтримувані функції {f}',
        fields={'f': r'\S+(?:, \S+)*'}),
    'unsupported_function': Msg(
        'unsupported function {f}',
        ru='неподдерживаемая функция {f}',
        uk='непідтримувана функція {f}',
        fields={'f': r'\S+'}),
    'cannot_read_formula': Msg(
        'cannot read the formula {f}: ',
        ru='не читается формула {f}: ',
        uk='не читається формула {f}: ',
        fields={'f': '=.+'}),
    'name_not_formula': Msg(
        'the name {n} is not a formula (',
        ru='имя {n} - не формула (',
        uk="ім'я {n} - не формула (",
        fields={'n': r'\S+'}),
    'unexpected_in': Msg(
        'unexpected {t} in {f}(...)',
        ru='неожиданный символ {t} в {f}(...)',
        uk='неочікуваний символ {t} у {f}(...)',
        fields={'t': '\'[^\']*\'|\\"[^\\"]*\\"', 'f': r'\S+'}),
    'unexpected': Msg(
        'unexpected {t}',
        ru='неожиданный символ {t}',
        uk='неочікуваний символ {t}',
        fields={'t': '\'[^\']*\'|\\"[^\\"]*\\"'}),
    'not_closed': Msg('{f}( is not closed', ru='{f}( не закрыта', uk='{f}( не закрито', fields={'f': r'\S+'}),
    'circular_more': Msg(
        'circular reference among {cells} and {n} more cells',
        ru='циклическая ссылка, ячейки: {cells} и ещё {n}',
        uk='циклічне посилання, клітинки: {cells} і ще {n}',
        fields={'n': r'\d+'}),
    'circular': Msg(
        'circular reference among ',
        ru='циклическая ссылка, ячейки: ',
        uk='циклічне посилання, клітинки: '),
    # possible copies (sheetkin.course.copies, report)
    'one_book_many_hands': Msg(
        'one issued book (variant {v}, issued to one student) handed in by {n} students',
        ru='одна выданная книга (вариант {v}, выдан одному студенту) сдана студентами: {n}',
        uk='одну видану книгу (варіант {v}, видано одному студентові) здали студенти: {n}',
        fields={'n': r'\d+'}),
    'one_book_many_hands_to': Msg(
        'one issued book (variant {v}, issued to {to}) handed in by {n} students',
        ru='одна выданная книга (вариант {v}, выдан {to}) сдана студентами: {n}',
        uk='одну видану книгу (варіант {v}, видано {to}) здали студенти: {n}',
        fields={'n': r'\d+'}),
    'same_variant_unassigned': Msg(
        'the same variant {v} from {n} students (no assignment: `variants --class-list` gives each student their own)',
        ru='один вариант {v} у студентов: {n} (без назначения: `variants --class-list` даёт каждому свой)',
        uk='один варіант {v} у студентів: {n} (без призначення: `variants --class-list` дає кожному свій)',
        fields={'n': r'\d+'}),
    'same_variant_given_changed': Msg(
        'the same issued variant {v}, its given data changed in one',
        ru='один выданный вариант {v}, в одной из книг изменены исходные данные',
        uk='один виданий варіант {v}, в одній із книг змінено вихідні дані'),
    'typed_equal_variant': Msg(
        "{n} typed numbers equal to variant {v}'s computed values ({what})",
        ru='введённых чисел, равных вычисленным значениям варианта {v} ({what}): {n}',
        uk='введених чисел, рівних обчисленим значенням варіанта {v} ({what}): {n}',
        fields={'n': r'\d+', 'v': r'\S+', 'what': r'[^)]*\)?'}),
    'identical_typed_wrong': Msg(
        '{n} identical typed numbers, wrong for one variant at least',
        ru='одинаковых введённых чисел, неверных хотя бы для одного варианта: {n}',
        uk='однакових введених чисел, неправильних хоча б для одного варіанта: {n}',
        fields={'n': r'\d+'}),
    'typed_equal_computed': Msg(
        '{n} typed numbers equal to what {who} computed',
        ru='введённых чисел, равных вычисленному в {who}: {n}',
        uk='введених чисел, рівних обчисленому в {who}: {n}',
        fields={'n': r'\d+'}),
    'same_wrong_formula': Msg(
        'the same wrong formula in {name}',
        ru='одна и та же неверная формула в {name}',
        uk='та сама неправильна формула в {name}',
        fields={'name': r'\S+'}),
    'key_issued': Msg(
        '(key {path}, issued to {who})',
        ru='(ключ {path}, выдан {who})',
        uk='(ключ {path}, видано {who})',
        fields={'path': '[^,)]+', 'who': '[^)]+'}),
    'key': Msg('(key {path})', ru='(ключ {path})', uk='(ключ {path})', fields={'path': r'[^,)]+'}),
    'possible_copy_files': Msg(
        'possible copy: {n} files ',
        ru='возможно, списано: файлов {n}: ',
        uk='можливо, списано: файлів {n}: ',
        fields={'n': r'\d+'}),
    'and_more': Msg(' and {n} more', ru=' и ещё {n}', uk=' і ще {n}', fields={'n': r'\d+'}, end=r'(?=\W|$)'),
    # why a file is unusable (sheetkin.xlsx: package, cells, convert; sheetkin.course: book,
    # validator, batch)
    'password_protected': Msg(
        'password-protected ({what})',
        ru='защищена паролем ({what})',
        uk='захищено паролем ({what})',
        fields={'what': '[^)]*'}),
    'conversion_failed': Msg(
        "LibreOffice's conversion to .xlsx {how}",
        ru='преобразование LibreOffice в .xlsx {how}',
        uk='перетворення LibreOffice на .xlsx {how}',
        fields={'how': 'failed|timed out'}),
    'not_xlsx_file': Msg(
        'not an .xlsx file ({what})',
        ru='не файл .xlsx ({what})',
        uk='не файл .xlsx ({what})',
        end='(?=;|$)'),
    'corrupt_zip': Msg(
        'corrupt or truncated zip archive ({what})',
        ru='zip-архив повреждён или обрезан ({what})',
        uk='zip-архів пошкоджений або обрізаний ({what})',
        end='(?=;|$)'),
    'file_more_than': Msg(
        'file is more than {size}',
        ru='файл больше {size}',
        uk='файл більший за {size}',
        fields={'size': '[^;]+'}),
    'file_size': Msg('file is {size}', ru='файл размером {size}', uk='файл розміром {size}', fields={'size': r'[^;]+'}),
    'at_most_limit': Msg(
        "expected at most {size} (sheetkin's limit for a workbook)",
        ru='ожидалось не более {size} (предел sheetkin для книги)',
        uk='очікувалося не більше {size} (межа sheetkin для книги)'),
    'uncompressed_all': Msg(
        'more than {size} uncompressed in all',
        ru='больше {size} в распакованном виде всего',
        uk='більше {size} у розпакованому вигляді загалом',
        fields={'size': r'\S+ \S+'}),
    'uncompressed': Msg(
        'more than {size} uncompressed',
        ru='больше {size} в распакованном виде',
        uk='більше {size} у розпакованому вигляді',
        fields={'size': r'\S+ \S+'}),
    'contains_macros': Msg(
        'contains macros ({what})',
        ru='содержит макросы ({what})',
        uk='містить макроси ({what})',
        fields={'what': '[^)]*'}),
    'contains_macros_or_enabled': Msg(
        'contains macros or is macro-enabled ({what})',
        ru='содержит макросы ({what})',
        uk='містить макроси ({what})',
        fields={'what': '[^)]*'}),
    'links_other_files': Msg(
        'links to other files ({what})',
        ru='ссылается на другие файлы ({what})',
        uk='посилається на інші файли ({what})',
        end='(?=;|$)'),
    'no_embedded_scene': Msg(
        "no embedded scene (hidden sheet '{sheet}'); expected a workbook made by `sheetkin workbook`",
        ru="нет встроенной сцены (скрытый лист '{sheet}'); ожидалась книга, сделанная `sheetkin workbook`",
        uk="немає вбудованої сцени (прихований аркуш '{sheet}'); очікувалася книга, зроблена `sheetkin workbook`",
        fields={'sheet': "[^']*"}),
    'no_table_rows': Msg(
        'no sheet holds the rows of the issued table (names such as {names}... in a column)',
        ru='ни один лист не содержит строк выданной таблицы (имён вроде {names}... в столбце)',
        uk='жоден аркуш не містить рядків виданої таблиці (назв на зразок {names}... у стовпці)'),
    'no_longer_reads': Msg(
        '{what}; and it no longer reads: ',
        ru='{what}; и она больше не читается: ',
        uk='{what}; і вона більше не читається: '),
    'internal_error': Msg(
        'internal error while validating ({what}); this is a bug in sheetkin {v}: please report it with this file',
        ru='внутренняя ошибка при проверке ({what}); это ошибка sheetkin {v}: сообщите о ней, приложив этот файл',
        uk='внутрішня помилка під час перевірки ({what}); це помилка sheetkin {v}: повідомте про неї, доклавши цей '
           'файл',
        fields={'what': '.+', 'v': r'\S+'}),
}

# fixed phrases of the validator's messages, said after REPORT (longest first, whole phrases)
REPORT_PHRASES: dict[str, Msg] = {
    'encrypted_excel_workbook': Msg(
        'an encrypted Excel workbook',
        ru='зашифрованная книга Excel',
        uk='зашифрована книга Excel'),
    'encrypted_xls_workbook': Msg(
        'an encrypted .xls workbook',
        ru='зашифрованная книга .xls',
        uk='зашифрована книга .xls'),
    'encrypted_opendocument_spreadsheet': Msg(
        'an encrypted OpenDocument spreadsheet',
        ru='зашифрованная таблица OpenDocument',
        uk='зашифрована таблиця OpenDocument'),
    'password_protected_encrypted_workbook': Msg(
        'a password-protected, encrypted workbook',
        ru='защищённая паролем, зашифрованная книга',
        uk='захищена паролем, зашифрована книга'),
    'workbook_saved_without_password': Msg(
        'a workbook saved without a password (File > Save As, untick the password)',
        ru='нужна книга, сохранённая без пароля (Файл > Сохранить как, снять пароль)',
        uk='потрібна книга, збережена без пароля (Файл > Зберегти як, зняти пароль)'),
    'expected_xlsx_save_it': Msg(
        'expected .xlsx: save it as Excel Workbook (.xlsx) without a password',
        ru='ожидался .xlsx: сохраните как книгу Excel (.xlsx) без пароля',
        uk='очікувався .xlsx: збережіть як книгу Excel (.xlsx) без пароля'),
    'expected_excel_workbook_saved': Msg(
        'expected an Excel workbook saved as .xlsx',
        ru='ожидалась книга Excel, сохранённая как .xlsx',
        uk='очікувалася книга Excel, збережена як .xlsx'),
    'expected_complete_xlsx_file': Msg(
        'expected a complete .xlsx file: save or copy it again',
        ru='ожидался целый файл .xlsx: сохраните или скопируйте его заново',
        uk='очікувався цілий файл .xlsx: збережіть або скопіюйте його знову'),
    'expected_xlsx_libreoffice_file': Msg(
        'expected .xlsx: in LibreOffice, File > Save As > Excel 2007-365 (.xlsx)',
        ru='ожидался .xlsx: в LibreOffice Файл > Сохранить как > Excel 2007-365 (.xlsx)',
        uk='очікувався .xlsx: у LibreOffice Файл > Зберегти як > Excel 2007-365 (.xlsx)'),
    'expected_xlsx_workbook': Msg(
        'expected an .xlsx workbook',
        ru='ожидалась книга .xlsx',
        uk='очікувалася книга .xlsx'),
    'expected_xlsx_file': Msg('expected an .xlsx file', ru='ожидался файл .xlsx', uk='очікувався файл .xlsx'),
    'expected_unencrypted_xlsx_file': Msg(
        'expected an unencrypted .xlsx file',
        ru='ожидался незашифрованный файл .xlsx',
        uk='очікувався незашифрований файл .xlsx'),
    'encrypted_password_protected_zip': Msg(
        'is encrypted (password-protected zip entries)',
        ru='зашифрован (части zip защищены паролем)',
        uk='зашифрований (частини zip захищено паролем)'),
    'opendocument_spreadsheet_ods': Msg(
        'an OpenDocument spreadsheet, .ods',
        ru='таблица OpenDocument, .ods',
        uk='таблиця OpenDocument, .ods'),
    'excel_binary_workbook_xlsb': Msg(
        'an Excel binary workbook, .xlsb',
        ru='двоичная книга Excel, .xlsb',
        uk='двійкова книга Excel, .xlsb'),
    'empty_file_0_bytes': Msg('empty file (0 bytes)', ru='пустой файл (0 байт)', uk='порожній файл (0 байтів)'),
    'no_such_file': Msg('no such file', ru='нет такого файла', uk='немає такого файлу'),
    'directory': Msg('is a directory', ru='это папка', uk='це тека'),
    'not_spreadsheet': Msg('not a spreadsheet', ru='не таблица', uk='не таблиця'),
    'plain_text': Msg('plain text', ru='простой текст', uk='звичайний текст'),
    'not_zip_archive': Msg('not a zip archive', ru='не zip-архив', uk='не zip-архів'),
    'end_missing': Msg('its end is missing', ru='нет его конца', uk='немає його кінця'),
    'failed': Msg('failed', ru='не удалось', uk='не вдалося'),
    'timed_out': Msg('timed out', ru='не завершилось вовремя', uk='не завершилося вчасно'),
    'embedded_scene': Msg('(embedded scene)', ru='(встроенная сцена)', uk='(вбудована сцена)'),
    'old_binary_excel_xls': Msg(
        'an old binary Excel .xls file, or another OLE compound file',
        ru='старая двоичная книга Excel .xls или другой составной файл OLE',
        uk='стара двійкова книга Excel .xls або інший складений файл OLE'),
    'xml_or_html': Msg('XML or HTML', ru='XML или HTML', uk='XML або HTML'),
    'no_row_depends_on': Msg(
        'no row depends on it',
        ru='от неё не зависит ни одна строка',
        uk='від неї не залежить жоден рядок'),
    'non_number': Msg('a non-number', ru='не число', uk='не число'),
    'issued_one_student': Msg('issued to one student', ru='выдан одному студенту', uk='видано одному студентові'),
    'byte_identical_files': Msg('byte-identical files', ru='файлы совпадают побайтно', uk='файли збігаються побайтово'),
    'same_student_name': Msg('the same student name', ru='одно и то же имя студента', uk="те саме ім'я студента"),
    'check_rows_deleted': Msg('Check rows deleted', ru='Удалённые строки проверки', uk='Видалені рядки перевірки'),
    'check_statuses_typed_over': Msg(
        'Check statuses typed over their formulas',
        ru='Статусы проверок, введённые поверх формул',
        uk='Статуси перевірок, введені поверх формул'),
    'notes': Msg('Notes', ru='Примечания', uk='Примітки'),
    'identity': Msg('identity: ', ru='кто сдал: ', uk='хто здав: '),
    'unusable': Msg('unusable: ', ru='не проверяется: ', uk='не перевіряється: '),
    'no_name_typed': Msg('no name typed', ru='имя не введено', uk="ім'я не введено"),
    'empty': Msg('empty', ru='пусто', uk='порожньо'),
    'formula_ends_too_early': Msg('the formula ends too early', ru='формула обрывается', uk='формула обривається'),
    'unbalanced_parentheses': Msg('unbalanced parentheses', ru='непарные скобки', uk='непарні дужки'),
}

CHECKS_FAILING = {"ru": "{n} {n:строка проверки не выполнена|строки проверки не выполнены|строк проверки не выполнено}",
                  "uk": "{n} {n:рядок перевірки не виконано|рядки перевірки не виконано|рядків перевірки не виконано}"}
TYPED = {"ru": "{n} {n:введена числом|введены числами|введены числами}",
         "uk": "{n} {n:введено числом|введено числами|введено числами}"}

# the grading vocabulary (sheetkin.course.grades: verdicts, counts, the score explained)
GRADING: dict[str, Msg] = {
    # a count: the noun agrees with its number (sheetkin.course.grades, report)
    'not_judged_check_by_hand': Msg('not judged, check by hand: {r} rows, {c} check rows',
                                    ru='не оценено, проверьте вручную: строк {r}, строк проверки {c}',
                                    uk='не оцінено, перевірте вручну: рядків {r}, рядків перевірки {c}',
                                    fields={'r': r'\d+', 'c': r'\d+'}),
    'a_of_n_rows': Msg('{a} of {n} rows', ru='{a} из {n} {n:строки|строк|строк}',
                       uk='{a} з {n} {n:рядка|рядків|рядків}', fields={'a': r'\d+', 'n': r'\d+'}),
    'a_of_n_check_rows': Msg('{a} of {n} check rows', ru='{a} из {n} {n:строки|строк|строк} проверки',
                             uk='{a} з {n} {n:рядка|рядків|рядків} перевірки', fields={'a': r'\d+', 'n': r'\d+'}),
    'n_check_rows_failing': Msg(
        '{n} check rows failing',
        ru=CHECKS_FAILING['ru'],
        uk=CHECKS_FAILING['uk'],
        fields={'n': r'\d+'}),
    'n_check_row_failing': Msg(
        '{n} check row failing',
        ru=CHECKS_FAILING['ru'],
        uk=CHECKS_FAILING['uk'],
        fields={'n': r'\d+'}),
    'n_typed_not_computed': Msg('{n} typed, not computed', ru=TYPED['ru'], uk=TYPED['uk'], fields={'n': r'\d+'}),
    'n_typed_paren_not_computed': Msg('{n} typed (not computed)', ru=TYPED['ru'], uk=TYPED['uk'], fields={'n': r'\d+'}),
    'n_missing_or_empty': Msg('{n} missing or empty',
                              ru='{n} {n:отсутствует или пуста|отсутствуют или пусты|отсутствуют или пусты}',
                              uk='{n} {n:відсутній або порожній|відсутні або порожні|відсутні або порожні}',
                              fields={'n': r'\d+'}),
    # words and phrases, said in this order
    'g_their_right_positions': Msg('their right positions', ru='их верные положения', uk='їхні правильні положення'),
    'g_formulas_reading_only_typed': Msg(
        'formulas reading only typed numbers, none of the given data',
        ru='формулы читают только введённые числа, а не исходные данные',
        uk='формули читають лише введені числа, а не вихідні дані'),
    'g_computed_right': Msg(' computed right', ru=' вычислены верно', uk=' обчислено правильно'),
    'g_intact_and_filled': Msg(' intact and filled in', ru=' на месте и заполнены', uk=' на місці й заповнені'),
    'g_correct_computed': Msg(' correct (computed)', ru=' верно (вычислены)', uk=' правильно (обчислені)'),
    'g_not_filled_rows_they': Msg(
        'not filled in (rows they check are empty)',
        ru='не заполнены (проверяемые строки пусты)',
        uk='не заповнені (рядки, які вони перевіряють, порожні)'),
    'g_no_formula_computed_rows': Msg(
        'no formula in the computed rows: at most',
        ru='нет формул в вычисляемых строках: не более',
        uk='немає формул в обчислюваних рядках: не більше'),
    'g_graded_against_issued_variant': Msg(
        'graded against the issued variant',
        ru='оценено по выданному варианту',
        uk='оцінено за виданим варіантом'),
    'g_no_computed_rows_grade': Msg(
        'no computed rows to grade',
        ru='нет вычисляемых строк для оценки',
        uk='немає обчислюваних рядків для оцінки'),
    'g_typed_paren_not_computed': Msg('typed (not computed)', ru='введены числами', uk='введені числами'),
    'g_typed_not_computed': Msg(
        'typed, not computed',
        ru='введены числами, не вычислены',
        uk='введені числами, не обчислені'),
    'g_missing_or_empty': Msg('missing or empty', ru='отсутствуют или пусты', uk='відсутні або порожні'),
    'g_that_apply_passing': Msg('that apply passing', ru='применимых выполнены', uk='застосовних виконано'),
    'g_status_typed_over': Msg('status typed over', ru='статус введён вручную', uk='статус введено вручну'),
    'g_given_data_changed': Msg('given data changed', ru='исходные данные изменены', uk='вихідні дані змінено'),
    'g_accepted_accept_typed': Msg(
        'accepted (--accept-typed)',
        ru='приняты (--accept-typed)',
        uk='прийнято (--accept-typed)'),
    'g_they_earn_nothing': Msg('they earn nothing', ru='баллов не приносят', uk='балів не приносять'),
    'g_check_rows': Msg('check rows', ru='строки проверки', uk='рядки перевірки'),
    'g_seal_broken': Msg('seal broken', ru='печать нарушена', uk='печатку порушено'),
    'g_all_correct': Msg('all correct', ru='всё верно', uk='усе правильно'),
    'g_mistakes': Msg('mistakes', ru='есть ошибки', uk='є помилки'),
    'g_unusable': Msg('unusable', ru='не проверяется', uk='не перевіряється'),
    'g_typed_over': Msg('typed over', ru='введены вручную', uk='введено вручну'),
    'g_failing': Msg('failing', ru='не выполнены', uk='не виконано'),
    'g_deleted': Msg('deleted', ru='удалены', uk='видалено'),
    'g_wrong': Msg('wrong', ru='неверно', uk='неправильно'),
    'g_rules': Msg('(the rules:', ru='(правила:', uk='(правила:'),
    'g_score': Msg('score', ru='оценка', uk='оцінка'),
    'g_of': Msg(' of ', ru=' из ', uk=' з '),
    'g_row': Msg('(row ', ru='(строка ', uk='(рядок '),
}

# the usage errors of `validate` and `variants` (argparse's, sheetkin.course.issued, classlist,
# variants, sheetkin.cli.commands), said before the validator's messages
ERRORS: dict[str, Msg] = {
    'following_arguments_are_required': Msg(
        'the following arguments are required: {what}',
        ru='не указаны обязательные аргументы: {what}',
        uk="не вказано обов'язкові аргументи: {what}",
        end=r'(?= \(see |$)'),
    'argument_invalid_choice_choose': Msg(
        'argument {opt}: invalid choice: {v} (choose from {list})',
        ru='аргумент {opt}: недопустимое значение {v} (допустимы: {list})',
        uk='аргумент {opt}: неприпустиме значення {v} (припустимі: {list})',
        fields={'opt': r'\S+', 'v': "'[^']*'", 'list': '[^)]*'}),
    'argument_expected_whole_number': Msg(
        'argument {opt}: expected a whole number, got {v}',
        ru='аргумент {opt}: ожидалось целое число, получено {v}',
        uk='аргумент {opt}: очікувалося ціле число, отримано {v}',
        fields={'opt': r'\S+', 'v': '\'[^\']*\'|\\"[^\\"]*\\"'}),
    'argument_expected_number_got': Msg(
        'argument {opt}: expected a number >= {n}, got {v}',
        ru='аргумент {opt}: ожидалось число не меньше {n}, получено {v}',
        uk='аргумент {opt}: очікувалося число не менше {n}, отримано {v}',
        fields={'opt': r'\S+', 'n': r'\d+', 'v': '\'[^\']*\'|\\"[^\\"]*\\"'}),
    'argument_expected_one': Msg(
        'argument {opt}: expected one argument',
        ru='аргумент {opt}: ожидалось одно значение',
        uk='аргумент {opt}: очікувалося одне значення',
        fields={'opt': r'\S+'}),
    'unrecognized_arguments': Msg(
        'unrecognized arguments: {what}',
        ru='неизвестные аргументы: {what}',
        uk='невідомі аргументи: {what}',
        end=r'(?= \(see |$)'),
    'see_help': Msg(
        "(see '{prog} --help')",
        ru="(см. '{prog} --help')",
        uk="(див. '{prog} --help')",
        fields={'prog': "[^']+"}, end='$'),
    'no_roster_file_moved': Msg(
        '{f}: no such roster file; `variants --class-list` keeps it in {moved}',
        ru='{f}: нет такого файла roster; `variants --class-list` хранит его в {moved}',
        uk='{f}: немає такого файлу roster; `variants --class-list` зберігає його в {moved}',
        fields={'moved': '.+'}, start='^', end='$'),
    'no_roster_file': Msg(
        '{f}: no such roster file',
        ru='{f}: нет такого файла roster (его пишет `sheetkin variants`)',
        uk='{f}: немає такого файлу roster (його пише `sheetkin variants`)',
        start='^', end='$'),
    'no_such_key_file': Msg(
        '{f}: no such key file (`sheetkin variants` writes .sheetkin-key in its --out folder)',
        ru='{f}: нет такого файла-ключа (`sheetkin variants` пишет .sheetkin-key в свою папку --out)',
        uk='{f}: немає такого файлу-ключа (`sheetkin variants` пише .sheetkin-key у свою теку --out)',
        start='^', end='$'),
    'no_such_csv': Msg(
        '{f}: {opt}: no such file',
        ru='{f}: {opt}: нет такого файла',
        uk='{f}: {opt}: немає такого файлу',
        fields={'opt': '--class-list|--worksheet'}, start='^', end='$'),
    'class_list_columns': Msg(
        "{f}:1: --class-list: expected columns 'First name' and 'Last name' (or 'Full name') and one of {ids}; got "
        '{got}',
        ru="{f}:1: --class-list: ожидались столбцы 'First name' и 'Last name' (или 'Full name') и один из {ids} (или "
           'их русские названия из Moodle); получено {got}',
        uk="{f}:1: --class-list: очікувалися стовпці 'First name' і 'Last name' (або 'Full name') та один із {ids} "
           '(або їхні російські назви з Moodle); отримано {got}',
        fields={'got': '.*'}, start='^', end='$'),
    'binary_not_csv': Msg(
        '{f}: {opt}: not UTF-8 text but a binary file (a workbook?); save it as CSV UTF-8',
        ru='{f}: {opt}: не текст UTF-8, а двоичный файл (книга?); сохраните его как CSV UTF-8',
        uk='{f}: {opt}: не текст UTF-8, а двійковий файл (книга?); збережіть його як CSV UTF-8',
        fields={'opt': '--class-list|--worksheet'}, start='^', end='$'),
    'not_utf8_csv': Msg(
        '{f}:{line}: {opt}: not UTF-8 (nor Windows-1251) text; ',
        ru='{f}:{line}: {opt}: не текст UTF-8 (и не Windows-1251); ',
        uk='{f}:{line}: {opt}: не текст UTF-8 (і не Windows-1251); ',
        fields={'f': '[^:]+', 'line': r'\d+', 'opt': '--class-list|--worksheet'}, start='^'),
    'class_list_empty': Msg(
        '{f}: --class-list: empty; expected a header and one line per student',
        ru='{f}: --class-list: файл пуст; ожидались заголовок и по строке на студента',
        uk='{f}: --class-list: файл порожній; очікувалися заголовок і по рядку на студента',
        start='^', end='$'),
    'class_list_line_without': Msg(
        '{f}:{line}: --class-list: a line without a name or a {id}',
        ru='{f}:{line}: --class-list: строка без имени или без {id}',
        uk='{f}:{line}: --class-list: рядок без імені або без {id}',
        fields={'f': '[^:]+', 'line': r'\d+', 'id': '.+'}, start='^', end='$'),
    'class_list_no_student': Msg(
        '{f}: --class-list names no student',
        ru='{f}: в --class-list нет ни одного студента',
        uk='{f}: у --class-list немає жодного студента',
        start='^', end='$'),
    'class_list_without_grades': Msg(
        "--class-list fills grades.csv's identifier column: give --grades GRADES.csv too",
        ru='--class-list заполняет столбец идентификатора grades.csv: укажите и --grades GRADES.csv',
        uk='--class-list заповнює стовпець ідентифікатора grades.csv: вкажіть і --grades GRADES.csv',
        start='^', end='$'),
    'out_of_expected': Msg(
        "--out-of {v}: expected the grade item's maximum, more than 0",
        ru='--out-of {v}: ожидался максимум элемента оценивания, больше 0',
        uk='--out-of {v}: очікувався максимум елемента оцінювання, більше 0',
        fields={'v': r'\S+'}, start='^', end='$'),
    'scale_expected': Msg(
        '--scale: {v}: expected NAME=LEAST SCORE (0..100), e.g. {e}',
        ru='--scale: {v}: ожидалось ИМЯ=НАИМЕНЬШИЙ БАЛЛ (0..100), например {e}',
        uk='--scale: {v}: очікувалося НАЗВА=НАЙМЕНШИЙ БАЛ (0..100), наприклад {e}',
        fields={'v': '\'.*?\'|\\".*?\\"', 'e': '.+'}, start='^', end='$'),
    'exists_refusing': Msg(
        '{f}: exists; refusing to overwrite it (use --force: an issued roster and key are then kept beside the new '
        'ones, dated; or another --out)',
        ru='{f}: уже есть; не перезаписываю (--force: выданные roster и ключ тогда сохраняются рядом с новыми, с '
           'датой; или другая папка --out)',
        uk='{f}: уже є; не перезаписую (--force: видані roster і ключ тоді зберігаються поруч із новими, з датою; '
           'або інша тека --out)',
        start='^', end='$'),
    'out_not_folder': Msg(
        '--out {f}: not a folder',
        ru='--out {f}: не папка',
        uk='--out {f}: не тека',
        start='^', end='$'),
    'vary_no_given_value': Msg(
        '--vary {v}: no given value {name} in this scene; valid: {list}',
        ru='--vary {v}: в этой схеме нет исходного значения {name}; допустимы: {list}',
        uk='--vary {v}: у цій схемі немає вихідного значення {name}; припустимі: {list}',
        fields={'v': r'\S+', 'name': "'[^']*'", 'list': '.+'}, start='^', end='$'),
}

# the warnings and closing lines of `validate` and `variants` (sheetkin.course.grades,
# class_grading, sheetkin.cli.commands)
WARNINGS: dict[str, Msg] = {
    'submission_graded': Msg(
        '{f}: {n} submission(s) graded',
        ru='{f}: оценено работ: {n}',
        uk='{f}: оцінено робіт: {n}',
        fields={'n': r'\d+'}, start='^', end='$'),
    'worksheet_graded': Msg(
        "{f}: Moodle's grading worksheet {w} with {n} submission(s) graded (upload it: Upload grading worksheet)",
        ru='{f}: ведомость оценок Moodle {w}, оценено работ: {n} (загрузите её: «Загрузить ведомость оценок»)',
        uk='{f}: відомість оцінок Moodle {w}, оцінено робіт: {n} (завантажте її: «Завантажити відомість оцінок»)',
        fields={'n': r'\d+'}, start='^', end='$'),
    'no_class_list_column': Msg(
        'no --class-list: the column {c} is empty; Moodle identifies a student by it, not by name (fill it in, or '
        "give Moodle's participants export as --class-list)",
        ru='нет --class-list: столбец {c} пуст; Moodle узнаёт студента по нему, а не по имени (заполните его или '
           'укажите экспорт участников Moodle как --class-list)',
        uk="немає --class-list: стовпець {c} порожній; Moodle впізнає студента за ним, а не за ім'ям (заповніть його "
           'або вкажіть експорт учасників Moodle як --class-list)',
        fields={'c': "'[^']*'"}),
    'unmatched_submissions': Msg(
        '{n} submission(s) not found (or found twice) in the class list, their {c} left empty: {list}',
        ru='работ не найдено (или найдено дважды) в списке группы: {n}, их {c} оставлен пустым: {list}',
        uk='робіт не знайдено (або знайдено двічі) у списку групи: {n}, їхній {c} залишено порожнім: {list}',
        fields={'n': r'\d+', 'c': "'[^']*'", 'list': '.+'}),
    'newer': Msg(' (newer: ', ru=' (новее: ', uk=' (новіший: '),
    'one_grade_per_student': Msg(
        'one grade per student: {n} older file(s) not graded: {list}',
        ru='одна оценка на студента: более старых файлов не оценено: {n}: {list}',
        uk='одна оцінка на студента: старіших файлів не оцінено: {n}: {list}',
        fields={'n': r'\d+', 'list': '.+'}),
    'books_not_own': Msg(
        '{n} book(s) not handed in by their own student: {list}',
        ru='книг, сданных не своим студентом: {n}: {list}',
        uk='книг, зданих не своїм студентом: {n}: {list}',
        fields={'n': r'\d+', 'list': '.+'}),
    'copies_held': Msg(
        '{n} possible cop(ies) held for review, their score left empty (--copies keep: their score; --copies zero: '
        '0): {list}',
        ru='возможных копий отложено для проверки: {n}, их балл оставлен пустым (--copies keep: их балл; --copies '
           'zero: 0): {list}',
        uk='можливих копій відкладено для перевірки: {n}, їхній бал залишено порожнім (--copies keep: їхній бал; '
           '--copies zero: 0): {list}',
        fields={'n': r'\d+', 'list': '.+'}),
    'students_absent': Msg(
        '{n} student(s) of the class list handed nothing in, their score left empty: {list}',
        ru='студентов списка группы, ничего не сдавших: {n}, их балл оставлен пустым: {list}',
        uk='студентів списку групи, що нічого не здали: {n}, їхній бал залишено порожнім: {list}',
        fields={'n': r'\d+', 'list': '.+'}),
    'worksheet_missing_participants': Msg(
        'the worksheet has no line for participant(s) {list}: their grade is not in it',
        ru='в ведомости нет строки для участников {list}: их оценки в ней нет',
        uk='у відомості немає рядка для учасників {list}: їхньої оцінки в ній немає'),
    'roster_contradicts_seals': Msg(
        "{f} contradicts {n} of the {m} sealed books (their seals check, the roster's given data differ): is it "
        "another class's roster, or re-written? Each sealed book is graded against its sealed data",
        ru='{f} противоречит {n} из {m} запечатанных книг (их печати верны, а исходные данные roster другие): это '
           'roster другой группы или переписанный? Каждая запечатанная книга оценена по своим данным',
        uk='{f} суперечить {n} із {m} запечатаних книг (їхні печатки правильні, а вихідні дані roster інші): це '
           'roster іншої групи чи переписаний? Кожну запечатану книгу оцінено за її даними',
        fields={'n': r'\d+', 'm': r'\d+'}, start='^', end='$'),
    'key_matches_no_seal': Msg(
        "none of the {n} issued books' seals matches the key: is the key (or --roster's folder) another class's?",
        ru='ни одна из {n} выданных книг не запечатана этим ключом: ключ (или папка --roster) от другой группы?',
        uk='жодну з {n} виданих книг не запечатано цим ключем: ключ (або тека --roster) від іншої групи?',
        fields={'n': r'\d+'}, start='^', end='$'),
    'roster_has_no_variant': Msg(
        "none of the {n} books' variants is in {f}: is it another class's roster?",
        ru='ни одного из вариантов {n} книг нет в {f}: это roster другой группы?',
        uk='жодного з варіантів {n} книг немає в {f}: це roster іншої групи?',
        fields={'n': r'\d+'}, start='^', end='$'),
    'variants_written': Msg(
        '{out}: {n} variants of {scene} (seed {seed}: --seed {seed} makes the same again){who}; {roster}; the key '
        '{key} stays with you',
        ru='{out}: вариантов схемы {scene}: {n} (seed {seed}: --seed {seed} даёт те же снова){who}; {roster}; ключ '
           '{key} остаётся у вас',
        uk='{out}: варіантів схеми {scene}: {n} (seed {seed}: --seed {seed} дає ті самі знову){who}; {roster}; ключ '
           '{key} залишається у вас',
        fields={'n': r'\d+', 'seed': r'\d+', 'who': '.*?', 'roster': '[^;]+', 'key': '.+'}, start='^', end='$'),
    'assigned_students': Msg(
        ', assigned to the {n} students of {f} ({a})',
        ru=', выданных {n} студентам из {f} ({a})',
        uk=', виданих {n} студентам із {f} ({a})',
        fields={'n': r'\d+', 'a': '[^()]+'}),
    'upload_moodle_one_book': Msg(
        'upload to Moodle {s} (one book per student, named by the student); {t} is yours (keys, roster, '
        'assignment.csv, the key): never upload it; grade with --roster {r}',
        ru='загрузите в Moodle {s} (по книге на студента, названной по студенту); {t} - ваша (ключи, roster, '
           'assignment.csv, ключ): никогда её не загружайте; оценивайте с --roster {r}',
        uk='завантажте в Moodle {s} (по книзі на студента, названій за студентом); {t} - ваша (ключі, roster, '
           'assignment.csv, ключ): ніколи її не завантажуйте; оцінюйте з --roster {r}',
        fields={'r': '.+'}, start='^', end='$'),
}

# a Picture's captions and notes (sheetkin.views.drawing, animate)
DRAWING: dict[str, Msg] = {
    'cannot_assemble': Msg(': cannot assemble', ru=': не собирается', uk=': не збирається'),
    'near_toggle': Msg(
        ': near a toggle (group {g})',
        ru=': близко к мёртвому положению (группа {g})',
        uk=': близько до мертвого положення (група {g})',
        fields={'g': '[^)]*'}),
    'group_cannot_assemble': Msg(
        'group {g} ({k}) cannot assemble for crank angles {a}..{b} deg',
        ru='группа {g} ({k}) не собирается при углах кривошипа {a}..{b} град',
        uk='група {g} ({k}) не збирається при кутах кривошипа {a}..{b} град',
        fields={'g': r'\S+', 'k': '[^)]*', 'a': r'\S+', 'b': r'\S+'}),
    'near_toggle_at': Msg(
        'group {g}: |det_g{h}| < {t} at crank angles near {a} deg',
        ru='группа {g}: |det_g{h}| < {t} при углах кривошипа около {a} град',
        uk='група {g}: |det_g{h}| < {t} при кутах кривошипа близько {a} град',
        fields={'g': r'\S+', 'h': r'\S+', 't': r'\S+'}),
    'velocity_scale': Msg(
        'velocity vectors: 1 m/s = {x} m of the drawing',
        ru='векторы скоростей: 1 м/с = {x} м рисунка',
        uk='вектори швидкостей: 1 м/с = {x} м рисунка',
        fields={'x': r'\S+'}),
    'drawn_narrower': Msg(
        'drawn {w} px wide, not {s}: at equal scale the mechanism would be more than {m} px tall',
        ru='нарисовано шириной {w} пикс., а не {s}: в равном масштабе механизм был бы выше {m} пикс.',
        uk='намальовано завширшки {w} пікс., а не {s}: у рівному масштабі механізм був би вищим за {m} пікс.',
        fields={'w': r'\d+', 's': r'\d+', 'm': r'\d+'}),
    'deg': Msg(' deg', ru=' град', uk=' град', end=r'(?=\W|$)'),
    'variant': Msg(' (variant {v})', ru=' (вариант {v})', uk=' (варіант {v})', fields={'v': r'[^()]+'}, end=r'$'),
}

# domain -> its sections, said in this order: (entries, whether they are fixed phrases said
# longest first and as whole phrases)
DOMAINS: dict[str, tuple[tuple[dict[str, Msg], bool], ...]] = {
    "report": ((REPORT, False), (REPORT_PHRASES, True)),
    "grading": ((GRADING, False),),
    "errors": ((ERRORS, False),),
    "warnings": ((WARNINGS, False),),
    "drawing": ((DRAWING, False),),
}
CATALOGUE: dict[str, Msg] = {key: entry for sections in DOMAINS.values() for section, _ in sections
                             for key, entry in section.items()}
