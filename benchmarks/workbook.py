"""Benchmark of the workbook writer: a 360-column workbook of the shaper.

    python benchmarks/workbook.py [--repeat 5]

Times build (rows, formulas, formats, charts) and save (openpyxl writing the xlsx, then
sheetkin's evaluator computing every formula's cached value and writing it in: issue 20) of
the seed-001 shaper with 360 crank positions (1 deg steps), best and median of --repeat runs.
Target (issue 3): under 1 s without the cached values; they about double the time (measured
figures in docs/verification.md).
"""
from __future__ import annotations

import argparse
import io
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sheetkin.kinematics.scene import override_crank  # noqa: E402
from sheetkin.sheet.workbook import build_workbook  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--positions", type=int, default=360)
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 13 columns, once")
    args = ap.parse_args(argv)
    if args.tiny:
        args.repeat, args.positions = 1, 13
    for stem, step in (("shaper", -1.0), ("fourbar", 1.0)):
        text = (ROOT / "workbooks" / f"{stem}.toml").read_text(encoding="utf-8")
        text, scene = override_crank(text, stem, positions=args.positions, step_deg=step * 360 / args.positions)
        builds, saves = [], []
        for _ in range(args.repeat):
            t = time.perf_counter()
            wb = build_workbook(scene, scene_text=text)
            t1 = time.perf_counter()
            buf = io.BytesIO()
            wb.save(buf)
            builds.append(t1 - t)
            saves.append(time.perf_counter() - t1)
        total = [b + s for b, s in zip(builds, saves, strict=False)]
        ws = wb.worksheets[0]
        print(f"{stem}, {args.positions} columns, {ws.max_row} rows, {len(buf.getvalue()) / 1024:.0f} KB: "
              f"build {min(builds):.3f} s + save {min(saves):.3f} s; total best {min(total):.3f} s, "
              f"median {statistics.median(total):.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
