"""Benchmark: the copy report of a class of identical books stays linear (issues 21, 23).

    python benchmarks/copies.py [--sizes 50 200] [--jobs N] [--tiny]

Run on demand, not by the tests. N byte-identical copies of workbooks/fourbar.xlsx (one
student's book handed in N times under other names) are validated as a class by
`sheetkin validate FOLDER --grades G --html H` (a process, start-up included). Before issue
23 200 files gave 19,900 copy pairs: a 10.6 MB HTML page and a 2.7 MB grades.csv. Printed
per N: wall time, the HTML's, grades.csv's and stdout's sizes, and the "possible copy:"
lines (one per cluster).
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run(n: int, jobs: int | None) -> dict:
    with tempfile.TemporaryDirectory(prefix="sheetkin-copies-") as tmp:
        folder = Path(tmp) / "class"
        folder.mkdir()
        for k in range(n):
            shutil.copyfile(ROOT / "workbooks" / "fourbar.xlsx", folder / f"student{k:04d}.xlsx")
        grades, html = Path(tmp) / "grades.csv", Path(tmp) / "report.html"
        cmd = [sys.executable, "-m", "sheetkin", "validate", str(folder), "--grades", str(grades),
               "--html", str(html), "--progress", "never"] + (["--jobs", str(jobs)] if jobs else [])
        t = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, env={"PYTHONPATH": str(ROOT),
                                                                                  "PATH": "/usr/bin:/bin"})
        wall = time.perf_counter() - t
        return {"files": n, "seconds": round(wall, 1), "html_bytes": html.stat().st_size,
                "grades_bytes": grades.stat().st_size, "stdout_bytes": len(done.stdout.encode()),
                "copy_lines": done.stdout.count("possible copy:"), "exit": done.returncode}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=int, nargs="+", default=[50, 200])
    ap.add_argument("--jobs", type=int)
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: a class of 2 copies")
    args = ap.parse_args()
    if args.tiny:               # every benchmark script has a --tiny smoke run (tests/studies)
        args.sizes = [2]
    for n in args.sizes:
        print(run(n, args.jobs), flush=True)


if __name__ == "__main__":
    main()
