"""The outputs of `sheetkin evaluate` for a fixed set of books, written into a folder: a
byte-identity harness for speed work on the evaluator (issue 32).

    PYTHONPATH=$PWD python tools/evaluate_outputs.py OUT [--inputs DIR] [--book X.xlsx ...]
    diff -r BASELINE OUT

The books: the bundled workbooks (workbooks/*.xlsx), the issued books of the tests
(tests/data/issued/0.2.0/shaper, 0.1.0/fourbar), and the 360-column shaper and four-bar,
made once into --inputs (default /tmp/sheetkin-evaluate-inputs) with the tree's
`sheetkin workbook` and reused; --book adds any other (a book LibreOffice saved, say). For
every book, five runs: --format table, csv and json, `--sheet plotted` and a missing sheet;
each run's stdout, and its stderr with the exit code. Run it with each tree (PYTHONPATH) into
two folders and compare them.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RUNS = {"table": ["--format", "table"], "csv": ["--format", "csv"], "json": ["--format", "json"],
        "plotted.csv": ["--format", "csv", "--sheet", "plotted"],
        "nosuch.csv": ["--format", "csv", "--sheet", "nosuch"]}


def books(inputs: Path, extra: list[str]) -> list[Path]:
    inputs.mkdir(parents=True, exist_ok=True)
    made = []
    for scene in ("shaper", "fourbar"):
        out = inputs / f"{scene}360.xlsx"
        if not out.exists():
            subprocess.run([sys.executable, "-m", "sheetkin", "workbook", str(ROOT / "workbooks" / f"{scene}.toml"),
                            "--positions", "360", "--step-deg", "-1", "-o", str(out)], check=True, capture_output=True)
        made.append(out)
    issued = ROOT / "tests" / "data" / "issued"
    return [*sorted((ROOT / "workbooks").glob("*.xlsx")), *sorted((issued / "0.2.0" / "shaper").glob("*.xlsx")),
            *sorted((issued / "0.1.0" / "fourbar").glob("*.xlsx")), *made, *map(Path, extra)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--inputs", type=Path, default=Path("/tmp/sheetkin-evaluate-inputs"))
    ap.add_argument("--book", action="append", default=[], help="another book to evaluate (repeatable)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for book in books(args.inputs, args.book):
        stem = "_".join(book.resolve().relative_to(ROOT).parts if book.resolve().is_relative_to(ROOT)
                        else ("inputs", book.name))
        for name, flags in RUNS.items():
            res = subprocess.run([sys.executable, "-m", "sheetkin", "evaluate", str(book), *flags],
                                 capture_output=True, env=dict(os.environ))
            (args.out / f"{stem}.{name}").write_bytes(res.stdout)
            (args.out / f"{stem}.{name}.err").write_bytes(res.stderr + f"rc {res.returncode}\n".encode())
    print(f"{len(list(args.out.iterdir()))} files in {args.out}")


if __name__ == "__main__":
    main()
