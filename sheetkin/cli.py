"""Command line: `sheetkin compute SCENE.toml [--format table|csv|json] [--at DEG ...]`.

Exit codes: 0 done, 2 unusable input (a scene mistake, a bad option), 3 the mechanism
cannot be assembled at some requested position (the message gives the intervals).
Every error is one line on stderr; no traceback reaches the user.
"""
from __future__ import annotations

import argparse
import json
import math
import shutil
import sys

import numpy as np

from . import __version__
from .compute import TOGGLE_THRESHOLD, AssemblyError, assembly_gaps, compute, unit
from .scene import SceneError, load_scene

EXIT_INPUT, EXIT_ASSEMBLY = 2, 3


def _finite_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of degrees, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def _positive_float(text: str) -> float:
    v = _finite_float(text)
    if v <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return v


class _Parser(argparse.ArgumentParser):
    """argparse, but a mistake is one line (no usage block), as every sheetkin error."""

    def error(self, message):
        self.exit(EXIT_INPUT, f"sheetkin: error: {message} (see '{self.prog} --help')\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="sheetkin",
        description="Kinematic analysis of planar linkages in the spreadsheet workflow of "
                    "Alyushin's course (MGGU).")
    parser.add_argument("--version", action="version", version=f"sheetkin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    p = sub.add_parser(
        "compute", help="positions, velocities and accelerations of every link and point",
        description="Compute the kinematics of a scene (see README, 'Scene files') at every "
                    "crank position: link angles, angular velocities and accelerations; "
                    "coordinates, velocities and accelerations of every moving joint and point; "
                    "slides of sliders. Names follow shared/spec/scene.md.")
    p.add_argument("scene", metavar="SCENE.toml", help="the scene file")
    p.add_argument("--format", choices=["table", "csv", "json"], default="table",
                   help="table: one row per quantity, readable (default); csv: one row per "
                        "position, the contract's columns; json: the same as records")
    p.add_argument("--at", metavar="DEG", type=_finite_float, action="append",
                   help="crank angle in degrees; repeatable; replaces the scene's positions")
    p.add_argument("--analogs", action="store_true",
                   help="add the velocity and acceleration analogs d/dphi, d2/dphi2 "
                        "(columns vqx_A, vq_A, aqx_A, omegaq_2, epsq_2, vqs_B, ...)")
    p.add_argument("--allow-gaps", action="store_true",
                   help="where a group cannot assemble, mark those positions (assembled = "
                        "false, empty values) and compute the rest instead of failing")
    p.add_argument("--toggle-threshold", type=_positive_float, default=TOGGLE_THRESHOLD,
                   metavar="X", help="flag positions whose normalised group determinant "
                   f"(sine of the transmission angle for RRR) is below X (default {TOGGLE_THRESHOLD})")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    return parser


def _fmt(v, scale: float = 0.0) -> str:
    """Six significant digits; round-off noise (below 1e-12 of the row's largest) shows as 0."""
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "NO"
    if abs(v) <= 1e-12 * scale:
        v = 0.0
    return f"{v + 0.0:.6g}"


def _row(values) -> list[str]:
    nums = [abs(v) for v in values if isinstance(v, float) and math.isfinite(v)]
    scale = max(nums, default=0.0)
    return [_fmt(v, scale) for v in values]


def format_table(df, width: int | None = None) -> str:
    """Quantities as rows, positions as columns (like the lecture's workbook), paged to width."""
    width = width or shutil.get_terminal_size((120, 24)).columns
    names = [c for c in df.columns if c != "phi_1"]
    label_w = max(len(c) for c in df.columns) + 2
    unit_w = max(len(unit(c)) for c in df.columns) + 2
    col_w = 13
    per_page = max(1, (width - label_w - unit_w) // col_w)
    lines = [df.attrs.get("title", "")] if df.attrs.get("title") else []
    for start in range(0, len(df), per_page):
        page = df.iloc[start:start + per_page]
        lines.append("")
        lines.append("phi_1".ljust(label_w) + "deg".ljust(unit_w) +
                     "".join(t.rjust(col_w) for t in _row(list(page["phi_1"]))))
        lines.append("-" * (label_w + unit_w + col_w * len(page)))
        for name in names:
            lines.append(name.ljust(label_w) + unit(name).ljust(unit_w) +
                         "".join(t.rjust(col_w) for t in _row(list(page[name]))))
    return "\n".join(lines) + "\n"


def format_json(df, warnings: list[str]) -> str:
    records = [{k: (None if isinstance(v, float) and math.isnan(v) else
                    (bool(v) if isinstance(v, (bool, np.bool_)) else v))
                for k, v in row.items()} for row in df.to_dict(orient="records")]
    return json.dumps({"title": df.attrs.get("title", ""),
                       "units": {c: unit(c) for c in df.columns if unit(c)},
                       "warnings": warnings, "positions": records}, indent=1) + "\n"


def _toggle_warnings(df) -> list[str]:
    out = []
    flagged = df[df["near_toggle"] != ""]
    if len(flagged):
        groups = sorted({g for s in flagged["near_toggle"] for g in s.split(",")}, key=int)
        for g in groups:
            at = flagged[flagged["near_toggle"].str.split(",").apply(lambda s: g in s)]["phi_1"]
            shown = ", ".join(f"{v:g}" for v in at.iloc[:8]) + (" ..." if len(at) > 8 else "")
            out.append(f"group {g} is near a toggle position (|det_g{g}| small: velocities and "
                       f"accelerations lose accuracy) at crank angles {shown} deg")
    return out


def cmd_compute(args) -> int:
    scene = load_scene(args.scene)
    df = compute(scene, args.at, analogs=args.analogs, allow_gaps=args.allow_gaps,
                 toggle_threshold=args.toggle_threshold)
    warnings = _toggle_warnings(df)
    if "assembled" in df:
        gaps = assembly_gaps(scene, df["phi_1"].to_numpy())
        warnings.insert(0, "; ".join(map(str, gaps)) + " (those positions are marked assembled = false)")
    if args.format == "csv":
        text = df.to_csv(index=False, lineterminator="\n")
    elif args.format == "json":
        text = format_json(df, warnings)
    else:
        text = format_table(df)
    if args.output:
        with open(args.output, "w", encoding="utf-8", newline="") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    for w in warnings:
        print(f"sheetkin: warning: {w}", file=sys.stderr)
    return 0


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return {"compute": cmd_compute}[args.command](args)
    except SceneError as e:
        print(f"sheetkin: error: {e}", file=sys.stderr)
        return EXIT_INPUT
    except AssemblyError as e:
        print(f"sheetkin: error: {args.scene}: {e}", file=sys.stderr)
        return EXIT_ASSEMBLY
    except OSError as e:
        print(f"sheetkin: error: {e.filename or ''}: {e.strerror}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("sheetkin: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
