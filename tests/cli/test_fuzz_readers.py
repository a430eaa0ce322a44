"""Issue 23, item 5: fuzzers for the small readers (roster, class list, key) and the command
line's options. Whatever the bytes or the option values, only our errors come out: a
return value, or one line (RosterError, GradesError, an OSError naming the file, exit 2);
never another exception, never exit 70."""
from __future__ import annotations

import string
from pathlib import Path

from helpers.clirun import run
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sheetkin.cli.args import build_parser
from sheetkin.course.grades import GradesError, read_class_list
from sheetkin.course.issued import RosterError, read_key, read_roster
from sheetkin.views import animate

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "workbooks" / "fourbar.toml"
FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])

_CSV_CHARS = string.ascii_letters + string.digits + ",;\t\"'\n\r .-+eE#\\\x00\xa0é—"
_ROSTER_HEAD = "variant,exercise,key,scene,L1,L2\n"
_CLASS_HEAD = "First name,Last name,Email address\n"


def csvish(head: str):
    """Text near the format: a real header (sometimes) then random fields and lines."""
    field = st.one_of(st.text(_CSV_CHARS, max_size=12), st.sampled_from(["1", "0.1", "nan", "inf", "-1e999",
                                                                         "1e308", '"a,b"', '""', "a\"b"]))
    line = st.lists(field, max_size=8).map(lambda f: ",".join(f))
    body = st.lists(line, max_size=12).map("\n".join)
    return st.tuples(st.booleans(), body).map(lambda t: (head if t[0] else "") + t[1])


def raw_bytes():
    return st.one_of(st.binary(max_size=400), csvish(_ROSTER_HEAD).map(lambda s: s.encode("utf-8")),
                     st.text(max_size=200).map(lambda s: s.encode("utf-8", "surrogatepass")))


def _one_line(e: BaseException):
    text = str(e)
    assert text and "\n" not in text and "Traceback" not in text, repr(text)


@FUZZ
@given(data=st.one_of(raw_bytes(), csvish(_ROSTER_HEAD).map(str.encode)))
def test_roster_reader_only_our_errors(tmp_path, data):
    path = tmp_path / "roster.csv"
    path.write_bytes(data)
    try:
        roster = read_roster(path)
    except RosterError as e:
        _one_line(e)
        assert str(path) in str(e)
    else:
        assert roster.rows


@FUZZ
@given(data=st.one_of(raw_bytes(), csvish(_CLASS_HEAD).map(str.encode),
                      csvish(_CLASS_HEAD.replace(",", ";")).map(str.encode)))
def test_class_list_reader_only_our_errors(tmp_path, data):
    path = tmp_path / "class.csv"
    path.write_bytes(data)
    try:
        read_class_list(str(path))
    except (GradesError, OSError) as e:
        _one_line(e)


@FUZZ
@given(data=st.one_of(st.binary(max_size=200), st.text("0123456789abcdefABCDEFxyz \n\t\r", max_size=140)
                      .map(str.encode)))
def test_key_reader_only_our_errors(tmp_path, data):
    path = tmp_path / ".sheetkin-key"
    path.write_bytes(data)
    try:
        key = read_key(path)
    except RosterError as e:
        _one_line(e)
    else:
        assert len(key) >= 16


# the option values an attacker or an unlucky user types
_NUMBERS = ["0", "1", "-1", "0.5", "1e-12", "1E+1000000", "1e-999999999", "nan", "-inf", "inf", "", " ", "x",
            "0x10", "1_000", "٣", "1e308", "-0", "+5", "10000000000000000000000", "1e6", "3600", "4000", "100"]


@settings(max_examples=120, deadline=None)
@given(opt=st.sampled_from(["--frames", "--size", "--fps", "--toggle-threshold"]),
       value=st.one_of(st.sampled_from(_NUMBERS), st.text(max_size=8)))
def test_animate_options_only_our_errors(opt, value):
    try:
        args = build_parser().parse_args(["animate", str(FOURBAR), "-o", "x.gif", f"{opt}={value}"])
    except SystemExit as e:
        assert e.code == 2
        return
    animate.check_caps(args.frames, args.fps, args.size)        # what parses is within the caps


def _range_part():
    return st.one_of(st.sampled_from(_NUMBERS), st.integers(-720, 720).map(str),
                     st.decimals(-720, 720, places=3, allow_nan=False).map(str))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(start=_range_part(), stop=_range_part(),
       step=st.one_of(st.sampled_from(["0", "1E-999999999", "1E+1000000", "nan", "", "x", "-1e-20", "1e13"]),
                      st.integers(1, 90).map(str), st.integers(-90, -1).map(str)),
       extra=st.sampled_from([[], ["--format", "json"], ["--analogs"], ["--allow-gaps"], ["--format", "csv"]]))
def test_compute_range_only_our_errors(capsys, start, stop, step, extra):
    code, out, err = run(capsys, "compute", FOURBAR, f"--range={start}:{stop}:{step}", *extra)
    assert code in (0, 2, 3), err
    if code:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("sheetkin: error: "), err


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(argv=st.lists(st.one_of(st.sampled_from(["--at", "--jobs", "--positions", "--step-deg", "--phi0-deg",
                                                "-n", "--seed", "--min-det", "--omega", "--kw", "--l3"]),
                               st.sampled_from(_NUMBERS)), max_size=6),
       command=st.sampled_from(["compute", "workbook", "validate", "variants", "synth"]))
def test_any_options_only_our_errors(capsys, tmp_path, command, argv):
    """Random option soup for each command: argparse's exit 2 or the command's own; never
    exit 70. (Outputs would go to the working folder: --check and --out keep them in tmp.)"""
    fixed = {"compute": ["compute", str(FOURBAR)], "workbook": ["workbook", str(FOURBAR), "--check"],
             "validate": ["validate", str(ROOT / "workbooks" / "fourbar.xlsx")],
             "variants": ["variants", str(FOURBAR), "--out", str(tmp_path / "v")],
             "synth": ["synth", "crank-rocker"]}[command]
    if command == "variants" and "-n" not in argv:
        argv = [*argv, "-n", "2"]                       # 30 variants by default: too slow here
    if command == "variants":
        i = argv.index("-n")
        if i + 1 < len(argv) and argv[i + 1].strip().lstrip("+").isdigit() and int(argv[i + 1]) > 3:
            argv = argv[:i + 1] + ["2"] + argv[i + 2:]
    code, out, err = run(capsys, *fixed, *argv)
    assert code in (0, 1, 2, 3), err
    assert "internal error" not in err and "Traceback" not in err
