"""Validation that scales (sheetkin.course.batch, sheetkin.course.reference): the reference of a variant
is the generated sheet with the variant's inputs, evaluated, and equals the workbook rebuilt
for that variant cell for cell; a batch gives the same reports in one process and in a
pool, in the order of the files."""
from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import openpyxl
import pytest

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.course import reference
from sheetkin.course.batch import validate_many
from sheetkin.course.caches import clear_caches
from sheetkin.course.grades import report_dict
from sheetkin.course.issued import Options
from sheetkin.sheet.workbook import write_workbook

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"


def _same_book(a, b, scene):
    """Equal on every graded row: the reference leaves out the sheet's own check rows and
    the summary above row 5 (reference.template_sheet), and nothing else."""
    (sa,), (sb,) = a.order, b.order
    checks = reference.check_row_names(scene)
    names = b.sheets[sb].consts
    keep = [r for r in range(5, b.tag[sb].shape[0]) if names.get((r, 1)) not in checks]
    assert len(keep) > 40
    assert np.array_equal(a.tag[sa][keep], b.tag[sb][keep])
    assert np.array_equal(a.num[sa][keep], b.num[sb][keep], equal_nan=True)
    assert list(a.txt[sa][keep].ravel()) == list(b.txt[sb][keep].ravel())
    dropped = {r for r in range(5, b.tag[sb].shape[0]) if names.get((r, 1)) in checks}
    # the check rows keep their cells per position (which apply is the reference's), not their status
    kept = reference.template_sheet(scene)[0].formulas
    assert dropped and not any((r in dropped and c < 5) or r < 5 for r, c in kept)


def _variants(scene):
    c = scene.crank
    g = scene.groups[0]
    yield scene
    yield dataclasses.replace(scene, crank=dataclasses.replace(c, length=c.length * 0.9, phi0_deg=7.5, omega=-3.0))
    yield dataclasses.replace(scene, crank=dataclasses.replace(c, step_deg=2.0, positions=9))
    if hasattr(g, "branch"):            # a kind with two assemblies: the other branch
        flipped = dataclasses.replace(g, params=dataclasses.replace(g.params, branch=-g.branch))
        yield dataclasses.replace(scene, groups=(flipped,) + scene.groups[1:],
                                  plan=tuple((k, flipped if it is g else it) for k, it in scene.plan))


@pytest.mark.parametrize("stem", ["fourbar", "shaper", "shaper_dynamics", "slotted_lever"])
def test_reference_from_the_template_is_the_rebuilt_workbook(stem):
    scene = sheetkin.load_scene(WORKBOOKS / f"{stem}.toml")
    clear_caches()
    for variant in _variants(scene):
        _same_book(reference.reference_book(variant), reference.build_reference(variant), variant)
    # one generated sheet per structure (positions), however many variants
    assert reference.kept_structures() == 2


def test_reference_is_cached_per_variant():
    scene = sheetkin.load_scene(WORKBOOKS / "fourbar.toml")
    clear_caches()
    a = reference.reference_book(scene)
    assert reference.reference_book(dataclasses.replace(scene, source="other.toml", title="x")) is a
    other = dataclasses.replace(scene, crank=dataclasses.replace(scene.crank, length=0.15))
    assert reference.reference_book(other) is not a


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    """Six submissions: copies, two variants, a wrong row, a foreign file, an unusable input."""
    d = tmp_path_factory.mktemp("batch")
    text = (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
    base = d / "a_base.xlsx"
    write_workbook(sheetkin.parse_scene(text, "fourbar.toml"), base, scene_text=text)
    shutil.copy(base, d / "b_copy.xlsx")

    def edited(name, change):
        wb = openpyxl.load_workbook(base)
        ws = wb.worksheets[0]
        rows = {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value}
        change(ws, rows)
        wb.save(d / name)

    edited("c_variant.xlsx", lambda ws, rows: setattr(ws.cell(rows["L1"], 4), "value", 0.12))
    edited("d_variant_wrong.xlsx", lambda ws, rows: (setattr(ws.cell(rows["Fi0"], 4), "value", 5),
                                                   setattr(ws.cell(rows["omega_2"], 6), "value", 1.5)))
    edited("e_text_input.xlsx", lambda ws, rows: setattr(ws.cell(rows["L1"], 4), "value", "0.14 m"))
    (d / "f_notes.xlsx").write_text("not a workbook")
    return sorted(d.glob("*.xlsx"))


def test_pool_gives_the_same_reports_in_order(batch):
    # the students' own variants (the given data they typed) are graded: --accept-changed-inputs
    own = Options(accept_changed=True)
    one = [report_dict(r) for r in validate_many(batch, jobs=1, options=own)]
    done = []
    two = [report_dict(r) for r in validate_many(batch, jobs=2, progress=lambda i, p: done.append((i, p)), options=own)]
    assert one == two
    assert [r["path"] for r in two] == [str(p) for p in batch]
    assert done == list(enumerate(batch, 1))
    oks = [r["ok"] for r in one]
    assert oks == [True, True, True, False, False, False]
    assert one[3]["summary"]["causes"] == ["omega_2"]


def test_validate_jobs_option(batch, capsys):
    code = main(["validate", *map(str, batch), "--jobs", "2", "--json"])
    two = capsys.readouterr().out
    code1 = main(["validate", *map(str, batch), "--jobs", "1", "--json"])
    one = capsys.readouterr().out
    assert code == code1 == 2 and one == two
    with pytest.raises(SystemExit) as info:
        main(["validate", str(batch[0]), "--jobs", "0"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "--jobs" in err and len(err.splitlines()) == 1
