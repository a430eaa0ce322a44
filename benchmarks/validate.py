"""Benchmark of `sheetkin validate` on a faculty's worth of submissions (issue 15).

    python benchmarks/validate.py [--jobs N] [--sizes 100 300 1000] [--baseline-tree DIR]

Run on demand, not by the tests. Submissions are the four-bar's workbook (seed 000) with
each student's own variant: the crank length L1 in the input block changed (0.14 + k 1e-6 m,
k = 0, 1, ...), so every file has a reference of its own; the rest of the workbook is the
generated one, so every file is correct. The files are made by patching the cell in the
sheet's XML (the workbook is generated once per number of columns). Every time is the wall
clock of `sheetkin validate FOLDER --json` as a process (start-up included), --jobs as given
(default: one per core) and --jobs 1:

* files/s at 13, 37 and 360 columns (40 distinct variants each);
* 40 distinct variants against 40 copies of one variant (13 columns): the ratio of times
  (target <= 4);
* 100, 300, 1000 distinct submissions (13 columns), and 10,000 extrapolated from a line
  fitted to those (time = a + b files).
With --baseline-tree DIR (another checkout, e.g. the main branch before this change) the
40-variant folders are also validated by that tree's code (PYTHONPATH=DIR).
"""
from __future__ import annotations

import argparse
import io
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sheetkin.kinematics.scene import override_crank  # noqa: E402
from sheetkin.sheet.workbook import write_workbook  # noqa: E402

SCENE = ROOT / "workbooks" / "fourbar.toml"
COLUMNS = {13: 30.0, 37: 10.0, 360: 1.0}             # positions: crank step (deg)


def base_workbook(columns: int, folder: Path) -> tuple[bytes, int]:
    """The generated workbook with `columns` positions (bytes) and the row of L1."""
    text = SCENE.read_text(encoding="utf-8")
    text, scene = override_crank(text, str(SCENE), positions=columns, step_deg=COLUMNS[columns])
    path = folder / f"base{columns}.xlsx"
    write_workbook(scene, path, scene_text=text)
    from sheetkin.sheet.workbook import sheet_rows
    row = 5 + [r.name for r in sheet_rows(scene).rows].index("L1")
    return path.read_bytes(), row


def variant_bytes(base: bytes, row: int, value: float) -> bytes:
    """The workbook with L1 (cell D<row> of the first sheet) set to value."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(base)) as zin, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "xl/worksheets/sheet1.xml":
                data, n = re.subn(rb'(<c r="D%d"[^>]*>\s*<v>)[^<]*(</v>)' % row,
                                  rb"\g<1>" + repr(value).encode() + rb"\g<2>", data, count=1)
                assert n == 1, "L1 cell not found"
            zout.writestr(item, data)
    return out.getvalue()


def make_folder(folder: Path, base: bytes, row: int, count: int, distinct: bool) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    same = variant_bytes(base, row, 0.14)
    for k in range(count):
        (folder / f"s{k:05d}.xlsx").write_bytes(variant_bytes(base, row, 0.14 + 1e-6 * k) if distinct else same)
    return folder


def validate_time(folder: Path, jobs: int | None, tree: Path = ROOT) -> float:
    argv = [sys.executable, "-m", "sheetkin", "validate", str(folder), "--json"]
    # each file's L1 is its student's own variant: graded on its own input block (a changed
    # input is otherwise a failure, graded against the embedded scene); a baseline tree
    # older than that option cannot be compared
    argv.append("--accept-changed-inputs")
    if jobs is not None:
        argv += ["--jobs", str(jobs)]
    env = dict(os.environ, PYTHONPATH=str(tree))
    t = time.perf_counter()
    p = subprocess.run(argv, cwd=tree, env=env, capture_output=True)
    wall = time.perf_counter() - t
    if p.returncode != 0:
        raise RuntimeError(f"validate {folder}: exit {p.returncode}: {p.stderr.decode()[-400:]}")
    reports = json.loads(p.stdout)["reports"]
    assert all(r["ok"] for r in reports), "a generated submission was not all correct"
    return wall


def one_file(d: Path, base: bytes, row: int, runs: int) -> dict:
    """`sheetkin validate ONE.xlsx` against `python -c "import numpy"`, interleaved (the
    machine's load hits both alike): best and median of `runs`, and the ratio of the bests
    (target: within 4x)."""
    path = d / "one.xlsx"
    path.write_bytes(variant_bytes(base, row, 0.14))
    cmds = {"numpy": [sys.executable, "-c", "import numpy"],
            "validate": [sys.executable, "-m", "sheetkin", "validate", str(path), "--json"]}
    times: dict[str, list[float]] = {k: [] for k in cmds}
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for _ in range(runs):
        for k, argv in cmds.items():
            t = time.perf_counter()
            subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, check=True)
            times[k].append(time.perf_counter() - t)
    out = {k: (min(v), float(np.median(v))) for k, v in times.items()}
    out["ratio"] = out["validate"][0] / out["numpy"][0]
    print(f"one-file validate {out['validate'][0]:.3f} s, python -c 'import numpy' {out['numpy'][0]:.3f} s "
          f"(best of {runs}): {out['ratio']:.1f}x (target <= 4x)")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--jobs", type=int, default=None, help="processes (default: one per core)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 1000])
    ap.add_argument("--columns", type=int, nargs="+", default=[13, 37, 360])
    ap.add_argument("--baseline-tree", type=Path, help="also time this checkout's validate on the 40-file folders")
    ap.add_argument("--json", metavar="FILE")
    ap.add_argument("--files", type=int, default=40, help="files of the variant folders (default 40)")
    ap.add_argument("--startup-runs", type=int, default=10, help="interleaved runs of one-file validate and numpy")
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 13 columns, a few files, once")
    args = ap.parse_args()
    if args.tiny:
        args.sizes, args.columns, args.files, args.startup_runs = [2, 4], [13], 3, 1
    jobs_label = args.jobs or os.cpu_count()
    res = {"cpus": os.cpu_count(), "jobs": jobs_label, "load_before": os.getloadavg()}
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        bases = {c: base_workbook(c, d) for c in args.columns}
        res["one_file"] = one_file(d, *bases[args.columns[0]], args.startup_runs)
        nf = args.files
        print(f"files/s, {nf} distinct variants (validate --jobs {jobs_label} / --jobs 1"
              + (" / baseline tree, its default" if args.baseline_tree else "") + "):")
        res["files_per_s"] = {}
        for c in args.columns:
            folder = make_folder(d / f"v{c}", *bases[c], nf, distinct=True)
            t_n, t_1 = validate_time(folder, args.jobs), validate_time(folder, 1)
            row = {"jobs": nf / t_n, "jobs1": nf / t_1}
            if args.baseline_tree:
                row["baseline"] = nf / validate_time(folder, None, args.baseline_tree)
            res["files_per_s"][c] = row
            print(f"  {c:>4} columns: {row['jobs']:6.1f} / {row['jobs1']:6.1f}"
                  + (f" / {row['baseline']:6.1f}" if "baseline" in row else ""))
        if 13 in bases:
            same = make_folder(d / "same13", *bases[13], nf, distinct=False)
            distinct = d / "v13"
            t_same, t_dist = validate_time(same, args.jobs), validate_time(distinct, args.jobs)
            t_same1, t_dist1 = validate_time(same, 1), validate_time(distinct, 1)
            res["variants_40_vs_1"] = {"one_variant": t_same, "forty": t_dist, "ratio": t_dist / t_same,
                                       "one_variant_jobs1": t_same1, "forty_jobs1": t_dist1,
                                       "ratio_jobs1": t_dist1 / t_same1}
            print(f"\n{nf} files, 13 columns: one variant {t_same:.2f} s, {nf} variants {t_dist:.2f} s: "
                  f"ratio {t_dist / t_same:.2f} (--jobs 1: {t_same1:.2f} s, {t_dist1:.2f} s, "
                  f"ratio {t_dist1 / t_same1:.2f}); target <= 4")
            base, row = bases[13]
            big = make_folder(d / "many", base, row, max(args.sizes), distinct=True)
            files = sorted(big.glob("*.xlsx"))
            times = {}
            for n in sorted(args.sizes):
                sub = d / f"n{n}"
                sub.mkdir()
                for f in files[:n]:
                    os.link(f, sub / f.name)
                times[n] = validate_time(sub, args.jobs)
                print(f"  {n:>6} distinct submissions: {times[n]:7.1f} s ({n / times[n]:.1f} files/s)")
            ns = np.array(sorted(times))
            a, b = np.polynomial.polynomial.polyfit(ns, [times[n] for n in ns], 1)
            res["submissions"] = {"measured": times, "fit_a": a, "fit_b": b, "extrapolated_10000": a + b * 10000}
            print(f"  10,000 extrapolated (time = {a:.2f} + {b * 1000:.1f} ms x files): {a + b * 10000:7.0f} s "
                  f"({(a + b * 10000) / 60:.1f} min); each further book {b:.3f} s (target <= 0.06 s)")
    res["load_after"] = os.getloadavg()
    print(f"\nload average before / after: {res['load_before'][0]:.1f} / {res['load_after'][0]:.1f}")
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=1, default=str))


if __name__ == "__main__":
    main()
