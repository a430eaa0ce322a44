"""The worst case at every cap of issue 23 (docs/reliability.md): time and peak memory of
each command given a file at the cap (it must be read and worked on) or past it (it must be
refused at once), for one file and for a batch.

    python benchmarks/worst_case.py [--out benchmarks/results/worst_case] [--only NAME ...] [--skip-heavy] [--tiny]

Run on demand, not by the tests. Each case runs `python -m sheetkin ...` (or a small Python
snippet for a reader alone) as a process; its peak memory is the largest sum of the resident
sizes of the process and all its children (workers, LibreOffice), sampled from /proc every
50 ms; its time is the wall clock, start-up included (about 1 s of imports here). Writes
worst_case.csv and prints a Markdown table. Linux only (/proc).
"""
from __future__ import annotations

import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sheetkin.course.batch import max_jobs  # noqa: E402
from sheetkin.course.book import MAX_EMBEDDED_POINTS  # noqa: E402
from sheetkin.course.issued import MAX_ROSTER_BYTES  # noqa: E402
from sheetkin.files import MAX_AT_FILE_BYTES, MAX_CLASS_LIST_BYTES  # noqa: E402
from sheetkin.kinematics.caps import MAX_SCENE_BYTES  # noqa: E402
from sheetkin.views.animate import MAX_FRAMES, MAX_SIZE  # noqa: E402
from sheetkin.xlsx.package import Limits  # noqa: E402

WORKBOOKS = ROOT / "workbooks"
FOURBAR = WORKBOOKS / "fourbar.toml"
LIMITS = Limits()


def _tree(pid: int) -> list[int]:
    kids: dict[int, list[int]] = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                ppid = int((d / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            kids.setdefault(ppid, []).append(int(d.name))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo += kids.get(p, [])
    return out


def _rss(pids: list[int]) -> int:
    total = 0
    for p in pids:
        try:
            for line in Path(f"/proc/{p}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1]) * 1024
        except OSError:
            pass
    return total


def measure(argv: list[str], cwd: Path, timeout: float = 900) -> tuple[float, int, int, str]:
    """(seconds, peak bytes of the process tree, exit code, last line of stderr)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    t0 = time.monotonic()
    proc = subprocess.Popen(argv, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    peak = 0
    tick = 0
    while proc.poll() is None:
        if time.monotonic() - t0 > timeout:
            proc.kill()
            break
        peak = max(peak, _rss(_tree(proc.pid) if tick % 10 == 0 or peak == 0 else [proc.pid]))
        tick += 1
        time.sleep(0.05)
    err = proc.stderr.read() if proc.stderr else ""
    proc.wait()
    last = (err.strip().splitlines() or [""])[-1]
    return time.monotonic() - t0, peak, proc.returncode, last


def sk(*args) -> list[str]:
    return [sys.executable, "-m", "sheetkin", *map(str, args)]


def py(code: str) -> list[str]:
    return [sys.executable, "-c", code]


# --------------------------------------------------------------------------- the files
def scene_at_cap(d: Path) -> Path:
    """The four-bar padded with comment lines to just under MAX_SCENE_BYTES."""
    base = FOURBAR.read_text(encoding="utf-8")
    line = "# " + "x" * 9_000 + "\n"
    n = (MAX_SCENE_BYTES - len(base.encode()) - 100) // len(line)
    p = d / "scene_cap.toml"
    p.write_text(base + line * n, encoding="utf-8")
    return p


def roster_at_cap(d: Path) -> Path:
    head = "variant,exercise,key,scene,L1,L2,L3\n"
    row = "v{:07d},e.xlsx,k.xlsx,s.toml,0.14,0.5,0.34\n"
    n = (MAX_ROSTER_BYTES - len(head)) // len(row.format(0)) - 1
    p = d / "roster.csv"
    p.write_text(head + "".join(row.format(i) for i in range(n)), encoding="utf-8")
    return p


def class_list_at_cap(d: Path) -> Path:
    head = "First name,Last name,Email address\n"
    row = "Ivan{0:06d},Petrov{0:06d},s{0:06d}@example.org\n"
    n = (MAX_CLASS_LIST_BYTES - len(head)) // len(row.format(0)) - 1
    p = d / "class.csv"
    p.write_text(head + "".join(row.format(i) for i in range(n)), encoding="utf-8")
    return p


def at_file_at_cap(d: Path) -> Path:
    line = "123.456789012345678\n"
    n = MAX_AT_FILE_BYTES // len(line) - 1
    p = d / "angles.txt"
    with open(p, "w") as f:
        block = line * 100_000
        for _ in range(n // 100_000):
            f.write(block)
    return p


def text_doubling_book(d: Path) -> Path:
    import openpyxl
    wb = openpyxl.Workbook()
    ws = wb.active
    ws["A1"] = '="ab"'
    for r in range(2, 42):
        ws[f"A{r}"] = f"=A{r - 1}&A{r - 1}"
    p = d / "doubling.xlsx"
    wb.save(p)
    return p


def fods(d: Path, rows: int, cols: int, name: str) -> Path:
    p = d / name
    p.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n<office:document xmlns:office="urn:oasis:names:tc:opendocument:'
        'xmlns:office:1.0" xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" xmlns:text="urn:'
        'oasis:names:tc:opendocument:xmlns:text:1.0" office:mimetype="application/vnd.oasis.opendocument.'
        'spreadsheet"><office:body><office:spreadsheet><table:table table:name="S">'
        f'<table:table-row table:number-rows-repeated="{rows}"><table:table-cell office:value-type="float" '
        f'office:value="1" table:number-columns-repeated="{cols}"><text:p>1</text:p></table:table-cell>'
        '</table:table-row></table:table></office:spreadsheet></office:body></office:document>', encoding="utf-8")
    return p


def big_book(d: Path) -> Path:
    """An .xlsx at max_cells: 100,000 rows x 20 numbers, written as XML directly."""
    p = d / "cells_cap.xlsx"
    rows, cols = LIMITS.max_rows, LIMITS.max_cells // LIMITS.max_rows
    letters = [chr(ord("A") + i) for i in range(cols)]
    main = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
    rel = "http://schemas.openxmlformats.org/officeDocument/2006/relationships"
    with zipfile.ZipFile(p, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-'
                   'types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.'
                   'relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override '
                   'PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.'
                   'spreadsheetml.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType='
                   '"application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/></Types>')
        z.writestr("_rels/.rels", f'<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/'
                   f'relationships"><Relationship Id="r1" Type="{rel}/officeDocument" Target="xl/workbook.xml"/>'
                   '</Relationships>')
        z.writestr("xl/workbook.xml", f'<workbook xmlns="{main}" xmlns:r="{rel}"><sheets><sheet name="S" '
                   'sheetId="1" r:id="rId1"/></sheets></workbook>')
        z.writestr("xl/_rels/workbook.xml.rels", '<Relationships xmlns="http://schemas.openxmlformats.org/'
                   f'package/2006/relationships"><Relationship Id="rId1" Type="{rel}/worksheet" '
                   'Target="worksheets/sheet1.xml"/></Relationships>')
        with z.open("xl/worksheets/sheet1.xml", "w") as f:
            f.write(f'<worksheet xmlns="{main}"><sheetData>'.encode())
            for r in range(1, rows + 1):
                f.write((f'<row r="{r}">' + "".join(f'<c r="{c}{r}"><v>{r}.5</v></c>' for c in letters)
                         + "</row>").encode())
            f.write(b"</sheetData></worksheet>")
    return p


def points_at_cap(d: Path) -> Path:
    """The four-bar with MAX_EMBEDDED_POINTS points, as a workbook."""
    base = FOURBAR.read_text(encoding="utf-8")
    extra = "".join(f'\n[[point]]\nname = "P{i}"\nlink = 2\nfrom = "A"\nalong = {0.01 * (i + 1):.2f}\n'
                    for i in range(MAX_EMBEDDED_POINTS - 2))
    scene = d / "points_cap.toml"
    scene.write_text(base + extra, encoding="utf-8")
    subprocess.run(sk("workbook", scene, "-o", d / "points_cap.xlsx"), check=True, capture_output=True,
                   env=dict(os.environ, PYTHONPATH=str(ROOT)))
    return d / "points_cap.xlsx"


def groups_past_cap(d: Path) -> Path:
    import openpyxl
    wb = openpyxl.load_workbook(WORKBOOKS / "fourbar.xlsx")
    ws = wb["scene"] if "scene" in wb.sheetnames else wb.worksheets[-1]
    row = ws.max_row + 1
    for i in range(400):
        for k, line in enumerate(["[[group]]", 'type = "RRR"', "links = [8, 9]"]):
            ws.cell(row + 3 * i + k, 1, line)
    p = d / "groups400.xlsx"
    wb.save(p)
    return p


def cases(d: Path, heavy: bool):
    yield "scene at the cap (8 MB)", "compute", sk("compute", scene_at_cap(d), "-o", d / "o.csv", "--format", "csv")
    yield "scene: /dev/zero", "compute", sk("compute", "/dev/zero")
    roster = roster_at_cap(d)
    yield "roster at the cap (5 MB)", "validate --roster", sk("validate", WORKBOOKS / "fourbar.xlsx",
                                                              "--roster", roster)
    yield "class list at the cap (5 MB)", "validate --grades --class-list", sk(
        "validate", WORKBOOKS / "fourbar.xlsx", "--grades", d / "g.csv", "--class-list", class_list_at_cap(d))
    at = at_file_at_cap(d)
    yield "--at-file at the cap (20 MB): read only", "read_angles", py(
        f"from sheetkin.cli.angles import read_angles; print(len(read_angles({str(at)!r})))")
    at.unlink()
    yield "text doubled 40 times (cap 32,767 characters)", "evaluate", sk("evaluate", text_doubling_book(d))
    yield ".fods at the cells cap (100,000 x 20): the gate", "check_opendocument", py(
        "from sheetkin.xlsx.convert import check_opendocument; "
        f"check_opendocument({str(fods(d, LIMITS.max_rows, 20, 'cap.fods'))!r})")
    yield ".fods past the cap (1,000,000 rows)", "evaluate", sk("evaluate", fods(d, 1_000_000, 10, "bomb.fods"))
    big = big_book(d)
    yield "book at max_cells (2,000,000 numbers)", "evaluate", sk("evaluate", big, "-o", d / "e.txt")
    yield "book at max_cells", "workbook --check", sk("workbook", FOURBAR, "--check", "-o", big)
    yield "book at max_cells", "validate", sk("validate", big)
    yield f"embedded scene: {MAX_EMBEDDED_POINTS} points (the cap)", "validate", sk("validate", points_at_cap(d))
    yield "embedded scene: 400 groups (past the cap)", "validate", sk("validate", groups_past_cap(d))
    yield f"animate --frames {MAX_FRAMES}", "animate .html", sk("animate", FOURBAR, "--frames", MAX_FRAMES,
                                                              "-o", d / "a.html")
    yield f"animate --size {MAX_SIZE}", "animate .png", sk("animate", FOURBAR, "--size", MAX_SIZE, "-o", d / "a.png")
    if heavy:
        yield "animate --frames 265 --size 320 (the GIF pixel cap)", "animate .gif", sk(
            "animate", FOURBAR, "--frames", 265, "-o", d / "a.gif")
        yield f"animate --frames {MAX_FRAMES} (past the GIF pixel cap)", "animate .gif", sk(
            "animate", FOURBAR, "--frames", MAX_FRAMES, "-o", d / "b.gif")
    klass = d / "class"
    klass.mkdir()
    for i in range(40):
        shutil.copy(WORKBOOKS / "fourbar.xlsx", klass / f"s{i:02d}.xlsx")
    yield f"batch: 40 books, --jobs {max_jobs()} (the cap)", "validate", sk(
        "validate", klass, "--jobs", max_jobs(), "--html", d / "r.html", "--grades", d / "gr.csv")
    yield "batch: 40 books, --jobs 1", "validate", sk("validate", klass, "--jobs", 1)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "worst_case"))
    ap.add_argument("--only", nargs="*", help="run the cases whose name contains one of these")
    ap.add_argument("--skip-heavy", action="store_true", help="leave out the GIFs")
    ap.add_argument("--tiny", action="store_true",
                    help="a smoke run for CI: the first two cases only, no CSV written")
    a = ap.parse_args()
    out = Path(a.out)
    if not a.tiny:              # a smoke run leaves the recorded results alone
        out.mkdir(parents=True, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory(prefix="sheetkin-worst-") as tmp:
        d = Path(tmp)
        for k, (name, command, argv) in enumerate(cases(d, not a.skip_heavy)):
            if a.tiny and k == 2:   # the cases' files are made as they come: stop before the big ones
                break
            if a.only and not any(o in name for o in a.only):
                continue
            secs, peak, code, last = measure(argv, d)
            rows.append({"case": name, "command": command, "seconds": f"{secs:.1f}",
                         "peak_MB": f"{peak / 1e6:.0f}", "exit": code, "says": last[:150]})
            print(f"| {name} | {command} | {secs:.1f} | {peak / 1e6:.0f} | {code} | {last[:90]} |", flush=True)
    if a.tiny:
        return
    with open(out / "worst_case.csv", "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
