"""Issue 30, the fourth round of hostile input: what students type reaches the teacher
harmless, and one student never blocks the class. Each test makes the attacker's file."""
from __future__ import annotations

import csv
import io
import json
import os
import re
import unicodedata
from pathlib import Path

import pytest
from helpers.classbooks import fill, issue_variants

from sheetkin.cli.commands import main
from sheetkin.course.classlist import moodle_submitter, read_class_list
from sheetkin.course.copies import Copies
from sheetkin.course.grades import grade_lines, grades_csv
from sheetkin.course.identity import assignment_text, identify, read_assignment, same_name_loosely
from sheetkin.course.issued import parse_roster, roster_text
from sheetkin.course.report_model import Report, RowReport
from sheetkin.untrusted import compare_key, csv_cell, from_csv_cell, plain_text, shown_text

FORMULA = ("=", "+", "-", "@", "\t", "\r")
# what must never reach a terminal, a report or a CSV cell raw
RAW = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u061c\u200b-\u200f\u202a-\u202e\u2060-\u2069\ufeff\u2028\u2029]")
FORGED = "\x1b[2K\r\x1b[1Aall correct; score 100.0\n\u202eevil\u2066\x9b2J"


def _rep(path, student="", variant="", error=None):
    rep = Report(path, rows=[RowReport("ok", 10, "correct")], positions=13, student=student, variant=variant,
                 error=error)
    rep.checks_total, rep.marks = 10, {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}, "values": {}}
    return rep


def _csv(data: bytes) -> list[list[str]]:
    return list(csv.reader(io.StringIO(data.decode("utf-8-sig"), newline="")))


# --------------------------------------------------------------------------- 1. neutralized text
@pytest.mark.parametrize("text", ["=cmd|'/Ccalc'!A0@x.ru", "+7-1", "-1", "@Петров", "\t=1", "\r=1",
                                  "  =HYPERLINK(\"http://x\")", "=1+1"])
def test_csv_cell_keeps_a_formula_as_text(text):
    cell = csv_cell(text)
    assert cell.startswith("'") and not RAW.search(cell)
    assert from_csv_cell(cell) == shown_text(text)      # read back as typed (controls as escapes)


@pytest.mark.parametrize("text", ["Иванов Иван", "a=b", "v07", "", "1.5", "ivanov@example.org"])
def test_csv_cell_leaves_plain_text(text):
    assert csv_cell(text) == text and from_csv_cell(text) == text


def test_shown_text_escapes_every_hidden_character():
    shown = shown_text(FORGED)
    assert not RAW.search(shown) and "\n" not in shown
    assert "\\x1b" in shown and "\\u202e" in shown and "\\x9b" in shown and "\\r" in shown
    # the escape is the mark: the raw text can be read back from it
    assert shown.isascii() and shown.encode().decode("unicode_escape") == FORGED


def test_look_alike_names_compare_equal():
    plain = "Иванов Иван"
    for look_alike in ("Ива\u200bнов Иван", "\u202dИванов\u202c Иван", "Иванов\u00a0Иван", "ИВАНОВ  иван",
                       "Ива\ufeffнов\u2060 Иван"):
        assert compare_key(look_alike) == compare_key(plain), look_alike
        assert compare_key(shown_text(look_alike)) == compare_key(plain)     # also as reports show it
    assert compare_key("Ｉｖａｎｏｖ") == compare_key("ivanov")                   # NFKC
    assert plain_text("a\u0301") == unicodedata.normalize("NFKC", "a\u0301")


def test_class_list_email_is_neutralized_in_grades_csv(tmp_path):
    """A student's e-mail in the class list (editable in a Moodle profile) was written raw
    into grades.csv's identifier column."""
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,=cmd|'/Ccalc'!A0@x.ru\n"
                  "Анна,Петрова,+7-1@x.ru\n", encoding="utf-8")
    class_list = read_class_list(str(cl))
    reps = [_rep("a.xlsx", "Иванов Иван"), _rep("b.xlsx", "Петрова Анна")]
    lines, _ = grade_lines(reps, Copies(), class_list, identities=identify(reps, class_list, mtimes=[0, 0]))
    rows = _csv(grades_csv(lines))
    assert [r[0] for r in rows[1:]] == ["'=cmd|'/Ccalc'!A0@x.ru", "'+7-1@x.ru"]
    for row in rows:
        for cell in row:
            assert not cell.startswith(FORMULA) and not RAW.search(cell), cell


def test_assignment_csv_cells_neutralized_and_read_back(tmp_path):
    """`variants --class-list` wrote every cell of assignment.csv raw."""
    rows = [("=HYPERLINK(\"http://x\",\"Иванов\")", "=cmd|'/Ccalc'!A0@x.ru", "v1", "v1-x-exercise.xlsx"),
            ("@Петров", "+7-1", "v2", "v2-Петров-exercise.xlsx"),
            ("Сидоров\u202eвор", "-1", "v3", "v3-exercise.xlsx")]
    text = assignment_text("Email address", rows)
    for row in csv.reader(io.StringIO(text)):
        for cell in row:
            assert not cell.startswith(FORMULA) and not RAW.search(cell), cell
    path = tmp_path / "assignment.csv"
    path.write_text(text, encoding="utf-8")
    got = read_assignment(path)
    assert got.people["=cmd|'/Ccalc'!A0@x.ru"][0] == "=HYPERLINK(\"http://x\",\"Иванов\")"
    assert got.people["+7-1"] == ("@Петров", "v2", "v2-Петров-exercise.xlsx")
    assert got.people["-1"][0] == "Сидоров\\u202eвор"          # marked, never raw


def test_roster_text_cells_neutralized_numbers_kept():
    text = roster_text(["L1"], [("=v1", {"exercise": "=v1-exercise.xlsx", "key": "k.xlsx", "scene": "@v1.toml"},
                                 {"L1": -0.5})])
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[1][0] == "'=v1" and rows[1][3] == "'@v1.toml" and rows[1][-1] == "-0.5"
    roster = parse_roster(text)
    assert "=v1" in roster.rows and roster.files["=v1"]["scene"] == "@v1.toml"


# --------------------------------------------------------------------------- 2. identity
def test_participant_id_from_the_folder_names_last_fields():
    """A full name embedding 'Петров_102_assignsubmission_file_' gave the attacker's book
    Петров's participant number."""
    folder = "Петров_102_assignsubmission_file_x_5501_assignsubmission_file_"
    sub = moodle_submitter(f"{folder}/lab.xlsx")
    assert sub is not None and sub.participant == "5501"
    assert moodle_submitter("Иван Иванов_12_assignsubmission_file_/a.xlsx").participant == "12"
    # flat: the name Moodle writes has no underscore, so its first `_id_assign..._` is Moodle's;
    # an original name copying a classmate's prefix does not change whose file it is
    assert moodle_submitter("Иван Иванов_12_assignsubmission_file_lab.xlsx").participant == "12"
    assert moodle_submitter("Иван Иванов_12_assignsubmission_file_Петров_102_assignsubmission_file_.xlsx"
                            ).participant == "12"
    # a student's own sub-folder named after a classmate's does not count: the outermost does
    inner = moodle_submitter("Иван Иванов_12_assignsubmission_file_/Петров_102_assignsubmission_file_/a.xlsx")
    assert inner.participant == "12"


def test_attackers_book_does_not_take_over_petrovs_grade(tmp_path):
    """One grade per student dropped Петров's real book as 'not graded'."""
    petrov = _rep("class.zip/Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Петров Пётр")
    evil = _rep("class.zip/Петров_102_assignsubmission_file_x_5501_assignsubmission_file_/lab.xlsx", "Петров Пётр")
    ids = identify([petrov, evil], None, mtimes=[1, 2])
    assert ids[0].superseded_by is None and ids[1].superseded_by is None
    assert ids[0].who != ids[1].who


def test_a_typed_name_in_a_blind_book_never_takes_over_a_grade(tmp_path):
    """Blind marking grades a book under the name typed in it; that name must not drop the
    named student's own book (a newer upload used to supersede it) nor give one student two
    lines. Two participants typing one name: neither is graded under it."""
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nПётр,Петров,petrov@x.ru\nИван,Иванов,ivanov@x.ru\n",
                  encoding="utf-8")
    class_list = read_class_list(str(cl))
    reps = [_rep("Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Петров Пётр"),
            _rep("Participant_104_assignsubmission_file_/lab.xlsx", "Петров П."),
            _rep("Participant_105_assignsubmission_file_/lab.xlsx", "Иванов Иван"),
            _rep("Participant_106_assignsubmission_file_/lab.xlsx", "Иванов Иван"),
            _rep("Participant_107_assignsubmission_file_/a.xlsx", "Иванов Иван")]
    ids = identify(reps, class_list, mtimes=[1, 2, 1, 1, 2])
    assert [m.superseded_by for m in ids] == [None] * 5
    assert [m.ident for m in ids] == ["petrov@x.ru", "", "", "", ""]
    assert "claimed by Participant 104" in ids[1].unmatched
    lines, warnings = grade_lines(reps, Copies(), class_list, identities=ids)
    emails = [line[0] for line in lines[1:] if line[0]]
    assert sorted(emails) == ["ivanov@x.ru", "petrov@x.ru"] and len(emails) == len(set(emails))
    status = {line[0]: line[-1] for line in lines[1:] if line[0]}
    assert status["ivanov@x.ru"] == "not handed in" and status["petrov@x.ru"] == "graded"
    assert "4 submission(s) not found" in " ".join(warnings)
    # one participant's two books: still one grade (the newest)
    again = identify([reps[4], _rep("Participant_107_assignsubmission_file_/b.xlsx", "Иванов Иван")], class_list,
                     mtimes=[1, 2])
    assert again[0].superseded_by == 1 and again[1].ident == "ivanov@x.ru"


def test_name_typed_in_another_students_folder_flagged_without_class_list():
    reps = [_rep("Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Иванов Иван"),
            _rep("Ivan Ivanov_103_assignsubmission_file_/lab.xlsx", "Иванов И.И."),       # transliterated: fine
            _rep("Participant_104_assignsubmission_file_/lab.xlsx", "Сидоров")]         # blind marking: cannot tell
    ids = identify(reps, None, mtimes=[0, 0, 0])
    assert any(f.startswith("found in the folder of Пётр Петров") and "Иванов Иван" in f for f in ids[0].flags)
    assert not ids[1].flags and not ids[2].flags
    lines, warnings = grade_lines(reps, Copies(), None, identities=ids)
    assert "1 book(s) not handed in by their own student" in " ".join(warnings)


def test_same_name_loosely():
    assert same_name_loosely("Щукин А.", "Schukin Alexey") and same_name_loosely("Петров", "Пётр Петров")
    assert not same_name_loosely("Иванов Иван", "Пётр Петров")
    assert same_name_loosely("Ива\u200bнов", "Иван Иванов")


def test_zero_width_and_override_names_match_the_class_list(tmp_path):
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,ivanov@x.ru\nПётр,Петров,petrov@x.ru\n",
                  encoding="utf-8")
    class_list = read_class_list(str(cl))
    for typed in ("Ива\u200bнов Иван", "\u202eИванов Иван", "Иванов\u3000Иван", shown_text("Ива\u200bнов Иван")):
        assert class_list.ident_of(typed) == "ivanov@x.ru", typed
    # "found in the folder of": the zero-width space no longer hides the classmate's name
    reps = [_rep("Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Ива\u200bнов Иван")]
    ids = identify(reps, class_list, mtimes=[0])
    assert ids[0].flags and ids[0].flags[0].startswith("found in the folder of Петров Пётр")


def _letters(k: int) -> str:
    """A distinct Cyrillic word for each k (names hold letters only: digits are not part of one)."""
    abc = "абвгдежзиклмнопрстуфхцчшщэюя"
    out = ""
    while True:
        k, r = divmod(k, len(abc))
        out += abc[r]
        if not k:
            return out


def test_name_matching_is_precomputed_once_per_class_list(tmp_path):
    """800 books against a 100,000-line class list took 94 s (every name compared with
    every line); the list is indexed once."""
    import time
    cl = tmp_path / "class.csv"
    lines = ["First name,Last name,Email address"]
    lines += [f"Ив{_letters(k)},Петр{_letters(k)},s{k}@x.ru" for k in range(100_000)]
    cl.write_text("\n".join(lines) + "\n", encoding="utf-8")
    class_list = read_class_list(str(cl))
    start = time.perf_counter()
    assert class_list.ident_of("Петра Ива") == "s0@x.ru"      # the first match indexes the list
    indexed = time.perf_counter() - start
    start = time.perf_counter()
    got = [class_list.ident_of(f"Петр{_letters(k * 97)} Ив{_letters(k * 97)}") for k in range(800)]
    got += [class_list.ident_of(f"Петр{_letters(k * 89)} И.") for k in range(800)]
    took = time.perf_counter() - start
    assert got[:800] == [f"s{k * 97}@x.ru" for k in range(800)]
    assert got[800:] == [f"s{k * 89}@x.ru" for k in range(800)]
    # each match a few lookups (comparing with every line: 1,600 x 100,000 name keys, hours);
    # generous bounds for a busy 2-core VM (4 s and 1 s measured there)
    assert took < 5 and indexed < 30, (took, indexed)


# --------------------------------------------------------------------------- 1. the terminal
def _with_text(book: Path, placeholder: str, text: str) -> Path:
    """The book with `text` where `placeholder` was, written as Excel escapes a control
    character in its XML (_x001B_): what openpyxl refuses to write, an attacker writes."""
    import zipfile
    xml = "".join(f"_x{ord(c):04X}_" if ord(c) < 0x20 or 0x7f <= ord(c) <= 0x9f else c for c in text)
    tmp = book.with_suffix(".tmp")
    with zipfile.ZipFile(book) as src, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename.endswith(".xml"):
                data = data.replace(placeholder.encode(), xml.encode())
            dst.writestr(info, data)
    tmp.replace(book)
    return book


@pytest.fixture(scope="module")
def books(tmp_path_factory):
    return issue_variants(tmp_path_factory.mktemp("issued"))


def test_forged_line_never_reaches_the_terminal(tmp_path, books, capsys):
    """ESC, CR/LF, C1 CSI and a bidi override typed in D1 and put in a zip entry's name
    reached the terminal raw: a forged 'all correct; score 100.0' line was printed."""
    import zipfile
    ex, key = books["v1"]
    book = _with_text(fill(ex, key, tmp_path / "b.xlsx", student="ZZFORGEDZZ"), "ZZFORGEDZZ", FORGED)
    z = tmp_path / "class.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.write(book, f"Иван Иванов_12_assignsubmission_file_/\x1b[2Kok\r\u202e{'x' * 3}.xlsx")
        zf.write(book, "Пётр Петров_13_assignsubmission_file_/lab.xlsx")
    html, grades = tmp_path / "r.html", tmp_path / "g.csv"
    code = main(["validate", str(z), "--html", str(html), "--grades", str(grades), "--jobs", "1"])
    out = capsys.readouterr()
    assert code in (0, 1, 2)
    for text in (out.out, out.err, html.read_text(encoding="utf-8"), grades.read_text(encoding="utf-8-sig")):
        assert not RAW.search(text.replace("\r\n", "").replace("\n", "")), RAW.search(text.replace("\n", ""))
    assert "\\x1b" in out.out                                       # shown, marked
    for line in out.out.splitlines():
        assert not line.startswith("all correct")
    main(["validate", str(z), "--json", "--jobs", "1"])
    data = capsys.readouterr().out
    assert not RAW.search(json.loads(data)[0]["student"] if isinstance(json.loads(data), list) else data)


# --------------------------------------------------------------------------- 3. inputs are never outputs
def _roster(folder: Path) -> Path:
    """A roster naming a scene file beside it, and the assignment beside it."""
    (folder / "v1.toml").write_text("scene", encoding="utf-8")
    roster = folder / "roster.csv"
    roster.write_text(roster_text(["L1"], [("v1", {"exercise": "v1-exercise.xlsx", "key": "v1-key.xlsx",
                                                   "scene": "v1.toml"}, {"L1": 0.1})]), encoding="utf-8")
    (folder / "assignment.csv").write_text(assignment_text("Email address", [("Иванов Иван", "i@x.ru", "v1",
                                                                               "v1-exercise.xlsx")]),
                                           encoding="utf-8")
    return roster


@pytest.mark.parametrize("target, option", [("class/moodle.zip", "--grades"), ("issued/assignment.csv", "--grades"),
                                            ("issued/v1.toml", "--html"), ("issued/.sheetkin-key-20261101", "--html")])
def test_files_read_are_refused_as_outputs(tmp_path, capsys, target, option):
    """--grades onto the class's assignment.csv, --html onto a roster's scene file and
    --grades onto a zip in the input folder overwrote each."""
    (tmp_path / "class").mkdir()
    (tmp_path / "issued").mkdir()
    roster = _roster(tmp_path / "issued")
    (tmp_path / "issued" / ".sheetkin-key").write_text("00" * 32 + "\n")
    (tmp_path / "issued" / ".sheetkin-key-20261101").write_text("11" * 32 + "\n")
    (tmp_path / "class" / "a.xlsx").write_bytes(b"not a book")
    (tmp_path / "class" / "moodle.zip").write_bytes(b"PK\x05\x06" + b"\0" * 18)
    out = tmp_path / target
    before = out.read_bytes()
    code = main(["validate", str(tmp_path / "class"), "--roster", str(roster), option, str(out)])
    err = capsys.readouterr().err
    assert code == 2 and out.read_bytes() == before
    assert "refusing to overwrite it" in err and len(err.strip().splitlines()) == 1


# --------------------------------------------------------------------------- 4. one submission never blocks the class
def _patch_central(zpath: Path, entry: str, field: str, value: int) -> None:
    """Rewrite one field of an entry's central directory header: what a forged zip says."""
    import struct
    data = bytearray(zpath.read_bytes())
    at = data.index(b"PK\x01\x02" + data[data.index(b"PK\x01\x02") + 4:data.index(b"PK\x01\x02") + 4], 0)
    name = entry.encode()
    while True:
        at = data.index(b"PK\x01\x02", at)
        n = struct.unpack_from("<H", data, at + 28)[0]
        if data[at + 46:at + 46 + n] == name:
            break
        at += 4
    struct.pack_into("<I", data, at + {"compress_size": 20, "file_size": 24}[field], value)
    zpath.write_bytes(bytes(data))


def _reports(paths) -> dict[str, Report]:
    from sheetkin.course.batch import submission_files, validate_many
    found = submission_files([str(p) for p in paths])
    return {found.name(f): rep for f, rep in zip(found.files, validate_many(found.files, 1), strict=True)}


def test_one_submission_never_blocks_the_class(tmp_path, books):
    """One 200-letter Cyrillic file name (400 bytes) or one 51 MB upload refused the whole
    Moodle zip; a student's work.zip was skipped without a word; of two files under one
    entry name the first was dropped silently; cp866 names came out as mojibake."""
    import zipfile
    ex, key = books["v1"]
    good = fill(ex, key, tmp_path / "good.xlsx", student="Иванов Иван").read_bytes()
    other = fill(ex, key, tmp_path / "other.xlsx", student="Иванов Иван", group="ГМ-21").read_bytes()
    inner = io.BytesIO()
    with zipfile.ZipFile(inner, "w") as zf:
        zf.writestr("lab.xlsx", good)
    long_name = "Л" * 200 + ".xlsx"
    z = tmp_path / "class.zip"
    with zipfile.ZipFile(z, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("Иван Иванов_1_assignsubmission_file_/lab.xlsx", good)
        zf.writestr(f"Пётр Петров_2_assignsubmission_file_/{long_name}", good)
        zf.writestr("Анна Петрова_3_assignsubmission_file_/big.xlsx", b"\0" * (51 * 2 ** 20))
        zf.writestr("Олег Сидоров_4_assignsubmission_file_/work.zip", inner.getvalue())
        zf.writestr("Ольга Смирнова_5_assignsubmission_file_/lab.xlsx", good)
        zf.writestr("Ольга Смирнова_5_assignsubmission_file_/lab.xlsx", other)     # the same name twice
        zf.writestr("Yan Kim_6_assignsubmission_file_/PPPPPP.xlsx", good)            # renamed to cp866 below
    data = z.read_bytes().replace(b"PPPPPP.xlsx", "Петров.xlsx".encode("cp866"))
    z.write_bytes(data)
    got = _reports([z])
    names = list(got)
    assert len(got) == 7, names
    lines = {n: (r.error or "") for n, r in got.items()}
    assert not lines[f"{z}/Иван Иванов_1_assignsubmission_file_/lab.xlsx"]
    assert not lines[f"{z}/Пётр Петров_2_assignsubmission_file_/{long_name}"]           # graded
    assert "51 MB" in lines[f"{z}/Анна Петрова_3_assignsubmission_file_/big.xlsx"] or \
        "unpacks to 53,477,376 bytes" in lines[f"{z}/Анна Петрова_3_assignsubmission_file_/big.xlsx"]
    assert not lines[f"{z}/Олег Сидоров_4_assignsubmission_file_/work.zip/lab.xlsx"]    # graded, named
    twice = [n for n in names if "Смирнова" in n]
    assert len(twice) == 2 and "entry 2 of this name" in twice[1]
    assert {got[n].group for n in twice} == {"", "ГМ-21"}                              # neither dropped
    cp866 = f"{z}/Yan Kim_6_assignsubmission_file_/Петров.xlsx"
    assert not lines[cp866] and any("cp866" in n for n in got[cp866].notes)
    for n, line in lines.items():
        assert "\n" not in line and "internal error" not in line, (n, line)


def test_a_name_marked_utf8_but_not_is_that_entrys_note(tmp_path, books):
    """A zip entry whose name is marked UTF-8 but is not (a zipper's slip, a crafted name)
    made zipfile refuse the whole class's zip: now the name is read as a DOS name (cp866,
    said in a note) and every book of the class is graded."""
    import zipfile
    ex, key = books["v1"]
    good = fill(ex, key, tmp_path / "good.xlsx", student="Иванов Иван").read_bytes()
    z = tmp_path / "class.zip"
    with zipfile.ZipFile(z, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("Иван Иванов_1_assignsubmission_file_/lab.xlsx", good)
        zf.writestr("Yan Kim_2_assignsubmission_file_/Иванов.xlsx", good)          # marked UTF-8 (0x800)
    # the same number of bytes, no longer UTF-8, the mark kept: in both headers of the entry
    bad = "ИвановИванов".encode("cp866")
    assert len(bad) == len("Иванов".encode()) and zipfile.ZipFile(z).infolist()[1].flag_bits & 0x800
    z.write_bytes(z.read_bytes().replace("Иванов.xlsx".encode(), bad + b".xlsx"))
    with pytest.raises(UnicodeDecodeError):
        zipfile.ZipFile(z)                           # what refused the whole class before
    got = _reports([z])
    assert len(got) == 2, list(got)
    assert all(not r.error for r in got.values()), {n: r.error for n, r in got.items()}
    odd = next(n for n in got if "Yan Kim" in n)
    assert odd.endswith("ИвановИванов.xlsx") and any("cp866" in note for note in got[odd].notes)


@pytest.mark.parametrize("field, value, refused", [("file_size", 100, True), ("file_size", 10_000_000, True),
                                                   ("compress_size", 50, True), ("compress_size", 2_000_000, False)])
def test_a_lying_header_is_that_entrys_line(tmp_path, books, field, value, refused):
    """A zip whose header lies about its size gave 'internal error ... please report'. (A
    packed size larger than the data is harmless: the stream ends where it ends, its CRC
    checks, the book is graded.)"""
    import zipfile
    ex, key = books["v1"]
    good = fill(ex, key, tmp_path / "good.xlsx", student="Иванов Иван").read_bytes()
    z = tmp_path / "class.zip"
    with zipfile.ZipFile(z, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("A A_1_assignsubmission_file_/lab.xlsx", good)
        zf.writestr("B B_2_assignsubmission_file_/lab.xlsx", good)
    _patch_central(z, "B B_2_assignsubmission_file_/lab.xlsx", field, value)
    got = _reports([z])
    assert not got[f"{z}/A A_1_assignsubmission_file_/lab.xlsx"].error
    line = got[f"{z}/B B_2_assignsubmission_file_/lab.xlsx"].error
    assert bool(line) == refused
    assert not line or "internal error" not in line and "\n" not in line and "B B_2" in line, line


def test_unpacked_bytes_capped_across_the_run(tmp_path, monkeypatch):
    """A 1.8 MB zip of 37 x 50 MB zero 'xlsx' wrote 1.8 GB to TMPDIR before any check (two
    such zips: 3.7 GB; the cap was per zip). Judged from the ratio before unpacking; the
    run's total is capped over every zip."""
    import tempfile
    import zipfile

    import sheetkin.course.batch as batch
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    zips = []
    for k in range(2):
        z = tmp_path / f"bomb{k}.zip"
        with zipfile.ZipFile(z, "w", zipfile.ZIP_DEFLATED) as zf:
            for i in range(5):
                zf.writestr(f"S{i}_{i}_assignsubmission_file_/z.xlsx", b"\0" * 50_000_000)
        zips.append(z)
    got = _reports(zips)
    assert len(got) == 10 and all("zip bomb" in r.error for r in got.values())
    written = sum(f.stat().st_size for f in (tmp_path / "tmp").rglob("*") if f.is_file())
    assert written == 0
    # the run's cap, over two zips of honest (incompressible) entries
    monkeypatch.setattr(batch, "ZIP_MAX_BYTES", 250_000)
    for k in range(2):
        with zipfile.ZipFile(tmp_path / f"ok{k}.zip", "w") as zf:
            for i in range(2):
                zf.writestr(f"T{k}{i}_{i}_assignsubmission_file_/t.xlsx", os.urandom(100_000))
    got = _reports([tmp_path / "ok0.zip", tmp_path / "ok1.zip"])
    capped = [n for n, r in got.items() if r.error and "in one run" in r.error]
    assert len(got) == 4 and len(capped) == 2 and all("ok1.zip" in n for n in capped)


# --------------------------------------------------------------------------- 5, 6. bounded work, clear failures
def test_a_file_taking_too_long_is_reported_and_the_class_goes_on(tmp_path, monkeypatch):
    """A worker stalled on one file (30,000 defined names in a cycle took minutes) held the
    class: past the per-file time limit the file gets its line, the others are graded."""
    import time

    import sheetkin.course.batch as batch

    def validate(path, options=None):
        if "slow" in str(path):
            time.sleep(60)
        return Report(str(path))
    monkeypatch.setattr(batch, "_validate_one", validate)
    paths = [tmp_path / "a.xlsx", tmp_path / "slow.xlsx", tmp_path / "b.xlsx"]
    for jobs in (1, 2):
        start = time.monotonic()
        reps = list(batch.validate_many(paths, jobs, time_limit=1.0))
        took = time.monotonic() - start
        assert [r.path for r in reps] == [str(p) for p in paths]
        assert not reps[0].error and not reps[2].error
        assert "took longer than 1 s" in reps[1].error and str(paths[1]) in reps[1].error
        assert took < 20, (jobs, took)


def test_variants_class_size_cap(tmp_path):
    from sheetkin.course.variants import MAX_CLASS_SIZE, check_class_size
    from sheetkin.kinematics.scene import SceneError
    cl = tmp_path / "class.csv"
    cl.write_text("Full name,Email address\n" + "".join(f"Студент {k},s{k}@x.ru\n" for k in range(MAX_CLASS_SIZE + 1)),
                  encoding="utf-8")
    with pytest.raises(SceneError, match=f"names {MAX_CLASS_SIZE + 1:,} students"):
        check_class_size(read_class_list(str(cl)))
    code = main(["variants", str(Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml"),
                 "--class-list", str(cl), "--out", str(tmp_path / "out")])
    assert code == 2 and not (tmp_path / "out").exists()


def test_failed_variants_leaves_nothing_that_blocks_the_rerun(tmp_path, monkeypatch):
    """A `variants` run that failed on a full disk left a key that blocked the rerun."""
    import errno

    import sheetkin.course.variants as variants
    scene = Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml"
    vs = variants.make_variants(scene.read_text(encoding="utf-8"), str(scene), 2, seed=5)
    real, calls = variants._atomic_book, []

    def full_disk(path, wb):
        calls.append(path)
        if len(calls) == 3:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        real(path, wb)
    monkeypatch.setattr(variants, "_atomic_book", full_disk)
    out = tmp_path / "issued"
    with pytest.raises(OSError, match="No space"):
        variants.write_variants(vs, out, charts=False)
    assert list(out.iterdir()) == []
    monkeypatch.setattr(variants, "_atomic_book", real)
    roster = variants.write_variants(vs, out, charts=False)          # the rerun, without --force
    assert roster.is_file() and (out / ".sheetkin-key").is_file()
    # a failed --force run over an issued class leaves the issued roster and key as they were
    key_before, roster_before = (out / ".sheetkin-key").read_bytes(), roster.read_bytes()
    calls.clear()
    monkeypatch.setattr(variants, "_atomic_book", full_disk)
    with pytest.raises(OSError):
        variants.write_variants(vs, out, charts=False, force=True)
    assert (out / ".sheetkin-key").read_bytes() == key_before and roster.read_bytes() == roster_before
    assert not list(out.glob(".sheetkin-key-*")) and not list(out.glob("roster-*"))


@pytest.fixture
def mounted(tmp_path):
    """mount(options) -> a folder on a tmpfs of its own (read-only, or 64 KB: a full disk);
    skipped where mounting is not allowed."""
    import subprocess
    points = []

    def mount(options: str) -> Path:
        point = tmp_path / f"mnt{len(points)}"
        point.mkdir()
        if subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(point)],
                          capture_output=True).returncode != 0:
            pytest.skip("cannot mount a tmpfs here")
        points.append(point)
        return point
    yield mount
    for point in points:
        subprocess.run(["umount", "-l", str(point)], capture_output=True)


WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"


@pytest.mark.parametrize("argv", [["validate", "{book}", "--html", "{out}/r.html"],
                                  ["evaluate", "{book}", "-o", "{out}/e.csv"],
                                  ["workbook", "{scene}", "-o", "{out}/w.xlsx"],
                                  ["animate", "{scene}", "-o", "{out}/a.html", "--frames", "4"]])
def test_read_only_output_folder_named_before_the_work(mounted, capsys, argv):
    """A read-only output folder was reported after the work, naming the temporary
    .sheetkin-XXXX.part."""
    import time
    out = mounted("ro,size=64k")
    args = [a.format(book=WORKBOOKS / "fourbar.xlsx", scene=WORKBOOKS / "fourbar.toml", out=out) for a in argv]
    start = time.monotonic()
    code = main(args)
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert args[args.index(next(a for a in args if str(out) in a))] in err and ".part" not in err
    assert "Read-only file system" in err
    assert time.monotonic() - start < 5          # refused before the work


def test_animate_full_disk_names_the_file(mounted, capsys):
    """`animate` reported a full disk as 'stdout'."""
    out = mounted("size=64k")
    target = out / "a.gif"
    code = main(["animate", str(WORKBOOKS / "fourbar.toml"), "-o", str(target), "--frames", "60"])
    err = capsys.readouterr().err
    assert code == 2 and f"{target}: No space left on device" in err and "stdout" not in err, err
    assert list(out.iterdir()) == []


# --------------------------------------------------------------------------- 7. fuzz
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_HOSTILE = st.sampled_from(list("=+-@\t\r\n\x1b\x07\x9b\x85\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069"
                                "\u200b\u200c\u200d\u200e\u200f\u2060\ufeff\u2028\u2029\x00\x7f"))
_TEXT = st.lists(st.one_of(_HOSTILE, st.characters(codec="utf-8", exclude_characters="/\\")),
                 min_size=1, max_size=24).map("".join)


def _no_raw(text: str, where: str) -> None:
    m = RAW.search(text)
    assert m is None, (where, repr(text[max(0, m.start() - 20):m.end() + 20]))


def _check_outputs(reports, class_list=None) -> None:
    from sheetkin.course.class_grading import printable_report
    from sheetkin.course.report import html_report, json_report, summary_table, text_report
    reports = [printable_report(r) for r in reports]
    ids = identify(reports, class_list, mtimes=[0] * len(reports))
    for rep in reports:
        _no_raw(text_report(rep, "ru").replace("\n", ""), "text")
    _no_raw(summary_table(reports, "ru").replace("\n", ""), "summary")
    _no_raw(html_report(reports, Copies(), "ru", ids).replace("\n", ""), "html")
    data = json.loads(json_report(reports, Copies(), "ru"))

    def walk(x):
        if isinstance(x, str):
            _no_raw(x, "json")
        elif isinstance(x, dict):
            for k, v in x.items():
                walk(k)
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
    walk(data)
    lines, warnings = grade_lines(reports, Copies(), class_list, identities=ids)
    for w in warnings:
        _no_raw(w, "warning")
    for row in _csv(grades_csv(lines)):
        for cell in row:
            _no_raw(cell, "grades.csv")
            assert not cell.lstrip(" ").startswith(FORMULA), cell


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.lists(st.tuples(_TEXT, _TEXT, _TEXT), min_size=1, max_size=3))
def test_fuzz_names_reach_no_output_raw(people):
    """Names typed in D1, Moodle folder names and file names: no raw control, bidi or
    formula-leading text in the text report, JSON, HTML or grades.csv."""
    reports = [_rep(f"{folder}_{k + 1}_assignsubmission_file_/{file}.xlsx", name)
               for k, (name, folder, file) in enumerate(people)]
    reports.append(_rep(f"{people[0][1]}.xlsx", people[0][0], error=f"{people[0][2]}: not a zip file"))
    _check_outputs(reports)


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.lists(st.tuples(_TEXT, _TEXT), min_size=1, max_size=3))
def test_fuzz_class_list_and_assignment_reach_no_csv_raw(people):
    rows = [(name, ident, "v1", "v1-exercise.xlsx") for name, ident in people]
    for row in csv.reader(io.StringIO(assignment_text("Email address", rows))):
        for cell in row:
            _no_raw(cell, "assignment.csv")
            assert not cell.lstrip(" ").startswith(FORMULA), cell


@settings(max_examples=15, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.lists(_TEXT.filter(lambda t: "\x00" not in t), min_size=1, max_size=3, unique=True))
def test_fuzz_zip_entry_names_reach_no_output_raw(tmp_path_factory, names):
    """Zip entry names (the whole pipeline: unpacked, validated, reported). No NUL: Python's
    zipfile cuts a name at it, writing and reading."""
    import zipfile
    folder = tmp_path_factory.mktemp("fuzz")
    z = folder / "class.zip"
    with zipfile.ZipFile(z, "w") as zf:
        for k, name in enumerate(names):
            zf.writestr(f"{name}_{k + 1}_assignsubmission_file_/{name}.xlsx", b"not a workbook")
    from sheetkin.course.batch import submission_files, validate_many
    from sheetkin.course.class_grading import show_as
    found = submission_files([str(z)])
    reports = []
    for f, rep in zip(found.files, validate_many(found.files, 1), strict=True):
        show_as(rep, str(f), found.name(f))
        reports.append(rep)
    assert len(reports) == len(names)
    for twice in found.twice:
        _no_raw(twice, "note")
    _check_outputs(reports)


def test_roster_scene_over_the_cap_is_not_read(tmp_path):
    """A roster's scene column naming a 1.5 GB file was read whole (2.9 GB)."""
    import resource

    from sheetkin.course.copies import computed_values
    from sheetkin.kinematics.scene import SceneError
    huge = tmp_path / "v1.toml"
    with open(huge, "wb") as f:
        f.truncate(1_500_000_000)                  # sparse: no disk, but 1.5 GB to a reader
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with pytest.raises(SceneError, match="8,000,000"):
        computed_values(huge)
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 100_000     # KB: nothing read


def test_class_list_names_reach_the_flags_escaped(tmp_path):
    """A Moodle full name (editable in a profile) in the class list reaches the identity
    flags, printed on the terminal: escaped there too."""
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван\x1b[2K,Иванов,i@x.ru\nПётр,Петров\u202e,p@x.ru\n",
                  encoding="utf-8")
    class_list = read_class_list(str(cl))
    reps = [_rep("Пётр Петров_102_assignsubmission_file_/lab.xlsx", "Иванов Иван")]
    ids = identify(reps, class_list, mtimes=[0])
    assert ids[0].flags and all(not RAW.search(f) for f in ids[0].flags)
    assert "\\u202e" in ids[0].flags[0] and "\\x1b" in ids[0].flags[0]


def test_a_file_given_twice_is_noted_escaped(tmp_path):
    from sheetkin.course.batch import submission_files
    f = tmp_path / "a\x1b[2K\u202e.xlsx"
    f.write_bytes(b"x")
    found = submission_files([str(tmp_path), str(f)])
    assert len(found.files) == 1 and found.twice and not RAW.search(found.twice[0])
    assert not RAW.search(found.name(found.files[0]))


def test_assignment_csv_names_its_identifier_in_its_header_old_files_still_read(tmp_path):
    """issue 34: no "# Email address,,," line a spreadsheet shows as a stray row; the files
    written before that (with it) are read as they were."""
    rows = [("Иванов Иван", "1001", "v1", "v1-Иванов-exercise.xlsx")]
    text = assignment_text("ID number", rows)
    assert text.splitlines()[0] == "student,identifier (ID number),variant,exercise" and "#" not in text
    new, old = tmp_path / "new.csv", tmp_path / "old.csv"
    new.write_text(text, encoding="utf-8")
    old.write_text("student,identifier,variant,exercise\n# ID number,,,\nИванов Иван,1001,v1,v1-Иванов-exercise.xlsx\n",
                   encoding="utf-8")
    for path in (new, old):
        got = read_assignment(path)
        assert got.id_header == "ID number" and got.people == {"1001": ("Иванов Иван", "v1", "v1-Иванов-exercise.xlsx")}
