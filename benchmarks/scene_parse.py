"""Time to parse a scene with many [[point]]s (issue 11: 20,000 points in under a second).

    python benchmarks/scene_parse.py [--points 20000] [--repeat 5]

Prints best and median wall time of tomllib alone and of sheetkin's parse_scene (which
includes tomllib) for points measured from the crank's joint ("flat") and for points each
measured from the next one in the file ("chain", the order that made the old placement
quadratic).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from sheetkin.kinematics.scene import parse_scene  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=20_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 200 points, once")
    args = ap.parse_args()
    if args.tiny:
        args.points, args.repeat = 200, 1
    base = (ROOT / "workbooks" / "fourbar.toml").read_text(encoding="utf-8")
    n = args.points
    flat = "".join(f'[[point]]\nname = "P{i}"\nlink = 2\nfrom = "A"\nalong = {i * 1e-5}\n' for i in range(n))
    chain = "".join(f'[[point]]\nname = "P{i}"\nlink = 2\nfrom = "{"A" if i == 0 else f"P{i - 1}"}"\n'
                    f"along = 1e-5\n" for i in reversed(range(n)))
    print(f"{n} points, best / median of {args.repeat} (s)")
    for name, text in (("flat", base + flat), ("chain", base + chain)):
        for what, fn in (("tomllib.loads", tomllib.loads), ("parse_scene", parse_scene)):
            times = []
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                fn(text)
                times.append(time.perf_counter() - t0)
            print(f"{name:<6}{what:<15}{min(times):8.3f} {statistics.median(times):8.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
