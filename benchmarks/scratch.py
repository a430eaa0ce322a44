"""Benchmark of grading a workbook built from scratch (issue 33) against an issued one.

    python benchmarks/scratch.py [--runs 3] [--out benchmarks/results/scratch/scratch.json]

Run on demand, not by the tests. For each of the lecture's schemes (four-bar, crank-slider,
slotted lever, shaper, Scotch yoke: the RPP group), in this process, best of --runs:

* issued: `validate` of the scheme's key workbook (sheetkin's own, filled in, 13 or 7
  positions), the reference cache emptied before each run (a class's books each have a
  variant of their own);
* scratch rows / scratch columns: `validate --scene` of the same work built from scratch
  (tests/helpers/scratchbooks.py: the lecture's formulas in the student's own layout, Russian labels;
  a row per quantity in degrees, a column per quantity in radians), the same caches emptied;
* the ratio scratch / issued (target: at most 3).

And the search's bound: the four-bar's from-scratch book beside a sheet of 100,000 other
numbers (2000 x 50), graded; the time of locating alone (index, look-ups, lines compared).
Books are written by openpyxl (no LibreOffice; the tests type theirs through UNO), so both
kinds are read without saved values, on the same footing.
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from helpers.scratchbooks import student_book, with_draft_sheet, write_openpyxl  # noqa: E402

from sheetkin.course import scratch, validator  # noqa: E402
from sheetkin.course.caches import clear_caches  # noqa: E402
from sheetkin.course.grades import score  # noqa: E402
from sheetkin.course.reference import reference_book  # noqa: E402
from sheetkin.kinematics.scene import load_scene  # noqa: E402
from sheetkin.sheet.workbook import write_workbook  # noqa: E402
from sheetkin.xlsx.cells import read_book  # noqa: E402

SCHEMES = ("fourbar", "crank_slider", "slotted_lever", "shaper", "scotch_yoke")


def _best(runs: int, fn) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(runs):
        clear_caches()
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "scratch" / "scratch.json"))
    ap.add_argument("--tiny", action="store_true", help="a smoke run: the four-bar once, nothing written")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        for name in SCHEMES[:1] if args.tiny else SCHEMES:
            toml = ROOT / "workbooks" / f"{name}.toml"
            scene = load_scene(str(toml))
            key = d / f"{name}-key.xlsx"
            write_workbook(scene, key, scene_text=toml.read_text(encoding="utf-8"))
            opts = scratch.ScratchOptions(scene=scene)
            t_issued, rep = _best(args.runs, lambda key=key: validator.validate(key))
            assert score(rep) == 100.0, (name, rep.error)
            row = {"scheme": name, "positions": scene.crank.positions, "issued_s": round(t_issued, 3)}
            for orient, angles in (("row", "deg"), ("col", "rad")):
                path = write_openpyxl(student_book(scene, orient, angles), d / f"{name}-{orient}.xlsx")
                t, rep = _best(args.runs, lambda path=path, opts=opts: validator.validate(path, options=opts))
                assert score(rep) == 100.0, (name, orient)
                row[f"scratch_{orient}_s"] = round(t, 3)
                row[f"ratio_{orient}"] = round(t / t_issued, 2)
            rows.append(row)
            print(json.dumps(row, ensure_ascii=False), flush=True)
        if args.tiny:
            return 0
        big = _big_book(d, load_scene(str(ROOT / "workbooks" / "fourbar.toml")))
        rows.append(big)
        print(json.dumps(big, ensure_ascii=False), flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(rows, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"{out}: written")
    return 0


def _big_book(d: Path, scene) -> dict:
    path = with_draft_sheet(write_openpyxl(student_book(scene, "row", "deg"), d / "big.xlsx"))
    opts = scratch.ScratchOptions(scene=scene)
    t, rep = _best(1, lambda: validator.validate(path, options=opts))
    raw = read_book(path)
    book = scratch._evaluate(raw)
    qs = scratch.quantities(scene, reference_book(scene))
    t0 = time.perf_counter()
    loc = scratch.locate(raw, book, scene, qs)
    t_locate = time.perf_counter() - t0
    return {"scheme": "fourbar + 100k numbers", "cells_indexed": loc.cells_indexed, "graded_s": round(t, 3),
            "locate_s": round(t_locate, 3), "score": score(rep)}


if __name__ == "__main__":
    raise SystemExit(main())
