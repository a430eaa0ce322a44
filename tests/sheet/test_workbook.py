"""The real spreadsheet is the test: generated workbooks recalculated in LibreOffice.

Every workbook below is generated, (for some) edited with openpyxl as a user would, and
recalculated by LibreOffice in ONE soffice run (a session fixture); then every accepted-
value row is compared with the reference solver: |difference| <= 1e-9 relative, absolute
for values below 1 (angles modulo 360).
"""
from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.libreoffice import is_error, recalculate
from helpers.scenes import FOURBAR, OFFSET_CHAIN, SIX_BAR
from helpers.sheetrows import TOL, compare_accepted, row_values, rows_of, set_input

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.kinematics.scene import override_crank
from sheetkin.sheet.workbook import (
    MARKERS,
    SCENE_SHEET,
    build_workbook,
    built_fingerprint,
    embedded_scene_text,
    write_workbook,
)
from sheetkin.xlsx.cells import read_book

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
BUNDLED = sorted(p.stem for p in WORKBOOKS.glob("*.toml"))

# a four-bar whose coupler is too short for part of the revolution (gaps ~18.7..161.3 deg)
SHORT_COUPLER = FOURBAR.replace("lengths = [0.5, 0.34]", "lengths = [0.45, 0.2]").replace(
    "O1 = [0.0, -0.53]", "O1 = [0.0, -0.6]")
@pytest.fixture(scope="session")
def books(soffice, tmp_path_factory):
    """Generate every workbook the tests need, then recalculate them all in one soffice run."""
    src = tmp_path_factory.mktemp("generated")
    made: dict[str, tuple[Path, sheetkin.Scene]] = {}

    def make(key, text, *, name=None, **kw):
        scene = sheetkin.parse_scene(text, f"{key}.toml")
        path = src / f"{key}.xlsx"
        write_workbook(scene, path, scene_text=text, **kw)
        made[key] = (path, scene)
        return path

    for stem in BUNDLED:
        make(stem, (WORKBOOKS / f"{stem}.toml").read_text(encoding="utf-8"))
    make("english", (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8"), lang="en")
    # live: L1 and the crank's omega changed after generation
    live = make("live", (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8"))
    set_input(live, "L1", 0.12)
    set_input(live, "Fi_t0", -7.5)
    make("gaps", SHORT_COUPLER)
    make("offset_chain", OFFSET_CHAIN)
    make("six_bar", SIX_BAR)
    text360, _ = override_crank((WORKBOOKS / "shaper.toml").read_text(encoding="utf-8"), "shaper360",
                                positions=360, step_deg=-1.0)
    make("shaper360", text360)
    make("exercise", (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8"), exercise=True)
    # a mistake on purpose: eps_3's formula with its sign flipped in every column
    broken = make("broken", (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8"))
    wb = openpyxl.load_workbook(broken)
    ws = wb.worksheets[0]
    r = rows_of(ws)["eps_3"]
    for k in range(13):
        cell = ws.cell(r, 5 + k)
        cell.value = "=-(" + cell.value[1:] + ")"
    wb.save(broken)
    out = recalculate([p for p, _ in made.values()], tmp_path_factory.mktemp("recalculated"))
    return {key: (openpyxl.load_workbook(out[path.resolve()], data_only=True).worksheets[0], scene, path)
            for key, (path, scene) in made.items()}


@pytest.mark.parametrize("key", BUNDLED + ["english", "offset_chain", "six_bar"])
def test_accepted_values_equal_the_solver(books, key):
    ws, scene, _ = books[key]
    compare_accepted(ws, scene, sheetkin.compute(scene))
    assert ws["D3"].value.startswith("all checks pass" if key == "english" else "все проверки выполнены")


def test_formulas_are_live(books):
    """L1 and Fi_t changed in the input block after generation: everything follows."""
    ws, scene, _ = books["live"]
    changed = dataclasses.replace(scene, crank=dataclasses.replace(scene.crank, length=0.12, omega=-7.5))
    df = sheetkin.compute(changed)
    assert df["v_A"].iloc[0] == pytest.approx(0.9)          # 0.12 * 7.5: the change is real
    compare_accepted(ws, changed, df)
    assert ws["D3"].value.startswith("все проверки выполнены")


def test_non_assembling_columns_show_a_marker_not_errors(books):
    ws, scene, _ = books["gaps"]
    df = sheetkin.compute(scene, allow_gaps=True)
    ok = df["assembled"].to_numpy()
    assert ok.any() and not ok.all()
    rows = rows_of(ws)
    errors = [(ws.cell(r, c).coordinate, ws.cell(r, c).value) for r in range(1, ws.max_row + 1)
              for c in range(1, ws.max_column + 1) if is_error(ws.cell(r, c).value)]
    assert not errors, f"error cells: {errors[:5]}"
    for name in sheetkin.column_names(scene):
        got = row_values(ws, rows[name], len(df))
        gap_cells = {got[k] for k in np.flatnonzero(~ok)}
        if name == "phi_1" or name.endswith("_A"):
            continue                                        # the crank always moves
        assert gap_cells == {MARKERS["ru"]}, f"{name}: {gap_cells}"
    for name in sheetkin.column_names(scene):     # the assembled columns equal the solver
        got = row_values(ws, rows[name], len(df))
        ref = df[name].to_numpy()
        for k in np.flatnonzero(ok):
            d = abs(got[k] - ref[k])
            if name.startswith("phi_"):
                d = min(d, 360 - d)
            assert d <= TOL * max(1.0, abs(ref[k])), (name, k, got[k], ref[k])
    assert ws["D3"].value.startswith("все проверки выполнены")       # checks skip the marked columns


def test_360_columns_and_numeric_derivative_checks(books):
    """With a 1 deg step the central-difference checks are active, and they pass."""
    ws, scene, _ = books["shaper360"]
    compare_accepted(ws, scene, sheetkin.compute(scene))
    rows = rows_of(ws)
    fd = [name for name in rows if name.startswith("fd_")]
    assert len(fd) >= 8
    for name in fd:
        vals = row_values(ws, rows[name], 360)
        assert vals[0] == "н/д" and vals[-1] == "н/д"
        assert all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals[1:-1]), name
        assert ws.cell(rows[name], 4).value == 0, name
    assert ws["D3"].value.startswith("все проверки выполнены")


def test_bundled_steps_are_too_coarse_for_numeric_derivatives(books):
    ws, _, _ = books["fourbar"]
    rows = rows_of(ws)
    assert set(row_values(ws, rows["fd_vx_B"], 13)) == {"н/д"}


def test_a_wrong_formula_is_caught_by_the_checks(books):
    """eps_3 with its sign flipped: the acceleration of B through link 3 no longer agrees."""
    ws, _, _ = books["broken"]
    rows = rows_of(ws)
    assert ws.cell(rows["chk_a_B_3"], 4).value == 1
    assert ws.cell(rows["chk_v_B_3"], 4).value == 0
    failing = [name for name, r in rows.items() if str(name).startswith("chk") and ws.cell(r, 4).value != 0]
    # the accelerations put back into their system, B's and S3's accelerations through link 3
    assert failing == ["chk_asys_g1", "chk_a_B_3", "chk_a_S3_3"]
    # the summary counts them apart from the passing and the inactive ones, in Russian plurals
    # (D3 short, as it prints on every page; the counts in E2:I2)
    assert ws["D3"].value == "есть невыполненные проверки: 3 проверки"
    assert [ws.cell(2, c).value for c in range(5, 10)] == [46, 27, 3, 16, 0]
    assert (ws["E2"].value, ws["F2"].value, ws["G2"].value, ws["H2"].value, ws["I2"].value) == (46, 27, 3, 16, 0)


def test_inactive_checks_say_na_not_a_green_zero(books):
    """At 30 deg the numeric-derivative checks are off: their status is "н/д", coloured
    grey by a rule that comes before the green one."""
    ws, _, _ = books["fourbar"]
    rows = rows_of(ws)
    fd = [n for n in rows if str(n).startswith("fd_")]
    assert fd and all(ws.cell(rows[n], 4).value == "н/д" for n in fd)
    assert all(ws.cell(rows[n], 4).value == 0 for n in rows if str(n).startswith("chk"))
    assert ws["H2"].value == len(fd) and ws["G2"].value == 0


def test_exercise_workbook(books):
    """Computed rows empty; inputs, names, units and check rows kept; checks fail until filled."""
    ws, scene, path = books["exercise"]
    raw = openpyxl.load_workbook(path).worksheets[0]
    rows = rows_of(raw)
    for name in sheetkin.column_names(scene):
        vals = row_values(raw, rows[name], 13)
        if name == "phi_1":
            assert all(str(v).startswith("=") for v in vals)
        else:
            assert vals == [None] * 13, name
        assert raw.cell(rows[name], 2).value is not None           # the unit stays
    assert raw.cell(rows["L1"], 4).value == 0.14
    assert str(raw.cell(rows["chk_AB"], 5).value).startswith("=")
    # nothing filled in yet: every check says so (grey), none is a green 0, none counts as failing
    checks = [n for n in rows if str(n).startswith(("chk", "fd_"))]
    assert {ws.cell(rows[n], 4).value for n in checks} == {"не заполнено"}
    assert ws["D3"].value == "заполнены не все строки"
    assert [ws.cell(2, c).value for c in range(5, 10)] == [0, 0, 0, 0, len(checks)]
    assert not any(ws.cell(rows[n], 4).value == 0 for n in checks)
    # no green: on every check row the first colour rule (it stops the others) is grey while
    # the status is text, and the status cell's grey rule comes before its green one
    rules = {}
    for cf in raw.conditional_formatting:
        for rule in cf.rules:
            rules.setdefault(str(cf.sqref), []).append((rule.priority, rule.formula[0], rule.stopIfTrue))
    for n in checks:
        r = rows[n]
        # (blank, white on white, while not filled in; then grey while the status is text)
        first, second = sorted(rules[f"E{r}:Q{r}"])[:2]
        assert first[1:] == (f'$D{r}="не заполнено"', True), (n, first)
        assert second[1:] == (f"NOT(ISNUMBER($D{r}))", True), (n, second)
        order = [f for _, f, _ in sorted(rules[f"D{r}"])]
        assert order.index(f"ISTEXT(D{r})") < order.index(f"AND(ISNUMBER(D{r}),D{r}=0)")


def test_only_what_the_scene_needs():
    """A four-bar's workbook has no slider or slotted-lever rows, and vice versa."""
    names = {}
    for stem in ("fourbar", "slotted_lever"):
        scene = sheetkin.load_scene(WORKBOOKS / f"{stem}.toml")
        ws = build_workbook(scene).worksheets[0]
        names[stem] = set(rows_of(ws))
    assert not {n for n in names["fourbar"] if re.match(r"(h|cu|su|e|s_[pm])_g|s_|vs_|as_", str(n))}
    assert not {n for n in names["slotted_lever"] if re.match(r"(P|Q|F|psi_[pm]|xi_[pm])_g", str(n))}
    assert "x_B" in names["fourbar"] and "x_B" not in names["slotted_lever"]


@pytest.mark.parametrize("stem", BUNDLED)
def test_a_check_row_at_least_every_8_rows(stem):
    """The lecture (step 10): check the results every 5-8 rows of the program."""
    ws = build_workbook(sheetkin.load_scene(WORKBOOKS / f"{stem}.toml")).worksheets[0]
    rows = rows_of(ws)
    start = rows["i"]
    gap = worst = 0
    for r in range(start, ws.max_row + 1):
        status = ws.cell(r, 4).value
        if ws.cell(r, 2).value is None and ws.cell(r, 3).value is None:
            continue                                    # a section heading
        gap = 0 if "ISERROR(" in str(status) else gap + 1         # a check row's status (sheetkin/sheet/checks.py)
        worst = max(worst, gap)
    assert 5 <= worst <= 8


def test_names_units_descriptions_and_language():
    scene = sheetkin.load_scene(WORKBOOKS / "fourbar.toml")
    ru = build_workbook(scene).worksheets[0]
    en = build_workbook(scene, lang="en").worksheets[0]
    r = rows_of(ru)["omega_3"]
    assert (ru.cell(r, 1).value, ru.cell(r, 2).value, en.cell(r, 2).value) == ("omega_3", "рад/с", "rad/s")
    assert re.search("[а-я]", ru.cell(r, 3).value) and not re.search("[а-я]", en.cell(r, 3).value)
    assert ru.title == "Кинематика" and en.title == "Kinematics"
    # every computed cell is a formula; nothing is baked in
    for name in sheetkin.column_names(scene):
        assert all(str(v).startswith("=") for v in row_values(ru, rows_of(ru)[name], 13)), name


def test_scene_is_embedded(tmp_path):
    text = (WORKBOOKS / "shaper.toml").read_text(encoding="utf-8")
    scene = sheetkin.parse_scene(text, "shaper.toml")
    write_workbook(scene, tmp_path / "b.xlsx", scene_text=text)
    back = embedded_scene_text(read_book(tmp_path / "b.xlsx").sheets[SCENE_SHEET])
    assert back == text
    assert sheetkin.parse_scene(back, "shaper.toml") == scene


def test_charts():
    scene = sheetkin.load_scene(WORKBOOKS / "fourbar.toml")
    charts = built_fingerprint(build_workbook(scene))["charts"]
    assert len(charts) == 5          # the mechanism, trajectories, speeds, accelerations, omegas
    ws = build_workbook(scene).worksheets[0]
    rows = rows_of(ws)
    flat = " ".join(" ".join(c) for c in charts)
    for name in ("x_B", "y_B", "v_S2", "a_S3", "omega_2", "omega_3", "phi_1"):
        assert f"$E${rows[name]}:$Q${rows[name]}" in flat, name


@pytest.mark.parametrize("stem", BUNDLED)
def test_committed_workbooks_are_not_stale(stem, capsys):
    code = main(["workbook", "--check", str(WORKBOOKS / f"{stem}.toml")])
    assert code == 0, capsys.readouterr().out


def test_check_finds_a_stale_workbook(tmp_path, capsys):
    text = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    (tmp_path / "f.toml").write_text(text)
    assert main(["workbook", str(tmp_path / "f.toml")]) == 0
    assert main(["workbook", "--check", str(tmp_path / "f.toml")]) == 0
    (tmp_path / "f.toml").write_text(text.replace("length    = 0.14", "length    = 0.15"))
    assert main(["workbook", "--check", str(tmp_path / "f.toml")]) == 1
    assert "stale" in capsys.readouterr().out
    (tmp_path / "f.xlsx").unlink()
    assert main(["workbook", "--check", str(tmp_path / "f.toml")]) == 1


def test_workbook_command_options(tmp_path, capsys):
    src = WORKBOOKS / "shaper.toml"
    out = tmp_path / "s.xlsx"
    assert main(["workbook", str(src), "-o", str(out), "--positions", "24", "--step-deg", "-15",
                 "--lang", "en"]) == 0
    ws = openpyxl.load_workbook(out).worksheets[0]
    assert ws.max_column == 4 + 24
    scene = sheetkin.parse_scene(embedded_scene_text(read_book(out).sheets[SCENE_SHEET]))
    assert (scene.crank.positions, scene.crank.step_deg) == (24, -15.0)
    assert main(["workbook", str(src), str(WORKBOOKS / "fourbar.toml"), "-o", str(out)]) == 2
    assert main(["workbook", str(src), "-o", str(tmp_path / "s.txt")]) == 2
    assert main(["workbook", str(tmp_path / "missing.toml")]) == 2
    err = capsys.readouterr().err
    assert "-o names one file" in err and ".xlsx" in err and "no such file" in err


def test_readme_pictures_render(soffice, pdftoppm, tmp_path):
    """tests/helpers/render_pictures.py (the README's pictures) works: PNG pages of real size (the
    animations are tested in test_animate.py)."""
    from helpers.render_pictures import render
    for png in render(tmp_path):
        data = png.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
        assert width > 600 and height > 400, (png, width, height)


@pytest.mark.parametrize("stem", BUNDLED)
def test_numeric_derivative_checks_pass_at_the_largest_step_they_run(stem, tmp_path):
    """At |Delta_Fi| = FD_MAX_STEP_DEG the central-difference checks are active and, for
    every bundled mechanism (the quick-return ones included), within their tolerance: a red
    check there would be the finite differences' own error, not a mistake."""
    from sheetkin.sheet.workbook import FD_MAX_STEP_DEG
    from sheetkin.xlsx.evaluator import evaluate
    text = (WORKBOOKS / f"{stem}.toml").read_text(encoding="utf-8")
    sign = 1.0 if sheetkin.parse_scene(text).crank.step_deg > 0 else -1.0
    text, scene = override_crank(text, stem, positions=int(360 / FD_MAX_STEP_DEG) + 1,
                                 step_deg=sign * FD_MAX_STEP_DEG)
    path = tmp_path / f"{stem}.xlsx"
    write_workbook(scene, path, scene_text=text)
    ws = openpyxl.load_workbook(path).worksheets[0]
    fd = {name: r for name, r in rows_of(ws).items() if str(name).startswith("fd_")}
    assert fd
    book = evaluate(path)
    sheet = book.order[0]
    for name, r in fd.items():
        assert isinstance(book.value(sheet, r, 6), float), name          # active, not n/a
        assert book.value(sheet, r, 4) == 0, name
