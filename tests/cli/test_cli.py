"""`sheetkin compute`: outputs, exit codes and messages.

Numbers are checked against an independent solution of the four-bar (circle intersection,
derivatives by finite differences in the crank angle), and the non-assembly intervals
against roots of the RRR discriminant P^2 + Q^2 - F^2 found here with scipy's brentq.
"""
from __future__ import annotations

import csv
import io
import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers.clirun import run
from helpers.scenes import FOURBAR  # the spec's four-bar
from scipy.optimize import brentq

import sheetkin

# The contract's columns for this scene, in order, written out from the spec.
FOURBAR_COLUMNS = ["phi_1", "phi_2", "omega_2", "eps_2", "phi_3", "omega_3", "eps_3"] + [
    f"{q}_{p}" for p in ("A", "B", "S2", "S3")
    for q in ("x", "y", "vx", "vy", "v", "ax", "ay", "a")]

L1, OMEGA = 0.14, 20.0


def _subst(text, old, new):
    assert text.count(old) == 1
    return text.replace(old, new)


# coupler 0.25 + rocker 0.34 = 0.59 < max |A O1| = 0.67: no assembly around phi_1 = 90 deg
SHORT = _subst(FOURBAR, "lengths = [0.5, 0.34]", "lengths = [0.25, 0.34]")
SHORT_GEOMETRY = dict(o1=(0.0, -0.53), l2=0.25, l3=0.34)
# O1 on the x axis, coupler 0.5, rocker 0.08: |L2 - L3| = 0.42 > min |A O1| = 0.39 (a gap
# around phi_1 = 0 that wraps past 360) and L2 + L3 = 0.58 < 0.67 (a gap around 180)
WRAP = _subst(_subst(_subst(FOURBAR, "O1 = [0.0, -0.53]", "O1 = [0.53, 0.0]"),
                     "lengths = [0.5, 0.34]", "lengths = [0.5, 0.08]"),
              "along = 0.2129", "along = 0.05")
WRAP_GEOMETRY = dict(o1=(0.53, 0.0), l2=0.5, l3=0.08)


# --------------------------------------------------------------------------- independent model
def fourbar_pose(phi, o1=(0.0, -0.53), l2=0.5, l3=0.34, branch=-1, l_s2=0.39035, l_s3=0.2129):
    """Positions (m) and link angles (rad) of the four-bar at crank angle phi (rad)."""
    ax, ay = L1 * math.cos(phi), L1 * math.sin(phi)
    dx, dy = o1[0] - ax, o1[1] - ay
    d = math.hypot(dx, dy)
    a = (l2 * l2 - l3 * l3 + d * d) / (2 * d)       # from A along A->O1 to the chord
    h = math.sqrt(l2 * l2 - a * a)
    ux, uy = dx / d, dy / d
    bx, by = ax + a * ux - branch * h * uy, ay + a * uy + branch * h * ux   # +1: left of A->O1
    p2, p3 = math.atan2(by - ay, bx - ax), math.atan2(by - o1[1], bx - o1[0])
    return {"A": (ax, ay), "B": (bx, by),
            "S2": (ax + l_s2 * math.cos(p2), ay + l_s2 * math.sin(p2)),
            "S3": (o1[0] + l_s3 * math.cos(p3), o1[1] + l_s3 * math.sin(p3))}, {2: p2, 3: p3}


def fourbar_expected(phi_deg, omega=OMEGA, **geometry):
    """The contract's quantities at phi_deg, and their analogs (d/dphi, d2/dphi2).

    With epsilon = 0, d/dt = omega d/dphi: derivatives by a 5-point stencil in phi.
    """
    h = 1e-3
    phi = math.radians(phi_deg)
    poses = [fourbar_pose(phi + k * h, **geometry) for k in (-2, -1, 0, 1, 2)]

    def d1(f):
        return (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)

    def d2(f):
        return (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * h * h)

    out, analogs = {"phi_1": phi_deg}, {}
    for k in (2, 3):
        ang = np.unwrap([pose[1][k] for pose in poses])
        out[f"phi_{k}"] = math.degrees(ang[2]) % 360.0
        out[f"omega_{k}"], out[f"eps_{k}"] = omega * d1(ang), omega ** 2 * d2(ang)
        analogs[f"omegaq_{k}"], analogs[f"epsq_{k}"] = d1(ang), d2(ang)
    for p in ("A", "B", "S2", "S3"):
        xs, ys = [pose[0][p][0] for pose in poses], [pose[0][p][1] for pose in poses]
        vqx, vqy, aqx, aqy = d1(xs), d1(ys), d2(xs), d2(ys)
        out.update({f"x_{p}": xs[2], f"y_{p}": ys[2],
                    f"vx_{p}": omega * vqx, f"vy_{p}": omega * vqy,
                    f"v_{p}": abs(omega) * math.hypot(vqx, vqy),
                    f"ax_{p}": omega ** 2 * aqx, f"ay_{p}": omega ** 2 * aqy,
                    f"a_{p}": omega ** 2 * math.hypot(aqx, aqy)})
        analogs.update({f"vqx_{p}": vqx, f"vqy_{p}": vqy, f"vq_{p}": math.hypot(vqx, vqy),
                        f"aqx_{p}": aqx, f"aqy_{p}": aqy, f"aq_{p}": math.hypot(aqx, aqy)})
    return out, analogs


def discriminant(phi_deg, o1, l2, l3):
    """P^2 + Q^2 - F^2 of the RRR dyad A-B-O1 (negative: cannot assemble)."""
    phi = math.radians(phi_deg)
    p, q = o1[0] - L1 * math.cos(phi), o1[1] - L1 * math.sin(phi)
    f = (p * p + q * q + l2 * l2 - l3 * l3) / (2 * l2)
    return p * p + q * q - f * f


def gap_intervals(o1, l2, l3):
    """Crank-angle intervals (start, end) in [0, 360) where the discriminant is negative."""
    grid = np.arange(0.0, 360.0 + 0.25, 0.25)
    vals = [discriminant(x, o1, l2, l3) for x in grid]
    roots = [brentq(discriminant, grid[i], grid[i + 1], args=(o1, l2, l3), xtol=1e-12)
             for i in range(len(grid) - 1) if vals[i] * vals[i + 1] < 0]
    starts = [r for r in roots if discriminant(r + 1e-3, o1, l2, l3) < 0]
    ends = [r for r in roots if discriminant(r - 1e-3, o1, l2, l3) < 0]
    assert len(starts) == len(ends) >= 1
    out = []
    for s in starts:
        e = min(ends, key=lambda e: (e - s) % 360.0)
        out.append((s % 360.0, e % 360.0))
    return out


GAP_RE = re.compile(r"group 1 \(RRR A-B-O1\) cannot assemble for crank angles "
                    r"(-?\d+\.\d\d)\.\.(-?\d+\.\d\d) deg")


def printed_gaps(text):
    return [(float(a), float(b)) for a, b in GAP_RE.findall(text)]


def same_interval(printed, exact, tol=0.0051):
    """Printed to 0.01 deg: each end within half a hundredth (plus round-off) of the root."""
    def close(a, b):
        return abs((a - b + 180.0) % 360.0 - 180.0) <= tol
    return close(printed[0], exact[0]) and close(printed[1], exact[1])


# --------------------------------------------------------------------------- running the CLI
@pytest.fixture
def scene_file(tmp_path):
    def make(text=FOURBAR, name="fourbar.toml"):
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path
    return make


def run_process(*argv, cwd=None):
    return subprocess.run([sys.executable, "-m", "sheetkin", *map(str, argv)], cwd=cwd,
                          capture_output=True, text=True, timeout=120)


def read_csv(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], [dict(zip(rows[0], r, strict=False)) for r in rows[1:]]


def assert_error_line(err, code, expected_code=2):
    assert code == expected_code
    lines = err.splitlines()
    assert len(lines) == 1, f"expected one line on stderr, got: {err!r}"
    assert lines[0].startswith("sheetkin: error: ")
    assert "Traceback" not in err


def table_values(out):
    """{row label: [cell strings]} of the table format (labels, unit, then one cell per position)."""
    rows = {}
    for line in out.splitlines():
        parts = line.split()
        if parts:
            rows.setdefault(parts[0], []).extend(parts[1:])
    return rows


# --------------------------------------------------------------------------- table, csv, json
def test_table_has_every_contract_name_and_the_values_at_150(capsys, scene_file):
    code, out, err = run(capsys, "compute", scene_file(), "--at", "150")
    assert code == 0 and err == ""
    assert "Crank-rocker four-bar" in out
    rows = table_values(out)
    expected, _ = fourbar_expected(150.0)
    assert set(FOURBAR_COLUMNS) <= set(rows)
    for name in FOURBAR_COLUMNS:
        printed, want = float(rows[name][-1]), expected[name]
        # six significant digits: off by at most half a unit of the sixth digit
        half_unit = 0.5 * 10.0 ** (math.floor(math.log10(abs(want))) - 5)
        assert abs(printed - want) <= half_unit * 1.001, (name, rows[name][-1], want)


def test_table_without_at_has_every_scene_position(capsys, scene_file):
    code, out, _ = run(capsys, "compute", scene_file())
    assert code == 0
    cells = table_values(out)["phi_1"]
    numbers = [float(c) for c in cells if re.fullmatch(r"-?\d+(\.\d+)?", c)]
    assert numbers == [30.0 * i for i in range(13)]


def test_csv_columns_start_with_the_contract_names(capsys, scene_file):
    path = scene_file()
    code, out, err = run(capsys, "compute", path, "--format", "csv")
    assert code == 0 and err == ""
    header, records = read_csv(out)
    names = sheetkin.column_names(sheetkin.load_scene(path))
    assert names == FOURBAR_COLUMNS
    assert header[:len(names)] == names
    assert len(records) == 13


def test_csv_values_and_repeated_at_order(capsys, scene_file):
    code, out, _ = run(capsys, "compute", scene_file(), "--format", "csv",
                       "--at", "150", "--at", "30", "--at", "200.5", "--at", "30")
    assert code == 0
    header, records = read_csv(out)
    assert [float(r["phi_1"]) for r in records] == [150.0, 30.0, 200.5, 30.0]
    for r in records:
        expected, _ = fourbar_expected(float(r["phi_1"]))
        for name in FOURBAR_COLUMNS:
            assert float(r[name]) == pytest.approx(expected[name], rel=1e-7, abs=1e-9), name
    assert records[1] == records[3]


@pytest.mark.parametrize("path", sorted(Path(sheetkin.__file__).parents[1]
                                        .joinpath("workbooks").glob("*.toml")),
                         ids=lambda p: p.name)
def test_csv_columns_of_bundled_scenes(capsys, path):
    code, out, _ = run(capsys, "compute", path, "--format", "csv", "--at", "10", "--at", "20")
    assert code == 0
    header, records = read_csv(out)
    names = sheetkin.column_names(sheetkin.load_scene(path))
    assert header[:len(names)] == names
    assert len(records) == 2


def test_shaper_csv_has_slider_columns(capsys):
    path = Path(sheetkin.__file__).parents[1] / "workbooks" / "shaper.toml"
    code, out, _ = run(capsys, "compute", path, "--format", "csv", "--at", "248.2614")
    assert code == 0
    header, _ = read_csv(out)
    for name in ("phi_5", "omega_5", "eps_5", "x_D", "v_D", "a_C", "s_A", "vs_A", "as_A",
                 "s_D", "vs_D", "as_D"):
        assert name in header


def test_json(capsys, scene_file):
    code, out, err = run(capsys, "compute", scene_file(), "--format", "json",
                         "--at", "150", "--at", "30")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert {"title", "units", "warnings", "positions"} <= set(data)
    assert data["title"] == "Crank-rocker four-bar"
    assert data["warnings"] == []
    units = data["units"]
    for name in FOURBAR_COLUMNS:
        head = name.split("_")[0]
        want = {"phi": "deg", "omega": "rad/s", "eps": "rad/s^2", "x": "m", "y": "m",
                "vx": "m/s", "vy": "m/s", "v": "m/s", "ax": "m/s^2", "ay": "m/s^2",
                "a": "m/s^2"}[head]
        assert units[name] == want, name
    assert [p["phi_1"] for p in data["positions"]] == [150.0, 30.0]
    for p in data["positions"]:
        expected, _ = fourbar_expected(p["phi_1"])
        for name in FOURBAR_COLUMNS:
            assert p[name] == pytest.approx(expected[name], rel=1e-7, abs=1e-9), name


def test_analogs(capsys, scene_file):
    code, out, _ = run(capsys, "compute", scene_file(), "--format", "csv", "--at", "150",
                       "--analogs")
    assert code == 0
    header, (row,) = read_csv(out)
    assert header[:len(FOURBAR_COLUMNS)] == FOURBAR_COLUMNS
    _, analogs = fourbar_expected(150.0)
    for name, want in analogs.items():
        assert name in header, name
        assert float(row[name]) == pytest.approx(want, rel=1e-7, abs=1e-9), name
    # crank: vq_A = d(A)/dphi = L1 (-sin, cos), aq_A = -L1 (cos, sin)
    assert float(row["vqx_A"]) == pytest.approx(-L1 * math.sin(math.radians(150)))
    assert float(row["aqy_A"]) == pytest.approx(-L1 * math.sin(math.radians(150)))


def test_no_analog_columns_without_the_option(capsys, scene_file):
    code, out, _ = run(capsys, "compute", scene_file(), "--format", "csv", "--at", "150")
    header, _ = read_csv(out)
    assert not [c for c in header if re.match(r"(vq|aq|omegaq|epsq)", c)]


@pytest.mark.parametrize("fmt", ["csv", "json", "table"])
def test_output_file(capsys, scene_file, tmp_path, fmt):
    path = scene_file()
    code, expected, _ = run(capsys, "compute", path, "--format", fmt, "--at", "150")
    assert code == 0 and expected
    target = tmp_path / f"out.{fmt}"
    code, out, err = run(capsys, "compute", path, "--format", fmt, "--at", "150", "-o", target)
    assert code == 0 and out == "" and err == ""
    assert target.read_text(encoding="utf-8") == expected
    target.unlink()
    code, out, _ = run(capsys, "compute", path, "--format", fmt, "--at", "150",
                       "--output", target)
    assert code == 0 and out == "" and target.read_text(encoding="utf-8") == expected


def test_output_into_missing_directory_is_exit_2(capsys, scene_file, tmp_path):
    target = tmp_path / "no" / "such" / "dir" / "out.csv"
    code, out, err = run(capsys, "compute", scene_file(), "--format", "csv", "-o", target)
    assert_error_line(err, code, 2)
    assert str(target) in err


# --------------------------------------------------------------------------- toggle threshold
def test_toggle_threshold(capsys, scene_file):
    path = scene_file()
    code, out, err = run(capsys, "compute", path, "--at", "150")
    assert code == 0 and "toggle" not in err
    # |det| is the sine of the transmission angle, <= 1: a threshold of 1.5 flags every position
    code, out, err = run(capsys, "compute", path, "--at", "150", "--at", "30",
                         "--toggle-threshold", "1.5")
    assert code == 0
    (line,) = err.splitlines()
    assert line.startswith("sheetkin: warning: ") and "group 1" in line and "toggle" in line
    assert "150" in line and "30" in line


def test_near_toggle_just_outside_a_gap_is_flagged(capsys, scene_file):
    """At the edge of assembly the dyad is stretched straight: the transmission angle is 0."""
    (start, _end), = gap_intervals(**SHORT_GEOMETRY)
    code, out, err = run(capsys, "compute", scene_file(SHORT), "--format", "json",
                         "--at", f"{start - 1e-4:.6f}")
    assert code == 0
    data = json.loads(out)
    assert any("group 1" in w and "toggle" in w for w in data["warnings"])
    assert "toggle" in err


# --------------------------------------------------------------------------- bad input: exit 2
BAD_SCENES = {
    "syntax error": _subst(FOURBAR, "omega    = 20.0", "omega    = 20,0"),
    "branch 0": _subst(FOURBAR, "branch  = -1", "branch  = 0"),
    "unknown type": _subst(FOURBAR, 'type    = "RRR"', 'type    = "RRX"'),
    "positions 0": _subst(FOURBAR, "positions = 13", "positions = 0"),
    "typo": _subst(FOURBAR, "length   = 0.14", "lenght   = 0.14"),
}


@pytest.mark.parametrize("name", BAD_SCENES)
def test_bad_scene_exit_2_one_line(capsys, scene_file, name):
    path = scene_file(BAD_SCENES[name], "bad.toml")
    code, out, err = run(capsys, "compute", path, "--format", "csv")
    assert_error_line(err, code, 2)
    assert out == ""
    with pytest.raises(sheetkin.SceneError) as info:
        sheetkin.load_scene(path)
    assert err == f"sheetkin: error: {info.value}\n"
    assert re.match(rf"sheetkin: error: {re.escape(str(path))}:\d+: ", err)


def test_missing_directory_and_non_utf8_scene_exit_2(capsys, tmp_path):
    missing = tmp_path / "missing.toml"
    folder = tmp_path / "folder.toml"
    folder.mkdir()
    latin = tmp_path / "latin.toml"
    latin.write_bytes(FOURBAR.replace("Student", "Schüler").encode("latin-1"))
    for path, word in ((missing, r"no such file|not found"), (folder, "directory"),
                       (latin, "UTF-8")):
        code, out, err = run(capsys, "compute", path)
        assert_error_line(err, code, 2)
        assert out == ""
        assert str(path) in err and re.search(word, err, re.I)


@pytest.mark.parametrize("argv, word", [
    (["compute", "{scene}", "--bogus"], "--bogus"),
    (["compute", "{scene}", "--format", "xml"], "xml"),
    (["compute", "{scene}", "--at", "abc"], "abc"),
    (["compute", "{scene}", "--at", "nan"], "nan"),
    (["compute", "{scene}", "--toggle-threshold", "0"], "0"),
    (["compute"], "SCENE"),
    (["frobnicate", "{scene}"], "frobnicate"),
    ([], "COMMAND"),
], ids=["unknown option", "bad format", "bad angle", "nan angle", "zero threshold",
        "no scene", "unknown command", "no command"])
def test_bad_command_line_exit_2(capsys, scene_file, argv, word):
    path = scene_file()
    code, out, err = run(capsys, *[a.format(scene=path) for a in argv])
    assert code == 2
    assert out == ""
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]
    assert re.match(r"sheetkin( compute)?: error: ", last)
    assert word in last


@pytest.mark.parametrize("argv", [["--bogus"], ["--at", "abc"]], ids=["unknown option", "bad angle"])
def test_bad_option_is_one_line(capsys, scene_file, argv):
    code, out, err = run(capsys, "compute", scene_file(), *argv)
    assert_error_line(err, code, 2)


# --------------------------------------------------------------------------- cannot assemble: exit 3
def test_short_coupler_exit_3_with_the_interval(capsys, scene_file):
    (exact,) = gap_intervals(**SHORT_GEOMETRY)
    assert 18.0 < exact[0] < 19.5 and 160.5 < exact[1] < 162.0     # sanity of the root finding
    path = scene_file(SHORT, "short.toml")
    for argv in (["--at", "90"], [], ["--at", "0", "--at", "160", "--format", "csv"]):
        code, out, err = run(capsys, "compute", path, *argv)
        assert_error_line(err, code, 3)
        assert out == ""
        assert str(path) in err
        (gap,) = printed_gaps(err)
        assert same_interval(gap, exact), (gap, exact)


def test_interval_wrapping_past_360(capsys, scene_file):
    exact = gap_intervals(**WRAP_GEOMETRY)
    assert len(exact) == 2
    wrap = next(g for g in exact if g[0] > g[1])            # around phi_1 = 0
    middle = next(g for g in exact if g[0] < g[1])          # around phi_1 = 180
    path = scene_file(WRAP, "wrap.toml")
    code, _, err = run(capsys, "compute", path, "--at", "355")
    assert_error_line(err, code, 3)
    (gap,) = printed_gaps(err)
    assert same_interval(gap, wrap), (gap, wrap)
    code, _, err = run(capsys, "compute", path, "--at", "0", "--at", "180", "--at", "90")
    assert_error_line(err, code, 3)
    gaps = printed_gaps(err)
    assert len(gaps) == 2
    assert any(same_interval(g, wrap) for g in gaps) and any(same_interval(g, middle) for g in gaps)


def test_never_assembles(capsys, scene_file):
    never = _subst(FOURBAR, "lengths = [0.5, 0.34]", "lengths = [0.1, 0.1]")
    code, _, err = run(capsys, "compute", scene_file(never, "never.toml"))
    assert_error_line(err, code, 3)
    (gap,) = printed_gaps(err)
    assert gap[1] - gap[0] == pytest.approx(360.0)


def test_allow_gaps_csv(capsys, scene_file):
    (exact,) = gap_intervals(**SHORT_GEOMETRY)
    path = scene_file(SHORT, "short.toml")
    code, out, err = run(capsys, "compute", path, "--format", "csv", "--allow-gaps")
    assert code == 0
    (line,) = err.splitlines()
    assert line.startswith("sheetkin: warning: ")
    (gap,) = printed_gaps(line)
    assert same_interval(gap, exact)
    header, records = read_csv(out)
    assert header[:len(FOURBAR_COLUMNS)] == FOURBAR_COLUMNS
    assert "assembled" in header
    assert len(records) == 13
    depends_on_group = [c for c in FOURBAR_COLUMNS
                        if not (c == "phi_1" or c.endswith("_A"))]
    good = []
    for r in records:
        phi = float(r["phi_1"])
        fits = discriminant(phi, **SHORT_GEOMETRY) >= 0
        assert r["assembled"] == str(fits), phi
        if fits:
            good.append(phi)
            expected, _ = fourbar_expected(phi, **SHORT_GEOMETRY)
            for name in FOURBAR_COLUMNS:
                assert float(r[name]) == pytest.approx(expected[name], rel=1e-6, abs=1e-9), name
        else:
            assert all(r[c] == "" for c in depends_on_group), r
    assert sorted(set(good) ^ {30.0 * i for i in range(13)}) == [30.0, 60.0, 90.0, 120.0, 150.0]
    # the assembled rows are what a run at those angles alone gives
    code, plain, _ = run(capsys, "compute", path, "--format", "csv",
                         *[a for phi in good for a in ("--at", phi)])
    assert code == 0
    _, plain_records = read_csv(plain)
    for r, p in zip([r for r in records if r["assembled"] == "True"], plain_records, strict=False):
        assert all(r[c] == p[c] for c in FOURBAR_COLUMNS)


def test_allow_gaps_json_and_table(capsys, scene_file):
    path = scene_file(SHORT, "short.toml")
    code, out, err = run(capsys, "compute", path, "--format", "json", "--allow-gaps",
                         "--at", "0", "--at", "90")
    assert code == 0
    assert err.startswith("sheetkin: warning: ")
    data = json.loads(out)
    first, second = data["positions"]
    assert first["assembled"] is True and second["assembled"] is False
    assert all(second[c] is None for c in FOURBAR_COLUMNS if c != "phi_1" and not c.endswith("_A"))
    assert all(isinstance(first[c], float) for c in FOURBAR_COLUMNS)
    assert len(data["warnings"]) == 1 and printed_gaps(data["warnings"][0])
    code, out, err = run(capsys, "compute", path, "--allow-gaps", "--at", "0", "--at", "90")
    assert code == 0 and "warning" in err
    phi2 = table_values(out)["phi_2"]
    assert phi2[-1] in ("-", "", "nan", "NaN")                  # the 90 deg cell is empty
    assert float(phi2[-2]) == pytest.approx(fourbar_expected(0.0, **SHORT_GEOMETRY)[0]["phi_2"],
                                            rel=1e-5)


def test_allow_gaps_with_nothing_failing_changes_nothing(capsys, scene_file):
    path = scene_file()
    _, plain, _ = run(capsys, "compute", path, "--format", "csv")
    code, out, err = run(capsys, "compute", path, "--format", "csv", "--allow-gaps")
    assert code == 0 and err == "" and out == plain


# --------------------------------------------------------------------------- help
def test_program_help(capsys):
    code, out, _ = run(capsys, "--help")
    assert code == 0
    for word in ("compute", "--version", "--help"):
        assert word in out


def test_compute_help_mentions_every_option(capsys):
    code, out, _ = run(capsys, "compute", "--help")
    assert code == 0
    for word in ("SCENE.toml", "--format", "table", "csv", "json", "--at", "DEG", "--analogs",
                 "--allow-gaps", "--toggle-threshold", "-o", "--output", "--help"):
        assert word in out, word


def test_version(capsys):
    code, out, _ = run(capsys, "--version")
    assert code == 0 and sheetkin.__version__ in out


# --------------------------------------------------------------------------- as a process
def test_process_bad_scene_no_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(BAD_SCENES["branch 0"], encoding="utf-8")
    proc = run_process("compute", bad, "--format", "csv")
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert "Traceback" not in proc.stderr
    (line,) = proc.stderr.splitlines()
    assert line.startswith(f"sheetkin: error: {bad}:") and "branch" in line


def test_process_non_utf8_and_directory(tmp_path):
    latin = tmp_path / "latin.toml"
    latin.write_bytes(b"title = \"caf\xe9\"\n")
    for path in (latin, tmp_path):
        proc = run_process("compute", path)
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
        assert len(proc.stderr.splitlines()) == 1


def test_process_cannot_assemble(tmp_path):
    short = tmp_path / "short.toml"
    short.write_text(SHORT, encoding="utf-8")
    proc = run_process("compute", "short.toml", "--at", "90", cwd=tmp_path)
    assert proc.returncode == 3 and proc.stdout == ""
    assert "Traceback" not in proc.stderr
    (line,) = proc.stderr.splitlines()
    (gap,) = printed_gaps(line)
    (exact,) = gap_intervals(**SHORT_GEOMETRY)
    assert same_interval(gap, exact)


def test_process_ok(tmp_path):
    scene = tmp_path / "fourbar.toml"
    scene.write_text(FOURBAR, encoding="utf-8")
    proc = run_process("compute", scene, "--format", "csv", "--at", "150")
    assert proc.returncode == 0 and proc.stderr == ""
    header, (row,) = read_csv(proc.stdout)
    assert header[:len(FOURBAR_COLUMNS)] == FOURBAR_COLUMNS
    assert float(row["phi_2"]) == pytest.approx(fourbar_expected(150.0)[0]["phi_2"], rel=1e-9)


def test_process_help():
    proc = run_process("compute", "--help")
    assert proc.returncode == 0 and "--allow-gaps" in proc.stdout


@pytest.mark.skipif(shutil.which("sheetkin") is None, reason="console script not installed")
def test_console_script_bad_option():
    proc = subprocess.run(["sheetkin", "compute", "x.toml", "--bogus"], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and "--bogus" in proc.stderr
