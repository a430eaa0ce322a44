"""One answer in three engines (issue 20, items 4 and 5): sheetkin's evaluator, LibreOffice and
Gnumeric agree on every formula cell of every bundled book (workbooks/*.xlsx) and of a key and
an exercise book of `sheetkin variants` for every bundled scene, statuses and summaries
included; errors compare as "an error". And dead points: the four-bar of tests/helpers/scenes.py
(SHORT) is sampled exactly at its dead points (0 and 360 deg, where its discriminant is 0 in
exact arithmetic, -3.5e-18 in numpy, 0 in LibreOffice): compute, the workbook in each engine,
the evaluator and the validator decide those positions alike, and no check is red.

LibreOffice recalculates every book in one soffice run; Gnumeric takes one ssconvert process
per book (it converts one file at a time).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.engines import cached_values, differences, evaluator_values, formula_cells, gnumeric_recalc, same
from helpers.libreoffice import recalculate
from helpers.scenes import SHORT

import sheetkin
from sheetkin.course.validator import validate
from sheetkin.course.variants import make_variants, write_variants
from sheetkin.groups.motion import DEAD_POINT, at_dead_points_zero
from sheetkin.groups.rows import DEAD_POINT_TEXT
from sheetkin.kinematics.scene import load_scene, parse_scene
from sheetkin.kinematics.solver import solve
from sheetkin.sheet.workbook import write_workbook

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
SHEET = "Кинематика"


# scenes whose variants are compared: together they hold all five group kinds
VARIED = ("crank_slider", "kulisa_moving_axis", "three_group_chain")


def _variant_books(out: Path) -> list[Path]:
    """A key and an exercise book of one variant of each VARIED scene."""
    books = []
    for toml in (WORKBOOKS / f"{stem}.toml" for stem in VARIED):
        d = out / toml.stem
        write_variants(make_variants(toml.read_text(encoding="utf-8"), str(toml), 1, seed=3), d)
        books += sorted(d.glob("*-key.xlsx")) + sorted(d.glob("*-exercise.xlsx"))
    return books


@pytest.fixture(scope="module")
def engines(tmp_path_factory, soffice, ssconvert):
    """{book: (formulas, {engine: values})} for every book of the module."""
    tmp = tmp_path_factory.mktemp("engines")
    short = tmp / "short.toml"
    short.write_text(SHORT, encoding="utf-8")
    write_workbook(parse_scene(SHORT, str(short)), tmp / "short.xlsx", scene_text=SHORT)
    write_workbook(parse_scene(SHORT, str(short)), tmp / "short-exercise.xlsx", exercise=True, scene_text=SHORT)
    books = sorted(WORKBOOKS.glob("*.xlsx")) + _variant_books(tmp / "variants") + [tmp / "short.xlsx",
                                                                                   tmp / "short-exercise.xlsx"]
    assert len({b.name for b in books}) == len(books)
    lo = recalculate(books, tmp / "libreoffice")
    out = {}
    for b in books:
        formulas = formula_cells(b)
        out[b.name] = (formulas, {"sheetkin": evaluator_values(b, formulas),
                                  "libreoffice": cached_values(lo[b.resolve()], formulas),
                                  "gnumeric": cached_values(gnumeric_recalc(b, tmp / "gnumeric"), formulas)})
    return out


def _names() -> list[str]:
    return sorted(p.name for p in WORKBOOKS.glob("*.xlsx"))


@pytest.mark.parametrize("name", _names())
def test_bundled_book_one_answer(engines, name):
    formulas, values = engines[name]
    assert len(formulas) > 1000
    diff = differences(formulas, values)
    assert not diff, f"{name}: the engines disagree:\n" + "\n".join(diff)


def test_variant_books_one_answer(engines):
    """Keys and exercises of variants of scenes with all five group kinds; the exercise's
    checks say "not filled in" in every engine, the key's pass in every engine."""
    keys = [n for n in engines if n.endswith("-key.xlsx")]
    assert len(keys) == len(VARIED)
    assert {g.type for s in VARIED for g in load_scene(WORKBOOKS / f"{s}.toml").groups} == {
        "RRR", "RRP", "RPR", "PRP", "RPP"}
    for name in keys + [n for n in engines if n.endswith("-exercise.xlsx") and not n.startswith("short")]:
        formulas, values = engines[name]
        diff = differences(formulas, values)
        assert not diff, f"{name}: the engines disagree:\n" + "\n".join(diff)
        failing = {e: v[(SHEET, "G2")] for e, v in values.items()}
        assert all(f == 0 for f in failing.values()), (name, failing)
        unfilled = {e: v[(SHEET, "I2")] for e, v in values.items()}
        assert all((u > 0) == name.endswith("-exercise.xlsx") for u in unfilled.values()), (name, unfilled)


def test_check_status_and_summary_agree_with_the_old_construct_gone(engines):
    """The construct Gnumeric read differently is gone from every status cell, and the
    fourbar's statuses are 0 or n/a in all three (Gnumeric failed 46 of 46 with it)."""
    formulas, values = engines["fourbar.xlsx"]
    assert not [f for f in formulas.values() if "ISERROR(" in f and "SUMPRODUCT(--ISERROR" in f]
    status = _status_cells(formulas)
    assert len(status) >= 40
    for e, v in values.items():
        assert all(v[k] in (0, "н/д") for k in status), e
        assert v[(SHEET, "D3")].startswith("все проверки выполнены"), (e, v[(SHEET, "D3")])


def _status_cells(formulas: dict) -> list[tuple[str, str]]:
    """The check rows' status cells (column D below the summary in D3)."""
    return [k for k, f in formulas.items() if k[0] == SHEET and k[1][0] == "D" and k[1] != "D3"
            and "не заполнено" in f]


def _row_of(path: Path, name: str) -> int:
    wb = openpyxl.load_workbook(path, read_only=True)
    try:
        for r, (a,) in enumerate(wb[SHEET].iter_rows(min_col=1, max_col=1, values_only=True), start=1):
            if a == name:
                return r
    finally:
        wb.close()
    raise KeyError(name)


def test_dead_point_rule_is_one_number():
    assert float(DEAD_POINT_TEXT) == DEAD_POINT


def test_dead_points_decided_alike(engines, tmp_path):
    """SHORT at 0 and 360 deg: numpy's discriminant is -3.5e-18 before the rule, LibreOffice's 0;
    with the rule every engine and compute say "does not assemble" there, the same positions
    assemble everywhere, no check is red, and the validator passes the key."""
    scene = parse_scene(SHORT, "short.toml")
    df = sheetkin.compute(scene, allow_gaps=True)
    assembled = df["assembled"].to_numpy()
    assert not assembled[0] and not assembled[-1] and assembled[1] and assembled[-2]
    path = tmp_path / "short.xlsx"
    write_workbook(scene, path, scene_text=SHORT)
    formulas, values = engines["short.xlsx"]
    row = _row_of(path, "asm_g1")
    cols = [openpyxl.utils.get_column_letter(5 + k) for k in range(len(assembled))]
    for engine, v in values.items():
        guard = [v[(SHEET, f"{c}{row}")] for c in cols]
        assert guard == [bool(a) for a in assembled], engine
        assert v[(SHEET, "G2")] == 0, (engine, v[(SHEET, "D3")])
        status = _status_cells(formulas)
        assert all(v[k] in (0, "н/д") for k in status), engine
    # every status and summary cell is the same in all three (column D, the counts E2:I2); an
    # angle row may differ by 2 pi at a branch cut (-pi and +pi are one angle), so not every cell
    decisions = [k for k in formulas if k[0] == SHEET and (k[1][0] == "D" or k[1] in ("E2", "F2", "G2", "H2", "I2"))]
    assert len(decisions) > 20
    for k in decisions:
        first = values["sheetkin"][k]
        assert all(same(first, values[e][k]) for e in ("libreoffice", "gnumeric")), (k, formulas[k])
    report = validate(path)
    assert report.error is None and not report.failing_checks and not report.wrong, report


def test_dead_point_snap_in_numpy():
    """SHORT's RRR discriminant at 0 deg as solve_rrr computes it is -3.5e-18 (0 in exact
    arithmetic); the rule makes it 0 (does not assemble) and keeps values off the band."""
    p, q, l2, l3 = 0.3 - 0.2 * np.cos(0.0), 0.0 - 0.2 * np.sin(0.0), 0.25, 0.15
    f = (p * p + q * q + l2 * l2 - l3 * l3) / (2.0 * l2)
    raw = np.array([p * p + q * q - f * f, 1e-6, -1e-6, np.nan])
    assert -1e-17 < raw[0] < 0
    snapped = at_dead_points_zero(raw, p * p + q * q)
    assert snapped[0] == 0 and snapped[1] == raw[1] and snapped[2] == raw[2] and np.isnan(snapped[3])
    sol = solve(parse_scene(SHORT, "short.toml"), [0.0, 30.0, 360.0])
    assert sol.failed[1].tolist() == [True, False, True]
