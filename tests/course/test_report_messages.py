"""Issue 22, item 6: the validator's own messages (given data changed, a broken seal, the
reasons a file is unusable, typed numbers, the notes, identities, copies) and grades.csv's
headers in the teacher's language: a class with every kind of message, validated with
--lang ru, uk and en through the command line."""
from __future__ import annotations

import contextlib
import csv
import html
import io
import os
import re
import shutil
from pathlib import Path

import pytest
from helpers.classbooks import fill, row_values, set_input, type_numbers

from sheetkin.course.grades import COLUMNS, grade_lines
from sheetkin.course.report_texts import COLUMN_NAMES
from sheetkin.messages import REPORT, REPORT_PHRASES, say

ROOT = Path(__file__).resolve().parents[2]
TEACHER = Path("issued") / "teacher"     # issue 34: the teacher's folder of `variants --class-list`
CLASS = ("Фамилия;Имя;Индивидуальный номер;Адрес электронной почты\n"
         "Иванов;Иван;1001;ivanov@example.org\nПетрова;Анна;1002;petrova@example.org\n"
         "Сидоров;Пётр;1003;sidorov@example.org\nОрлов;Денис;1004;orlov@example.org\n")
# names of things, not words of a language: programs, formats, commands, cell references
NAMES = {"xlsx", "xls", "xlsb", "ods", "zip", "xml", "html", "ole", "excel", "libreoffice", "opendocument",
         "moodle", "sheetkin", "scene", "workbook", "variants", "class", "list"}


def _english(text: str) -> set[str]:
    return {w.lower() for w in re.findall(r"[A-Za-z]+(?:'[a-z]+)?", text)}


def _table_words() -> set[str]:
    """The English words of the validator's messages (3 letters or more, the fields left out)."""
    texts = [re.sub(r"\{\w+\}", " ", m.en) for m in (*REPORT.values(), *REPORT_PHRASES.values())]
    texts += list(COLUMNS)
    return {w for t in texts for w in _english(t) if len(w) >= 3} - NAMES


def _moodle_folder(sub: Path, name: str, n: int) -> Path:
    folder = sub / f"{name}_{n}_assignsubmission_file_"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _break_seal(ws, rows):
    sc = ws.parent["scene"]
    for r in range(1, sc.max_row + 1):
        if str(sc.cell(r, 1).value or "").startswith("length = "):
            sc.cell(r, 1).value = "length = 0.05"
            return


def _checks_spoiled(ws, rows):
    chk = [n for n in rows if str(n).startswith("chk_")]
    ws.cell(rows[chk[0]], 4).value = 0                      # a status typed over its formula
    for c in range(1, 20):
        ws.cell(rows[chk[1]], c).value = None               # a check row deleted
    ws["Z200"] = "проверил"                                 # a cell outside the issued table


@pytest.fixture(scope="module")
def klass(tmp_path_factory):
    """Moodle's folders: a typed row (Ivanov), changed given data (Petrova), an edited scene
    sheet (Sidorov), check rows deleted and typed over (Orlov), Ivanov's book byte for byte
    in Orlov's folder (a copy, issued to another, handed in by another, not graded), a text
    file and an empty file named .xlsx (unusable)."""
    d = tmp_path_factory.mktemp("messages")
    (d / "class.csv").write_text(CLASS, encoding="utf-8")
    iss = d / "issued"
    assert run_main("variants", ROOT / "workbooks" / "fourbar.toml", "--out", iss, "--class-list",
                    d / "class.csv", "--seed", "4") == 0

    def ex(v, who):
        return iss / "students" / f"fourbar-0{v}-{who}-exercise.xlsx"

    def key(v):
        return iss / "teacher" / f"fourbar-0{v}-key.xlsx"
    sub = d / "submissions"
    iv = fill(ex(1, "Иванов_Иван"), key(1), _moodle_folder(sub, "Иван Иванов", 1) / "ivanov.xlsx",
              student="Иванов Иван", group="ГИ-21", change=type_numbers("omega_2", row_values(key(1), "omega_2"), 3))
    fill(ex(2, "Петрова_Анна"), key(2), _moodle_folder(sub, "Анна Петрова", 2) / "petrova.xlsx",
         student="Петрова Анна", group="ГИ-21", change=set_input("L1", 0.05))
    fill(ex(3, "Сидоров_Пётр"), key(3), _moodle_folder(sub, "Пётр Сидоров", 3) / "sidorov.xlsx",
         student="Сидоров Пётр", group="ГИ-21", change=_break_seal)
    orlov = _moodle_folder(sub, "Денис Орлов", 4)
    own = fill(ex(4, "Орлов_Денис"), key(4), orlov / "orlov.xlsx", student="Орлов Денис", group="ГИ-21",
               change=_checks_spoiled)
    os.utime(own, (1e9, 1e9))
    shutil.copy(iv, orlov / "orlov-final.xlsx")
    bad = _moodle_folder(sub, "Participant", 9)
    (bad / "broken.xlsx").write_text("this is not a workbook\n")
    (bad / "empty.xlsx").write_bytes(b"")
    typed = fill(iss / "teacher" / "fourbar-02-exercise.xlsx", key(2), bad / "typed.xlsx", student="Кузнецов Олег",
                 change=_all_typed(key(2)))
    os.utime(typed, (2e9, 2e9))                 # the newest of the folder, and usable: graded
    return d


def _all_typed(key: Path):
    """Every computed cell's formula replaced by the number it gives: a book with no formula
    ("typed, not computed")."""
    from sheetkin.xlsx.evaluator import evaluate
    book = evaluate(key)
    sheet = book.order[0]

    def change(ws, rows):
        for name, r in rows.items():
            for c in range(4, 18):
                v = ws.cell(r, c).value
                if isinstance(v, str) and v.startswith("=") and not str(name).startswith("chk_"):
                    got = book.value(sheet, r, c)
                    ws.cell(r, c).value = got if isinstance(got, float) else None
    return change


def run_main(*argv) -> int:
    from sheetkin.cli.commands import main
    return main([str(a) for a in argv])


@pytest.fixture(scope="module")
def said(klass):
    """{lang: (text on stdout, the HTML page's visible text, grades.csv's rows)}."""
    out = {}
    for lang in ("ru", "uk", "en"):
        page, grades = klass / f"r-{lang}.html", klass / f"g-{lang}.csv"
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            code = run_main("validate", klass / "submissions", "--roster", klass / TEACHER / "roster.csv",
                            "--key", klass / TEACHER / ".sheetkin-key", "--class-list", klass / "class.csv",
                            "--grades", grades, "--html", page, "--lang", lang, "--progress", "never", "--jobs", "1")
        assert code == 2                                   # unusable files among them
        text = page.read_text(encoding="utf-8")
        visible = html.unescape(re.sub(r"<script>.*?</script>|<style>.*?</style>|<[^>]+>", " ", text, flags=re.S))
        rows = list(csv.reader(io.StringIO(grades.read_bytes().decode("utf-8-sig"), newline="")))
        out[lang] = (buf.getvalue(), visible, rows)
    return out


def _free_of_names(text: str) -> str:
    """The text without file paths, e-mails, row names and commands (what stays as it is)."""
    text = re.sub(r"\S*(?:/|\.xlsx|@)\S*", " ", text)
    text = re.sub(r"(?<!\w)'[^'\n]*'(?!\w)", " ", text)    # quoted names (a Moodle folder, a typed name)
    text = re.sub(r"`[^`]*`|--[\w-]+|\w*_\w*|\b[A-Z]{1,3}\d+\b|scene!C2", " ", text)
    return text.replace("Email address", " ")               # Moodle's own column name (kept)


@pytest.mark.parametrize("lang", ["ru", "uk"])
def test_every_kind_of_message_in_the_teachers_language(said, lang):
    text, visible, rows = said[lang]
    csv_text = "\n".join(",".join(r) for r in rows)
    english = _table_words()
    for where, what in (("text", text), ("html", visible), ("grades.csv", csv_text)):
        left = _english(_free_of_names(what)) & english
        assert not left, (where, sorted(left))
    expect = {
        "ru": ["введены числами, не вычислены", "не оценена: ",
               "исходные данные изменены: L1", "лист сцены изменён", "не файл .xlsx", "пустой файл (0 байт)",
               "введено 3.", "возможно, списано", "файлы совпадают побайтно", "Кто сдал: найдена в папке",
               "выдана Иванов Иван", "строки проверки удалены", "статус проверки введён поверх",
               "ячеек вне выданной таблицы"],
        "uk": ["введені числами, не обчислені", "не оцінено: ",
               "вихідні дані змінено: L1", "аркуш сцени змінено", "не файл .xlsx", "порожній файл (0 байтів)",
               "введено 3.", "можливо, списано", "файли збігаються побайтово", "Хто здав: знайдено в теці",
               "видано Иванов Иван", "рядки перевірки видалено",
               "статус перевірки введено поверх", "клітинок поза виданою таблицею"],
    }[lang]
    everything = text + visible + csv_text
    assert [e for e in expect if e not in everything] == []


def test_grades_headers_by_language_the_identifier_as_moodle_names_it(said):
    heads = {lang: said[lang][2][0] for lang in said}
    assert heads["en"] == ["Email address", "Identifier", *COLUMNS]
    for lang in ("ru", "uk"):
        assert heads[lang][:2] == ["Email address", "Identifier"]     # Moodle's import matches them by name
        assert heads[lang][2:] == [COLUMN_NAMES[lang][c] for c in COLUMNS]
        assert not _english(" ".join(heads[lang][2:]))
    # the numbers stay numbers in every language: the score column is the same
    score = {lang: [r[COLUMNS.index("score") + 2] for r in said[lang][2][1:]] for lang in said}
    assert score["ru"] == score["uk"] == score["en"] and "0.0" in score["en"]
    changed = {lang: [r[COLUMNS.index("given data changed") + 2] for r in said[lang][2][1:]] for lang in said}
    assert sorted(set(changed["ru"])) == ["да", "нет"] and sorted(set(changed["uk"])) == ["ні", "так"]
    assert sorted(set(changed["en"])) == ["no", "yes"]


def test_english_stays_english(said):
    text, visible, rows = said["en"]
    assert "given data changed: L1" in text and "scene sheet edited" in text
    assert "found in the folder of" in visible and "byte-identical files" in visible
    assert not re.search("[А-Яа-яЁё]", _free_of_names(text).replace("ГИ-21", "").split("\n")[0])
    # the scan of the other languages would see these words
    assert len(_english(_free_of_names(text + visible)) & _table_words()) > 20


def test_the_column_names_have_every_language():
    for lang in ("ru", "uk"):            # the messages' languages: tests/test_messages.py
        assert set(COLUMNS) <= COLUMN_NAMES[lang].keys()


@pytest.mark.parametrize("message, ru", [
    ("a.xlsx: password-protected (an encrypted Excel workbook); a workbook saved without a password (File > Save "
     "As, untick the password)", "a.xlsx: защищена паролем (зашифрованная книга Excel); нужна книга, сохранённая "
     "без пароля (Файл > Сохранить как, снять пароль)"),
    ("failed.xlsx: LibreOffice's conversion to .xlsx failed", "failed.xlsx: преобразование LibreOffice в .xlsx "
     "не удалось"),
    ("big.xlsx: file is more than 50 MB; expected at most 50 MB (sheetkin's limit for a workbook)",
     "big.xlsx: файл больше 50 MB; ожидалось не более 50 MB (предел sheetkin для книги)"),
    ("a.xlsx: some reason no table knows", "a.xlsx: some reason no table knows"),
])
def test_say_values_and_file_names(message, ru):
    assert say(message, "ru") == ru
    assert say(message, "en") == message


def test_grade_lines_default_is_english():
    """The Python API speaks English unless told, as it did."""
    lines, _ = grade_lines([], None)
    assert lines == [["Email address", "Identifier", *COLUMNS]]


def test_json_notes_in_the_teachers_language(klass):
    """--json keeps its keys and verdicts for programs; its notes (identity, check rows
    deleted, cells outside the table) and copies' reasons follow --lang."""
    import json
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        run_main("validate", klass / "submissions", "--roster", klass / TEACHER / "roster.csv", "--class-list",
                 klass / "class.csv", "--grades", klass / "g-json.csv", "--json", "--lang", "uk", "--progress",
                 "never", "--jobs", "1")
    books = json.loads(buf.getvalue())["reports"]
    notes = [n for b in books for n in b.get("notes", [])]
    assert any(n.startswith("хто здав: ") for n in notes) and any("рядки перевірки видалено" in n for n in notes)
    assert not any(n.startswith("identity: ") for n in notes)
    assert {b["verdict"] for b in books} >= {"unusable", "given data changed", "mistakes"}   # for programs
    whys = [c["why"] for b in books for c in b["possible_copy_of"]]
    assert whys and all("файли збігаються побайтово" in w for w in whys)


# the reasons of unusable files a class brings (each made where it arises: sheetkin.xlsx, the
# validator), said whole in Russian and Ukrainian
REASONS = [
    "a.xlsx: not an .xlsx file (an OpenDocument spreadsheet, .ods); expected .xlsx: in LibreOffice, File > Save "
    "As > Excel 2007-365 (.xlsx)",
    "a.xlsx: file is more than 50 MB; expected at most 50 MB (sheetkin's limit for a workbook)",
    "a.xlsx: no embedded scene (hidden sheet 'scene'); expected a workbook made by `sheetkin workbook`",
    "a.xlsx: corrupt or truncated zip archive (its end is missing); expected a complete .xlsx file: save or copy "
    "it again",
    "a.xlsx: contains macros (xl/vbaProject.bin); expected an .xlsx workbook",
    "a.ods: LibreOffice's conversion to .xlsx timed out",
    "a.xls: password-protected (an encrypted .xls workbook); a workbook saved without a password (File > Save As, "
    "untick the password)",
    "a.xlsx: not an .xlsx file (an old binary Excel .xls file, or another OLE compound file); expected .xlsx: save "
    "it as Excel Workbook (.xlsx) without a password",
    "a.xlsx: internal error while validating (KeyError: 'x'); this is a bug in sheetkin 0.16: please report it with "
    "this file",
    "a.xlsx: scene sheet edited: its seal (scene!C2) is missing; and it no longer reads: a.xlsx (embedded scene)",
]


@pytest.mark.parametrize("reason", REASONS)
@pytest.mark.parametrize("lang", ["ru", "uk"])
def test_unusable_reasons_said_whole(reason, lang):
    said = say(reason, lang)
    left = _english(_free_of_names(said)) & _table_words()
    assert not left, (said, sorted(left))
    assert said != reason and said.split(":")[0] == reason.split(":")[0]       # the file's name as it is


def _evaluator_problems(tmp_path: Path) -> list[str]:
    """The notes the evaluator gives of cells it cannot compute (what the report shows the
    teacher under "cannot evaluate"), from a workbook that has each kind."""
    import openpyxl
    from openpyxl.workbook.defined_name import DefinedName

    from sheetkin.xlsx.evaluator import evaluate
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Кинематика"
    ws["A1"], ws["A2"], ws["A3"], ws["A4"] = "=NOSUCHFUNCTION(1)", "=SUM(1,2", "=1+*2", "=arr"
    ws["A5"], ws["B1"], ws["B2"] = "=NOSUCH(1)+OTHERFN(2)", "=B2+1", "=B1+1"
    wb.defined_names["arr"] = DefinedName("arr", attr_text="1+*2")     # {1,2,3} reads since array constants
    wb.save(tmp_path / "p.xlsx")
    problems = evaluate(tmp_path / "p.xlsx", strict=False).problems
    for what in ("unsupported function NOSUCHFUNCTION", "cannot read the formula", "is not a formula",
                 "circular reference among", "unsupported functions"):
        assert any(what in p for p in problems), (what, problems)
    return problems


@pytest.mark.parametrize("lang", ["ru", "uk"])
def test_evaluator_notes_said_whole(tmp_path, lang):
    """"unsupported function COLUMN", "cannot read the formula =...: unexpected '{'", "the
    name X is not a formula", "circular reference among ...": English in a Russian report."""
    for p in _evaluator_problems(tmp_path):
        said = say(p, lang)
        left = _english(_free_of_names(re.sub(r"=\S+|[A-Z]{4,}", " ", said))) & _table_words()
        assert not left, (said, sorted(left))
        assert said != p and said.split("!")[0] == p.split("!")[0]       # the cells as they are
