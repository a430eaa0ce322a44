"""Issue 21 (4-6) and issue 23 (a file given twice, copies as clusters): who handed in
each book, names in Russian forms, Moodle's folders and zip, one grade per student, the
assignment sealed in each student's book, loud teacher's mistakes, .xls and passwords."""
from __future__ import annotations

import csv
import io
import json
import os
import shutil
import struct
import zipfile
from pathlib import Path

import pytest
from helpers.classbooks import fill, issue_variants, type_numbers
from helpers.libreoffice import recalculate

from sheetkin.cli.commands import main
from sheetkin.course.classlist import moodle_submitter, read_class_list
from sheetkin.course.copies import Copies, possible_copies
from sheetkin.course.grades import COLUMNS, grade_lines, grades_csv
from sheetkin.course.identity import identify
from sheetkin.course.issued import parse_roster, read_roster
from sheetkin.course.report import copies_lines, html_report
from sheetkin.course.report_model import Report, RowReport
from sheetkin.xlsx.cells import password_protected

ROOT = Path(__file__).resolve().parents[2]
CLASS = ("Фамилия;Имя;Индивидуальный номер;Адрес электронной почты\n"
         "Иванов;Иван;1001;ivanov@example.org\n"
         "Петрова;Анна;1002;petrova@example.org\n"
         "Сидоров;Пётр;1003;sidorov@example.org\n"
         "Иванов;Илья;1004;ilya.ivanov@example.org\n"
         "Смирнова;Анна Сергеевна;1005;smirnova@example.org\n")


@pytest.fixture
def class_list(tmp_path):
    path = tmp_path / "class.csv"
    path.write_bytes(CLASS.encode("cp1251"))        # a Russian Excel's CSV: ";" and Windows-1251
    return read_class_list(str(path))


@pytest.mark.parametrize("typed, who", [
    ("Петрова Анна Сергеевна", ["petrova@example.org"]),      # the patronymic the list does not hold
    ("СИДОРОВ П.", ["sidorov@example.org"]),
    ("Сидоров Петр", ["sidorov@example.org"]),                 # ё typed as е
    ("Пётр Сидоров", ["sidorov@example.org"]),
    ("Петрова А.", ["petrova@example.org"]),
    ("Петрова А.С.", ["petrova@example.org"]),
    ("Смирнова А.С.", ["smirnova@example.org"]),               # the list holds the patronymic
    ("Смирнова А.П.", []),                                     # ... and it is another one
    ("Иванов Иван Иванович", ["ivanov@example.org"]),
    ("Иванов И.", ["ivanov@example.org", "ilya.ivanov@example.org"]),   # several: listed
    ("Иванов", ["ivanov@example.org", "ilya.ivanov@example.org"]),
    ("Петров А.", []),                                         # no one
    ("Петрова Мария", []),
    ("", []),
])
def test_russian_name_forms(class_list, typed, who):
    assert class_list.id_header == "Email address"
    assert sorted(p.ident for p in class_list.match(typed)) == sorted(who)
    assert class_list.ident_of(typed) == (who[0] if len(who) == 1 else "")


def test_moodle_folder_and_flat_names():
    s = moodle_submitter("all/Иван Иванов_12345_assignsubmission_file_/книга.xlsx")
    assert (s.name, s.participant) == ("Иван Иванов", "12345")
    s = moodle_submitter("all/Анна Петрова_77_assignsubmission_file_book_v2.xlsx")     # no folders
    assert (s.name, s.participant) == ("Анна Петрова", "77")
    assert moodle_submitter("all/Participant_9_assignsubmission_file_/a.xlsx").name == "Participant"
    assert moodle_submitter("class/ivanov.xlsx") is None


def _rep(path, student="", variant="", issued_to="", error=None):
    rep = Report(path, rows=[RowReport("ok", 10, "correct")], positions=13, student=student, variant=variant,
                 issued_to=issued_to, error=error)
    rep.checks_total, rep.marks = 10, {"typed": {}, "formulas": {}, "inputs": {}, "depends": {}, "values": {}}
    return rep


def test_one_grade_per_student_and_books_in_the_wrong_folder(class_list, tmp_path):
    """The newest of a student's files is graded, the older listed; a book whose typed
    name is another student's is flagged in the folder's student's line."""
    def file(name, age):
        p = tmp_path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(b"x")
        os.utime(p, (1e9 - age, 1e9 - age))
        return str(p)
    reps = [_rep(file("Иван Иванов_1_assignsubmission_file_/old.xlsx", 100), "Иванов И.И."),
            _rep(file("Иван Иванов_1_assignsubmission_file_/new.xlsx", 10), "Иванов Иван"),
            _rep(file("Пётр Сидоров_3_assignsubmission_file_/a.xlsx", 10), "Петрова Анна"),
            _rep(file("Participant_4_assignsubmission_file_/a.xlsx", 10), "Петрова Анна"),
            _rep(file("loose.xlsx", 10), "Никто Никтоевич")]
    ids = identify(reps, class_list)
    # blind marking ("Participant"): graded under the name typed in the book (issue 34)
    assert [m.ident for m in ids] == ["ivanov@example.org", "ivanov@example.org", "sidorov@example.org",
                                      "petrova@example.org", ""]
    assert ids[3].participant == "4" and ids[3].submitter == "Participant 4" and not ids[3].flags
    assert ids[0].superseded_by == 1 and ids[1].superseded_by is None
    assert "found in the folder of Сидоров Пётр, but Петрова Анна's name is typed in it" in ids[2].flags
    lines, warnings = grade_lines(reps, Copies(), class_list, identities=ids)
    # then the class list's students who handed nothing in
    assert [r[0] for r in lines[1:]] == ["ivanov@example.org", "sidorov@example.org", "petrova@example.org", "",
                                         "ilya.ivanov@example.org", "smirnova@example.org"]
    assert [r[1] for r in lines[1:4]] == ["Participant 1", "Participant 3", "Participant 4"]
    text = " ".join(warnings)
    assert "1 older file(s) not graded" in text and "old.xlsx (newer:" in text
    assert "no one in the class list is named 'Никто Никтоевич'" in text
    assert "not handed in by their own student" in text


def test_sealed_identity_against_the_submitter(class_list, tmp_path):
    """A book issued to Ivanov and handed in from Sidorov's folder; one issued book handed
    in by two students; a shared variant (more students than variants) is not a copy."""
    folder = "Пётр Сидоров_3_assignsubmission_file_"
    reps = [_rep(f"{folder}/a.xlsx", "Иванов Иван", "v1", "ivanov@example.org"),
            _rep("Иван Иванов_1_assignsubmission_file_/a.xlsx", "Иванов Иван", "v1", "ivanov@example.org"),
            _rep("Анна Петрова_2_assignsubmission_file_/a.xlsx", "Петрова Анна", "v2", "petrova@example.org"),
            _rep("Илья Иванов_4_assignsubmission_file_/a.xlsx", "Иванов Илья", "v2", "ilya.ivanov@example.org")]
    ids = identify(reps, class_list, mtimes=[0.0] * 4)
    assert ids[0].ident == "sidorov@example.org"
    assert any(f.startswith("issued to Иванов Иван (ivanov@example.org), handed in by Пётр Сидоров")
               for f in ids[0].flags)
    assert not ids[1].flags and not ids[2].flags
    copies = possible_copies(reps, [None] * 4, [m.who for m in ids], {"v1": 2, "v2": 2})
    assert copies.others(0) == [1] and "one issued book (variant v1, issued to ivanov@example.org) handed in by 2" \
        in copies.why(0)
    assert 2 not in copies and 3 not in copies         # v2 issued to both: their own books
    # without an assignment, one variant from two students is listed for the teacher
    plain = [_rep("a.xlsx", "Петрова Анна", "v2"), _rep("b.xlsx", "Иванов Илья", "v2")]
    copies = possible_copies(plain, [None] * 2, ["a", "b"], None)
    assert "the same variant v2 from 2 students" in copies.why(0)


def test_copy_report_is_linear_in_the_class(tmp_path):
    """200 byte-identical files were 19,900 pairs: a 10.6 MB HTML page and a 2.7 MB
    grades.csv. Now one cluster: sizes grow with the class, not its square."""
    sizes = {}
    for n in (50, 200):
        reps = [_rep(f"s{k:03d}.xlsx", f"Студент {k}") for k in range(n)]
        copies = possible_copies(reps, ["same"] * n)
        assert len(copies.clusters) == 1 and copies.clusters[0].members == list(range(n))
        assert copies_lines(reps, copies).count("possible copy:") == 1
        page = html_report(reps, copies)
        data = grades_csv(grade_lines(reps, copies)[0])
        sizes[n] = (len(page), len(data), len(copies_lines(reps, copies)))
    for a, b in zip(sizes[50], sizes[200], strict=True):
        assert b < 4.5 * a, sizes                   # linear (x4), not quadratic (x16)
    assert sizes[200][0] < 400_000 and sizes[200][1] < 60_000


def test_typed_numbers_equal_to_what_a_classmate_computed():
    """A book of typed numbers wrong for its variant, equal to the values a classmate's
    formulas computed: linked to that classmate, by file and name."""
    values = {("omega_2", k): -2.123456 * k for k in range(1, 8)}
    honest = _rep("petrova.xlsx", "Петрова Анна", "v2")
    honest.marks["values"] = dict(values)
    copier = _rep("orlov.xlsx", "Орлов Денис", "v1")
    copier.marks["typed"] = {c: round(v, 4) for c, v in values.items()}
    copier.rows.append(RowReport("omega_2", 40, "wrong", wrong_cells=list(range(1, 8))))
    other = _rep("volkov.xlsx", "Волков Антон", "v3")
    other.marks["values"] = {c: v + 1 for c, v in values.items()}
    copies = possible_copies([honest, copier, other], [None] * 3)
    assert copies.others(1) == [0] and 2 not in copies
    assert "7 typed numbers equal to what petrova.xlsx (Петрова Анна) computed" in copies.why(1)


def test_roster_from_a_russian_excel(tmp_path):
    """roster.csv re-saved by a Russian Excel: ";" between fields, decimal commas, Windows-1251."""
    text = "variant,exercise,key,scene,L1,x_D\nfourbar-01,a.xlsx,b.xlsx,c.toml,0.141,-0.25\n"
    excel = "variant;exercise;key;scene;L1;x_D;;\r\nfourbar-01;a.xlsx;b.xlsx;c.toml;0,141;-0,25;;\r\n;;;;;;;\r\n"
    path = tmp_path / "roster.csv"
    path.write_bytes(excel.encode("cp1251"))
    assert read_roster(path).rows == parse_roster(text).rows == {"fourbar-01": {"L1": 0.141, "x_D": -0.25}}


def _grades(path: Path) -> list[dict]:
    return list(csv.DictReader(io.StringIO(path.read_bytes().decode("utf-8-sig"), newline="")))


def test_file_given_twice_is_validated_once(tmp_path, capsys):
    books = issue_variants(tmp_path / "issued")
    book = fill(*books["v1"], tmp_path / "a.xlsx", student="Иванов Иван")
    (tmp_path / "link.xlsx").symlink_to(book)
    grades = tmp_path / "g.csv"
    code = main(["validate", str(book), str(tmp_path), str(tmp_path / "link.xlsx"), str(book),
                 "--grades", str(grades), "--progress", "never", "--jobs", "1", "--lang", "en"])
    out, err = capsys.readouterr()
    rows = _grades(grades)
    files = sorted(Path(r["file"]).name for r in rows)
    assert files == ["a.xlsx", "v1-exercise.xlsx", "v1-key.xlsx", "v2-exercise.xlsx", "v2-key.xlsx",
                     "v3-exercise.xlsx", "v3-key.xlsx", "v4-exercise.xlsx", "v4-key.xlsx", "v5-exercise.xlsx",
                     "v5-key.xlsx"], files
    # the folder holds a.xlsx and the link again; the link and a.xlsx are named again after it
    assert err.count("given twice; validated once") == 4 and code in (0, 1)
    assert "a.xlsx" not in " ".join(r["possible copy of"] for r in rows)      # never a copy of itself


def _encrypted_ooxml(plain_ole: Path, out: Path) -> Path:
    """An OLE file whose stream is named EncryptedPackage, as Excel's "Encrypt with
    password" writes an .xlsx: LibreOffice's own .xls container with its Workbook renamed."""
    data = bytearray(plain_ole.read_bytes())
    shift = struct.unpack_from("<H", data, 0x1E)[0]
    first = struct.unpack_from("<I", data, 0x30)[0]
    at = data.index("Workbook".encode("utf-16-le"), (first + 1) << shift)
    name = "EncryptedPackage".encode("utf-16-le") + b"\0\0"
    data[at:at + 64] = name + bytes(64 - len(name))
    struct.pack_into("<H", data, at + 64, len(name))
    out.write_bytes(bytes(data))
    return out


def test_xls_converted_and_passwords_named(tmp_path, soffice, capsys):
    """Books saved by LibreOffice through UNO: an .xls is graded like the .xlsx it was; an
    .xls, an .ods and an encrypted .xlsx with a password are each named as such."""
    from helpers.unosave import save_as
    books = issue_variants(tmp_path / "issued")
    book = fill(*books["v2"], tmp_path / "b.xlsx", student="Петрова Анна")
    saved = tmp_path / "saved"
    saved.mkdir()
    save_as([(book, saved / "plain.xls", None), (book, saved / "locked.xls", "secret"),
             (book, saved / "locked.ods", "secret")])
    _encrypted_ooxml(saved / "plain.xls", saved / "locked.xlsx")
    assert password_protected(saved / "plain.xls") == ""
    assert password_protected(saved / "locked.xls") == "an encrypted .xls workbook"
    assert password_protected(saved / "locked.ods") == "an encrypted OpenDocument spreadsheet"
    assert password_protected(saved / "locked.xlsx") == "an encrypted Excel workbook"
    grades = tmp_path / "g.csv"
    assert main(["validate", str(saved), "--grades", str(grades), "--progress", "never", "--jobs", "1",
                 "--lang", "en"]) == 2
    rows = {Path(r["file"]).name: r for r in _grades(grades)}
    assert rows["plain.xls"]["score"] == "100.0" and rows["plain.xls"]["student"] == "Петрова Анна"
    for name in ("locked.xls", "locked.ods", "locked.xlsx"):
        assert "password-protected" in rows[name]["likely causes"] and rows[name]["score"] == "0.0", rows[name]
        assert "conversion failed" not in rows[name]["likely causes"]
    capsys.readouterr()


def test_moodle_zip_read_as_it_is(tmp_path, soffice, capsys):
    """Moodle's "download all submissions": a zip of folders named for each student. The
    books are saved by LibreOffice; the identity comes from the folder, matched with the
    class list (a Russian Excel's CSV); a student's old and new versions give one grade; a
    book in another student's folder is flagged; a blind-marking folder is listed."""
    books = issue_variants(tmp_path / "issued")
    filled = tmp_path / "filled"
    filled.mkdir()
    fill(*books["v1"], filled / "ivanov_old.xlsx", student="Иванов И.", change=type_numbers("omega_2", [0.5] * 13))
    fill(*books["v1"], filled / "ivanov.xlsx", student="Иванов И.")
    fill(*books["v2"], filled / "petrova.xlsx", student="Петрова Анна Сергеевна")
    fill(*books["v3"], filled / "sidorov.xlsx", student="СИДОРОВ П.")
    saved = tmp_path / "saved"
    recalculate(sorted(filled.glob("*.xlsx")), saved)
    folders = {"ivanov_old.xlsx": ("Иван Иванов_501", 1_700_000_000), "ivanov.xlsx": ("Иван Иванов_501", 1_700_100_000),
               "petrova.xlsx": ("Анна Петрова_502", 1_700_000_000),
               "sidorov.xlsx": ("Пётр Сидоров_503", 1_700_000_000)}
    zpath = tmp_path / "Кинематика-Задание 1-12345.zip"
    with zipfile.ZipFile(zpath, "w") as zf:
        for name, (folder, when) in folders.items():
            info = zipfile.ZipInfo(f"{folder}_assignsubmission_file_/{name}", _date(when))
            zf.writestr(info, (saved / name).read_bytes())
        # Сидоров hands in Петрова's book too, from his folder; a blind-marking participant
        zf.writestr(zipfile.ZipInfo("Пётр Сидоров_503_assignsubmission_file_/petrova_copy.xlsx", _date(1_600_000_000)),
                    (saved / "petrova.xlsx").read_bytes())
        zf.writestr("Participant_504_assignsubmission_file_/x.xlsx", (saved / "sidorov.xlsx").read_bytes())
        zf.writestr("Иван Иванов_501_assignsubmission_onlinetext_/onlinetext.html", "<p>done</p>")
    cl = tmp_path / "class.csv"
    cl.write_bytes(CLASS.encode("cp1251"))
    grades = tmp_path / "grades.csv"
    code = main(["validate", str(zpath), "--grades", str(grades), "--class-list", str(cl), "--progress", "never",
                 "--lang", "en"])
    out, err = capsys.readouterr()
    assert code == 1, err
    every = _grades(grades)
    # every class-list student has a line (issue 34): the two who handed nothing in have no file
    absent = [r for r in every if not r["file"]]
    assert sorted(r["Email address"] for r in absent) == ["ilya.ivanov@example.org", "smirnova@example.org"]
    rows = [r for r in every if r["file"]]
    by_file = {r["file"].split(".zip/")[1]: r for r in rows}
    assert all(r["file"].startswith(str(zpath) + "/") for r in rows)
    assert set(by_file) == {"Иван Иванов_501_assignsubmission_file_/ivanov.xlsx",
                            "Анна Петрова_502_assignsubmission_file_/petrova.xlsx",
                            "Пётр Сидоров_503_assignsubmission_file_/sidorov.xlsx",
                            "Participant_504_assignsubmission_file_/x.xlsx"}
    ids = {k.split("_")[0]: r["Email address"] for k, r in by_file.items()}
    assert ids == {"Иван Иванов": "ivanov@example.org", "Анна Петрова": "petrova@example.org",
                   "Пётр Сидоров": "sidorov@example.org", "Participant": ""}
    assert by_file["Иван Иванов_501_assignsubmission_file_/ivanov.xlsx"]["score"] == "100.0"
    assert "older file(s) not graded" in err and "ivanov_old.xlsx" in err
    assert "Participant" in err and "not found" in err
    # Сидоров's newest file is his own (petrova_copy is older): graded; the copy is listed
    assert "petrova_copy.xlsx" in err
    assert "possible copy" in out and "byte-identical" in out
    assert main(["validate", str(zpath), "--class-list", str(cl), "--grades", str(tmp_path / "g2.csv"), "--json",
                 "--progress", "never", "--lang", "en"]) == 1
    books = json.loads(capsys.readouterr().out)
    notes = [n for b in books["reports"] for n in b["notes"] if n.startswith("identity: ")]
    assert any("older files of this student not graded" in n for n in notes)


def _date(stamp: float) -> tuple:
    import time
    return time.localtime(stamp)[:6]


def test_found_in_another_students_folder_flagged(tmp_path, class_list):
    reps = [_rep("Пётр Сидоров_3_assignsubmission_file_/a.xlsx", "Петрова А.")]
    lines, warnings = grade_lines(reps, Copies(), class_list, identities=identify(reps, class_list, mtimes=[0]))
    identity = lines[1][2 + COLUMNS.index("identity")]
    assert lines[1][0] == "sidorov@example.org" and "found in the folder of Сидоров Пётр" in identity
    assert "1 book(s) not handed in by their own student" in " ".join(warnings)


def test_unpacking_refuses_names_outside(tmp_path):
    from sheetkin.course.batch import submission_files
    from sheetkin.kinematics.scene import SceneError
    z = tmp_path / "bad.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("../evil.xlsx", b"x")
    with pytest.raises(SceneError, match="points outside the archive"):
        submission_files([str(z)])
    assert not (tmp_path.parent / "evil.xlsx").exists()
    shutil.rmtree(tmp_path / "none", ignore_errors=True)


def test_typed_numbers_of_another_variant_no_one_handed_in(tmp_path):
    """The numbers of a variant nobody handed in (a key, an absent classmate), typed into
    another variant's book: named by the variant's key file and the student it was issued to."""
    from sheetkin.course.copies import computed_values, roster_variants
    from sheetkin.course.identity import read_assignment
    cl = tmp_path / "class.csv"
    cl.write_bytes(CLASS.encode("cp1251"))
    out = tmp_path / "issued"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "3", "--class-list", str(cl),
                 "--out", str(out), "--seed", "2"]) == 0
    out = out / "teacher"                  # issue 34: the teacher's folder of a class list's issue
    roster = read_roster(out / "roster.csv")
    theirs = computed_values(out / "fourbar-03.toml")
    rep = _rep("orlov.xlsx", "Орлов Денис", "fourbar-01")
    cells = [c for c in theirs if c[0] == "omega_2"]
    rep.marks["typed"] = {c: round(theirs[c], 5) for c in cells}
    rep.rows.append(RowReport("omega_2", 40, "wrong", wrong_cells=[k for _, k in cells]))
    honest = _rep("ivanov.xlsx", "Иванов Иван", "fourbar-01")
    assignment = read_assignment(out / "assignment.csv")
    assert assignment.assigned() == {"fourbar-01": 2, "fourbar-02": 2, "fourbar-03": 1}
    copies = possible_copies([rep, honest], [None, None], ["a", "b"], assignment.assigned(),
                             roster_variants(roster, assignment))
    why = copies.why(0)
    assert f"{len(cells)} typed numbers equal to variant fourbar-03's computed values" in why
    assert "fourbar-03-key.xlsx, issued to Сидоров Пётр" in why
    assert 1 not in copies
    # grades.csv, --json and the HTML row carry it as the text report does (one vocabulary)
    from sheetkin.course.report import json_report
    lines, _ = grade_lines([rep, honest], copies, None)
    col = lines[0].index("possible copy of")
    assert lines[1][col] == why and lines[2][col] == ""
    lines, _ = grade_lines([rep, honest], copies, None, lang="ru")
    assert "(ключ " in lines[1][col] and "выдан Сидоров Пётр" in lines[1][col] and "(key " not in lines[1][col]
    books = json.loads(json_report([rep, honest], copies))["reports"]
    assert books[0]["possible_copy_of"] == [{"file": str(out / "fourbar-03-key.xlsx"), "student": "Сидоров Пётр",
                                             "why": why.split("; ")[0]}]
    assert books[1]["possible_copy_of"] == []
    assert "fourbar-03-key.xlsx" in copies_lines([rep, honest], copies)
    page = html_report([rep, honest], copies)
    assert page.count("fourbar-03-key.xlsx, issued to") >= 3      # the row, the details, the group
