"""A class, end to end (issue 13): variants -> students' books filled in and saved by
LibreOffice -> validate (with the roster) -> grades.csv and the HTML report.

Eight students on five variants: two honest, a sign error, a rounded number typed over a
formula, changed given data, a byte-for-byte copy, a copy of typed numbers with another
variant's given data typed in, and a copy of a wrong formula. All books are saved by one
LibreOffice run, as a student's spreadsheet program would save them."""
from __future__ import annotations

import csv
import io
import re
import shutil
import zipfile
from pathlib import Path

import openpyxl
from helpers.classbooks import both, fill, flip_sign, issue_variants, row_values, rows_of, type_numbers
from helpers.libreoffice import recalculate

from sheetkin.cli.commands import main
from sheetkin.course.report_model import Report

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
NAMES = {"ivanov": "Иванов Иван", "petrova": "Петрова Анна", "sidorov": "Сидоров Пётр",
         "kuznetsov": "Кузнецов Олег", "smirnov": "Смирнов Илья", "copier_bytes": "Орлов Денис",
         "copier_typed": "Волков Антон", "copier_formula": "=cmd|' /C calc'!A0"}


def given_data(book: Path) -> dict[int, float]:
    """{row: value} of the numbers in column D that are typed (the input block)."""
    ws = openpyxl.load_workbook(book).worksheets[0]
    return {r: ws.cell(r, 4).value for r in range(5, ws.max_row + 1)
            if isinstance(ws.cell(r, 4).value, (int, float)) and not isinstance(ws.cell(r, 4).value, bool)}


def retype_given(book: Path):
    """Type another variant's given data over the book's own (a copier's disguise)."""
    values = given_data(book)

    def change(ws, rows):
        for r, v in values.items():
            ws.cell(r, 4).value = v
    return change


def students_books(issued: dict[str, tuple[Path, Path]], folder: Path) -> Path:
    """The class's books (before saving), in `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    v1, v2, v3, v4, v5 = list(issued)[:5]
    om = row_values(issued[v4][1], "omega_2")

    def book(name, v, change=None):
        return fill(*issued[v], folder / f"{name}.xlsx", student=NAMES[name], group="ГМ-21", change=change)

    def changed_l1(ws, rows):
        ws.cell(rows["L1"], 4).value = 0.05
    book("ivanov", v1)
    book("petrova", v2)
    book("sidorov", v3, flip_sign("omega_3"))
    book("kuznetsov", v4, type_numbers("omega_2", om))
    book("smirnov", v5, changed_l1)
    # kuznetsov's book, v2's given data typed in; sidorov's book, v1's given data typed in
    book("copier_typed", v4, both(type_numbers("omega_2", om), retype_given(issued[v2][0])))
    book("copier_formula", v3, both(flip_sign("omega_3"), retype_given(issued[v1][0])))
    return folder


def save_by_libreoffice(folder: Path, out: Path) -> Path:
    """Every book opened and saved by LibreOffice (one soffice run); then a byte-for-byte
    copy of ivanov's saved book handed in as copier_bytes's."""
    recalculate(sorted(folder.glob("*.xlsx")), out)
    shutil.copy(out / "ivanov.xlsx", out / "copier_bytes.xlsx")
    return out


def read_grades(path: Path) -> dict[str, dict]:
    data = path.read_bytes()
    assert data.startswith("\ufeff".encode())
    return {Path(r["file"]).stem: r for r in csv.DictReader(io.StringIO(data.decode("utf-8-sig"), newline=""))}


def check_class(grades: dict[str, dict], page: str, with_identity: bool) -> None:
    assert set(grades) == set(NAMES)
    g = grades
    for honest in ("ivanov", "petrova"):
        assert g[honest]["score"] == "100.0" and g[honest]["likely causes"] == ""
        assert g[honest]["given data changed"] == "no"
    assert g["petrova"]["possible copy of"] == ""
    assert "copier_bytes.xlsx" in g["ivanov"]["possible copy of"]
    assert "byte-identical" in g["ivanov"]["possible copy of"]
    assert g["sidorov"]["likely causes"] == "omega_3" and float(g["sidorov"]["score"]) < 100
    assert "copier_formula.xlsx" in g["sidorov"]["possible copy of"]
    assert "the same wrong formula in omega_3" in g["sidorov"]["possible copy of"]
    assert float(g["kuznetsov"]["score"]) < 100
    assert "copier_typed.xlsx" in g["kuznetsov"]["possible copy of"]
    assert "identical typed numbers" in g["copier_typed"]["possible copy of"]
    for name in ("smirnov", "sidorov", "kuznetsov"):        # honest mistakes are not copies ...
        assert all(other not in g[name]["possible copy of"] for other in ("ivanov.", "petrova.", "smirnov."))
    if "given_changed" in Report.__dataclass_fields__ and g["smirnov"]["variant"]:   # issued books (branch issued)
        assert g["smirnov"]["given data changed"] == "yes" and g["smirnov"]["score"] == "0.0"
        assert "given data changed: L1" in page
    if with_identity:                                       # the student's own cells (branch issued)
        expected = dict(NAMES, copier_bytes=NAMES["ivanov"])     # a copy names whom it copied
        expected["copier_formula"] = "'" + NAMES["copier_formula"]   # stays text in a spreadsheet
        assert {k: r["student"] for k, r in g.items()} == expected
        assert {r["group"] for r in g.values()} == {"ГМ-21"}
        assert "=cmd|" in page
    # the HTML: every name links to its details; the copies link to each other
    ids = re.findall(r"<details id='([^']+)'", page)
    links = re.findall(r"<a href='#([^']+)' data-open='([^']+)'>", page)
    assert len(ids) == len(NAMES) and all(h == o and h in ids for h, o in links)
    summary = page.split("<tbody>")[1].split("</tbody>")[0]
    assert len(re.findall(r"<tr><td><a href='#", summary)) == len(NAMES)
    assert page.count("possible copy of: <a href=") == 6            # three pairs, both ways
    assert "<script>" not in summary


def test_class_loop_with_books_made_here(tmp_path, soffice, capsys):
    """The loop with variants made here (five crank lengths of the four-bar): runs before
    `sheetkin variants` exists, and keeps testing the grades without it."""
    issued = issue_variants(tmp_path / "issued")
    saved = save_by_libreoffice(students_books(issued, tmp_path / "filled"), tmp_path / "submitted")
    grades, html = tmp_path / "grades.csv", tmp_path / "report.html"
    # --copies keep: the scores of the books of a pair are checked here (held by default:
    # tests/course/test_moodle_import.py)
    code = main(["validate", str(saved), "--grades", str(grades), "--copies", "keep", "--html", str(html),
                 "--progress", "never",
                 "--lang", "en"])                   # the report in English (the books' language by default)
    assert code == 1
    out = capsys.readouterr().out
    assert out.count("possible copy: ") == 3
    with_identity = "student" in rows_of(openpyxl.load_workbook(issued["v1"][0]).worksheets[0])
    check_class(read_grades(grades), html.read_text(encoding="utf-8"), with_identity)


def _issued_books(folder: Path) -> dict[str, tuple[Path, Path]]:
    """{variant id: (exercise, key)} as roster.csv names them."""
    rows = list(csv.DictReader(io.StringIO((folder / "roster.csv").read_text(encoding="utf-8-sig"))))
    out = {}
    for row in rows:
        vid = next(v for k, v in row.items() if k and "variant" in k.lower())
        books = [v for v in row.values() if isinstance(v, str) and v.lower().endswith(".xlsx")]
        key = next(b for b in books if "key" in Path(b).name.lower())
        exercise = next(b for b in books if b != key)
        out[vid] = tuple((p if Path(p).is_absolute() else folder / p) for p in (exercise, key))
    return out


def test_class_loop_with_variants(tmp_path, soffice, capsys):
    issued_dir = tmp_path / "issued"
    assert main(["variants", str(WORKBOOKS / "fourbar.toml"), "-n", "5", "--out", str(issued_dir), "--seed", "1"]) == 0
    issued = _issued_books(issued_dir)
    assert len(issued) == 5
    saved = save_by_libreoffice(students_books(issued, tmp_path / "filled"), tmp_path / "submitted")
    class_list = tmp_path / "class.csv"
    class_list.write_text("First name,Last name,Email address\n" + "".join(
        f"{n.split()[1]},{n.split()[0]},{k}@example.org\n" for k, n in NAMES.items() if " " in n
        and not n.startswith("=")), encoding="utf-8")
    # as Moodle's "download all submissions" gives them: a folder per student (one of them
    # under blind marking); the identity is the folder's, matched with the class list
    for k, name in enumerate(NAMES):
        who = "Participant" if NAMES[name].startswith("=") else " ".join(reversed(NAMES[name].split()))
        folder = saved / f"{who}_{101 + k}_assignsubmission_file_"
        folder.mkdir()
        (saved / f"{name}.xlsx").rename(folder / f"{name}.xlsx")
    grades, html = tmp_path / "grades.csv", tmp_path / "report.html"
    code = main(["validate", str(saved), "--roster", str(issued_dir / "roster.csv"), "--grades", str(grades),
                 "--copies", "keep", "--class-list", str(class_list), "--html", str(html), "--progress", "never",
                 "--lang", "en"])
    assert code == 1
    g = read_grades(grades)
    check_class(g, html.read_text(encoding="utf-8"), with_identity=True)
    # each book graded under its folder's student; Orlov handed in Ivanov's book: flagged
    assert {k: r["Email address"] for k, r in g.items()} == {
        k: ("" if k == "copier_formula" else f"{k}@example.org") for k in NAMES}
    assert "found in the folder of Орлов Денис, but Иванов Иван's name is typed in it" in g["copier_bytes"]["identity"]
    assert all(r["variant"] for r in g.values())
    # a copier's given data differ from the variant they were issued
    assert g["copier_typed"]["given data changed"] == "yes" and g["copier_typed"]["score"] == "0.0"


ASSIGNED = (("Иванов", "Иван"), ("Петрова", "Анна"), ("Сидоров", "Пётр"), ("Кузнецов", "Олег"),
            ("Смирнов", "Илья"), ("Орлова", "Дарья"))


def test_class_loop_with_assignment(tmp_path, soffice, capsys):
    """Issue 21: `variants --class-list` gives six students four variants (two share one),
    each their own exercise with their identity sealed; the books are filled in, saved by
    LibreOffice and handed in as Moodle's zip; the teacher then re-runs `variants --force`
    by mistake. Kuznetsov hands in Ivanov's book; Sidorov types Petrova's computed values
    into his; Orlova pastes her own key's values (a typed book, no copy)."""
    out = tmp_path / "issued"
    cl = tmp_path / "class.csv"            # a Russian Excel's export: ";" and Windows-1251
    cl.write_bytes(("Фамилия;Имя;Адрес электронной почты\n" + "".join(
        f"{last};{first};s{k}@example.org\n" for k, (last, first) in enumerate(ASSIGNED))).encode("cp1251"))
    assert main(["variants", str(WORKBOOKS / "fourbar.toml"), "-n", "4", "--class-list", str(cl), "--out", str(out),
                 "--seed", "3"]) == 0
    home = out / "teacher"                 # issue 34: the teacher's folder, never uploaded
    rows = list(csv.DictReader(io.StringIO((home / "assignment.csv").read_text(encoding="utf-8"))))
    given = {r["identifier (Email address)"]: r for r in rows}      # the identifier's name in the header
    assert [given[f"s{k}@example.org"]["variant"] for k in range(6)] == [
        "fourbar-01", "fourbar-02", "fourbar-03", "fourbar-04", "fourbar-01", "fourbar-02"]    # k mod 4
    keys = {vid: ex_key[1] for vid, ex_key in _issued_books(home).items()}

    def book(k, change=None):
        r = given[f"s{k}@example.org"]
        ex = out / "students" / r["exercise"]            # the folder to hand out
        assert openpyxl.load_workbook(ex).worksheets[0].cell(1, 4).value == r["student"]    # the name in D1
        return fill(ex, keys[r["variant"]], tmp_path / "filled" / f"s{k}.xlsx", change=change)
    (tmp_path / "filled").mkdir()
    petrova = {n: row_values(keys["fourbar-02"], n) for n in ("omega_2", "omega_3")}
    own = row_values(keys["fourbar-02"], "omega_2")
    for k in (0, 1, 3, 4):
        book(k)
    book(2, both(*(type_numbers(n, v, 6) for n, v in petrova.items())))      # Petrova's numbers, typed
    book(5, type_numbers("omega_2", own, 9))                                  # her own key's values, typed
    saved = tmp_path / "saved"
    recalculate(sorted((tmp_path / "filled").glob("*.xlsx")), saved)
    zpath = tmp_path / "submissions.zip"
    with zipfile.ZipFile(zpath, "w") as zf:
        for k, (last, first) in enumerate(ASSIGNED):
            src = "s0.xlsx" if k == 3 else f"s{k}.xlsx"              # Kuznetsov hands in Ivanov's book
            zf.write(saved / src, f"{first} {last}_{700 + k}_assignsubmission_file_/{src}")
    # the teacher's mistake: the class issued again into its folder
    assert main(["variants", str(WORKBOOKS / "fourbar.toml"), "-n", "4", "--class-list", str(cl), "--out", str(out),
                 "--seed", "4"]) == 2
    assert main(["variants", str(WORKBOOKS / "fourbar.toml"), "-n", "4", "--class-list", str(cl), "--out", str(out),
                 "--seed", "4", "--force"]) == 0
    assert len(list(home.glob("roster-*.csv"))) == 1 and len(list(home.glob(".sheetkin-key-*"))) == 1
    assert len(list(home.glob("assignment-*.csv"))) == 1
    capsys.readouterr()
    grades, html = tmp_path / "grades.csv", tmp_path / "report.html"
    code = main(["validate", str(zpath), "--roster", str(home / "roster.csv"), "--class-list", str(cl),
                 "--grades", str(grades), "--copies", "keep", "--html", str(html), "--progress", "never",
                 "--lang", "en"])
    text, err = capsys.readouterr()
    assert code == 1
    warnings = [line for line in err.splitlines() if "contradicts" in line]
    assert len(warnings) == 1 and "graded against its sealed data" in warnings[0]
    g = {r["Email address"]: r for r in read_grades_rows(grades)}
    assert set(g) == {f"s{k}@example.org" for k in range(6)}
    for k in (0, 1, 4):                       # honest: sealed by the first key, graded on its data
        assert g[f"s{k}@example.org"]["score"] == "100.0", g[f"s{k}@example.org"]
    assert g["s4@example.org"]["possible copy of"] == ""            # shares fourbar-01 with Ivanov: issued so
    assert "Олег Кузнецов_703" in g["s0@example.org"]["possible copy of"]   # the book Kuznetsov handed in
    kuz = g["s3@example.org"]
    assert "issued to Иванов Иван (s0@example.org), handed in by Олег Кузнецов" in kuz["identity"]
    assert "s0.xlsx" in kuz["possible copy of"] and "byte-identical" in kuz["possible copy of"]
    assert "one issued book (variant fourbar-01" in kuz["possible copy of"]
    sid = g["s2@example.org"]
    assert "typed numbers equal to what" in sid["possible copy of"] and "(Петрова Анна)" in sid["possible copy of"]
    # Orlova's typed book copies nobody: she is named only as a source (she computed, on
    # Petrova's variant, the omega_3 that Sidorov typed)
    orl = g["s5@example.org"]["possible copy of"]
    assert "identical typed numbers" not in orl and all(
        why.endswith("(Орлова Дарья) computed") for why in orl.split(": ", 1)[1].split("; "))
    assert text.count("possible copy: ") == 2                     # two clusters
    assert "not handed in by their own student" in err


def read_grades_rows(path: Path) -> list[dict]:
    return list(csv.DictReader(io.StringIO(path.read_bytes().decode("utf-8-sig"), newline="")))
