"""`sheetkin compute`'s bulk output (sheetkin.views.floatfmt, sheetkin.views.output) and the angle
options (sheetkin.cli.angles): the numbers are Python's repr byte for byte; CSV and JSON written
block by block equal what pandas and json.dumps give for compute()'s DataFrame; gaps and
undefined values are never "nan"/"inf"; --range and --at-file mean what the README says
and refuse bad input in one line naming the file and line.
"""
from __future__ import annotations

import io
import json
import math
import os
import struct
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers.clirun import run
from helpers.scenes import FOURBAR  # noqa: E402
from hypothesis import given, settings
from hypothesis import strategies as st

import sheetkin
from sheetkin.cli.args import TOGGLE_THRESHOLD
from sheetkin.errors import InputError
from sheetkin.kinematics.table import TOGGLE_THRESHOLD as COMPUTE_TOGGLE_THRESHOLD
from sheetkin.kinematics.table import AngleRange, Block
from sheetkin.views.floatfmt import repr_slots
from sheetkin.views.output import Notes, _Text, write_compute

ROOT = Path(sheetkin.__file__).parents[1]
SHORT = FOURBAR.replace("lengths = [0.5, 0.34]", "lengths = [0.25, 0.34]")   # a group that cannot always assemble


def format_repr(x) -> list[str]:
    """[repr(float(v)) for v in x] through the bulk formatter ("" for non-finite values)."""
    slots, _ = repr_slots(x)
    return [row.tobytes().translate(None, b"\0").decode() for row in slots]


def one_error_line(err, code, expected=2):
    assert code == expected and len(err.splitlines()) == 1, err
    assert err.startswith("sheetkin: error: ") and "Traceback" not in err


# --------------------------------------------------------------------------- repr in bulk
def test_repr_of_random_bit_patterns_and_edge_values():
    rng = np.random.default_rng(15)
    bits = rng.integers(0, 2 ** 63, 300_000, dtype=np.int64).view(np.float64)
    edges = [0.0, -0.0, 1e16, 1e15, 9.999999999999999e15, 1e-4, 9.999e-5, 1e-5, 0.1, 0.3, 30.0,
             359.99999999999994, 2.0 ** 53, 2.0 ** 53 + 2, 5e-324, 1.7976931348623157e308,
             1e-200, 1e200, 1e-201, 1e201, 123456789012345680.0, 0.30000000000000004]
    values = np.concatenate([bits, edges, -np.array(edges),
                             rng.standard_normal(200_000) * 10.0 ** rng.integers(-9, 19, 200_000),
                             np.round(rng.standard_normal(50_000) * 1000, 3),
                             np.arange(0.0, 360.0, 0.1), [math.inf, -math.inf, math.nan],
                             # powers of two: the gap below is half the gap above
                             2.0 ** np.arange(-1074, 1024), np.nextafter(2.0 ** np.arange(-1000, 1000), 0),
                             3.0 * 2.0 ** np.arange(-1000, 1000)])
    got = format_repr(values)
    want = [repr(v) if math.isfinite(v) else "" for v in values.tolist()]
    bad = [(w, g) for w, g in zip(want, got, strict=False) if w != g]
    assert not bad, bad[:5]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=50))
def test_repr_hypothesis(values):
    assert format_repr(np.array(values)) == [repr(float(v)) for v in values]


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2 ** 64 - 1))
def test_repr_any_bits(bits):
    (x,) = struct.unpack("<d", struct.pack("<Q", bits))
    assert format_repr(np.array([x])) == [repr(x) if math.isfinite(x) else ""]


def _mixed(rng, n):
    """Every layout and every rare path of floatfmt in one array, shuffled: positional
    and exponent form, 1 to 17 digits, exponents of 1 to 3 digits, zeros of both signs,
    powers of two, values just below a power of ten (log10 rounds up), 9.99...5 rounding
    up a decade, exact short decimals, non-finite values and |x| beyond 1e+/-200."""
    digits = rng.integers(1, 10 ** 17, n).astype(np.float64) / 10.0 ** rng.integers(0, 17, n)
    special = [0.0, -0.0, math.inf, -math.inf, math.nan, 1e-201, -1e250, 5e-324, 1e-200, 1e200,
               0.5, 2.0, 1024.0, 2.0 ** -44, 2.0 ** 60, 1.5e-5, 1e16, 9.999999999999998e15,
               1234567890123456.8, 0.0001, 9.9999999999999991e-05, 0.9999999999999999,
               999.9999999999999, 99.99999999999999, 1e-100, -1.2345678901234567e-123,
               1.2345678901234567e+123, 30.0, 0.1, 0.3, 359.99999999999994]
    parts = [digits * 10.0 ** rng.integers(-8, 18, n),             # mostly positional, 1-17 digits
             digits * 10.0 ** rng.integers(-150, 150, n),          # mostly exponent form
             rng.standard_normal(n),
             np.nextafter(10.0 ** rng.integers(-30, 30, n), 0.0),  # just below a power of ten
             2.0 ** rng.integers(-600, 600, n),
             np.round(rng.standard_normal(n) * 100, rng.integers(0, 3)),
             np.repeat(special, 1 + n // len(special))]
    values = np.concatenate(parts)
    values *= np.where(rng.random(values.size) < 0.5, -1.0, 1.0)
    rng.shuffle(values)
    return values


@pytest.mark.parametrize("threads", [1, 2])
def test_repr_of_every_layout_mixed_in_chunks(threads):
    """Chunks (floatfmt.CHUNK numbers) where every kind of number sits next to the others,
    formatted on one and on two threads: what one element needs (exponent form, a repr
    fallback, a zero, a power of two) must not change its neighbours."""
    from sheetkin.views import floatfmt
    rng = np.random.default_rng(151)
    values = _mixed(rng, floatfmt.CHUNK // 2)
    assert values.size > 3 * floatfmt.CHUNK
    slots, finite = floatfmt.repr_slots(values, threads=threads)
    got = [row.tobytes().translate(None, b"\0").decode() for row in slots]
    want = [repr(v) if math.isfinite(v) else "" for v in values.tolist()]
    assert finite.tolist() == [math.isfinite(v) for v in values.tolist()]
    bad = [(w, g) for w, g in zip(want, got, strict=False) if w != g]
    assert not bad, bad[:5]
    assert not slots[:, 0].any()                      # byte 0 stays free for the separator


def test_repr_of_ordinary_chunks_keeps_exponents_and_fallbacks_apart():
    """A chunk of ordinary positional numbers with one exponent-form number, one zero and
    one number for repr's own fallback at each place: the neighbours are unchanged."""
    base = np.linspace(-7.3, 123.4, 64)
    want_base = [repr(v) for v in base.tolist()]
    for odd in (1.5e-07, -2.5e+16, 0.0, -0.0, 1e-250, 1.7976931348623157e308, 2.0 ** -30):
        for at in (0, 31, 63):
            values = base.copy()
            values[at] = odd
            want = list(want_base)
            want[at] = repr(odd)
            assert format_repr(values) == want


def test_repr_of_powers_of_ten_and_their_neighbours():
    """The double nearest 1e23 is below 10^23 (99999999999999991611392): its 17 digits
    99999999999999992 round up a decade to repr's "1e+23" (the carry); log10 of a double
    just below a power of ten rounds up to it (the exponent is corrected)."""
    tens = np.array([float(f"1e{k}") for k in range(-320, 309)])
    values = np.concatenate([tens, np.nextafter(tens, 0.0), np.nextafter(tens, np.inf)])
    values = np.concatenate([values, -values])
    assert format_repr(values) == [repr(v) for v in values.tolist()]
    assert format_repr(np.array([1e23, -1e-5, 1e16])) == ["1e+23", "-1e-05", "1e+16"]


def test_heap_is_kept_while_formatting_and_restored(monkeypatch):
    """repr_slots of many chunks sets glibc's M_TOP_PAD once, however deeply nested, and
    restores the default when the outermost call ends (also after an error)."""
    from sheetkin.views import floatfmt
    calls = []
    monkeypatch.setattr(floatfmt, "_mallopt", lambda param, value: calls.append((param, value)) or 1)
    values = np.linspace(0.1, 9.9, 3 * floatfmt.CHUNK)
    with floatfmt.heap_kept(1 << 20):
        floatfmt.repr_slots(values)
        assert calls == [(-2, 1 << 20)]
    assert calls == [(-2, 1 << 20), (-2, 128 * 1024)]
    with pytest.raises(ZeroDivisionError), floatfmt.heap_kept():
        1 / 0
    assert calls[-1] == (-2, 128 * 1024) and len(calls) == 4 and floatfmt._kept == 0


_SPECIAL = st.sampled_from([0.0, -0.0, 1e16, 9.999999999999998e15, 1e-4, 9.9999999999999991e-05,
                            0.9999999999999999, 2.0 ** -44, 0.5, 1e-201, 1e201, 1e-100, 1.5e+100,
                            5e-324, -1.2345678901234567e-123])


@settings(max_examples=300, deadline=None)
@given(st.lists(st.one_of(st.floats(allow_nan=False, allow_infinity=False), _SPECIAL,
                          st.integers(-10 ** 17, 10 ** 17).map(float),
                          st.decimals(allow_nan=False, allow_infinity=False, places=6).map(float)),
                min_size=1, max_size=80))
def test_repr_hypothesis_mixed_kinds(values):
    assert format_repr(np.array(values)) == [repr(float(v)) for v in values]


# --------------------------------------------------------------------------- CSV, JSON in blocks
def _written(scene, fmt, phi, block, **kw):
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out")
        warnings = write_compute(scene, phi, fmt, out, block=block, **kw)
        return Path(out).read_bytes(), warnings


def _same_as_pandas(text: bytes, df) -> None:
    """The CSV (polars' notation since issue 24) is pandas' to_csv of compute() cell for cell:
    the same header, texts and empty cells, and every number reads back as the same double."""
    ours = text.decode().split("\n")
    theirs = df.to_csv(index=False, lineterminator="\n").split("\n")
    assert len(ours) == len(theirs) and ours[0] == theirs[0]
    for a, b in zip(ours[1:], theirs[1:], strict=True):
        for x, y in zip(a.split(","), b.split(","), strict=True):
            if x == y:
                continue
            # only the notation differs (1e-05 / 0.00001, 1e-06 / 1e-6): the same bits; and a
            # CSV never says -0.0 (0.0: a newcomer reads -0.0 as a bug)
            assert x != "-0.0"
            assert np.float64(x).tobytes() == (np.float64(y) + 0.0).tobytes(), (x, y)


@pytest.mark.parametrize("name, kw", [("fourbar.toml", {}), ("shaper.toml", {"analogs": True}),
                                      ("shaper_dynamics.toml", {"dynamics": True})])
def test_csv_in_blocks_is_pandas_csv_of_compute(name, kw):
    scene = sheetkin.load_scene(ROOT / "workbooks" / name)
    phi = np.linspace(0.0, 360.0, 77, endpoint=False) + 0.123
    text, _ = _written(scene, "csv", phi, block=10, **kw)          # 8 blocks, the last short
    df = sheetkin.compute(scene, phi, **kw)
    if not kw.get("dynamics"):
        _same_as_pandas(text, df)
        return
    # the dynamics' sums round differently with the arrays' lengths (round-off at 1e-14 of
    # the terms): one block is pandas', blocks of 10 the same to round-off
    one, _ = _written(scene, "csv", phi, block=len(phi), **kw)
    _same_as_pandas(one, df)
    import pandas as pd
    got = pd.read_csv(io.BytesIO(text), keep_default_na=False)
    for c in df.columns[:-1]:
        scale = np.abs(df[c]).max() + 1e-300
        assert np.allclose(got[c].astype(float), df[c], rtol=0, atol=1e-12 * scale), c


def test_csv_numbers_read_back_as_the_same_doubles():
    """polars writes the CSV's numbers (issue 24): over every kind of double, each reads back
    bit for bit, and nothing is written as nan or inf."""
    names = ["phi_1", "omega_2", "det_g1"]
    rng = np.random.default_rng(24)
    n = 50_000
    values = np.concatenate([rng.standard_normal(n) * 10.0 ** rng.integers(-320, 308, n),
                             np.round(rng.random(n) * 1e4) / 1e4, rng.random(n) * 360,
                             [0.0, -0.0, 5e-324, -5e-324, 1.7976931348623157e308, 1e-5, 1e-6, 1e16, 1e15,
                              0.1 + 0.2, 123456789.0, 2.5e-5]])
    values = values[:values.size // 3 * 3].reshape(3, -1)
    blk = Block(0, values, np.zeros(values.shape[1], bool), np.zeros(values.shape[1], np.intp), [""])
    w = _Text("csv", names, 1, False, "t")
    lines = (w.head() + w.rows(blk) + w.tail([])).decode().splitlines()
    assert lines[0] == "phi_1,omega_2,det_g1,near_toggle"
    back = np.array([[float(x) for x in line.split(",")[:3]] for line in lines[1:]]).T
    assert back.tobytes() == (values + 0.0).tobytes()        # -0.0 is written 0.0, every other bit kept
    assert "-0.0," not in "\n".join(lines) and 5e-324 in back and -5e-324 in back


def test_json_in_blocks_is_json_of_compute():
    scene = sheetkin.load_scene(ROOT / "workbooks" / "fourbar.toml")
    phi = np.array([0.0, 30.0, 149.99, 200.5, 1e-7, 359.99999])
    text, warnings = _written(scene, "json", phi, block=4, toggle_threshold=0.99998)
    data = json.loads(text)
    df = sheetkin.compute(scene, phi, toggle_threshold=0.99998)
    assert list(data) == ["title", "units", "positions", "warnings"]
    assert data["warnings"] == warnings and any("toggle" in w for w in warnings)
    assert data["positions"] == [{k: (bool(v) if isinstance(v, np.bool_) else v) for k, v in r.items()}
                                 for r in df.astype({"near_toggle": str}).to_dict(orient="records")]
    # the layout is json.dumps(indent=1)'s
    assert text.decode() == json.dumps(data, indent=1) + "\n"


def test_gaps_empty_in_csv_null_in_json(tmp_path):
    scene = sheetkin.parse_scene(SHORT, "short.toml")
    phi = np.arange(0.0, 360.0, 10.0)
    text, warnings = _written(scene, "csv", phi, block=7, allow_gaps=True)
    df = sheetkin.compute(scene, phi, allow_gaps=True)
    _same_as_pandas(text, df)
    assert b"nan" not in text.lower() and b"inf" not in text.lower()
    assert "cannot assemble" in warnings[0]
    text, _ = _written(scene, "json", phi, block=7, allow_gaps=True)
    records = json.loads(text)["positions"]
    assert [r["assembled"] for r in records] == df["assembled"].tolist()
    assert all(r["phi_2"] is None for r in records if not r["assembled"])


def test_values_formatted_by_repr_itself_keep_their_first_character():
    """|x| beyond 1e+/-200 (and the rare near-ties) are formatted by repr itself: the text
    starts after the separator's byte, as the bulk numbers do ("e-250" was written for
    1e-250 before)."""
    names = ["phi_1", "omega_2", "det_g1"]
    table = np.array([[10.0, 20.0], [1e-250, -3e250], [2.5e-201, 0.5]])
    blk = Block(0, table, np.zeros(2, bool), np.zeros(2, np.intp), [""])
    for fmt in ("csv", "json"):
        w = _Text(fmt, names, 1, False, "t")
        text = (w.head() + w.rows(blk) + w.tail([])).decode()
        if fmt == "csv":
            assert text.splitlines()[1:] == ["10.0,1e-250,2.5e-201,", "20.0,-3e+250,0.5,"]
        else:
            rows = json.loads(text)["positions"]
            assert [(r["omega_2"], r["det_g1"]) for r in rows] == [(1e-250, 2.5e-201), (-3e250, 0.5)]


def test_undefined_values_outside_gaps_are_empty_and_warned():
    """Exactly at a toggle a rate can come out infinite: never written as inf/nan."""
    names = ["phi_1", "omega_2", "det_g1"]
    table = np.array([[10.0, 20.0, 30.0], [1.5, np.inf, np.nan], [0.5, 0.0, 0.5]])
    blk = Block(0, table, np.zeros(3, bool), np.zeros(3, np.intp), [""])
    for fmt, empty in (("csv", "20.0,,0.0"), ("json", '"omega_2": null')):
        w = _Text(fmt, names, 1, False, "t")
        text = (w.head() + w.rows(blk) + w.tail([])).decode()
        assert empty in text and "inf" not in text and "nan" not in text.lower()
    notes = Notes(1)
    notes.add(names, blk, False)
    (line,) = notes.warnings(None)
    assert "omega_2 (2 positions)" in line and "20, 30" in line


def test_cli_streams_many_blocks_to_stdout(capsys):
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--format", "csv",
                         "--range", "0:360:0.002")
    assert code == 0 and err == ""
    lines = out.splitlines()
    assert len(lines) == 1 + 180_000                      # eleven blocks of 16384
    assert lines[1].startswith("0.0,") and lines[-1].startswith("359.998,")
    assert lines[150_001].startswith("300.0,")            # exact decimal steps


# --------------------------------------------------------------------------- parquet
def test_parquet_equals_compute(tmp_path, capsys):
    pq = pytest.importorskip("pyarrow.parquet")
    target = tmp_path / "k.parquet"
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "shaper.toml", "--format", "parquet",
                         "--range", "0:360:1", "-o", target)
    assert code == 0 and out == "" and err == ""
    got = pq.read_table(target).to_pandas()
    df = sheetkin.compute(ROOT / "workbooks" / "shaper.toml", np.arange(0.0, 360.0, 1.0))
    assert list(got.columns) == list(df.columns)
    assert np.array_equal(got.drop(columns="near_toggle").to_numpy(), df.drop(columns="near_toggle").to_numpy())
    assert got["near_toggle"].tolist() == df["near_toggle"].astype(str).tolist()


def test_parquet_gaps_are_null(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    scene = sheetkin.parse_scene(SHORT, "short.toml")
    write_compute(scene, np.array([0.0, 90.0]), "parquet", str(tmp_path / "g.parquet"), allow_gaps=True)
    t = pq.read_table(tmp_path / "g.parquet")
    assert t.column("assembled").to_pylist() == [True, False]
    assert t.column("phi_2").to_pylist()[1] is None


def test_parquet_without_pyarrow_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)      # import pyarrow raises ImportError
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    target = tmp_path / "k.parquet"
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--format", "parquet",
                         "-o", target)
    one_error_line(err, code)
    assert "pip install 'sheetkin[parquet]'" in err and not target.exists()
    assert not list(tmp_path.iterdir())


def test_parquet_needs_a_file(capsys):
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--format", "parquet")
    one_error_line(err, code)
    assert "-o" in err and out == ""


# --------------------------------------------------------------------------- files: nothing lost
def test_failure_leaves_an_existing_output_untouched(tmp_path, capsys):
    short = tmp_path / "short.toml"
    short.write_text(SHORT, encoding="utf-8")
    target = tmp_path / "out.csv"
    target.write_text("precious\n")
    code, out, err = run(capsys, "compute", short, "--format", "csv", "--range", "0:360:1", "-o", target)
    one_error_line(err, code, 3)
    assert target.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv", "short.toml"]


# --------------------------------------------------------------------------- --range
def test_toggle_threshold_default_is_computes():
    assert TOGGLE_THRESHOLD == COMPUTE_TOGGLE_THRESHOLD


@pytest.mark.parametrize("spec, expected", [
    ("0:360:30", [30.0 * i for i in range(12)]),
    ("0:1:0.1", [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]),
    ("10:0:-2.5", [10.0, 7.5, 5.0, 2.5]),
    ("-90:90:45", [-90.0, -45.0, 0.0, 45.0]),
    ("0:1:0.3", [0.0, 0.3, 0.6, 0.9]),
    ("5:5.0001:1", [5.0]),
])
def test_range_is_arange_with_stop_excluded_and_exact_decimals(capsys, spec, expected):
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--format", "csv",
                         f"--range={spec}")
    assert code == 0, err
    got = [float(line.split(",")[0]) for line in out.splitlines()[1:]]
    assert got == expected                         # == : 0.3 is float("0.3"), not 0.1 * 3


@pytest.mark.parametrize("spec, word", [
    ("0:360:0", "STEP is 0"), ("0:360:-1", "no positions"), ("360:0:1", "no positions"),
    ("0:0:1", "no positions"), ("0:360", "START:STOP:STEP"), ("a:360:1", "'a'"),
    ("0:inf:1", "finite"), ("0:360:1e-7", "positions, more than"), ("0:1:0.0000000001", "decimal places"),
])
def test_range_refusals_are_one_line(capsys, spec, word):
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", f"--range={spec}")
    one_error_line(err, code)
    assert word in err and out == ""


def test_range_and_at_are_exclusive(capsys):
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--at", "10",
                         "--range", "0:10:1")
    one_error_line(err, code)
    assert "not allowed with" in err


# --------------------------------------------------------------------------- --at-file
def _csv_phi(out):
    return [float(line.split(",")[0]) for line in out.splitlines()[1:]]


def test_at_file_one_a_line(tmp_path, capsys):
    f = tmp_path / "angles.txt"
    f.write_text("# crank angles\n150\n\n  30.5 \n-1e-07\n200.5\n")
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--format", "csv",
                         "--at-file", f)
    assert code == 0 and err == ""
    assert _csv_phi(out) == [150.0, 30.5, -1e-07, 200.5]


def test_at_file_csv_column_phi_1_or_named(tmp_path, capsys):
    f = tmp_path / "angles.csv"
    f.write_text("id,phi_1,phi\n1,10,20\n2,\"11\",21\n\n")
    fourbar = ROOT / "workbooks" / "fourbar.toml"
    code, out, _ = run(capsys, "compute", fourbar, "--format", "csv", "--at-file", f)
    assert code == 0 and _csv_phi(out) == [10.0, 11.0]
    code, out, _ = run(capsys, "compute", fourbar, "--format", "csv", "--at-file", f"{f}:phi")
    assert code == 0 and _csv_phi(out) == [20.0, 21.0]
    # a CSV written by `sheetkin compute --format csv` is read back by its phi_1
    csv_out = tmp_path / "out.csv"
    code, _, _ = run(capsys, "compute", fourbar, "--format", "csv", "--range", "0:90:30", "-o", csv_out)
    code, out, _ = run(capsys, "compute", fourbar, "--format", "csv", "--at-file", csv_out)
    assert code == 0 and _csv_phi(out) == [0.0, 30.0, 60.0]


@pytest.mark.parametrize("text, spec, word", [
    ("10\n20\nabc\n", "", ":3: expected a number of degrees, got 'abc'"),
    ("10\nnan\n", "", ":2: expected a finite number"),
    ("10\n1e999\n", "", ":2: expected a finite number"),
    ("10\n20 30\n", "", ":2: expected a number"),
    ("", "", "no angles"),
    ("# only a comment\n\n", "", "no angles"),
    ("a,b\n1,2\n", "", ":1: no column 'phi_1' in the header (a, b); name one as FILE:COLUMN"),
    ("a,b\n1,2\n", ":c", ":1: no column 'c'"),
    ("x,phi_1\n1,2\n3\n", "", ":3: no value in column 'phi_1'"),
    ("x,phi_1\n1,oops\n", "", ":2: expected a number of degrees, got 'oops'"),
    ("phi_1\n", "", "no angles under"),
])
def test_at_file_errors_name_file_and_line(tmp_path, capsys, text, spec, word):
    f = tmp_path / "angles.txt"
    f.write_text(text)
    code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml", "--at-file", f"{f}{spec}")
    one_error_line(err, code)
    assert f"{f}{word}" in err or word in err, err
    assert str(f) in err and out == ""


def test_at_file_missing_or_not_text(tmp_path, capsys):
    (tmp_path / "bin").write_bytes(b"\xff\xfe\x00")
    for name, word in (("missing.txt", "no such file"), ("bin", "UTF-8"), (".", "directory")):
        code, out, err = run(capsys, "compute", ROOT / "workbooks" / "fourbar.toml",
                             "--at-file", tmp_path / name)
        one_error_line(err, code)
        assert word in err


@settings(max_examples=60, deadline=None)
@given(st.text(alphabet="0123456789.,-+eE#nainf \t\"x_phi1\n", max_size=60))
def test_at_file_fuzz_only_our_errors(tmp_path_factory, text):
    from sheetkin.cli.angles import read_angles
    f = tmp_path_factory.mktemp("fuzz") / "a.txt"
    f.write_text(text)
    try:
        values = read_angles(str(f))
    except InputError as e:              # the file's mistakes: the user's, one line naming it
        assert "\n" not in str(e) and str(f) in str(e)
    else:
        assert values.size and np.isfinite(values).all()


def test_angle_range_take_matches_exact_decimals():
    r = AngleRange(first=0, step=1, scale=10, count=100_000)
    assert np.array_equal(r.take(0, 100_000), np.array([float(f"{i / 10}") for i in range(100_000)]))


def test_output_to_a_pipe_a_symlink_and_a_file_with_its_mode(tmp_path, capsys):
    """Only new or regular files are written beside and renamed: a FIFO (like a device,
    /dev/null) is written as it is, a symbolic link stays a link, a file keeps its mode."""
    import stat
    fourbar = ROOT / "workbooks" / "fourbar.toml"
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    # the reader is open before the writer (a FIFO with no reader is refused at once, and a
    # reader thread's open could come late on a loaded machine); the CSV fits the pipe's buffer
    fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        code, out, err = run(capsys, "compute", fourbar, "--format", "csv", "-o", fifo)
        chunks = []
        while True:
            try:
                chunk = os.read(fd, 1 << 16)
            except BlockingIOError:
                break
            if not chunk:
                break
            chunks.append(chunk)
        got = [b"".join(chunks)]
    finally:
        os.close(fd)
    assert code == 0 and stat.S_ISFIFO(os.lstat(fifo).st_mode), err
    assert got and got[0].startswith(b"phi_1,") and got[0].count(b"\n") == 14
    real = tmp_path / "real.csv"
    real.write_text("old")
    real.chmod(0o600)
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    code, _, _ = run(capsys, "compute", fourbar, "--format", "csv", "-o", link)
    assert code == 0 and link.is_symlink() and real.read_text().startswith("phi_1,")
    code, _, _ = run(capsys, "compute", fourbar, "--format", "json", "-o", real)
    assert code == 0 and stat.S_IMODE(real.stat().st_mode) == 0o600 and real.read_text().startswith("{")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "pipe", "real.csv"]
