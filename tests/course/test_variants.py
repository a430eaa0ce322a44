"""`sheetkin variants` (issue 13, item 1): N distinct variants of a scheme that keep its
type of mechanism, assemble everywhere, stay away from toggles, rounded as a teacher prints
them; exercise and key books, scenes, roster.csv; reproducible; one-line refusals.

The properties are checked independently of sheetkin.course.variants: Grashof's inequality from
the lengths, the crank-slider's r + |e| < l, the solver at a finer grid than the module's."""
from __future__ import annotations

import csv
import itertools
import math
import os
import re
import zipfile
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.clirun import run
from helpers.realbooks import row_numbers

from sheetkin.cli.commands import main
from sheetkin.course.grades import all_correct
from sheetkin.course.issued import KEY_FILE, Options, given_values, read_key, read_roster
from sheetkin.course.validator import validate
from sheetkin.course.variants import BAND, MIN_DET, make_variants, parameters, ranges, write_variants
from sheetkin.kinematics.scene import SceneError, load_scene, parse_scene
from sheetkin.kinematics.solver import solve

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "workbooks").glob("*.toml"))


def text_of(name: str) -> str:
    return (ROOT / "workbooks" / name).read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def made():
    """30 variants of every bundled scene (the search itself is fast: no workbooks)."""
    return {p.name: make_variants(p.read_text(encoding="utf-8"), str(p), 30, seed=7) for p in SCENES}


def test_bundled_scenes_cover_all_five_kinds():
    kinds = {g.type for p in SCENES for g in load_scene(p).groups}
    assert kinds == {"RRR", "RRP", "RPR", "PRP", "RPP"}


@pytest.mark.parametrize("name", [p.name for p in SCENES])
def test_every_variant_assembles_far_from_toggles(made, name):
    """At the sheet's positions and on a finer revolution (0.25 deg) than the module's
    1 deg: every group assembles; |det| >= MIN_DET at the sheet (and within 5 % of it
    between the module's samples)."""
    vs = made[name]
    assert len(vs) == 30 and len({v.id for v in vs}) == 30
    for v in vs:
        sc = v.scene
        sheet = solve(sc, sc.crank_angles_deg())
        assert not any(np.any(f) for f in sheet.failed.values()), v.id
        assert all(np.min(np.abs(d)) >= MIN_DET for d in sheet.det.values()), v.id
        fine = solve(sc, np.arange(0.0, 360.0, 0.25))
        assert not any(np.any(f) for f in fine.failed.values()), v.id
        assert all(np.min(np.abs(d)) >= 0.95 * MIN_DET for d in fine.det.values()), v.id


def test_fourbar_variants_stay_crank_rockers(made):
    """Grashof: s + l <= p + q, the crank the shortest link: a crank-rocker."""
    for v in made["fourbar.toml"]:
        sc = v.scene
        (x0, y0), (x1, y1) = sc.frame["O"], sc.frame["O1"]
        links = [sc.crank.length, *sc.groups[0].lengths, math.hypot(x1 - x0, y1 - y0)]
        s, l = min(links), max(links)
        assert s + l <= sum(links) - s - l, v.id
        assert sc.crank.length == s, v.id


def test_crank_slider_variants_keep_a_full_turning_crank(made):
    """An offset crank-slider turns fully when r + |e| < l (e: the guide's offset)."""
    for v in made["crank_slider.toml"]:
        sc = v.scene
        g = sc.groups[0]
        assert sc.crank.length + abs(g.guide.point[1] - sc.frame["O"][1]) < g.length, v.id


@pytest.mark.parametrize("name", ["fourbar.toml", "shaper.toml", "slider_on_coupler.toml", "scotch_yoke.toml"])
def test_variants_differ_by_the_margin_rounded_within_the_band(made, name):
    """Each varied value (the lengths, coordinates and offsets in metres that are not 0) is
    on the millimetre grid and within +-10 % of the scene's; every two variants differ by
    at least 2 % of the scene's value in some value; the rest are the scene's own."""
    base = given_values(load_scene(ROOT / "workbooks" / name))
    varied = {n for r in ranges(parameters(text_of(name), name)) for n in r.param.names}
    assert varied and all(base[n] != 0 for n in varied)
    rows = [given_values(v.scene) for v in made[name]]
    for g in rows:
        for n, x in g.items():
            if n in varied:
                assert abs(x * 1000 - round(x * 1000)) < 1e-9 and len(repr(x).split(".")[-1]) <= 3, (n, x)
                assert abs(x - base[n]) <= BAND * abs(base[n]) + 1e-12, (n, x)
            else:
                assert x == base[n], (n, x)
    for a, b in itertools.combinations(rows, 2):
        assert any(abs(a[n] - b[n]) >= 0.02 * abs(base[n]) - 1e-12 for n in varied)


def test_vary_sets_a_range_and_other_units_round_on_their_grid():
    vs = make_variants(text_of("fourbar.toml"), "fourbar.toml", 5, 3, ["L2=0.45..0.55", "Fi_t0=10..30"])
    for v in vs:
        g = given_values(v.scene)
        assert 0.45 <= g["L2"] <= 0.55
        assert 10 <= g["Fi_t0"] <= 30 and abs(g["Fi_t0"] * 10 - round(g["Fi_t0"] * 10)) < 1e-9
    assert len({given_values(v.scene)["Fi_t0"] for v in vs}) > 1


def test_refusals_are_one_line(capsys, tmp_path):
    yoke = ROOT / "workbooks" / "scotch_yoke.toml"
    code, _, err = run(capsys, "variants", yoke, "-n", 2, "--out", tmp_path / "a", "--seed", 1,
                       "--vary", "L1=0.1..0.1", "--vary", "across_C=-0.3..-0.3")
    assert code == 2 and err.count("\n") == 1
    assert "only 1 acceptable variant of the 2 asked for" in err and "--vary" in err
    assert not (tmp_path / "a").exists()                 # nothing written
    code, _, err = run(capsys, "variants", yoke, "-n", 2, "--out", tmp_path / "a", "--vary", "L9=0.1..0.2")
    assert code == 2 and err.count("\n") == 1
    assert "no given value 'L9'" in err and "valid: L1, x_O, gx_g1, y_O" in err
    code, _, err = run(capsys, "variants", yoke, "-n", 2, "--out", tmp_path / "a", "--vary", "L1=0.2..0.1")
    assert code == 2 and "expected NAME=LO..HI" in err and err.count("\n") == 1
    code, _, err = run(capsys, "variants", yoke, "-n", 2, "--out", tmp_path / "a", "--vary", "Tol=0..1")
    assert code == 2 and "no given value 'Tol'" in err


def test_a_scheme_whose_crank_cannot_turn_is_refused(capsys, tmp_path):
    """A non-Grashof four-bar (the crank is not the shortest link) cannot be given out."""
    scene = tmp_path / "rocker.toml"
    scene.write_text(text_of("fourbar.toml").replace("length    = 0.14", "length    = 0.40"), encoding="utf-8")
    code, _, err = run(capsys, "variants", scene, "-n", 3, "--out", tmp_path / "v")
    assert code == 2 and err.count("\n") == 1
    assert "not fit for variants: group 1 cannot assemble" in err


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """Three fourbar variants on disk, through the command line."""
    out = tmp_path_factory.mktemp("variants") / "class"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "3", "--out", str(out),
                 "--seed", "11"]) == 0
    return out


def _column_d(ws) -> dict[str, object]:
    return {n: ws.cell(r, 4).value for n, r in row_numbers(ws).items()}


def test_roster_equals_the_books_input_blocks(written):
    with open(written / "roster.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert [r["variant"] for r in rows] == ["fourbar-01", "fourbar-02", "fourbar-03"]
    assert list(rows[0])[:4] == ["variant", "exercise", "key", "scene"]
    for r in rows:
        given = {k: float(v) for k, v in r.items() if k not in ("variant", "exercise", "key", "scene")}
        assert given == given_values(load_scene(written / r["scene"]))
        for which in ("exercise", "key"):
            wb = openpyxl.load_workbook(written / r[which])
            d = _column_d(wb.worksheets[0])
            assert {n: float(d[n]) for n in given} == given, (which, r["variant"])
            ws = wb.worksheets[0]                                  # the student's own cells, blank
            assert ws["D1"].value is None and ws["D2"].value is None and "student" not in d
            assert wb["scene"].sheet_state == "hidden" and wb["scene"]["C1"].value == r["variant"]
        ex = openpyxl.load_workbook(written / r["exercise"]).worksheets[0]
        key = openpyxl.load_workbook(written / r["key"]).worksheets[0]
        row = next(k for k in range(1, ex.max_row + 1) if ex.cell(k, 1).value == "x_B")
        assert ex.cell(row, 5).value is None and str(key.cell(row, 5).value).startswith("=")


def test_the_key_is_in_no_workbook(written):
    key = (written / KEY_FILE).read_text().strip()
    assert len(key) == 64 and (written / KEY_FILE).stat().st_mode & 0o077 == 0
    for book in written.glob("*.xlsx"):
        with zipfile.ZipFile(book) as z:
            assert not any(key.encode() in z.read(n) for n in z.namelist()), book


def test_same_seed_same_files_and_no_overwriting(written, tmp_path, capsys):
    again = tmp_path / "again"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "3", "--out", str(again),
                 "--seed", "11"]) == 0
    for name in ["roster.csv", "fourbar-01.toml", "fourbar-02.toml", "fourbar-03.toml"]:
        assert (again / name).read_bytes() == (written / name).read_bytes(), name
    other = tmp_path / "other"
    assert main(["variants", str(ROOT / "workbooks" / "fourbar.toml"), "-n", "3", "--out", str(other),
                 "--seed", "12"]) == 0
    assert (other / "roster.csv").read_bytes() != (written / "roster.csv").read_bytes()
    capsys.readouterr()
    key = (again / KEY_FILE).read_bytes()
    code, _, err = run(capsys, "variants", ROOT / "workbooks" / "fourbar.toml", "-n", 3, "--out", again, "--seed", 11)
    assert code == 2 and err.count("\n") == 1 and "exists; refusing to overwrite" in err and "--force" in err
    code, _, err = run(capsys, "variants", ROOT / "workbooks" / "fourbar.toml", "-n", 3, "--out", again,
                       "--seed", 13, "--force")
    # an issued class's key and roster are never overwritten: kept beside the new ones, dated
    assert code == 0 and (again / KEY_FILE).read_bytes() != key
    kept_keys = list(again.glob(KEY_FILE + "-*"))
    kept_rosters = list(again.glob("roster-*.csv"))
    assert [k.read_bytes() for k in kept_keys] == [key] and len(kept_rosters) == 1
    assert re.fullmatch(r"\.sheetkin-key-\d{8}-\d{6}", kept_keys[0].name)
    assert kept_rosters[0].read_bytes() == (written / "roster.csv").read_bytes()
    assert "kept (validate still checks the books sealed with it)" in err


def test_every_bundled_scene_writes_its_books(tmp_path):
    """Two variants of every bundled scene written out: scenes that parse to the roster's
    values, one exercise and one key book per variant; the key book validates as all
    correct against the roster (every group kind's variant sheet agrees with the solver)."""
    for p in SCENES:
        vs = make_variants(p.read_text(encoding="utf-8"), str(p), 2, seed=5)
        roster = write_variants(vs, tmp_path / p.stem, charts=False)
        with open(roster, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        assert len(rows) == 2
        for r in rows:
            sc = parse_scene((tmp_path / p.stem / r["scene"]).read_text(encoding="utf-8"))
            assert all(float(r[n]) == v for n, v in given_values(sc).items())
            assert (tmp_path / p.stem / r["exercise"]).stat().st_size > 0
        # the first key book is right against its roster row, sealed under the key
        opts = Options(read_roster(roster), read_key(tmp_path / p.stem / KEY_FILE))
        rep = validate(tmp_path / p.stem / rows[0]["key"], options=opts)
        assert all_correct(rep) and rep.seal == "ok" and rep.variant == rows[0]["variant"], (p.name, rep.error)


def test_help_documents_the_command(capsys):
    code, out, _ = run(capsys, "variants", "--help")
    assert code == 0
    for word in ("--vary", "--seed", "--force", "--min-det", "roster.csv", "crank-rocker", "millimetre"):
        assert word in " ".join(out.split()), word


def test_vary_names_are_the_input_blocks(capsys):
    with pytest.raises(SceneError, match="valid: L1, L2, L3, x_O, y_O, x_O1, y_O1, along_S2"):
        ranges(parameters(text_of("fourbar.toml")), ["Lx=1..2"])


DRAG_LINK = """title = "Double crank (drag link): the frame is the shortest link"
[frame]
O  = [0.0, 0.0]
O1 = [0.1, 0.0]
[crank]
pivot = "O"
joint = "A"
length = 0.25
phi0_deg = 0.0
step_deg = 30.0
positions = 13
omega = 10.0
epsilon = 0.0
[[group]]
type = "RRR"
links = [2, 3]
joints = ["A", "B", "O1"]
lengths = [0.3, 0.28]
branch = 1
"""


def test_a_double_crank_is_not_turned_into_a_crank_rocker():
    """With the crank shorter than the frame (L1 < 0.08 here) the drag link becomes a
    crank-rocker: it assembles everywhere, but link 3 rocks instead of turning. Such
    candidates are drawn (the range allows them, and their |det| passes 0.1) and refused."""
    rocker = parse_scene(DRAG_LINK.replace("length = 0.25", "length = 0.03"))
    from sheetkin.course.variants import assess
    assert assess(parse_scene(DRAG_LINK), 0.1) == ("", (1, 1, 1))
    assert assess(rocker, 0.1) == ("", (1, 0, 0))              # the coupler does not turn either
    vs = make_variants(DRAG_LINK, "drag.toml", 8, 2, ["L1=0.02..0.3"], min_det=0.1)
    for v in vs:
        sc = v.scene
        assert sc.crank.length > 0.1, v.id                     # the frame stays the shortest link
        links = [sc.crank.length, *sc.groups[0].lengths, 0.1]
        assert min(links) + max(links) <= sum(links) - min(links) - max(links)


def test_wide_ranges_keep_grashof():
    """L1 up to 0.4 would make the four-bar a non-Grashof triple rocker (s + l > p + q from
    L1 = 0.31): no such variant is kept."""
    vs = make_variants(text_of("fourbar.toml"), "fourbar.toml", 8, 1, ["L1=0.05..0.4", "L3=0.2..0.6"])
    for v in vs:
        sc = v.scene
        links = [sc.crank.length, *sc.groups[0].lengths, 0.53 * (given_values(sc)["y_O1"] / -0.53)]
        assert min(links) == sc.crank.length
        assert min(links) + max(links) <= sum(links) - min(links) - max(links), v.id


def test_help_constants_are_the_modules():
    from sheetkin.cli import args as cli_args
    from sheetkin.course import variants
    assert cli_args.VARIANTS_DEFAULTS == (variants.BAND, variants.MIN_DET, variants.MARGIN, variants.TRIES,
                                     variants.REVOLUTION_DEG)


def test_write_errors_name_the_file_or_the_folder(tmp_path, capsys, monkeypatch):
    """A read-only --out folder was reported by the temporary file's name
    ("out/..sheetkin-key.almuqx0p.tmp: Read-only file system"), and an --out that is a file
    as "out: File exists"."""
    import errno
    import tempfile
    scene = str(Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml")
    afile = tmp_path / "afile"
    afile.write_text("x")
    assert main(["variants", scene, "-n", "1", "--out", str(afile), "--seed", "1"]) == 2
    assert capsys.readouterr().err.strip().endswith(f"--out {afile}: not a folder")

    def read_only(*a, **kw):
        raise OSError(errno.EROFS, "Read-only file system")
    monkeypatch.setattr(tempfile, "mkstemp", read_only)
    out = tmp_path / "ro"
    assert main(["variants", scene, "-n", "1", "--out", str(out), "--seed", "1"]) == 2
    err = capsys.readouterr().err.strip()
    # the first file written names it (the key is written last since issue 30)
    assert err.startswith(f"sheetkin: error: {out}{os.sep}") and err.endswith(": Read-only file system")
    assert ".tmp" not in err and "\n" not in err


def test_vary_twice_for_one_value_is_refused():
    """--vary L2=0.45..0.55 --vary L2=0.4..0.6 used the last range without a word."""
    params = parameters(text_of("fourbar.toml"))
    with pytest.raises(SceneError, match=r"^--vary L2=0\.4\.\.0\.6: L2 is given a range twice$"):
        ranges(params, ["L2=0.45..0.55", "L2=0.4..0.6"])
    assert len(ranges(params, ["L2=0.45..0.55", "L3=0.3..0.4"])) == len(ranges(params, []))


def test_class_list_one_folder_to_hand_out_one_to_keep(tmp_path, capsys):
    """issue 34: `variants --class-list` put 16 exercises for 8 students in one folder (the
    students' own and the generic ones); now out/students holds one book per student, named
    by the student, out/teacher everything else, and the command says which to upload."""
    from sheetkin.cli.commands import main
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,i@x.ru\nАнна,Петрова,p@x.ru\nПётр,Сидоров,s@x.ru\n",
                  encoding="utf-8")
    out = tmp_path / "issued"
    scene = Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml"
    assert main(["variants", str(scene), "-n", "2", "--class-list", str(cl), "--out", str(out), "--seed", "1"]) == 0
    err = capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["students", "teacher"]
    handed = sorted(p.name for p in (out / "students").iterdir())
    assert len(handed) == 3 and all(any(n in h for h in handed) for n in ("Иванов", "Петрова", "Сидоров"))
    teacher = out / "teacher"
    kept = {p.name for p in teacher.iterdir()}
    assert {"roster.csv", ".sheetkin-key", "assignment.csv"} <= kept
    assert {f"fourbar-0{k}-{w}" for k in (1, 2) for w in ("key.xlsx", "exercise.xlsx")} <= kept
    assert not any(n in name for name in kept for n in ("Иванов", "Петрова", "Сидоров"))
    assert f"upload to Moodle {out / 'students'}" in err and f"--roster {teacher / 'roster.csv'}" in err
    assert f"{teacher}" in err.split("upload to Moodle")[1] and "never upload" in err


@pytest.mark.parametrize("layout", ["teacher", "old"])
def test_a_class_list_issue_grades_from_either_layout(tmp_path, capsys, layout):
    """The teacher's folder (out/teacher) and a class issued before it (roster, key and
    assignment.csv directly in --out): `validate --roster` checks the student's seal and
    finds the assignment beside the roster in both."""
    import json
    import shutil

    from sheetkin.cli.commands import main
    cl = tmp_path / "class.csv"
    cl.write_text("First name,Last name,Email address\nИван,Иванов,i@x.ru\nАнна,Петрова,p@x.ru\n", encoding="utf-8")
    out = tmp_path / "issued"
    scene = Path(__file__).resolve().parents[2] / "workbooks" / "fourbar.toml"
    assert main(["variants", str(scene), "-n", "2", "--class-list", str(cl), "--out", str(out), "--seed", "2"]) == 0
    home = out / "teacher"
    if layout == "old":
        for f in home.iterdir():
            shutil.move(str(f), str(out / f.name))
        home.rmdir()
        home = out
    book = next((out / "students").glob("*Петрова*"))
    capsys.readouterr()
    main(["validate", str(book), "--roster", str(home / "roster.csv"), "--json",
          "--progress", "never"])
    rep = json.loads(capsys.readouterr().out)["reports"][0]
    assert rep["seal"] == "ok" and rep["issued_to"] == "p@x.ru" and rep["variant"] == "fourbar-02"
    from sheetkin.course.identity import find_assignment
    found = find_assignment(str(home / "roster.csv"))
    assert found is not None and found.people["p@x.ru"][1:] == ("fourbar-02", book.name)


def test_the_old_roster_path_of_a_new_issue_points_to_the_teachers_folder(tmp_path):
    """`--roster OUT/roster.csv` for a class issued into OUT/teacher: one line naming where
    the roster is; without it, the plain "no such roster file"."""
    from sheetkin.course.issued import RosterError, read_roster
    (tmp_path / "teacher").mkdir()
    with pytest.raises(RosterError, match=r"^[^\n]*roster\.csv: no such roster file$"):
        read_roster(tmp_path / "roster.csv")
    (tmp_path / "teacher" / "roster.csv").write_text("variant,exercise,key,scene\n", encoding="utf-8")
    with pytest.raises(RosterError) as e:
        read_roster(tmp_path / "roster.csv")
    assert str(e.value).endswith(f"keeps it in {tmp_path / 'teacher' / 'roster.csv'}")
