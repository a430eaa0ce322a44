"""Hostile input, issue 23 (third round): work bounded by the caps, nothing lost, no exit 70
from any input, no silent wrong answer. Each case of the issue is a test here (the signals
and the killed worker: tests/cli/test_signals.py; the evaluator's functions:
tests/xlsx/test_excel_edge_cases.py)."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from helpers.clirun import run

from sheetkin.cli import args as cli_args
from sheetkin.course import batch
from sheetkin.course.book import MAX_EMBEDDED_GROUPS, MAX_EMBEDDED_POINTS
from sheetkin.files import MAX_AT_FILE_BYTES, MAX_CLASS_LIST_BYTES, MAX_KEY_BYTES, RefusedFile, read_bytes, shown
from sheetkin.views import animate

ROOT = Path(__file__).resolve().parents[2]
WORKBOOKS = ROOT / "workbooks"
FOURBAR = WORKBOOKS / "fourbar.toml"
BOOK = WORKBOOKS / "fourbar.xlsx"


def one_error(code, err, expected=2):
    assert code == expected, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sheetkin: error: "), err
    assert "internal error" not in err and "Traceback" not in err
    return lines[0]


def run_process(*argv, timeout=120, **kw):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "sheetkin", *map(os.fsdecode, argv)], env=env,
                          capture_output=True, text=True, timeout=timeout, **kw)


# --------------------------------------------------------------------------- 1. bounded
@pytest.mark.parametrize("argv", [
    ("compute", "/dev/zero"),
    ("compute", FOURBAR, "--at-file", "/dev/zero"),
    ("validate", BOOK, "--roster", "/dev/zero"),
    ("validate", BOOK, "--key", "/dev/zero"),
    ("evaluate", "/dev/zero"),
])
def test_devices_are_refused_before_reading(capsys, argv):
    line = one_error(*run(capsys, *argv)[::2])
    assert "/dev/zero" in line


def test_class_list_device_refused(capsys, tmp_path):
    code, _, err = run(capsys, "validate", BOOK, "--grades", tmp_path / "g.csv", "--class-list", "/dev/zero")
    assert "character device" in one_error(code, err)


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "book.xlsx"
    os.mkfifo(path)
    return path


@pytest.mark.parametrize("command", ["validate", "evaluate", "compute", "at-file", "roster", "key"])
def test_a_fifo_never_hangs(fifo, command):
    argv = {"validate": ("validate", fifo), "evaluate": ("evaluate", fifo), "compute": ("compute", fifo),
            "at-file": ("compute", FOURBAR, "--at-file", fifo), "roster": ("validate", BOOK, "--roster", fifo),
            "key": ("validate", BOOK, "--key", fifo)}[command]
    res = run_process(*argv, timeout=60)         # before: blocked forever opening the FIFO
    assert res.returncode == 2, res.stderr
    assert "internal error" not in res.stderr + res.stdout
    assert "not a regular file" in res.stderr + res.stdout


def test_read_bytes_caps_while_reading(tmp_path):
    f = tmp_path / "big"
    f.write_bytes(b"x" * 1001)
    with pytest.raises(RefusedFile, match="at most 1,000"):
        read_bytes(f, 1000)
    assert read_bytes(f, 1001) == b"x" * 1001
    assert MAX_KEY_BYTES < MAX_CLASS_LIST_BYTES < MAX_AT_FILE_BYTES


@pytest.mark.parametrize("opt, value, cap", [("--frames", "1000000", animate.MAX_FRAMES),
                                             ("--size", "100000000", animate.MAX_SIZE),
                                             ("--fps", "1e-12", None), ("--fps", "1000", None)])
def test_animation_caps(capsys, tmp_path, opt, value, cap):
    line = one_error(*run(capsys, "animate", FOURBAR, "-o", tmp_path / "x.gif", opt, value)[::2])
    assert opt in line
    assert not (tmp_path / "x.gif").exists()


def test_animate_caps_agree_with_the_parser():
    assert (cli_args.MAX_FRAMES, cli_args.MAX_SIZE, cli_args.FPS_RANGE) == \
        (animate.MAX_FRAMES, animate.MAX_SIZE, (animate.MIN_FPS, animate.MAX_FPS))
    assert batch.max_jobs() == cli_args.MAX_JOBS
    with pytest.raises(animate.AnimationError):
        animate.check_caps(36, float("nan"), 320)


def test_jobs_capped(capsys):
    line = one_error(*run(capsys, "validate", BOOK, "--jobs", "10000")[::2])
    assert "--jobs" in line and f"at most {batch.max_jobs()}" in line


def _scene_sheet_book(tmp_path, extra: str) -> Path:
    """The four-bar's book with `extra` appended to its hidden scene sheet's TOML."""
    import openpyxl
    wb = openpyxl.load_workbook(BOOK)
    ws = wb["scene"] if "scene" in wb.sheetnames else wb.worksheets[-1]
    row = ws.max_row + 1
    for k, line in enumerate(extra.splitlines()):
        ws.cell(row + k, 1, line)
    out = tmp_path / "embedded.xlsx"
    wb.save(out)
    return out


@pytest.mark.parametrize("kind, cap", [("point", MAX_EMBEDDED_POINTS), ("group", MAX_EMBEDDED_GROUPS)])
def test_embedded_scene_capped(capsys, tmp_path, kind, cap):
    extra = "".join(f'[[{kind}]]\nname = "X{i}"\n' for i in range(cap + 1))
    book = _scene_sheet_book(tmp_path, extra)
    code, out, err = run(capsys, "validate", book)
    assert code == 2 and "internal error" not in out + err
    assert f"[[{kind}]] tables" in out and f"at most {cap}" in out


def test_fods_expansion_refused_before_libreoffice(capsys, tmp_path):
    fods = tmp_path / "bomb.fods"
    fods.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n<office:document xmlns:office="urn:oasis:names:tc:opendocument:'
        'xmlns:office:1.0" xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" xmlns:text="urn:'
        'oasis:names:tc:opendocument:xmlns:text:1.0" office:mimetype="application/vnd.oasis.opendocument.'
        'spreadsheet"><office:body><office:spreadsheet><table:table table:name="S"><table:table-row '
        'table:number-rows-repeated="1000000"><table:table-cell office:value-type="float" office:value="1">'
        '<text:p>1</text:p></table:table-cell></table:table-row></table:table></office:spreadsheet>'
        '</office:body></office:document>', encoding="utf-8")
    assert fods.stat().st_size < 1500
    line = one_error(*run(capsys, "evaluate", fods)[::2])
    assert "1,000,000 rows" in line and "at most 100,000 rows" in line


def test_ods_zip_bomb_refused(capsys, tmp_path):
    ods = tmp_path / "bomb.ods"
    with zipfile.ZipFile(ods, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr(zipfile.ZipInfo("mimetype"), "application/vnd.oasis.opendocument.spreadsheet")
        z.writestr("content.xml", b"<a>" + b" " * 50_000_000 + b"</a>")
    line = one_error(*run(capsys, "evaluate", ods)[::2])
    assert "zip bomb" in line or "inflates" in line


def test_workbook_check_reads_through_the_gate(capsys, tmp_path):
    bomb = tmp_path / "fourbar.xlsx"
    with zipfile.ZipFile(bomb, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", "<Types/>")
        z.writestr("xl/workbook.xml", b"<a>" + b" " * 50_000_000 + b"</a>")
    code, out, err = run(capsys, "workbook", FOURBAR, "-o", bomb, "--check")
    line = one_error(code, err)
    assert "zip bomb" in line or "ratio" in line or "inflates" in line, line


def test_workbook_check_still_says_up_to_date(capsys):
    code, out, err = run(capsys, "workbook", FOURBAR, "--check")
    assert code == 0 and "up to date" in out, err


# --------------------------------------------------------------------------- 2. nothing lost
def _roster_with_key(tmp_path):
    (tmp_path / "roster.csv").write_text("variant,exercise,key,scene,L1\n1,a,b,c,0.1\n", encoding="utf-8")
    key = tmp_path / ".sheetkin-key"
    key.write_text("00112233445566778899aabbccddeeff\n", encoding="utf-8")
    return key


@pytest.mark.parametrize("opt", ["--html", "--grades"])
def test_the_key_beside_the_roster_is_an_input(capsys, tmp_path, opt):
    key = _roster_with_key(tmp_path)
    before = key.read_bytes()
    line = one_error(*run(capsys, "validate", BOOK, "--roster", tmp_path / "roster.csv", opt, key)[::2])
    assert "refusing to overwrite" in line
    assert key.read_bytes() == before


def test_at_file_is_an_input(capsys, tmp_path):
    angles = tmp_path / "a.txt"
    angles.write_text("0\n10\n")
    line = one_error(*run(capsys, "compute", FOURBAR, "--at-file", angles, "-o", angles)[::2])
    assert "refusing to overwrite" in line and angles.read_text() == "0\n10\n"


@pytest.mark.parametrize("fmt", ["csv", "json", "parquet", "table"])
def test_a_link_as_output_is_written_through(capsys, tmp_path, fmt):
    target = tmp_path / "target"
    target.write_text("old")
    link = tmp_path / "link.out"
    link.symlink_to(target)
    code, _, err = run(capsys, "compute", FOURBAR, "--format", fmt, "-o", link)
    assert code == 0, err
    assert link.is_symlink() and target.stat().st_size > 1000
    assert not list(tmp_path.glob(".sheetkin-*"))


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
@pytest.mark.parametrize("device", ["/dev/null", "/dev/stdout"])
def test_devices_as_output(tmp_path, fmt, device):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-m", "sheetkin", "compute", str(FOURBAR), "--format", fmt,
                          "-o", device], env=env, capture_output=True, timeout=120)
    assert res.returncode == 0, res.stderr
    if device == "/dev/stdout":
        assert res.stdout.startswith(b"PAR1" if fmt == "parquet" else b"phi_1")
    assert not list(Path("/dev").glob(".sheetkin-*"))


def test_a_fifo_without_reader_as_output_is_refused(capsys, tmp_path):
    fifo = tmp_path / "out.csv"
    os.mkfifo(fifo)
    line = one_error(*run(capsys, "compute", FOURBAR, "--format", "csv", "-o", fifo)[::2])
    assert "no reader" in line


def test_a_fifo_with_a_reader_gets_the_output(tmp_path):
    fifo = tmp_path / "out.csv"
    os.mkfifo(fifo)
    reader = subprocess.Popen(["cat", str(fifo)], stdout=subprocess.PIPE)
    import time
    time.sleep(0.3)
    res = run_process("compute", FOURBAR, "--format", "csv", "-o", fifo)
    got = reader.communicate(timeout=60)[0]
    assert res.returncode == 0, res.stderr
    assert got.count(b"\n") == 14          # the header and the scene's 13 positions


def test_html_and_workbook_written_by_rename(capsys, tmp_path):
    out = tmp_path / "r.html"
    out.write_text("old")
    os.chmod(out, 0o640)
    code, _, err = run(capsys, "validate", BOOK, "--html", out)
    assert code == 0, err
    assert "<html" in out.read_text(encoding="utf-8").lower()
    assert oct(out.stat().st_mode & 0o777) == oct(0o640)
    assert not list(tmp_path.glob(".sheetkin-*"))


# --------------------------------------------------------------------------- 3. no exit 70
@pytest.mark.parametrize("spec", ["0:1E+1000000:1", "0:1:1E-999999999", "1E+400:1:1", "0:1:-1E-20",
                                  "-1E+13:0:1", "0:1e999999999999999999:1"])
def test_absurd_ranges(capsys, spec):
    line = one_error(*run(capsys, "compute", FOURBAR, f"--range={spec}")[::2])
    assert "--range" in line


@pytest.fixture
def undecodable(tmp_path):
    folder = tmp_path / "class"
    folder.mkdir()
    name = os.fsdecode(b"st\xffud.xlsx")
    (folder / name).write_bytes(BOOK.read_bytes())
    return folder


def test_undecodable_names_are_escaped(undecodable, tmp_path):
    res = run_process("validate", undecodable, "--html", tmp_path / "r.html", "--grades", tmp_path / "g.csv")
    assert res.returncode == 0, res.stderr
    assert "st\\xffud.xlsx" in res.stdout
    assert "st\\xffud.xlsx" in (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "st\\xffud.xlsx" in (tmp_path / "g.csv").read_text(encoding="utf-8-sig")
    res = run_process("validate", undecodable, BOOK, "--json")
    assert res.returncode == 0, res.stderr
    json.loads(res.stdout)
    assert "st\\\\xffud.xlsx" in res.stdout          # JSON's escape of the backslash


def test_shown():
    assert shown(os.fsdecode(b"a\xffb")) == "a\\xffb"
    assert shown("\ud800x") == "\\ud800x"
    assert shown("plain") == "plain"


def _typed(tmp_path, value: str, cell: str | None = None) -> Path:
    """The four-bar's book with a computed cell (F41, y_A) replaced by the number `value`
    (or by `cell`, the <c> element's attributes after r=".." and its content)."""
    out = tmp_path / f"typed_{abs(hash((value, cell)))}.xlsx"
    with zipfile.ZipFile(BOOK) as zin, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zout:
        for info in zin.infolist():
            data = zin.read(info)
            if info.filename == "xl/worksheets/sheet1.xml":
                s = data.decode()
                m = [m for m in re.finditer(r'<c r="(F(\d+))"[^>]*><f>[^<]*</f><v>[^<]*</v></c>', s)
                     if int(m.group(2)) > 40][0]
                body = f"><v>{value}</v>" if cell is None else cell
                s = s[:m.start()] + f'<c r="{m.group(1)}"{body}</c>' + s[m.end():]
                data = s.encode()
            zout.writestr(info, data)
    return out


@pytest.mark.parametrize("value", ["NaN", "-INF", "inf", "1e999"])
def test_non_finite_typed_values_are_a_wrong_row(capsys, tmp_path, value):
    code, out, err = run(capsys, "validate", _typed(tmp_path, value))
    assert code == 1, out + err                   # mistakes found, not unusable, not exit 70
    assert "#NUM!" in out and "internal error" not in out


@pytest.mark.parametrize("what, cell", [
    ("a 40,000-character inline string", ' t="inlineStr"><is><t>' + "x" * 40_000 + "</t></is>"),
    ("a 40,000-character saved text result", ' t="str"><f>F40&amp;""</f><v>' + "x" * 40_000 + "</v>"),
    ("REPT a billion times", ' t="str"><f>REPT("ab",1E9)</f><v></v>'),
    ("text doubled 40 times", ' t="str"><f>REPT(REPT(REPT(REPT("ab",1000),1000),1000),1000)</f><v></v>'),
    ("the text #N/A typed", ' t="inlineStr"><is><t>#N/A</t></is>'),
    ("the text #N/A as a formula's result", ' t="str"><f>"#N/A"</f><v>#N/A</v>'),
])
def test_long_and_error_like_text_is_a_wrong_row(capsys, tmp_path, what, cell):
    """Text past Excel's 32,767 characters (read from the file, or made by a formula), or a
    text that spells an error, in a computed cell: that row is wrong, bounded in time."""
    import time
    t0 = time.monotonic()
    code, out, err = run(capsys, "validate", _typed(tmp_path, "", cell))
    assert code == 1, what + out + err            # mistakes found: not unusable, not exit 70
    assert "internal error" not in out + err and "Traceback" not in err
    assert time.monotonic() - t0 < 60


# --------------------------------------------------------------------------- 4. no silent wrong answer
def test_duplicate_sheet_names_refused(capsys, tmp_path):
    out = tmp_path / "dup.xlsx"
    with zipfile.ZipFile(BOOK) as zin, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zout:
        for info in zin.infolist():
            data = zin.read(info)
            if info.filename == "xl/workbook.xml":
                names = re.findall(rb'<sheet [^>]*name="([^"]+)"', data)
                data = data.replace(b'name="' + names[1] + b'"', b'name="' + names[0].upper() + b'"', 1)
            zout.writestr(info, data)
    code, stdout, err = run(capsys, "validate", out)
    assert code == 2 and "two sheets named" in stdout


def test_evaluate_json_is_strict(capsys, tmp_path):
    book = _typed(tmp_path, "NaN")
    code, out, err = run(capsys, "evaluate", book, "--format", "json")
    assert code == 0, err
    json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} is not JSON"))


def test_strict_json_rows_nulls_non_finite_values():
    from sheetkin.cli.commands import strict_json_rows

    # evaluate no longer builds a DataFrame (no pandas): the rows' names and their values
    rows, bad = strict_json_rows(["a", "b"], [[1.0, float("nan")], [float("-inf"), "x"]])
    assert rows == {"a": [1.0, None], "b": [None, "x"]}
    assert bad == ["a[2] = nan", "b[1] = -inf"]
    json.dumps(rows, allow_nan=False)


def test_gif_pixel_cap(capsys, tmp_path):
    """Ten frames at 4,000 px: about 120 million pixels, past MAX_GIF_PIXELS (990 frames at
    320 px took 1.7 GB): refused before drawing, nothing written."""
    line = one_error(*run(capsys, "animate", FOURBAR, "-o", tmp_path / "x.gif", "--frames", "10",
                          "--size", "4000")[::2])
    assert "million pixels" in line and f"{animate.MAX_GIF_PIXELS / 1e6:,.0f} million" in line
    assert not list(tmp_path.iterdir())


def test_ods_submission_has_no_false_disagreements(capsys, tmp_path, soffice):
    """The four-bar's book saved as .ods by LibreOffice (as a student would) and validated:
    its logical check cells are saved as 1/0, which equal TRUE/FALSE (every .ods submission
    was told "formula and saved value disagree")."""
    from sheetkin.xlsx import libreoffice
    src = tmp_path / "in" / "fourbar.xlsx"
    src.parent.mkdir()
    src.write_bytes(BOOK.read_bytes())
    libreoffice._convert([src], tmp_path, "ods", "ods", 300)
    code, out, err = run(capsys, "validate", tmp_path / "fourbar.ods", "--lang", "en")
    assert code == 0, out + err
    assert "disagree" not in out and "all correct" in out


def test_variants_of_an_undecodable_scene_name(tmp_path):
    scene = tmp_path / os.fsdecode(b"sc\xffene.toml")
    scene.write_bytes(FOURBAR.read_bytes())
    res = run_process("variants", scene, "-n", "2", "--seed", "1", "--out", tmp_path / "v", timeout=300)
    assert res.returncode == 0, res.stderr                # was exit 70 writing the variants' scenes
    text = next((tmp_path / "v").glob("*.toml")).read_text(encoding="utf-8")
    assert "sc\\xffene" in text
