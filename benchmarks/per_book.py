"""What each further distinct book of a class costs validation, in CPU and wall time (issue 24).

    python benchmarks/per_book.py [--books 20] [--columns 13] [--baseline-tree DIR] [--tiny]

Run on demand; CI runs --tiny. A class of distinct four-bar submissions (each its own crank
length L1, as benchmarks/validate.py makes them) is validated in one process: the first book
warms the caches (parsed formulas, run templates, the reference's template sheet), then
--books further books are timed, CPU (time.process_time) and wall. CPU time is what the
machine's load changes least: on the shared 2-core VM the wall time of a process varies
with the other engineers' work, its CPU time much less. With --baseline-tree DIR (a
checkout of another commit, e.g. `git archive e4f0a6e sheetkin workbooks | tar -x -C DIR`)
the same books are validated by that tree too, alternately, in the same session.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, sys, time
from pathlib import Path
sys.path.insert(0, sys.argv[1])
from sheetkin.course.validator import validate
from sheetkin.course.issued import Options
from sheetkin.course.grades import verdict      # the rule every tree has (Report.ok is gone since 0.3)
if len(sys.argv) > 3 and sys.argv[3] == "off":       # issue 31: the behavioural check switched off
    import sheetkin.course.nudge
    sheetkin.course.nudge.NUDGES = 0
files = sorted(Path(sys.argv[2]).glob("*.xlsx"))
opts = Options(accept_changed=True)
assert verdict(validate(files[0], options=opts)) == "all correct"
c, w = time.process_time(), time.perf_counter()
for f in files[1:]:
    r = validate(f, options=opts)
    assert verdict(r) == "all correct", r.error or r.reason
n = len(files) - 1
print(json.dumps({"cpu": (time.process_time() - c) / n, "wall": (time.perf_counter() - w) / n}))
"""


def per_book(tree: Path, folder: Path, behaviour: str = "on") -> dict:
    p = subprocess.run([sys.executable, "-c", CHILD, str(tree), str(folder), behaviour], capture_output=True, text=True,
                       cwd=tree, env=dict(os.environ, PYTHONPATH=str(tree)))
    if p.returncode != 0:
        raise RuntimeError(f"{tree}: {p.stderr[-800:]}")
    return json.loads(p.stdout.splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--books", type=int, default=20, help="further books timed after the first (default 20)")
    ap.add_argument("--columns", type=int, default=13, choices=[13, 37, 360])
    ap.add_argument("--rounds", type=int, default=2, help="alternating rounds over the trees (default 2)")
    ap.add_argument("--baseline-tree", type=Path, help="also validate with this checkout, alternately")
    ap.add_argument("--behaviour-off", action="store_true",
                    help="also this tree with the behavioural check (issue 31) switched off, alternately")
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 2 further books, one round")
    args = ap.parse_args(argv)
    if args.tiny:
        args.books, args.rounds = 2, 1
    sys.path.insert(0, str(ROOT / "benchmarks"))
    sys.path.insert(0, str(ROOT))
    import validate as V  # benchmarks/validate.py: the class's books
    trees = {"this tree": (ROOT, "on")} | ({"check off": (ROOT, "off")} if args.behaviour_off else {}) | (
        {"baseline": (args.baseline_tree.resolve(), "on")} if args.baseline_tree else {})
    print(f"load average before: {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as d:
        base, row = V.base_workbook(args.columns, Path(d))
        folder = V.make_folder(Path(d) / "class", base, row, args.books + 1, distinct=True)
        for k in range(args.rounds):
            for name, (tree, behaviour) in trees.items():
                r = per_book(tree, folder, behaviour)
                print(f"round {k + 1}, {name:<10}: each further book {r['cpu']:.4f} s CPU, {r['wall']:.4f} s wall "
                      f"({args.columns} columns, {args.books} books)", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.1f}; target: <= 0.06 s wall a book with --jobs 2, "
          "i.e. <= 0.12 s of one core's time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
