"""Before and after, same run: `sheetkin evaluate` of the 360-column shaper as a process
(CPU and wall time) and `evaluate()` in-process (CPU), for two source trees interleaved
round by round, and LibreOffice's `soffice --convert-to` of the same book (CPU of its
process tree, and wall time). CPU time is what a loaded machine distorts least.

    python benchmarks/evaluator_ab.py --rounds 6 --before /path/to/old/tree --after .
    python benchmarks/evaluator_ab.py --tiny        # a smoke run: the four-bar, one round, no LibreOffice

--bytecode: the trees' modules run from compiled bytecode, as an installed sheetkin does (pip
compiles .pyc files on install): PYTHONDONTWRITEBYTECODE is dropped and the bytecode goes to
a temporary PYTHONPYCACHEPREFIX, written by one untimed run of each tree. Without it the
environment decides (where PYTHONDONTWRITEBYTECODE=1, every process compiles every module).
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CODE_EVAL = ("import time,sys; from sheetkin.xlsx.evaluator import evaluate; t=time.process_time(); "
             "b=evaluate(sys.argv[1]); print(time.process_time()-t)")


def cpu_of(cmd, env, cwd):
    """(CPU seconds of the child, wall seconds, its stdout)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    out = subprocess.run(cmd, check=True, env=env, capture_output=True, text=True, cwd=cwd)
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), wall, out.stdout


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("--before", default=str(ROOT), help="the source tree before (default: this one)")
    ap.add_argument("--after", default=str(ROOT), help="the source tree after (default: this one)")
    ap.add_argument("--tiny", action="store_true", help="the four-bar at 13 positions, one round, no LibreOffice")
    ap.add_argument("--bytecode", action="store_true", help="run from compiled bytecode, as installed (see above)")
    args = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="sheetkin-ab-"))
    base_env = dict(os.environ)
    if args.bytecode:
        base_env.pop("PYTHONDONTWRITEBYTECODE", None)
    try:
        book = work / "book.xlsx"
        scene, extra = (("fourbar.toml", []) if args.tiny
                        else ("shaper.toml", ["--positions", "360", "--step-deg", "-1"]))
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        subprocess.run([sys.executable, "-m", "sheetkin", "workbook", str(ROOT / "workbooks" / scene), *extra,
                        "-o", str(book)], check=True, env=env, capture_output=True)
        trees = {"before": args.before, "after": args.after}
        res = {k: {"process cpu": [], "process wall": [], "evaluate cpu": []} for k in trees}
        tree_env = {name: {**base_env, "PYTHONPATH": root,
                           **({"PYTHONPYCACHEPREFIX": str(work / f"pyc-{name}")} if args.bytecode else {})}
                    for name, root in trees.items()}
        if args.bytecode:                   # one untimed run of each tree writes its bytecode
            for name in trees:
                cpu_of([sys.executable, "-m", "sheetkin", "evaluate", str(book), "--format", "csv",
                        "-o", os.devnull], tree_env[name], work)
        for _ in range(1 if args.tiny else args.rounds):
            for name in trees:
                env = tree_env[name]
                cpu, wall, _ = cpu_of([sys.executable, "-m", "sheetkin", "evaluate", str(book), "--format", "csv",
                                       "-o", os.devnull], env, work)
                res[name]["process cpu"].append(cpu)
                res[name]["process wall"].append(wall)
                _, _, out = cpu_of([sys.executable, "-c", CODE_EVAL, str(book)], env, work)
                res[name]["evaluate cpu"].append(float(out))
        for name, r in res.items():
            print(name, "; ".join(f"{k}: best {min(v):.3f} s, median {statistics.median(v):.3f} s"
                                  for k, v in r.items()))
        if args.tiny or not shutil.which("soffice"):
            return
        lo = []
        for i in range(2):     # LibreOffice: CPU of the soffice process tree for one file, same run
            out = work / f"lo{i}"
            out.mkdir()
            cpu, wall, _ = cpu_of(["soffice", f"-env:UserInstallation=file://{work}/lo-profile", "--headless",
                                   "--norestore", "--convert-to", "xlsx:Calc MS Excel 2007 XML", "--outdir",
                                   str(out), str(book)], os.environ, work)
            lo.append((cpu, wall))
            print("LibreOffice soffice --convert-to (1 file):", f"cpu {cpu:.2f} s, wall {wall:.2f} s")
        for name, r in res.items():     # the ratios: LibreOffice's best against each tree's best
            print(f"ratio LibreOffice / {name} `sheetkin evaluate` process: "
                  f"cpu {min(c for c, _ in lo) / min(r['process cpu']):.1f}x, "
                  f"wall {min(w for _, w in lo) / min(r['process wall']):.1f}x")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
