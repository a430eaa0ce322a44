"""Benchmark of the headless evaluator against the `formulas` package and LibreOffice.

    python benchmarks/evaluator.py [--repeat 5] [--copies 30] [--formulas-timeout 600]

Run on demand, not by the tests. On 360-column workbooks of the four-bar (1 deg steps) and
the shaper (-1 deg steps), made with `sheetkin workbook ... --positions 360`, it times:

* ours: sheetkin.xlsx.evaluator.evaluate(path), end to end (the input gate and reading the xlsx
  included), best and median of --repeat runs, twice: cold (the evaluator's caches of parsed
  formulas and run templates cleared before every run: one workbook on its own) and warm (the
  caches kept: what each further workbook of a class costs, the formulas being the same);
  and where the cold time goes (--phases: gate, inflating, reading the sheet XML, grouping
  runs, parsing formulas, ordering, numpy evaluation; best of --repeat);
* formulas (https://pypi.org/project/formulas/): formulas.ExcelModel().loads(path).finish()
  (load + compile) and .calculate(), separately, once, in a child process. If it fails or
  takes longer than --formulas-timeout seconds (default 600), it is timed on a 36-column
  workbook of the same mechanism instead, and the table says so. A few cells are compared
  with ours (sanity). `formulas` is NOT a dependency of sheetkin: install it for this
  benchmark with `pip install formulas`; without it that part is reported as skipped;
* LibreOffice headless: sheetkin.xlsx.libreoffice.recalculate() (the harness the tests use) of the
  one file, end to end (soffice start-up included), and the time per file when --copies
  copies are recalculated in one soffice call.

And: `sheetkin validate FOLDER` (subprocess, wall time, best and median of 3) on a folder of
--copies copies of the four-bar's 13-column workbook (workbooks/fourbar.xlsx); target < 10 s.

Prints a table of times and the ratios (their time / ours).
"""
from __future__ import annotations

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import sheetkin.xlsx.evaluator as E  # noqa: E402
import sheetkin.xlsx.runs as R  # noqa: E402
from sheetkin.xlsx.caches import clear_caches  # noqa: E402  (parsed formulas, run templates ...)
from sheetkin.xlsx.evaluator import evaluate  # noqa: E402

MECHANISMS = (("fourbar", 1.0), ("shaper", -1.0))


def make_workbook(stem: str, step: float, positions: int, out: Path) -> Path:
    subprocess.run([sys.executable, "-m", "sheetkin", "workbook", str(ROOT / "workbooks" / f"{stem}.toml"),
                    "--positions", str(positions), "--step-deg", str(step), "-o", str(out)],
                   check=True, capture_output=True, cwd=ROOT)
    return out


def time_ours(path: Path, repeat: int, cold: bool = True):
    times, book = [], None
    for _ in range(repeat):
        if cold:
            clear_caches()
        book = None                     # the previous book is freed outside the timing
        t = time.perf_counter()
        book = evaluate(path)
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times), book


def phases(path: Path, repeat: int) -> dict[str, float]:
    """Best time of each stage of a cold evaluate(path), through the modules' own steps."""
    from sheetkin.xlsx import cells as X
    from sheetkin.xlsx.package import open_package, sheet_parts
    best: dict[str, float] = {}

    def lap(name, t0):
        t = time.perf_counter()
        stage[name] = stage.get(name, 0.0) + t - t0
        return t

    for _ in range(repeat):
        clear_caches()
        stage: dict[str, float] = {}
        t = time.perf_counter()
        pkg = open_package(path)
        t = lap("input gate (open_package: checks, inflates and scans every part)", t)
        shared, (names, _local), sheets = X._shared_strings(pkg), X._defined_names(pkg), {}
        t = lap("shared strings, defined names", t)
        for info in sheet_parts(pkg):
            data = pkg.read(info.part)
            t = lap("inflating the sheet parts again (pkg.read)", t)
            sh = X._read_fast(pkg, data, info.name, info.state, shared, pkg.limits)
            if sh is None:
                sh = X._read_sheet(pkg, info.name, info.part, info.state, shared, pkg.limits)
            sheets[info.name] = sh
            t = lap("reading cells from the sheet XML", t)
        runs = [r for sh in sheets.values() for r in R.group_runs(sh)]
        t = lap("grouping formulas into runs", t)
        clear_caches()
        runs = [r for sh in sheets.values() for r in R.group_runs(sh)]   # templates kept
        names_key = frozenset(n.upper() for n in names)
        t = time.perf_counter()
        for run in runs:
            E._parse_run(run.formula, run.row, int(run.cols[0]), {n: None for n in names_key}, names_key)
        stage["parsing formulas (tokenizer, one per run; cold)"] = time.perf_counter() - t
        # the rest of evaluate_sheets, formulas parsed and templates kept: its grouping taken out
        t = time.perf_counter()
        E.evaluate_sheets(str(path), sheets, list(sheets), names)
        total = time.perf_counter() - t
        t = time.perf_counter()
        for sh in sheets.values():
            R.group_runs(sh)
        regroup = time.perf_counter() - t
        stage["ordering and numpy evaluation"] = max(0.0, total - regroup)
        for k, v in stage.items():
            best[k] = min(best.get(k, 1e9), v)
    best["FLOOR: unzip + parse (lxml) of the graded sheet"] = floor(path, repeat)
    return best


def floor(path: Path, repeat: int) -> float:
    """What reading the graded sheet costs at the least: inflating its part (zipfile) and
    parsing its XML (lxml, C), nothing interpreted: best of `repeat`."""
    import zipfile

    from lxml import etree
    best = 1e9
    for _ in range(repeat):
        t = time.perf_counter()
        with zipfile.ZipFile(path) as z:
            etree.fromstring(z.read("xl/worksheets/sheet1.xml"))
        best = min(best, time.perf_counter() - t)
    return best


def time_command(path: Path, repeat: int) -> tuple[float, float]:
    """`sheetkin evaluate PATH` as a process (start-up included): best and median wall time."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "sheetkin", "evaluate", str(path), "--format", "csv", "-o", "/dev/null"],
                       check=True, capture_output=True, cwd=ROOT)
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def sample_cells(book, count: int = 6) -> list[tuple[str, int, int]]:
    """A few numeric formula cells spread over the first sheet (first, middle, last columns)."""
    sheet = book.order[0]
    cells = sorted(book.sheets[sheet].formulas)
    numeric = [(r, c) for (r, c) in cells if isinstance(book.value(sheet, r, c), float)
               and not isinstance(book.value(sheet, r, c), bool)]
    rows = sorted({r for r, _ in numeric})
    picked = []
    for k in range(count):
        r = rows[(k * (len(rows) - 1)) // max(1, count - 1)]
        cols = [c for (rr, c) in numeric if rr == r]
        picked.append((sheet, r, cols[(k * len(cols)) // count]))
    return picked


# --------------------------------------------------------------------------- formulas (child)
def formulas_worker(path: str, cells_json: str) -> None:
    """Child process: load, compile and calculate with `formulas`; print JSON."""
    import formulas
    from openpyxl.utils import get_column_letter
    t = time.perf_counter()
    model = formulas.ExcelModel().loads(path).finish()
    t1 = time.perf_counter()
    solution = model.calculate()
    t2 = time.perf_counter()
    by_key = {k.upper(): v for k, v in solution.items()}
    name = Path(path).name.upper()
    values = []
    for sheet, r, c in json.loads(cells_json):
        key = f"'[{name}]{sheet.upper()}'!{get_column_letter(c)}{r}"
        v = by_key.get(key)
        if v is None:
            values.append(None)
            continue
        x = v.value[0, 0] if hasattr(v, "value") else v
        try:
            values.append(float(x))
        except (TypeError, ValueError):
            values.append(str(x))
    print(json.dumps({"load": t1 - t, "calc": t2 - t1, "values": values, "cells": len(solution)}))


def time_formulas(path: Path, cells, timeout: float):
    """(result dict, None) or (None, reason)."""
    try:
        import formulas  # noqa: F401
    except ImportError:
        return None, "not installed (pip install formulas)"
    cmd = [sys.executable, __file__, "--formulas-worker", str(path), json.dumps(cells)]
    t = time.perf_counter()
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, f"did not finish in {timeout:.0f} s"
    wall = time.perf_counter() - t
    if res.returncode != 0:
        return None, f"failed: {res.stderr.strip().splitlines()[-1] if res.stderr.strip() else res.returncode}"
    out = json.loads(res.stdout.strip().splitlines()[-1])
    out["wall"] = wall
    return out, None


def close(a, b) -> bool:
    return (isinstance(a, float) and isinstance(b, float)
            and abs(a - b) <= 1e-9 * max(1.0, abs(a)))


# --------------------------------------------------------------------------- LibreOffice
def time_libreoffice(path: Path, copies: int, work: Path):
    from sheetkin.xlsx.libreoffice import recalculate, soffice_path
    if soffice_path() is None:
        return None, None
    out = work / "lo_single"
    t = time.perf_counter()
    recalculate([path], out, timeout=1800)
    single = time.perf_counter() - t
    many = work / f"lo_many_{path.stem}"
    many.mkdir()
    paths = []
    for k in range(copies):
        p = many / f"{path.stem}_{k:02d}.xlsx"
        shutil.copy(path, p)
        paths.append(p)
    t = time.perf_counter()
    recalculate(paths, many / "out", timeout=3600)
    batch = time.perf_counter() - t
    return single, batch / copies


def time_validate(copies: int, work: Path):
    folder = work / "students"
    folder.mkdir()
    for k in range(copies):
        shutil.copy(ROOT / "workbooks" / "fourbar.xlsx", folder / f"student_{k:02d}.xlsx")
    times, rc = [], None
    for _ in range(3):
        t = time.perf_counter()
        res = subprocess.run([sys.executable, "-m", "sheetkin", "validate", str(folder), "--progress", "never"],
                             capture_output=True, text=True, cwd=ROOT)
        times.append(time.perf_counter() - t)
        rc = res.returncode
    return min(times), statistics.median(times), rc


# --------------------------------------------------------------------------- main
def fmt(x):
    return "-" if x is None else f"{x:.3f}"


def ratio(theirs, ours):
    if theirs is None or not ours:
        return "-"
    r = theirs / ours
    return f"{r:.1f}x" if r < 100 else f"{r:.0f}x"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5, help="runs of our evaluator (best and median)")
    ap.add_argument("--copies", type=int, default=30, help="copies for LibreOffice's batch and for validate")
    ap.add_argument("--formulas-timeout", type=float, default=600)
    ap.add_argument("--no-formulas", action="store_true")
    ap.add_argument("--no-libreoffice", action="store_true")
    ap.add_argument("--phases", action="store_true", help="where the cold time goes, per stage")
    ap.add_argument("--formulas-worker", nargs=2, metavar=("PATH", "CELLS"), help=argparse.SUPPRESS)
    ap.add_argument("--positions", type=int, default=360, help="columns of the workbooks (default 360)")
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 13 columns, once, no peers")
    args = ap.parse_args(argv)
    if args.tiny:
        args.positions, args.repeat, args.copies, args.no_formulas, args.no_libreoffice = 13, 1, 2, True, True
        args.phases = True
    if args.formulas_worker:
        formulas_worker(*args.formulas_worker)
        return 0

    rows, notes = [], []
    with tempfile.TemporaryDirectory(prefix="sheetkin-bench-") as tmp:
        work = Path(tmp)
        for stem, step in MECHANISMS:
            cols = args.positions
            path = make_workbook(stem, step * 360 / cols, cols, work / f"{stem}{cols}.xlsx")
            best, median, book = time_ours(path, args.repeat)
            wbest, wmedian, _ = time_ours(path, args.repeat, cold=False)
            print(f"{stem} {cols} columns: {book.cells} formula cells in {book.runs} runs; "
                  f"ours best {best:.3f} s, median {median:.3f} s (cold); "
                  f"best {wbest:.3f} s, median {wmedian:.3f} s (warm)", flush=True)
            cbest, cmedian = time_command(path, args.repeat)
            rows.append((f"{stem}{cols}", "ours: evaluate(), cold caches", best, median, "1x"))
            rows.append((f"{stem}{cols}", "ours: evaluate(), warm caches", wbest, wmedian, ratio(best, wbest)))
            rows.append((f"{stem}{cols}", "ours: `sheetkin evaluate` as a process", cbest, cmedian, ratio(cbest, best)))
            if args.phases:
                stages = phases(path, args.repeat)
                low = stages["FLOOR: unzip + parse (lxml) of the graded sheet"]
                for what, secs in stages.items():
                    rows.append((f"{stem}{cols}", f"  {what}", secs, None,
                                 f"{100 * secs / best:.0f}% of cold, {secs / low:.1f}x the floor"))

            if not args.no_formulas:
                cells = sample_cells(book)
                res, why = time_formulas(path, cells, args.formulas_timeout)
                label, ours_ref, ref_book = str(cols), best, book
                if res is None:
                    notes.append(f"formulas on {stem}{cols}: {why}; timed on 36 columns instead")
                    small = make_workbook(stem, step * 10, 36, work / f"{stem}36.xlsx")
                    b36, m36, ref_book = time_ours(small, args.repeat)
                    rows.append((f"{stem}36", "ours: evaluate(), cold caches", b36, m36, "1x"))
                    cells = sample_cells(ref_book)
                    res, why = time_formulas(small, cells, args.formulas_timeout)
                    label, ours_ref = "36", b36
                if res is None:
                    notes.append(f"formulas on {stem}36: {why}")
                else:
                    total = res["load"] + res["calc"]
                    rows.append((f"{stem}{label}", "formulas: load+compile", res["load"], None,
                                  ratio(res["load"], ours_ref)))
                    rows.append((f"{stem}{label}", "formulas: calculate", res["calc"], None,
                                  ratio(res["calc"], ours_ref)))
                    rows.append((f"{stem}{label}", "formulas: total", total, None, ratio(total, ours_ref)))
                    ok = 0
                    for (sheet, r, c), theirs in zip(cells, res["values"], strict=False):
                        mine = ref_book.value(sheet, r, c)
                        ok += close(mine, theirs)
                        if not close(mine, theirs):
                            notes.append(f"formulas differs at {stem}{label} {sheet}!R{r}C{c}: "
                                         f"ours {mine!r}, formulas {theirs!r}")
                    notes.append(f"sanity: formulas equals ours on {ok} of {len(cells)} sampled cells of {stem}{label}")
                print(f"  formulas done ({'ok' if res else why})", flush=True)

            if not args.no_libreoffice:
                single, per_file = time_libreoffice(path, args.copies, work)
                if single is None:
                    notes.append("LibreOffice (soffice) not found: skipped")
                else:
                    rows.append((f"{stem}{cols}", "LibreOffice: 1 file, 1 soffice run", single, None,
                                 ratio(single, best)))
                    rows.append((f"{stem}{cols}", "  LibreOffice 1 file / `sheetkin evaluate` process", single, None,
                                 f"{single / cbest:.1f}x (target >= 8x)"))
                    rows.append((f"{stem}{cols}", f"LibreOffice: per file, {args.copies} in 1 run", per_file, None,
                                 ratio(per_file, best)))
                print("  LibreOffice done", flush=True)

        vbest, vmedian, rc = time_validate(args.copies, work)
        rows.append((f"{args.copies} x fourbar13", "sheetkin validate FOLDER", vbest, vmedian,
                     "target < 10 s: " + ("met" if vmedian < 10 else "NOT met")))
        notes.append(f"validate exit code {rc} (0 = every workbook correct)")

    print()
    import os
    print(f"load average at the end: {os.getloadavg()[0]:.1f} (1 min)")
    width = max(40, *(len(r[1]) for r in rows))
    print(f"{'workbook':<16} {'what':<{width}} {'best s':>9} {'median s':>9}  vs ours (cold)")
    for wb, what, best, median, r in rows:
        print(f"{wb:<16} {what:<{width}} {fmt(best):>9} {fmt(median):>9}  {r}")
    for n in notes:
        print("note:", n)
    return 0


if __name__ == "__main__":
    sys.exit(main())
