"""The outputs of `sheetkin validate` for a fixed set of books, written into a folder: a
byte-identity harness for refactoring course/ and cmd_validate (issue 29).

    PYTHONPATH=$PWD python tools/validate_outputs.py OUT [--inputs DIR]
    diff -r BASELINE OUT

The books are made once into --inputs (default /tmp/sheetkin-validate-inputs) and reused:
the same bytes and file times on every run, so a rerun after a change compares like with
like. They are made the way tests/classbooks.py makes a class (openpyxl, no LibreOffice):
the bundled four-bar's variants (`variants -n 3 --seed 2026`) with their exercises and keys,
honest books, a sign error, rounded numbers typed over formulas, changed given data, a
byte-for-byte copy, a copy of typed numbers, an unusable file; and a class issued with
`--class-list`, handed in as Moodle's zip (one student handing in another's book).

For every run: stdout, stderr and the exit code, the text report in ru and en, --json,
--html and --grades. Masked: only the output folder (named in "GRADES.csv: ... graded"
lines), as <OUT>. The inputs' paths are fixed (--inputs) and the outputs carry no time; a
run into another --inputs folder differs by its paths only.
"""
from __future__ import annotations

import argparse
import csv
import io
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOURBAR = ROOT / "workbooks" / "fourbar.toml"
STUDENTS = (("Иванов", "Иван"), ("Петрова", "Анна"), ("Сидоров", "Пётр"), ("Кузнецов", "Олег"))


def sheetkin(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), SHEETKIN_DEBUG="")
    return subprocess.run([sys.executable, "-m", "sheetkin", *args], capture_output=True, env=env, cwd=ROOT)


def _issued(folder: Path) -> dict[str, tuple[Path, Path]]:
    """{variant: (exercise, key)} from the folder's roster.csv."""
    rows = list(csv.DictReader(io.StringIO((folder / "roster.csv").read_text(encoding="utf-8-sig"))))
    out = {}
    for row in rows:
        vid = next(v for k, v in row.items() if k and "variant" in k.lower())
        books = [v for v in row.values() if isinstance(v, str) and v.lower().endswith(".xlsx")]
        key = next(b for b in books if "key" in Path(b).name.lower())
        exercise = next(b for b in books if b != key)
        out[vid] = tuple((p if Path(p).is_absolute() else folder / p) for p in (exercise, key))
    return out


def make_inputs(d: Path) -> None:
    sys.path.insert(0, str(ROOT / "tests"))
    from helpers.classbooks import both, fill, flip_sign, row_values, set_input, type_numbers
    d.mkdir(parents=True)
    # the bundled class: three variants, their exercises and keys
    assert sheetkin("variants", str(FOURBAR), "-n", "3", "--seed", "2026", "--out", str(d / "issued")).returncode == 0
    issued = _issued(d / "issued")
    v1, v2, v3 = list(issued)
    books = d / "books"
    books.mkdir()
    om = row_values(issued[v3][1], "omega_2")
    fill(*issued[v1], books / "honest.xlsx", student="Иванов Иван", group="ГМ-21")
    fill(*issued[v2], books / "honest2.xlsx", student="Петрова Анна", group="ГМ-21")
    fill(*issued[v2], books / "wrong.xlsx", student="Сидоров Пётр", group="ГМ-21", change=flip_sign("omega_3"))
    fill(*issued[v3], books / "typed.xlsx", student="Кузнецов Олег", group="ГМ-21",
         change=type_numbers("omega_2", om))
    fill(*issued[v3], books / "typed_precise.xlsx", student="Смирнов Илья", group="ГМ-21",
         change=type_numbers("omega_2", om, 9))
    fill(*issued[v1], books / "changed.xlsx", student="Орлова Дарья", group="ГМ-21", change=set_input("L1", 0.05))
    fill(*issued[v2], books / "copied_typed.xlsx", student="Волков Антон", group="ГМ-21",
         change=both(type_numbers("omega_2", om), set_input("L1", 0.05)))
    fill(*issued[v1], books / "formula_copy.xlsx", student="=cmd|' /C calc'!A0", group="ГМ-21",
         change=flip_sign("omega_3"))
    shutil.copy(books / "honest.xlsx", books / "copied_bytes.xlsx")
    shutil.copy(issued[v2][0], books / "exercise_as_is.xlsx")
    shutil.copy(issued[v3][1], books / "key_as_is.xlsx")
    (books / "unusable.xlsx").write_bytes(b"not a workbook\n")
    # a class issued by --class-list, handed in as Moodle's zip
    cl = d / "class.csv"
    cl.write_text("Фамилия;Имя;Адрес электронной почты\n" + "".join(
        f"{last};{first};s{k}@example.org\n" for k, (last, first) in enumerate(STUDENTS)), encoding="utf-8")
    out = d / "assigned"
    assert sheetkin("variants", str(FOURBAR), "-n", "3", "--class-list", str(cl), "--out", str(out),
                    "--seed", "2026").returncode == 0
    keys = {vid: ek[1] for vid, ek in _issued(out / "teacher").items()}
    rows = csv.DictReader(io.StringIO((out / "teacher" / "assignment.csv").read_text(encoding="utf-8")))
    given = {next(v for k, v in r.items() if k.startswith("identifier")): r for r in rows
             if not r["student"].startswith("#")}
    filled = d / "filled"
    filled.mkdir()
    for k in range(len(STUDENTS)):
        r = given[f"s{k}@example.org"]
        change = flip_sign("omega_3") if k == 1 else None
        fill(out / "students" / r["exercise"], keys[r["variant"]], filled / f"s{k}.xlsx", change=change)
    with zipfile.ZipFile(d / "submissions.zip", "w") as zf:
        for k, (last, first) in enumerate(STUDENTS):
            src = "s0.xlsx" if k == 3 else f"s{k}.xlsx"            # Kuznetsov hands in Ivanov's book
            info = zipfile.ZipInfo(f"{first} {last}_{700 + k}_assignsubmission_file_/{src}", (2026, 1, 1, 0, 0, 0))
            zf.writestr(info, (filled / src).read_bytes())


def runs(d: Path) -> dict[str, list[str]]:
    """name -> validate's arguments (outputs added per run)."""
    books = sorted(str(p) for p in (d / "books").glob("*.xlsx"))
    roster = str(d / "issued" / "roster.csv")
    out: dict[str, list[str]] = {}
    for lang in ("ru", "en"):
        out[f"class-{lang}"] = [*books, "--roster", roster, "--lang", lang]
        out[f"class-noroster-{lang}"] = [*books, "--lang", lang]
        out[f"moodle-{lang}"] = [str(d / "submissions.zip"), "--roster",
                                 str(d / "assigned" / "teacher" / "roster.csv"),
                                 "--class-list", str(d / "class.csv"), "--lang", lang]
    out["class-default-lang"] = [*books, "--roster", roster]
    out["class-accept"] = [*books, "--roster", roster, "--accept-changed-inputs", "--accept-typed"]
    for b in books:
        if Path(b).stem in ("wrong", "typed", "changed", "unusable"):
            out[f"one-{Path(b).stem}"] = [b, "--roster", roster]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--inputs", type=Path, default=Path("/tmp/sheetkin-validate-inputs"))
    a = ap.parse_args()
    if not a.inputs.exists():
        make_inputs(a.inputs)
    a.out.mkdir(parents=True, exist_ok=True)
    for name, args in runs(a.inputs).items():
        o = a.out / name
        o.mkdir(exist_ok=True)
        common = ["validate", *args, "--progress", "never", "--jobs", "1"]
        files = ["--html", str(o / "report.html"), "--grades", str(o / "grades.csv")]
        text = files if "--class-list" in args else []       # --class-list needs --grades
        for tag, extra in (("text", text), ("json", ["--json", *files])):
            p = sheetkin(*common, *extra)
            # the one thing masked: the output folder, named in "GRADES.csv: written" lines
            (o / f"{tag}.stdout").write_bytes(p.stdout.replace(bytes(o), b"<OUT>"))
            (o / f"{tag}.stderr").write_bytes(p.stderr.replace(bytes(o), b"<OUT>"))
            (o / f"{tag}.code").write_text(f"{p.returncode}\n")
        print(name, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
