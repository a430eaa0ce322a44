"""The charts sheet's live drawing: recalculated in LibreOffice after the position cell (and
a length) were changed, its helper cells hold compute()'s points at that position; the
hidden paths sheet holds compute()'s coordinates over a revolution; the charts are to
equal scale."""
from __future__ import annotations

import math
import re
import zipfile
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.libreoffice import is_error, recalculate
from helpers.scenes import SHORT

import sheetkin
from sheetkin.kinematics import geometry
from sheetkin.sheet.charts import HELPER_COL, PATHS_SHEET, PLOT, equal_axes
from sheetkin.sheet.workbook import build_workbook

WB = Path(__file__).resolve().parents[2] / "workbooks"


def _rows(ws) -> dict[str, int]:
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if isinstance(ws.cell(r, 1).value, str)}


def _helper_series(cs) -> dict[str, list[tuple[object, object]]]:
    """{label: [(x, y), ...]} of the drawing's helper blocks (label, then one row per point)."""
    out, label = {}, None
    for r in range(3, cs.max_row + 1):
        name, x, y = (cs.cell(r, HELPER_COL + k).value for k in range(3))
        if name is not None:
            label = name
            out[label] = []
        if label is not None and (x is not None or y is not None):
            out[label].append((x, y))
        elif name is None:
            label = None
    return out


CASES = {
    # key: (scene text, position typed in B1, {input row: new value})
    "fourbar": ((WB / "fourbar.toml").read_text(), 4, {"L2": 0.52}),
    "shaper": ((WB / "shaper.toml").read_text(), 7, {}),
    "crank_slider": ((WB / "crank_slider.toml").read_text(), 10, {"L1": 0.09}),
    "slotted_lever": ((WB / "slotted_lever.toml").read_text(), 2, {}),
    "two_rockers_slotted": ((WB / "two_rockers_slotted.toml").read_text(), 5, {}),   # a moving guide
    "gap": (SHORT, 5, {}),            # position i = 5 (150 deg) cannot assemble
    # PRP: its fixed guide's angle is the input gamma2_g2 (a name no stage hard-codes)
    "slider_on_coupler": ((WB / "slider_on_coupler.toml").read_text(), 3, {"gamma2_g2": 80.0}),
}


@pytest.fixture(scope="module")
def books(soffice, tmp_path_factory):
    src = tmp_path_factory.mktemp("drawing")
    made = {}
    for key, (text, pos, inputs) in CASES.items():
        scene = sheetkin.parse_scene(text, f"{key}.toml")
        wb = build_workbook(scene, scene_text=text)
        ws, cs = wb.worksheets[0], wb.worksheets[1]
        cs["B1"] = pos
        rows = _rows(ws)
        for name, v in inputs.items():
            ws.cell(rows[name], 4).value = v
        path = src / f"{key}.xlsx"
        wb.save(path)
        made[key] = path
    out = recalculate(list(made.values()), tmp_path_factory.mktemp("drawing_out"))
    return {k: (openpyxl.load_workbook(out[p.resolve()], data_only=True), p) for k, p in made.items()}


def _changed(key):
    text, pos, inputs = CASES[key]
    for name, v in inputs.items():        # the same change in the scene text
        if key == "fourbar" and name == "L2":
            text = text.replace("lengths = [0.5, 0.34]", f"lengths = [{v}, 0.34]")
        elif name == "gamma2_g2":
            text = text.replace("{ through = [-0.15, 0.0], angle_deg = 90.0 }",
                                f"{{ through = [-0.15, 0.0], angle_deg = {v} }}")
        elif name == "L1":
            text = re.sub(r"(?m)^length\s*=\s*[0-9.]+", f"length = {v}", text, count=1)
    scene = sheetkin.parse_scene(text, f"{key}.toml")
    assert all(str(v) in text for v in inputs.values())
    return scene, pos


@pytest.mark.parametrize("key", ["fourbar", "shaper", "crank_slider", "slotted_lever", "two_rockers_slotted",
                                 "slider_on_coupler"])
def test_drawing_follows_position_and_lengths(books, key):
    wb, _ = books[key]
    cs = wb.worksheets[1]
    scene, pos = _changed(key)
    phi = scene.crank_angles_deg()[pos]          # B1 is the sheet's i, from 0
    df = sheetkin.compute(scene, [phi])
    assert cs["D1"].value == pytest.approx(phi, abs=1e-9)
    series = _helper_series(cs)
    st = geometry.structure(scene)
    drawn = 0
    for k, pts in st.members.items():
        if len(pts) < 2:
            continue
        label = f"звено {k}: {'-'.join(pts)}"
        got = np.array(series[label], dtype=float)
        want = np.array([geometry.point_xy(scene, df, p)[0] for p in pts])
        assert np.allclose(got[:len(pts)], want, rtol=1e-9, atol=1e-12), label
        drawn += 1
    assert drawn >= 2
    for b in st.blocks:               # the block's centre is the slider's point
        corners = np.array(series[f"ползун {b.link} в {b.at}"], dtype=float)[:4]
        assert np.allclose(corners.mean(axis=0), geometry.point_xy(scene, df, b.at)[0], atol=1e-12)


def _helper_scalars(cs) -> dict[str, object]:
    """{label: value} of the drawing's helper scalars (a guide's angle, cos, sin, base)."""
    return {cs.cell(r, HELPER_COL + 4).value: cs.cell(r, HELPER_COL + 5).value for r in range(3, cs.max_row + 1)
            if cs.cell(r, HELPER_COL + 4).value is not None}


def test_prp_guide_follows_its_angle_input(books):
    """slider_on_coupler's fixed guide (PRP's guides[1], input gamma2_g2) typed from 90 to
    80 deg: after LibreOffice's recalculation the drawn guide is the line through (-0.15, 0)
    at 80 deg (it was the constant =0+90.0), and the slider's block sits at the changed
    scene's L."""
    wb, _ = books["slider_on_coupler"]
    cs = wb.worksheets[1]
    scene, pos = _changed("slider_on_coupler")
    # the book is Russian by default: the guide of group 2 is "направляющая г2"
    assert _helper_scalars(cs)["направляющая г2: угол, град"] == pytest.approx(80.0, abs=1e-12)
    (x0, y0), (x1, y1) = np.array(_helper_series(cs)["направляющая г2"], dtype=float)
    u = np.array([math.cos(math.radians(80.0)), math.sin(math.radians(80.0))])
    assert abs((x1 - x0) * u[1] - (y1 - y0) * u[0]) < 1e-12 * math.hypot(x1 - x0, y1 - y0)    # along 80 deg
    assert abs((x0 + 0.15) * u[1] - y0 * u[0]) < 1e-12                                          # through the point
    df = sheetkin.compute(scene, [scene.crank_angles_deg()[pos]])      # B1 is the sheet's i, from 0
    want = geometry.point_xy(scene, df, "L")[0]
    on_fixed = [b for b in geometry.structure(scene).blocks if b.guide.link == 0]
    assert len(on_fixed) == 1
    corners = np.array(_helper_series(cs)[f"ползун {on_fixed[0].link} в L"], dtype=float)[:4]
    assert np.allclose(corners.mean(axis=0), want, atol=1e-12)
    assert abs(-(want[0] + 0.15) * u[1] + want[1] * u[0]) < 1e-12                             # L on the new line


def test_paths_sheet_equals_compute_over_a_revolution(books):
    wb, _ = books["fourbar"]
    scene, _ = _changed("fourbar")
    ps = wb[PATHS_SHEET]
    rows = _rows(ps)
    n = 361
    fine = sheetkin.compute(scene, scene.crank.phi0_deg + np.arange(n) * 1.0)
    for name in ("x_B", "y_B", "x_S2", "y_S3"):
        got = np.array([ps.cell(rows[name], 5 + k).value for k in range(n)], dtype=float)
        assert np.allclose(got, fine[name], rtol=1e-9, atol=1e-12), name


def test_position_in_a_gap_draws_nothing_but_the_crank(books):
    wb, _ = books["gap"]
    series = _helper_series(wb.worksheets[1])
    assert all(is_error(v) for v in series["звено 2: A-B"][1])      # B: #N/A, not plotted
    assert all(is_error(v) for v in series["звено 3: O1-B"][1])
    assert np.allclose(np.array(series["звено 1: O-A"], dtype=float)[1],
                       [0.2 * np.cos(np.radians(150)), 0.2 * np.sin(np.radians(150))])
    ps = wb[PATHS_SHEET]
    rows = _rows(ps)
    assert ps.cell(rows["x_B"], 5 + 150).value == "#N/A"      # a chart leaves it out (issue 20)


def test_trajectory_charts_are_to_equal_scale(books):
    """Both drawing charts: a plot area placed by hand (inner layout) and axis bounds with
    the same metres per centimetre on x and y."""
    _, path = books["fourbar"]
    with zipfile.ZipFile(path) as z:
        charts = [z.read(n).decode() for n in sorted(z.namelist()) if n.startswith("xl/charts/chart")]
    scaled = 0
    for xml in charts:
        if "layoutTarget" not in xml:
            continue
        scaled += 1
        x, y, w, h = (float(re.search(rf"<{t} val=\"([^\"]+)\"", xml).group(1)) for t in ("x", "y", "w", "h"))
        cm = re.findall(r"<scaling>.*?<max val=\"([^\"]+)\"\s*/>.*?<min val=\"([^\"]+)\"\s*/>", xml, re.S)
        (xmax, xmin), (ymax, ymin) = [(float(a), float(b)) for a, b in cm]
        assert (xmax - xmin) / (w * 16.0) == pytest.approx((ymax - ymin) / (h * 12.0), rel=1e-9)
    assert scaled == 2


def test_equal_axes_fit_the_box():
    box = (-0.31, -0.55, 0.15, 0.16)
    x0, x1, y0, y1, unit = equal_axes(box, PLOT)
    assert x0 <= box[0] and x1 >= box[2] and y0 <= box[1] and y1 >= box[3]
    assert (x1 - x0) / PLOT[2] / 16.0 == pytest.approx((y1 - y0) / PLOT[3] / 12.0)
    assert x0 / unit == pytest.approx(round(x0 / unit))


def test_exercise_has_no_paths_sheet():
    scene = sheetkin.load_scene(WB / "fourbar.toml")
    wb = build_workbook(scene, exercise=True)
    assert PATHS_SHEET not in wb.sheetnames


@pytest.mark.parametrize("key", list(CASES))
def test_evaluator_agrees_with_libreoffice_on_the_drawing(books, key):
    """sheetkin's evaluator (INDEX, NA) computes the helper cells as LibreOffice does."""
    from sheetkin.xlsx.evaluator import evaluate
    wb, path = books[key]
    lo = wb.worksheets[1]
    book = evaluate(path)
    sheet = book.order[1]
    compared = 0
    for r in range(1, lo.max_row + 1):
        for c in range(HELPER_COL + 1, HELPER_COL + 6):
            want = lo.cell(r, c).value
            if want is None or isinstance(want, str) and not is_error(want):
                continue
            got = book.value(sheet, r, c)
            if is_error(want):
                assert got == "#N/A", (r, c, got)
            else:
                assert got == pytest.approx(want, rel=1e-9, abs=1e-12), (r, c)
            compared += 1
    assert compared > 10
