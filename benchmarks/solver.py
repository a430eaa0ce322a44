"""Benchmark of the reference solver: crank positions per second, and memory at 1e6.

    python benchmarks/solver.py [--scene workbooks/fourbar.toml] [--repeat 5]

For 1e3, 1e5 and 1e6 positions it times (best and median of --repeat runs, wall clock):
  solve_table  the solver into its preallocated table (all contract columns + det_g*);
  compute      the public API, the same plus the pandas DataFrame and toggle flags.
For a scene with masses or loads (e.g. workbooks/shaper_dynamics.toml) it also times
  dynamics    compute(dynamics=True): the same plus energies, reactions and M_bal.
Peak memory at 1e6 is the peak resident set of a fresh process running `compute` once
(ru_maxrss), and that peak minus the process's size after importing sheetkin.
Targets (issue 2): >= 5e6 positions/s at 1e6 on this 2-core machine; peak < 1 GB.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import sheetkin  # noqa: E402
from sheetkin.kinematics.table import solve_table  # noqa: E402


def timings(fn, repeat: int) -> tuple[float, float]:
    """(best, median) wall time of `repeat` runs after one warm-up run."""
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times), float(np.median(times))


def _status_mb(field: str) -> float:
    """VmRSS / VmHWM of this process in MB. (ru_maxrss would be wrong here: Linux keeps it
    across execve, so a child started by a big parent inherits the parent's peak.)"""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) / 1024
    raise RuntimeError(f"no {field} in /proc/self/status")


def memory_child(scene_path: str, n: int) -> None:
    """Run once in a fresh process: print the resident sizes as JSON."""
    scene = sheetkin.load_scene(scene_path)
    phi = np.linspace(0.0, 360.0, n, endpoint=False)
    base = _status_mb("VmRSS")
    t = time.perf_counter()
    df = sheetkin.compute(scene, phi)
    first = time.perf_counter() - t
    print(json.dumps({"base_mb": base, "peak_mb": _status_mb("VmHWM"), "first_run_s": first,
                      "frame_mb": df.memory_usage(deep=True).sum() / 2**20}))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=str(ROOT / "workbooks" / "fourbar.toml"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--memory-child", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 1e3 positions, once")
    args = ap.parse_args(argv)
    sizes, child = (1_000, 100_000, 1_000_000), 1_000_000
    if args.tiny:
        args.repeat, sizes, child = 1, (1_000,), 10_000
    if args.memory_child:
        memory_child(args.scene, args.memory_child)
        return 0
    scene = sheetkin.load_scene(args.scene)
    print(f"scene {Path(args.scene).name}; {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, numpy {np.__version__}")
    dyn = scene.has_dynamics
    print(f"{'positions':>10} {'solve_table pos/s best / median':>32} {'compute pos/s best / median':>30}"
          + (f" {'dynamics pos/s best / median':>30}" if dyn else ""))
    for n in sizes:
        phi = np.linspace(0.0, 360.0, n, endpoint=False)
        s_best, s_med = timings(lambda phi=phi: solve_table(scene, phi), args.repeat)
        c_best, c_med = timings(lambda phi=phi: sheetkin.compute(scene, phi), args.repeat)
        line = f"{n:>10} {n / s_best:>20.3g} / {n / s_med:<9.3g} {n / c_best:>18.3g} / {n / c_med:<9.3g}"
        if dyn:
            d_best, d_med = timings(lambda phi=phi: sheetkin.compute(scene, phi, dynamics=True), args.repeat)
            line += f" {n / d_best:>18.3g} / {n / d_med:<9.3g}"
        print(line)
    out = subprocess.run([sys.executable, __file__, "--scene", args.scene, "--memory-child", str(child)],
                         capture_output=True, text=True, check=True)
    mem = json.loads(out.stdout)
    print(f"memory at {child:.0e} (compute, fresh process): peak RSS {mem['peak_mb']:.0f} MB, "
          f"{mem['peak_mb'] - mem['base_mb']:.0f} MB above the imported baseline; "
          f"the DataFrame holds {mem['frame_mb']:.0f} MB")
    print(f"first (cold) compute of {child:.0e} in that process: {mem['first_run_s']:.2f} s "
          f"({child / mem['first_run_s']:.3g} pos/s; fresh memory from the kernel costs page faults)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
