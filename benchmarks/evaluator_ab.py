"""Before and after, same run: `sheetkin evaluate` of the 360-column shaper as a process
(CPU and wall time) and `evaluate()` in-process (CPU), for two source trees interleaved
round by round, and LibreOffice's `soffice --convert-to` of the same book (CPU of its
process tree, and wall time). CPU time is what a loaded machine distorts least. The trees
run in alternating order (before-after, then after-before), and the median of the rounds'
after/before pairs is printed with the bests and medians.
LibreOffice runs with a profile that recalculates every formula on load, as the tests'
harness does (`recalculating_profile`): by default it keeps the values the book saved, and
the generated books save them, so before 2026-11-29 13:30 UTC its runs here loaded and saved
the book without recalculating it (measured then: 5.80 s best, 6.83 s median, against 6.48 s
and 6.60 s recalculating, 3 rounds each: within the machine's noise).

    python benchmarks/evaluator_ab.py --rounds 6 --before /path/to/old/tree --after .
    python benchmarks/evaluator_ab.py --tiny        # a smoke run: the four-bar, one round, no LibreOffice

--bytecode: the trees' modules run from compiled bytecode, as an installed sheetkin does (pip
compiles .pyc files on install): PYTHONDONTWRITEBYTECODE is dropped and the bytecode goes to
a temporary PYTHONPYCACHEPREFIX, written by one untimed run of each tree. Without it the
environment decides (where PYTHONDONTWRITEBYTECODE=1, every process compiles every module).

--callgrind: each tree's process also runs once under valgrind's callgrind, which counts the
instructions it executes: the same count in every run, whatever the machine's load or speed
(time on this VM drifts 1.4x within minutes), so a before/after difference of 1% is seen. It
counts instructions, not time: cache misses and the kernel's work (page faults) are not in it.
About a minute a tree. It implies --bytecode (a tree compiling its modules would count that).

--installed: each tree is built into a wheel and installed (not editable) into a fresh venv
of its own, with its dependencies, and the process timed is that venv's `sheetkin` console
script, as a user runs it: no editable-install finder and none of this machine's .pth
hooks at start-up (they cost 30-60 ms of every `python` here). About a minute per tree.
"""
from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sheetkin.xlsx.libreoffice import recalculating_profile  # noqa: E402

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


def install(root: str, venv: Path) -> Path:
    """The tree's wheel installed into a new venv (dependencies from pip's usual sources):
    the path of its `sheetkin` console script."""
    dist = venv.with_name(venv.name + "-dist")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(dist), root],
                   check=True, capture_output=True)
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, capture_output=True)
    subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q", *map(str, dist.glob("*.whl"))],
                   check=True, capture_output=True)
    return venv / "bin" / "sheetkin"


def libreoffice(book: Path, work: Path, name: str) -> tuple[float, float]:
    """(CPU of the soffice process tree, wall) for recalculating and saving one file."""
    out = work / name
    out.mkdir()
    cpu, wall, _ = cpu_of(["soffice", f"-env:UserInstallation=file://{work}/lo-profile", "--headless",
                           "--norestore", "--convert-to", "xlsx:Calc MS Excel 2007 XML", "--outdir",
                           str(out), str(book)], os.environ, work)
    return cpu, wall


def instructions(python: str, env: dict, work: Path, book: Path) -> int:
    """Instructions the `sheetkin evaluate` process executes, counted by callgrind; python:
    the tree's interpreter itself, not a launcher script (callgrind follows no child process)."""
    if shutil.which("valgrind") is None:
        sys.exit("evaluator_ab.py: --callgrind needs valgrind (apt-get install valgrind)")
    out = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={work}/callgrind.out",
                          python, "-m", "sheetkin", "evaluate", str(book), "--format", "csv", "-o", os.devnull],
                         env=env, cwd=work, capture_output=True, text=True, check=True)
    found = re.search(r"Collected : (\d+)", out.stderr)
    if found is None:
        sys.exit(f"evaluator_ab.py: no instruction count in valgrind's output:\n{out.stderr[-500:]}")
    return int(found.group(1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("--before", default=str(ROOT), help="the source tree before (default: this one)")
    ap.add_argument("--after", default=str(ROOT), help="the source tree after (default: this one)")
    ap.add_argument("--tiny", action="store_true", help="the four-bar at 13 positions, one round, no LibreOffice")
    ap.add_argument("--bytecode", action="store_true", help="run from compiled bytecode, as installed (see above)")
    ap.add_argument("--callgrind", action="store_true",
                    help="also count each tree's instructions under valgrind (deterministic, see above)")
    ap.add_argument("--installed", action="store_true",
                    help="time each tree's wheel installed into a venv, its console script (see above)")
    args = ap.parse_args()
    args.bytecode = args.bytecode or (args.callgrind and not args.installed)
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
        command = {name: [sys.executable, "-m", "sheetkin"] for name in trees}
        python = {name: sys.executable for name in trees}       # each tree's interpreter
        if args.installed:
            for name, root in trees.items():
                command[name] = [str(install(root, work / f"venv-{name}"))]
                python[name] = str(Path(command[name][0]).with_name("python"))
                tree_env[name] = {k: v for k, v in base_env.items() if k != "PYTHONPATH"}
                cpu_of([*command[name], "--version"], tree_env[name], work)
        if args.bytecode:                   # one untimed run of each tree writes its bytecode
            for name in trees:
                cpu_of([*command[name], "evaluate", str(book), "--format", "csv",
                        "-o", os.devnull], tree_env[name], work)
        lo_wanted = not args.tiny and shutil.which("soffice") is not None
        lo: list[tuple[float, float]] = []
        if lo_wanted:                       # an untimed run makes LibreOffice's profile
            recalculating_profile(work / "lo-profile")
            libreoffice(book, work, "lo-first")
        for i in range(1 if args.tiny else args.rounds):
            # the trees' order alternates (ABBA): whichever runs second in a round may find
            # the machine warmer or busier, and a fixed order put that on one tree
            for name in (list(trees) if i % 2 == 0 else list(reversed(trees))):
                env = tree_env[name]
                cpu, wall, _ = cpu_of([*command[name], "evaluate", str(book), "--format", "csv",
                                       "-o", os.devnull], env, work)
                res[name]["process cpu"].append(cpu)
                res[name]["process wall"].append(wall)
                _, _, out = cpu_of([python[name], "-c", CODE_EVAL, str(book)], env, work)
                res[name]["evaluate cpu"].append(float(out))
            if lo_wanted:       # LibreOffice in every round too: the machine's speed drifts
                lo.append(libreoffice(book, work, f"lo{i}"))
        if args.callgrind:
            counted = {name: instructions(python[name], tree_env[name], work, book) for name in trees}
            print("instructions (callgrind), `sheetkin evaluate` process: " +
                  ", ".join(f"{name} {n:,}" for name, n in counted.items()) +
                  f"; after/before {counted['after'] / counted['before']:.3f}")
        for name, r in res.items():
            print(name, "; ".join(f"{k}: best {min(v):.3f} s, median {statistics.median(v):.3f} s"
                                  for k, v in r.items()))
        paired = [a / b for a, b in zip(res["after"]["process cpu"], res["before"]["process cpu"], strict=True)]
        print(f"after/before process cpu, the median of the rounds' pairs: {statistics.median(paired):.3f} "
              f"({min(paired):.3f}-{max(paired):.3f})")
        if not lo:
            return
        print("LibreOffice soffice --convert-to (1 file), cpu: "
              f"best {min(c for c, _ in lo):.2f} s, median {statistics.median(c for c, _ in lo):.2f} s; "
              f"wall: best {min(w for _, w in lo):.2f} s")
        for name, r in res.items():
            # best against best, and the median of the rounds' own ratios (each round's
            # LibreOffice against the same round's process: robust to the drift)
            rounds = [c / p for (c, _), p in zip(lo, r["process cpu"], strict=True)]
            print(f"ratio LibreOffice / {name} `sheetkin evaluate` process: "
                  f"cpu {min(c for c, _ in lo) / min(r['process cpu']):.1f}x best/best, "
                  f"{statistics.median(rounds):.1f}x median of the rounds ({min(rounds):.1f}-{max(rounds):.1f}x); "
                  f"wall {min(w for _, w in lo) / min(r['process wall']):.1f}x best/best")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
