"""Benchmark of the command line: output speed, streaming memory, start-up (issue 15).

    python benchmarks/cli.py [--repeat 5] [--positions 1e5] [--stream 1e7] [--startup-runs 20]

Run on demand, not by the tests. Four-bar of seed 000 (workbooks/fourbar.toml):

* output: `sheetkin compute --range ... --format csv|json|parquet -o FILE` at --positions
  positions (1e5: --range 0:360:0.0036), as a process (wall clock, start-up included) and
  in-process (sheetkin.views.output.write_compute), best and median of --repeat; next to it, what
  the command did before (pandas: compute()'s DataFrame and DataFrame.to_csv, json.dumps of
  its records), once;
* streaming: the same command at --stream positions (1e7: --range 0:360:0.000036) to a file
  and to stdout (a pipe read and dropped), once each: wall clock, peak resident memory of
  the process (os.wait4's ru_maxrss) and bytes written;
* start-up: `python -c "import numpy"`, `sheetkin compute workbooks/fourbar.toml` (13
  positions, the table) and `sheetkin --help`, interleaved, --startup-runs runs each: best
  and median, and the ratios to numpy's import (target: compute within 2.5x).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
SCENE = ROOT / "workbooks" / "fourbar.toml"
ENV = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


def range_for(n: int) -> str:
    """0:360:STEP with exactly n positions (n a power of ten times 1, 2 or 5)."""
    step = 360 / n
    text = f"{step:.12f}".rstrip("0")
    return f"0:360:{text}"


def run(argv: list[str], stdout=subprocess.DEVNULL) -> tuple[float, float]:
    """(wall seconds, peak RSS in MB) of a child process. The peak comes from GNU time
    (/usr/bin/time -f %M): Linux keeps ru_maxrss across exec, so a child started directly by
    this (by then large) process would report this process's peak."""
    timer = "/usr/bin/time" if os.path.exists("/usr/bin/time") else None
    with tempfile.NamedTemporaryFile("r") as rss_file:
        full = ([timer, "-f", "%M", "-o", rss_file.name] if timer else []) + argv
        t = time.perf_counter()
        p = subprocess.Popen(full, stdout=stdout, stderr=subprocess.PIPE, env=ENV, cwd=ROOT)
        if stdout == subprocess.PIPE:                # read and drop, as a consumer would
            while p.stdout.read(1 << 20):
                pass
        status = p.wait()
        wall = time.perf_counter() - t
        if status != 0:
            raise RuntimeError(f"{argv}: exit {status}: {p.stderr.read().decode()[-500:]}")
        text = rss_file.read().strip().splitlines()
    return wall, (int(text[-1]) / 1024 if timer and text else float("nan"))


def best_median(times):
    return min(times), statistics.median(times)


def output_speed(n: int, repeat: int) -> dict:
    import numpy as np

    import sheetkin
    from sheetkin.cli.angles import parse_range
    from sheetkin.views.output import write_compute
    scene = sheetkin.load_scene(SCENE)
    spec = range_for(n)
    phi = parse_range(spec)
    assert len(phi) == n
    out = {"positions": n, "range": spec}
    with tempfile.TemporaryDirectory() as d:
        for fmt in ("csv", "json", "parquet"):
            target = os.path.join(d, f"out.{fmt}")
            try:
                import pyarrow  # noqa: F401
            except ImportError:
                if fmt == "parquet":
                    out[fmt] = "skipped: pyarrow not installed"
                    continue
            inproc, proc = [], []
            for _ in range(repeat):
                t = time.perf_counter()
                write_compute(scene, phi, fmt, target)
                inproc.append(time.perf_counter() - t)
                proc.append(run([sys.executable, "-m", "sheetkin", "compute", str(SCENE), "--range", spec,
                                 "--format", fmt, "-o", target])[0])
            out[fmt] = {"in_process": best_median(inproc), "process": best_median(proc),
                        "bytes": os.path.getsize(target)}
        # before: the DataFrame and pandas / json.dumps, as the command did
        t = time.perf_counter()
        df = sheetkin.compute(scene, phi.take(0, n))
        t_df = time.perf_counter() - t
        t = time.perf_counter()
        df.to_csv(os.path.join(d, "pandas.csv"), index=False, lineterminator="\n")
        t_csv = time.perf_counter() - t
        t = time.perf_counter()
        records = [{k: (None if isinstance(v, float) and v != v else (bool(v) if isinstance(v, np.bool_) else v))
                    for k, v in row.items()} for row in df.astype({"near_toggle": str}).to_dict(orient="records")]
        json.dumps({"positions": records}, indent=1)
        t_json = time.perf_counter() - t
        out["before"] = {"dataframe": t_df, "to_csv": t_csv, "json_dumps": t_json}
    out["writers"] = writers(scene, phi, repeat)
    return out


def writers(scene, phi, repeat: int) -> dict:
    """CSV writers on the same arrays (the blocks of compute_blocks, already computed): the
    command's (polars since issue 24), polars and pyarrow directly, our own formatter
    (sheetkin.views.floatfmt, which still writes JSON) and pandas; best of `repeat` (s)."""
    import io

    import numpy as np
    import pandas as pd
    import polars as pl
    import pyarrow as pa
    import pyarrow.csv as pacsv

    from sheetkin.kinematics.table import compute_blocks, table_names
    from sheetkin.views.floatfmt import repr_slots
    from sheetkin.views.output import _Text
    names = table_names(scene, False, False)
    blocks = list(compute_blocks(scene, phi))

    def command():
        w = _Text("csv", names, len(scene.groups), False, "")
        return w.head() + b"".join(w.rows(b) for b in blocks)

    def polars():
        out = io.BytesIO()
        for i, b in enumerate(blocks):
            pl.DataFrame({n: b.table[j] for j, n in enumerate(names)}).write_csv(out, include_header=i == 0)
        return out.getvalue()

    def pyarrow():
        out = io.BytesIO()
        for i, b in enumerate(blocks):
            pacsv.write_csv(pa.table({n: b.table[j] for j, n in enumerate(names)}), out,
                            pacsv.WriteOptions(include_header=i == 0))
        return out.getvalue()

    def floatfmt():
        # the numbers' text only (what the formatter did before issue 24, without the row assembly)
        return sum(int(repr_slots(np.ascontiguousarray(b.table.T).reshape(-1))[0].nbytes) for b in blocks)

    def pandas():
        out = io.StringIO()
        for i, b in enumerate(blocks):
            pd.DataFrame({n: b.table[j] for j, n in enumerate(names)}).to_csv(out, index=False, header=i == 0)
        return out.getvalue()

    res = {}
    for name, f in (("command (polars)", command), ("polars", polars), ("pyarrow", pyarrow),
                    ("floatfmt (numbers only)", floatfmt), ("pandas", pandas)):
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            f()
            times.append(time.perf_counter() - t)
        res[name] = best_median(times)
    return res


def streaming(n: int) -> dict:
    spec = range_for(n)
    base = [sys.executable, "-m", "sheetkin", "compute", str(SCENE), "--range", spec, "--format", "csv"]
    out = {"positions": n, "range": spec}
    with tempfile.TemporaryDirectory() as d:
        target = os.path.join(d, "big.csv")
        wall, rss = run(base + ["-o", target])
        out["file"] = {"seconds": wall, "peak_rss_mb": rss, "bytes": os.path.getsize(target)}
    wall, rss = run(base, stdout=subprocess.PIPE)
    out["stdout"] = {"seconds": wall, "peak_rss_mb": rss}
    # the baseline: a process that imports numpy and sheetkin.views.output and does nothing
    _, rss0 = run([sys.executable, "-c", "import sheetkin.views.output"])
    out["import_rss_mb"] = rss0
    return out


def startup(runs: int) -> dict:
    cmds = {"python -c 'import numpy'": [sys.executable, "-c", "import numpy"],
            "sheetkin compute workbooks/fourbar.toml": [sys.executable, "-m", "sheetkin", "compute", str(SCENE)],
            "sheetkin --help": [sys.executable, "-m", "sheetkin", "--help"]}
    times = {k: [] for k in cmds}
    for _ in range(runs):                        # interleaved: the machine's load hits all alike
        for k, argv in cmds.items():
            times[k].append(run(argv)[0])
    out = {k: best_median(v) for k, v in times.items()}
    base = out["python -c 'import numpy'"]
    out["ratio_compute"] = [a / b for a, b in zip(out["sheetkin compute workbooks/fourbar.toml"], base, strict=False)]
    out["ratio_help"] = [a / b for a, b in zip(out["sheetkin --help"], base, strict=False)]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--positions", type=float, default=1e5)
    ap.add_argument("--stream", type=float, default=1e7, help="0: skip the streaming run")
    ap.add_argument("--startup-runs", type=int, default=20)
    ap.add_argument("--only", choices=["output", "stream", "startup"], action="append")
    ap.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 1e3 positions, 1e4 streamed, once")
    args = ap.parse_args()
    if args.tiny:
        args.repeat, args.positions, args.stream, args.startup_runs = 1, 1e3, 1e4, 1
    parts = args.only or ["startup", "output", "stream"]
    res = {"load_before": os.getloadavg()}
    if "startup" in parts:
        res["startup"] = s = startup(args.startup_runs)
        print(f"start-up, best / median of {args.startup_runs} (s):")
        for k, (b, m) in s.items():
            label = {"ratio_compute": "compute / numpy import", "ratio_help": "--help / numpy import"}.get(k, k)
            print(f"  {label:<45} {b:8.3f} {m:8.3f}")
    if "output" in parts:
        res["output"] = o = output_speed(int(args.positions), args.repeat)
        print(f"\noutput of {o['positions']:.0e} positions (--range {o['range']}), best / median of {args.repeat} (s):")
        for fmt in ("csv", "json", "parquet"):
            v = o[fmt]
            if isinstance(v, str):
                print(f"  {fmt:<8} {v}")
                continue
            print(f"  {fmt:<8} in-process {v['in_process'][0]:7.3f} {v['in_process'][1]:7.3f}   "
                  f"process {v['process'][0]:7.3f} {v['process'][1]:7.3f}   {v['bytes'] / 1e6:7.1f} MB")
        b = o["before"]
        print(f"  before: DataFrame {b['dataframe']:.3f}, pandas to_csv {b['to_csv']:.3f}, "
              f"json.dumps of the records {b['json_dumps']:.3f}")
        w = o["writers"]
        fastest = min(v[0] for k, v in w.items() if k in ("polars", "pyarrow"))
        print("  CSV writers on the same arrays (best / median, s; ratio to the fastest library):")
        for k, (bt, md) in w.items():
            print(f"    {k:<26} {bt:8.3f} {md:8.3f}  {bt / fastest:5.2f}x")
        if "startup" in res:
            base = res["startup"]["sheetkin compute workbooks/fourbar.toml"][0]
            print(f"  csv process / 13-position compute process: {o['csv']['process'][0] / base:.2f}x (target <= 3x)")
    if "stream" in parts and args.stream:
        res["stream"] = st = streaming(int(args.stream))
        print(f"\nstreaming {st['positions']:.0e} positions as CSV (--range {st['range']}):")
        for k in ("file", "stdout"):
            v = st[k]
            extra = f", {v['bytes'] / 1e9:.2f} GB" if "bytes" in v else ""
            print(f"  to {k:<7} {v['seconds']:8.1f} s, peak RSS {v['peak_rss_mb']:.0f} MB{extra}")
        print(f"  (a process importing sheetkin.views.output: {st['import_rss_mb']:.0f} MB)")
    res["load_after"] = os.getloadavg()
    print(f"\nload average before / after: {res['load_before'][0]:.1f} / {res['load_after'][0]:.1f}")
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
