"""Hostile input, issue 11 items 4-6: absurd scenes get one line (exit 2), nothing the user
did not ask for is lost or executed, writing failures are one line, and a batch survives
any one file."""
from __future__ import annotations

import hashlib
import importlib
import json
import os
import re
import subprocess
import sys
import warnings
import zipfile
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.clirun import run
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import sheetkin
from sheetkin.kinematics.caps import MAX_DEPTH, MAX_MAGNITUDE, MAX_POSITIONS, WORKBOOK_MAX_POSITIONS
from sheetkin.kinematics.scene import SceneError, parse_scene
from sheetkin.sheet.workbook import write_workbook

compute_module = importlib.import_module("sheetkin.kinematics.table")
validator_module = importlib.import_module("sheetkin.course.validator")

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
FOURBAR = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")


def run_process(*argv, **kw):
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
    kw.setdefault("stdout", subprocess.PIPE)
    return subprocess.run([sys.executable, "-m", "sheetkin", *map(str, argv)], env=env,
                          stderr=subprocess.PIPE, text=True, **kw)


def one_error_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1, f"expected one line on stderr, got {err!r}"
    assert lines[0].startswith("sheetkin: error: ") and "Traceback" not in err
    return lines[0]


def mutate(old: str, new: str, base: str = FOURBAR) -> str:
    assert base.count(old) == 1, old
    return base.replace(old, new)


def line_of(text: str, anchor: str) -> int:
    return next(no for no, line in enumerate(text.splitlines(), 1) if anchor in line)


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


# --------------------------------------------------------------------------- absurd scenes
HUGE = "9" * 400
ABSURD = [
    # (id, old, new, key, anchor of the line blamed (None: no line), words in the message)
    ("positions above the cap", "positions = 13", f"positions = {MAX_POSITIONS + 1}", "positions",
     "positions =", [r"at most 100,000,000"]),
    ("positions 400 digits", "positions = 13", f"positions = {HUGE}", "positions", "positions =",
     [r"400 digits", r"at most 1e\+12"]),
    ("step 0", "step_deg  = 30.0", "step_deg  = 0.0", "step_deg", "step_deg", [r"nonzero"]),
    ("1e308", "omega     = 20.0", "omega     = 1e308", "omega", "omega", [r"1e\+308", r"too large"]),
    ("1e400 reads as inf", "omega     = 20.0", "omega     = 1e400", "omega", "omega", [r"finite", r"inf"]),
    ("length 400 digits", "length    = 0.14", f"length    = {HUGE}", "length", "length    =",
     [r"400 digits"]),
    ("5000 digits", "length    = 0.14", "length    = " + "9" * 5000, None, "length    =",
     [r"thousands of digits"]),
    ("nan in a frame point", "O1 = [0.0, -0.53]", "O1 = [0.0, nan]", "O1", "O1 =", [r"finite", r"nan"]),
    ("-inf in a point", "along = 0.2129", "along = -inf", "along", "along = -inf", [r"finite", r"-inf"]),
    ("nan in gravity", 'author = "sheetkin example"', 'author = "x"\ngravity = [nan, 0.0]', "gravity",
     "gravity", [r"finite"]),
    ("inf in a lengths array", "lengths = [0.5, 0.34]", "lengths = [inf, 0.34]", "lengths", "lengths",
     [r"finite"]),
    ("nesting past the cap", 'author = "sheetkin example"', "author = " + "[" * 12 + "]" * 12, "author",
     "author", [rf"deeper than {MAX_DEPTH}"]),
    ("nesting past the recursion limit", 'author = "sheetkin example"', "author = " + "[" * 2000 + "]" * 2000,
     None, None, [r"nested too deep"]),
    ("inline tables past the recursion limit", 'author = "sheetkin example"',
     "author = " + "{a = " * 1500 + "1" + "}" * 1500, None, None, [r"nested too deep"]),
    ("control character in the title", 'title  = "Кривошипно-коромысловый механизм"',
     'title = "a\\u0007b"', "title", "title", [r"control character", r"\\x07"]),
    ("newline in the author", 'author = "sheetkin example"', 'author = "a\\nb"', "author", "author",
     [r"control character"]),
    ("control character in a key", 'author = "sheetkin example"', '"a\\u001bb" = 1', None, None,
     [r"\\x1b"]),
    ("a line too long (a dotted key of 50,000 parts)", 'author = "sheetkin example"',
     "[" + ".".join(["a"] * 50_000) + "]", None, "[a.a", [r"more than 10,000 characters"]),
    ("text too long", 'author = "sheetkin example"', 'author = "' + "x" * 5000 + '"', "author", "author",
     [r"at most 1,000"]),
]


@pytest.mark.parametrize("name,old,new,key,anchor,words", ABSURD, ids=[c[0] for c in ABSURD])
def test_absurd_scene_is_one_line_exit_2(tmp_path, capsys, name, old, new, key, anchor, words):
    text = mutate(old, new)
    path = tmp_path / "absurd.toml"
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, out, err = run(capsys, "compute", path)
    assert code == 2 and out == ""
    line = one_error_line(err)
    assert len(line) < 700
    where = f"{path}:{line_of(text, anchor)}:" if anchor else f"{path}"
    assert line.startswith(f"sheetkin: error: {where}"), line
    if key:
        assert f"'{key}'" in line, line
    for w in words:
        assert re.search(w, line), (w, line)


def test_caps_allow_what_they_document():
    """The caps are not off by one: MAX_POSITIONS positions, numbers of magnitude 1e12 and
    nesting of MAX_DEPTH levels are accepted."""
    scene = parse_scene(mutate("positions = 13", f"positions = {MAX_POSITIONS}"))
    assert scene.crank.positions == MAX_POSITIONS
    scene = parse_scene(mutate('O1 = [0.0, -0.53]', f"O1 = [0.0, {-MAX_MAGNITUDE!r}]"))
    assert scene.frame["O1"] == (0.0, -MAX_MAGNITUDE)
    with pytest.raises(SceneError, match="too large"):
        parse_scene(mutate('O1 = [0.0, -0.53]', f"O1 = [0.0, {-MAX_MAGNITUDE * 1.0000001!r}]"))
    one = parse_scene(mutate("step_deg  = 30.0", "step_deg  = 0.0").replace("positions = 13", "positions = 1"))
    assert one.crank_angles_deg() == [0.0]


def test_workbook_column_cap(tmp_path, capsys):
    path = tmp_path / "wide.toml"
    text = mutate("positions = 13", f"positions = {WORKBOOK_MAX_POSITIONS + 1}")
    path.write_text(text, encoding="utf-8")
    code, _, err = run(capsys, "workbook", path)
    line = one_error_line(err)
    assert code == 2 and f"{path}:{line_of(text, 'positions =')}: [crank] key 'positions'" in line
    assert "16,380" in line and not (tmp_path / "wide.xlsx").exists()
    good = tmp_path / "f.toml"
    good.write_text(FOURBAR, encoding="utf-8")
    code, _, err = run(capsys, "workbook", good, "--positions", WORKBOOK_MAX_POSITIONS + 1)
    assert code == 2 and one_error_line(err).startswith("sheetkin: error: --positions:")


def _passes_plan(scene):
    """The placement order as the scene parser had it before (repeated passes over the
    file's points; quadratic): the reference for the linear placement."""
    from sheetkin.kinematics.scene import link_joints
    on_link = link_joints(scene.crank, scene.groups)
    placed, plan, pending = {1}, ["crank"], list(scene.points)

    def place():
        progress = True
        while progress:
            progress = False
            for p in list(pending):
                if p.link in placed and p.origin in on_link[p.link]:
                    plan.append(p.name)
                    on_link[p.link].append(p.name)
                    pending.remove(p)
                    progress = True
    place()
    for g in scene.groups:
        plan.append(f"group {g.index}")
        placed.update(g.links)
        place()
    return plan


SHAPER = (WORKBOOKS / "shaper.toml").read_text(encoding="utf-8")


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(1, 5), st.integers(0, 12)), min_size=1, max_size=10))
def test_point_placement_order_is_the_passes_order(spec):
    """Points measured from each other in any file order are placed exactly as the
    repeated passes placed them (so no workbook changes), in linear time."""
    names = [f"P{i}" for i in range(len(spec))]
    joints = ["A", "B", "C", "O", "D"]
    text = SHAPER + "".join(
        f'[[point]]\nname = "{n}"\nlink = {link}\nfrom = "{(names + joints)[k % (len(names) + len(joints))]}"\n'
        for n, (link, k) in zip(names, spec, strict=False))
    try:
        scene = parse_scene(text)
    except SceneError:
        return
    got = [("crank" if kind == "crank" else f"group {it.index}" if kind == "group" else it.name)
           for kind, it in scene.plan]
    assert got == _passes_plan(scene)


def test_twenty_thousand_points_parse(tmp_path):
    """20,000 [[point]]s, each measured from the one before (the order the passes found
    worst): parsed and placed; the time is measured in benchmarks/scene_parse.py."""
    pts = "".join(f'[[point]]\nname = "P{i}"\nlink = 2\nfrom = "{"A" if i == 0 else f"P{i - 1}"}"\n'
                  f"along = 1e-5\n" for i in reversed(range(20_000)))
    scene = parse_scene(FOURBAR + pts)
    placed = [it.name for kind, it in scene.plan if kind == "point" and it.name.startswith("P")]
    assert placed == [f"P{i}" for i in range(20_000)]


# --------------------------------------------------------------------------- numbers out
def test_toggle_gives_empty_cells_and_a_warning_never_inf(tmp_path):
    """Near a change point (det near 0) the rates lose accuracy, and exactly at it the group
    does not assemble (the dead-point rule, `sheetkin docs dead-points`): empty cells in the
    CSV, null in JSON (strict JSON), the warnings name the angles; numpy says nothing."""
    from helpers.scenes import CHANGE_POINT
    path = tmp_path / "cp.toml"
    path.write_text(CHANGE_POINT, encoding="utf-8")
    csv = run_process("compute", path, "--dynamics", "--at", "0.001", "--at", "1e-7", "--at", "0", "--at", "30",
                      "--format", "csv", "--allow-gaps")
    assert csv.returncode == 0 and "inf" not in csv.stdout.lower()
    assert all(line.startswith("sheetkin: warning: ") for line in csv.stderr.splitlines()), csv.stderr
    assert "toggle" in csv.stderr and "cannot assemble" in csv.stderr
    js = run_process("compute", path, "--dynamics", "--at", "0", "--format", "json", "--allow-gaps")

    def strict(token):
        raise AssertionError(f"not JSON: {token}")
    data = json.loads(js.stdout, parse_constant=strict)
    assert data["positions"][0]["omega_2"] is None


def test_overflow_is_an_error_line_not_inf(tmp_path, capsys, monkeypatch):
    """A non-finite result at an assembled position away from any toggle is an overflow:
    one line naming the column and the crank angle, exit 2, no CSV."""
    real = compute_module.solution_columns

    def overflowing(scene, sol, out=None):
        cols = real(scene, sol, out)
        cols["vx_B"][1] = np.inf
        return cols
    monkeypatch.setattr(compute_module, "solution_columns", overflowing)
    path = tmp_path / "f.toml"
    path.write_text(FOURBAR, encoding="utf-8")
    code, out, err = run(capsys, "compute", path, "--format", "csv")
    line = one_error_line(err)
    assert code == 2 and out == "" and "vx_B" in line and "crank angle 30 deg" in line and "overflow" in line


def test_compute_shows_no_numpy_warnings():
    """compute() runs numpy under errstate, also in its worker threads: with warnings as
    errors, a scene with a toggle and non-assembling positions computes (exactly at the
    change point the group does not assemble, the dead-point rule: allow_gaps keeps the rest)."""
    from helpers.scenes import CHANGE_POINT
    scene = parse_scene(CHANGE_POINT)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        df = sheetkin.compute(scene, np.linspace(0.0, 360.0, 4 * compute_module.CHUNK * 2 + 1),
                              dynamics=True, allow_gaps=True)
    assert not np.isinf(df.select_dtypes("number").to_numpy()).any()


def test_table_larger_than_memory_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(compute_module, "available_memory", lambda: 1_000_000)
    path = tmp_path / "f.toml"
    path.write_text(FOURBAR.replace("positions = 13", "positions = 100000"), encoding="utf-8")
    code, out, err = run(capsys, "compute", path)
    line = one_error_line(err)
    assert code == 2 and "GB" in line and "available" in line


@pytest.mark.parametrize("value", ["-1e-07", "-1E+2", "-.5", "-3"])
def test_negative_angle_in_exponent_notation(tmp_path, capsys, value):
    path = tmp_path / "f.toml"
    path.write_text(FOURBAR, encoding="utf-8")
    code, out, err = run(capsys, "compute", path, "--at", value, "--format", "csv")
    assert code == 0, err
    assert float(out.splitlines()[1].split(",")[0]) == float(value)


@pytest.mark.parametrize("argv", [["--at", "1e300"], ["--at", "-1e13"], ["--at", "nan"], ["--at", "-inf"]])
def test_option_numbers_have_the_scene_caps(tmp_path, capsys, argv):
    path = tmp_path / "f.toml"
    path.write_text(FOURBAR, encoding="utf-8")
    code, out, err = run(capsys, "compute", path, *argv)
    assert code == 2 and out == "" and "argument --at" in one_error_line(err)


def test_negative_exponent_in_other_options(tmp_path, capsys):
    path = tmp_path / "f.toml"
    path.write_text(FOURBAR, encoding="utf-8")
    code, _, err = run(capsys, "workbook", path, "--phi0-deg", "-1e-3", "--positions", "2",
                       "-o", tmp_path / "o.xlsx")
    assert code == 0, err


# --------------------------------------------------------------------------- nothing lost
@pytest.fixture(scope="module")
def book(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("book")
    path = d / "b.xlsx"
    write_workbook(parse_scene(FOURBAR, "fourbar.toml"), path, scene_text=FOURBAR)
    return path


def _copy(src: Path, dst: Path) -> Path:
    dst.write_bytes(src.read_bytes())
    return dst


def test_outputs_onto_inputs_are_refused(tmp_path, capsys, book):
    b = _copy(book, tmp_path / "b.xlsx")
    scene = tmp_path / "s.toml"
    scene.write_text(FOURBAR, encoding="utf-8")
    (tmp_path / "sub").mkdir()
    inner = _copy(book, tmp_path / "sub" / "c.xlsx")
    os.symlink(b, tmp_path / "link.xlsx")
    os.link(b, tmp_path / "hard.xlsx")
    os.symlink(scene, tmp_path / "link.toml")
    before = {p: digest(p) for p in (b, scene, inner)}
    cases = [
        (["evaluate", b, "-o", b], "-o/--output"),
        (["evaluate", b, "--output", tmp_path / "." / "b.xlsx"], "-o/--output"),
        (["evaluate", b, "-o", tmp_path / "link.xlsx"], "-o/--output"),
        (["evaluate", b, "-o", tmp_path / "hard.xlsx"], "-o/--output"),
        (["validate", b, "--html", b], "--html"),
        (["validate", tmp_path / "sub", "--html", inner], "--html"),
        (["validate", b, "--json", "--html", tmp_path / "hard.xlsx"], "--html"),
        (["compute", scene, "-o", scene], "-o/--output"),
        (["compute", scene, "-o", tmp_path / "link.toml"], "-o/--output"),
        (["workbook", scene, "-o", tmp_path / "link.toml"], "-o/--output"),
    ]
    for argv, option in cases:
        code, out, err = run(capsys, *argv)
        line = one_error_line(err)
        assert code == 2 and option in line and "refusing to overwrite" in line, (argv, line)
    code, _, err = run(capsys, "synth", "crank-rocker", "--kw", "1.2", "--l3", "0.3", "--yd", "0",
                       "--gamma1-deg", "30", "--gamma2-deg", "80", "-o", tmp_path / "x.toml",
                       "--workbook", tmp_path / "x.toml")
    assert code == 2 and "both" in one_error_line(err)
    assert {p: digest(p) for p in (b, scene, inner)} == before
    # and a different name is fine
    code, _, err = run(capsys, "evaluate", b, "-o", tmp_path / "values.txt")
    assert code == 0 and (tmp_path / "values.txt").exists(), err


def test_workbook_check_reads_through_the_gate(tmp_path, capsys):
    """`workbook --check` meets whatever file has the workbook's name: a text file, an
    .xlsx with a DTD, a zip that is not a workbook are refused by the input gate in one line."""
    scene = tmp_path / "f.toml"
    scene.write_text(FOURBAR, encoding="utf-8")
    out = tmp_path / "f.xlsx"
    assert run(capsys, "workbook", scene)[0] == 0
    code, so, _ = run(capsys, "workbook", scene, "--check")
    assert code == 0 and "up to date" in so
    good = out.read_bytes()
    out.write_text("not a workbook\n", encoding="utf-8")
    code, _, err = run(capsys, "workbook", scene, "--check")
    assert code == 2 and "zip" in one_error_line(err)
    with zipfile.ZipFile(out, "w") as z, zipfile.ZipFile(__import__("io").BytesIO(good)) as g:
        for name in g.namelist():
            data = g.read(name)
            if name == "xl/workbook.xml":
                dtd = b'<!DOCTYPE x [<!ENTITY a "aaaa">]>'
                data = data.replace(b"?>", b"?>" + dtd, 1) if data.startswith(b"<?xml") else dtd + data
            z.writestr(name, data)
    code, _, err = run(capsys, "workbook", scene, "--check")
    assert code == 2 and "DTD" in one_error_line(err)


def _text_cells_scene(title: str, author: str) -> str:
    return (FOURBAR.replace('title  = "Кривошипно-коромысловый механизм"', f"title = {json.dumps(title)}")
            .replace('author = "sheetkin example"', f"author = {json.dumps(author)}"))


INJECTIONS = [("=1+1", "@SUM(1,2)"), ("+A1", "-2+3"), ('=HYPERLINK("http://x","y")', "=cmd|' /C calc'!A0")]


def test_scene_text_is_written_as_text_not_formulas(tmp_path, soffice):
    """Title and author starting with = + - @ are text cells in the file, and stay text
    after LibreOffice opens, recalculates and saves the workbook. The title is E1 (D1-D2
    hold the student's name and group); the author is a line of the scene sheet's text."""
    from helpers.libreoffice import recalculate
    paths = []
    for k, (title, author) in enumerate(INJECTIONS):
        text = _text_cells_scene(title, author)
        path = tmp_path / f"inj{k}.xlsx"
        write_workbook(parse_scene(text, "inj.toml"), path, scene_text=text)
        with zipfile.ZipFile(path) as z:
            sheet = z.read("xl/worksheets/sheet1.xml").decode()
        cell = re.search(r'<c r="E1"[^>]*>.*?</c>', sheet).group()
        assert "<f>" not in cell and 't="f"' not in cell, cell
        paths.append(path)
    saved = recalculate(paths, tmp_path / "lo")
    for (title, author), path in zip(INJECTIONS, paths, strict=False):
        wb = openpyxl.load_workbook(saved[path.resolve()])
        ws = wb.worksheets[0]
        assert (ws["E1"].value, ws["E1"].data_type) == (title, "s")
        line = f"author = {json.dumps(author)}"
        assert [(c.value, c.data_type) for row in wb["scene"].iter_rows() for c in row
                if c.value == line] == [(line, "s")]


# --------------------------------------------------------------------------- writing fails
@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_full_disk_is_one_line_naming_the_file(tmp_path, capsys, book):
    scene = tmp_path / "f.toml"
    scene.write_text(FOURBAR, encoding="utf-8")
    full_xlsx = tmp_path / "full.xlsx"
    os.symlink("/dev/full", full_xlsx)
    for argv, name in [(["compute", scene, "-o", "/dev/full"], "/dev/full"),
                       (["evaluate", book, "-o", "/dev/full"], "/dev/full"),
                       (["validate", book, "--html", "/dev/full"], "/dev/full"),
                       (["workbook", scene, "-o", full_xlsx], str(full_xlsx)),
                       (["synth", "crank-rocker", "--kw", "1.2", "--l3", "0.3", "--yd", "0",
                         "--gamma1-deg", "30", "--gamma2-deg", "80", "--workbook", full_xlsx], str(full_xlsx))]:
        code, _, err = run(capsys, *argv)
        assert code == 2 and one_error_line(err) == f"sheetkin: error: {name}: No space left on device", err
    with open("/dev/full", "w") as full:
        r = run_process("compute", scene, stdout=full)
    assert r.returncode == 2 and one_error_line(r.stderr) == "sheetkin: error: stdout: No space left on device"


def test_closed_stdout_is_one_line(tmp_path):
    """`sheetkin compute x.toml | head -1`: the reader is gone; quiet (no line, no traceback), 141."""
    scene = tmp_path / "f.toml"
    scene.write_text(FOURBAR, encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
    p = subprocess.Popen([sys.executable, "-m", "sheetkin", "compute", scene, "--format", "csv"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    p.stdout.close()
    err = p.stderr.read().decode()
    p.wait(60)
    assert p.returncode == 141 and err == ""      # quiet, as `cat big | head` is


def test_internal_error_is_one_line(tmp_path, capsys, monkeypatch):
    """A bug anywhere (here: a crash inside compute) is one line with the exception's type
    and a request to report it, exit 70; SHEETKIN_DEBUG=1 would show the traceback."""
    def crash(*a, **k):
        raise KeyError("boom")
    monkeypatch.setattr("sheetkin.views.output.write_compute", crash)   # what `compute` runs (imported on use)
    monkeypatch.delenv("SHEETKIN_DEBUG", raising=False)
    scene = tmp_path / "f.toml"
    scene.write_text(FOURBAR, encoding="utf-8")
    code, _, err = run(capsys, "compute", scene)
    lines = err.splitlines()
    assert code == 70 and len(lines) == 1 and "internal error: KeyError" in lines[0] and "report" in lines[0]


# --------------------------------------------------------------------------- the batch survives
def test_batch_reports_every_file(tmp_path, capsys, monkeypatch, book):
    """Good files, a gate-refused file, a file with a malformed cell and a file whose
    validation crashes (monkeypatched): every file is reported, the crash as that file's
    one-line error with its exception type, and the exit code is 2 (unusable input)."""
    folder = tmp_path / "class"
    folder.mkdir()
    good = [_copy(book, folder / f"good{k}.xlsx") for k in range(2)]
    (folder / "refused.xlsx").write_text("a text file, not a workbook\n", encoding="utf-8")
    wb = openpyxl.load_workbook(book)
    ws = wb.worksheets[0]
    rows = {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1)}
    ws.cell(rows["omega_3"], 6).value = "=SIN(1,2)+((("
    wb.save(folder / "malformed.xlsx")
    crash = _copy(book, folder / "crash.xlsx")
    real = validator_module._validate

    def crashing(path, *args):
        if Path(path).name == crash.name:
            raise RecursionError("maximum recursion depth exceeded")
        return real(path, *args)
    monkeypatch.setattr(validator_module, "_validate", crashing)
    code, out, err = run(capsys, "validate", folder, "--json", "--progress", "never")
    reports = {Path(r["path"]).name: r for r in json.loads(out)["reports"]} if out.startswith("{") \
        else {Path(r["path"]).name: r for r in json.loads(out)}
    assert set(reports) == {"good0.xlsx", "good1.xlsx", "refused.xlsx", "malformed.xlsx", "crash.xlsx"}
    assert all(reports[g.name]["ok"] for g in good)
    assert reports["refused.xlsx"]["error"]
    msg = reports["crash.xlsx"]["error"]
    assert "\n" not in msg and "RecursionError" in msg and "report" in msg and msg.startswith(str(crash))
    assert reports["malformed.xlsx"]["error"] or not reports["malformed.xlsx"]["ok"]
    assert code == 2
    code, out, _ = run(capsys, "validate", *good)
    assert code == 0
