"""Peak memory and time of the evaluator on a workbook at sheetkin's input limits.

    python benchmarks/evaluator_memory.py [--out DIR] [--keep] [--parts distinct,runs,notes]

Run on demand, not by the tests. Builds (XML written directly, no openpyxl) one workbook
that sits at the documented limits of sheetkin.xlsx.package.Limits and the evaluator (README, "What
files the evaluator reads"), about 50 MB on disk, then evaluates it in a child process
(`sheetkin.xlsx.evaluator.evaluate(path, strict=False)`) and reports the child's peak resident
memory (VmHWM from /proc/self/status, and ru_maxrss) and wall time, for the whole run and
for reading alone (`read_book`). Target: peak RSS below 1 GB.

The workbook (every part below max_part_bytes, all below max_total_bytes, ratios below
max_ratio; used ranges below max_used_cells together; reads below max_reads):

* Data: random numbers and random text in a block of 1,400 rows x 1,000 columns (~90 MB
  of XML that deflate cannot squeeze much);
* Distinct: formula cells that are all different (no runs: each is tokenized, parsed and
  evaluated on its own), up to max_formula_chars of formula text in all;
* Runs: rows of formulas filled right over 4,000 columns with large relative ranges
  (=SUM(Data!A$1:A$2300)...: read in pieces, CHUNK_READS), absolute ranges over the whole
  Data block (=SUM(Data!$A$1:$ALL${DATA_ROWS})...), whole-grid ranges clipped to the used range
  ($A$1:$XFD$1048576), until the formulas read about max_reads cells; and one constant
  at Runs!A2000, so that the used ranges come near max_used_cells;
* Notes: 600 x 400 cells of random text, so that the file comes near max_file_bytes
  (50 MB) and the cells near max_cells.

In all about max_cells cells hold something.

Prints a table, and with --out writes DIR/evaluator_memory.json.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from openpyxl.utils import get_column_letter  # noqa: E402

from sheetkin.xlsx.package import Limits  # noqa: E402

NS = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
SML_CT = "application/vnd.openxmlformats-officedocument.spreadsheetml"
RNS = "http://schemas.openxmlformats.org/officeDocument/2006/relationships"
DATA_ROWS, DATA_COLS = 1400, 1000
FAR_ROW = 2000                 # a constant at Runs!A2000: the used range 2000 x 4000
RUN_COLS = 4000
NOTES_ROWS, NOTES_COLS = 600, 400


def _sheet(rows) -> bytes:
    """A worksheet part from (row number, [(column, xml of the cell's content)])."""
    out = [f'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<worksheet xmlns="{NS}"><sheetData>']
    for r, cells in rows:
        out.append(f'<row r="{r}">')
        out.extend(f'<c r="{get_column_letter(c)}{r}"{body}</c>' for c, body in cells)
        out.append("</row>")
    out.append("</sheetData></worksheet>")
    return "".join(out).encode()


def data_sheet(rng: random.Random) -> bytes:
    """Random numbers, and in every other column random text (inline strings): little for
    deflate to squeeze, so the file is large for its cells."""
    letters = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"

    def cell(c):
        if c % 2:
            return f"><v>{rng.random():.15f}</v>"
        return f' t="inlineStr"><is><t>{"".join(rng.choices(letters, k=40))}</t></is>'
    return _sheet((r, [(c, cell(c)) for c in range(1, DATA_COLS + 1)]) for r in range(1, DATA_ROWS + 1))


def notes_sheet(rng: random.Random, rows: int, cols: int) -> bytes:
    """Random text in every cell: brings the file near max_file_bytes and the cells near max_cells."""
    letters = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
    return _sheet((r, [(c, f' t="inlineStr"><is><t>{"".join(rng.choices(letters, k=36))}</t></is>')
                       for c in range(1, cols + 1)]) for r in range(1, rows + 1))


def distinct_sheet(rng: random.Random, chars: int) -> tuple[bytes, int, int]:
    """Formula cells all different, about `chars` characters of formula text in all."""
    rows, total, n, r = [], 0, 0, 0
    while total < chars:
        r += 1
        cells = []
        for c in range(1, 201):
            i, j = rng.randint(1, DATA_ROWS - 10), rng.randint(1, DATA_COLS - 10)
            a, b, c2, d = (get_column_letter(j + k) for k in range(4))
            f = (f"Data!{a}{i}*{rng.random():.12f}+SIN(Data!{b}{i + 1})"
                 f"-ROUND(IF(Data!{a}{i}>0.5,{rng.random():.9f},Data!{c2}{i}),3)"
                 f"+MAX(Data!{a}{i}:{d}{i + 9})")
            cells.append((c, f"><f>{f}</f>"))
            total += len(f)
            n += 1
        rows.append((r, cells))
    return _sheet(rows), n, total


def _data_col(c: int) -> str:
    """The Data sheet's column that run column c reads (they wrap around DATA_COLS)."""
    return get_column_letter((c - 1) % DATA_COLS + 1)


def runs_sheet(reads: int) -> tuple[bytes, int, int]:
    """Rows of formulas filled right over RUN_COLS columns, reading about `reads` cells."""
    rows, total, r = [], 0, 0
    kinds = [
        # per cell: a column of Data (2,500 cells), relative
        (lambda c: f"SUM(Data!{_data_col(c)}$1:{_data_col(c)}${DATA_ROWS})", DATA_ROWS),
        # one block for the run: the whole Data sheet, absolute, plus a relative cell
        (lambda c: f"SUM(Data!$A$1:$ALL${DATA_ROWS})+Data!{_data_col(c)}1", 1),
        # the whole grid, clipped to the used range
        (lambda c: f"MAX(Data!$A$1:$XFD$1048576)-{get_column_letter(c)}$1"
                   f"+SUMPRODUCT(Data!$A$1:$J${DATA_ROWS},Data!$B$1:$K${DATA_ROWS})", 1),
    ]
    k = 0
    while total < reads:
        r += 1
        make, per_cell = kinds[k % len(kinds)]
        k += 1
        rows.append((r, [(c, f"><f>{make(c)}</f>") for c in range(1, RUN_COLS + 1)]))
        # a row of 4,000 is 4 runs (the Data column wraps after 1,000): a block read once per run
        total += per_cell * RUN_COLS + (DATA_ROWS * DATA_COLS * (RUN_COLS // DATA_COLS) if per_cell == 1 else 0)
    rows.append((FAR_ROW, [(1, "><v>1</v>")]))
    return _sheet(rows), r, total


def build(path: Path, parts: set[str], limits: Limits, seed: int = 1) -> dict:
    rng = random.Random(seed)
    sheets = []
    info = {}
    t = time.perf_counter()
    sheets.append(("Data", data_sheet(rng)))
    if "distinct" in parts:
        # the distinct formulas' text is what parsing costs: the documented limit
        xml, n, chars = distinct_sheet(rng, limits.max_formula_chars - 60_000)
        sheets.append(("Distinct", xml))
        info.update(distinct_cells=n, distinct_chars=chars)
    if "runs" in parts:
        xml, nrows, reads = runs_sheet(int(limits.max_reads * 0.9))
        sheets.append(("Runs", xml))
        info.update(run_rows=nrows, run_cells=nrows * RUN_COLS, reads=reads)
    if "notes" in parts:
        sheets.append(("Notes", notes_sheet(rng, NOTES_ROWS, NOTES_COLS)))
        info.update(notes_cells=NOTES_ROWS * NOTES_COLS)
    wb = (f'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<workbook xmlns="{NS}" xmlns:r="{RNS}"><sheets>'
          + "".join(f'<sheet name="{n}" sheetId="{i + 1}" r:id="rId{i + 1}"/>' for i, (n, _) in enumerate(sheets))
          + "</sheets></workbook>")
    rels = ('<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            + "".join(f'<Relationship Id="rId{i + 1}" Type="{RNS}/worksheet" Target="worksheets/sheet{i + 1}.xml"/>'
                      for i in range(len(sheets))) + "</Relationships>")
    ct = ('<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
          '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
          '<Default Extension="xml" ContentType="application/xml"/>'
          f'<Override PartName="/xl/workbook.xml" ContentType="{SML_CT}.sheet.main+xml"/>'
          + "".join(f'<Override PartName="/xl/worksheets/sheet{i + 1}.xml" ContentType="{SML_CT}.worksheet+xml"/>'
                    for i in range(len(sheets))) + "</Types>")
    root_rels = ('<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
                 f'<Relationship Id="rId1" Type="{RNS}/officeDocument" Target="xl/workbook.xml"/></Relationships>')
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as z:
        z.writestr("[Content_Types].xml", ct)
        z.writestr("_rels/.rels", root_rels)
        z.writestr("xl/workbook.xml", wb)
        z.writestr("xl/_rels/workbook.xml.rels", rels)
        for i, (_, xml) in enumerate(sheets):
            z.writestr(f"xl/worksheets/sheet{i + 1}.xml", xml)
    with zipfile.ZipFile(path) as z:
        info["parts_mb"] = {i.filename: round(i.file_size / 1e6, 1) for i in z.infolist() if i.file_size > 1e6}
        info["uncompressed_mb"] = round(sum(i.file_size for i in z.infolist()) / 1e6, 1)
    info["file_mb"] = round(path.stat().st_size / 1e6, 1)
    info["build_s"] = round(time.perf_counter() - t, 1)
    return info


CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, sys.argv[1])
from sheetkin.xlsx.evaluator import evaluate
from sheetkin.xlsx.cells import read_book

def hwm():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
t = time.perf_counter()
if sys.argv[3] == "read":
    book = read_book(sys.argv[2])
    cells = sum(len(s.formulas) + len(s.consts) for s in book.sheets.values())
    out = {"cells": cells}
else:
    book = evaluate(sys.argv[2], strict=False)
    out = {"runs": book.runs, "formula_cells": book.cells, "notes": len(book.notes)}
out.update(seconds=time.perf_counter() - t, vmhwm=hwm(),
           maxrss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
print(json.dumps(out))
"""


def measure(path: Path, what: str) -> dict:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    p = subprocess.run([sys.executable, "-c", CHILD, str(ROOT), str(path), what],
                       capture_output=True, text=True, env=env)
    if p.returncode != 0:
        return {"error": p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"}
    return json.loads(p.stdout)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", metavar="DIR", help="write DIR/evaluator_memory.json")
    ap.add_argument("--keep", action="store_true", help="keep the workbook (printed path)")
    ap.add_argument("--parts", default="distinct,runs,notes", help="sheets besides Data (default distinct,runs,notes)")
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: the Data sheet only")
    args = ap.parse_args(argv)
    if args.tiny:
        global DATA_ROWS, DATA_COLS
        args.parts, DATA_ROWS, DATA_COLS = "", 14, 10
    limits = Limits()
    tmp = Path(tempfile.mkdtemp(prefix="sheetkin_mem_"))
    path = tmp / "at_the_limits.xlsx"
    info = build(path, set(filter(None, args.parts.split(","))), limits)
    print(f"workbook: {path} {info}", file=sys.stderr)
    res = {"workbook": info, "read": measure(path, "read"), "evaluate": measure(path, "evaluate")}
    for k in ("read", "evaluate"):
        m = res[k]
        if "error" in m:
            print(f"{k:<9} error: {m['error']}")
        else:
            print(f"{k:<9} {m['seconds']:7.1f} s   peak RSS {m['vmhwm'] / 1e6:7.0f} MB (VmHWM)   "
                  + " ".join(f"{a}={b}" for a, b in m.items() if a not in ("seconds", "vmhwm", "maxrss")))
    if args.out:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        (Path(args.out) / "evaluator_memory.json").write_text(json.dumps(res, indent=1) + "\n")
    if not args.keep:
        path.unlink()
        tmp.rmdir()
    return 0


if __name__ == "__main__":
    sys.exit(main())
