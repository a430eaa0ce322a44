"""The command line's options: the parser of every `sheetkin` command, with its help texts
(the user's reference for each option, so they are long). sheetkin/cli/commands.py runs the commands;
this module only describes them, so that it stays free of the commands' imports: `sheetkin
--help` loads neither numpy nor pandas (tests/cli/test_startup.py)."""
from __future__ import annotations

import argparse
import math
import os
import re

from sheetkin import __version__
from sheetkin.kinematics.caps import MAX_MAGNITUDE, MAX_POSITIONS

EXIT_INPUT = 2              # an unusable input or option (argparse's own exit code for a bad option)
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.I)
TOGGLE_THRESHOLD = 1e-2      # compute.TOGGLE_THRESHOLD, without importing numpy for --help (tested equal)


def _finite_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of degrees, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    if abs(v) > MAX_MAGNITUDE:      # the scene's cap on numbers (docs/mechanisms.md, "Caps")
        raise argparse.ArgumentTypeError(f"expected a magnitude of at most {MAX_MAGNITUDE:g}, got {text!r}")
    return v


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"expected a number >= 1, got {text!r}")
    if v > MAX_POSITIONS:
        raise argparse.ArgumentTypeError(f"expected at most {MAX_POSITIONS:,}, got {text!r}")
    return v


# sheetkin.course.batch.max_jobs() and sheetkin.views.animate's caps, without importing them
# for --help (tests/cli/test_hostile_input.py checks they are equal)
MAX_JOBS = max(4, 2 * (os.cpu_count() or 1))
MAX_FRAMES, MAX_SIZE = 3600, 4000           # animate's caps (views.animate's, tested equal)
FPS_RANGE = (0.1, 100.0)


def _capped_int(cap: int, why: str):
    def parse(text: str) -> int:
        v = _positive_int(text)
        if v > cap:
            raise argparse.ArgumentTypeError(f"expected at most {cap:,} ({why}), got {text!r}")
        return v
    return parse


def _fps(text: str) -> float:
    lo, hi = FPS_RANGE
    v = _positive_float(text)
    if not lo <= v <= hi:
        raise argparse.ArgumentTypeError(f"expected {lo:g} to {hi:g} frames per second (a GIF counts "
                                         f"in hundredths of a second), got {text!r}")
    return v


def _positive_float(text: str) -> float:
    v = _finite_float(text)
    if v <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return v


class _Parser(argparse.ArgumentParser):
    """argparse, but a mistake is one line (no usage block), as every sheetkin error."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        # argparse takes "-1e-07" for an option: its test for a negative number knows no
        # exponent (`--at -1e-07` said "expected one argument"). No sheetkin option looks
        # like a number, so every number-like token is a value.
        self._negative_number_matcher = _NEGATIVE_NUMBER

    error_lang: str | None = None   # ru, uk: the mistake said in it (help_texts.error_line)

    def error(self, message):
        from sheetkin.messages import message as text
        if message == text("argument_expected_one", opt="--range"):
            # `--range -90:90:1`: argparse takes the negative START for an option
            message += "; a negative START needs '=': --range=-90:90:1"
        from .help_texts import error_line
        self.exit(EXIT_INPUT, error_line(f"{message} " + text("see_help", prog=self.prog), self.error_lang) + "\n")


def build_parser(lang: str | None = None) -> argparse.ArgumentParser:
    """sheetkin's parser; lang ru or uk: the help of `validate` and `variants` in that
    language (sheetkin/cli/help_texts.py), None or en: English."""
    parser = _Parser(
        prog="sheetkin",
        description="Kinematic analysis of planar linkages in the spreadsheet workflow of "
                    "Alyushin's course (MGGU). Scene files (every key, group kind and output "
                    "name): see `sheetkin docs scene-format`; every page: `sheetkin docs`.")
    parser.add_argument("--version", action="version", version=f"sheetkin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in (_add_compute_parser, _add_workbook_parser, _add_evaluate_parser, _add_validate_parser,
                _add_bench_parser, _add_synth_parser, _add_animate_parser, _add_variants_parser,
                _add_examples_parser, _add_docs_parser):
        add(sub)
    if lang not in (None, "en"):
        from .help_texts import translate
        band, min_det, margin, tries, revolution = VARIANTS_DEFAULTS
        translate(parser, lang, {"band": f"{band:.0%}", "margin": f"{margin:.0%}", "tries": tries,
                                 "revolution": f"{revolution:g}", "min_det": f"{min_det:g}",
                                 "cpus": os.cpu_count() or 1, "max_jobs": MAX_JOBS})
    return parser


def _add_compute_parser(sub) -> None:
    """`sheetkin compute`: the kinematics of a scene at its crank positions."""
    p = sub.add_parser(
        "compute", help="positions, velocities and accelerations of every link and point",
        description="Compute the kinematics of a scene (`sheetkin docs scene-format`) at every "
                    "crank position: link angles, angular velocities and accelerations; "
                    "coordinates, velocities and accelerations of every moving joint and point; "
                    "slides of sliders. The scene format and the names: `sheetkin docs scene-format`; "
                    "the options at length: `sheetkin docs compute`.")
    p.add_argument("scene", metavar="SCENE.toml", help="the scene file")
    p.add_argument("--format", choices=["table", "csv", "json", "parquet"], default="table",
                   help="table: one row per quantity, readable (default); csv: one row per "
                        "position, the columns named in the scene format (phi_2, x_B, vx_B, ...), "
                        "numbers as Python's repr (the shortest "
                        "decimal that reads back as the same double), empty cells where there is "
                        "no value; json: the same as records (null where there is no value); "
                        "parquet: the same columns in a parquet file (needs -o and pyarrow: "
                        "pip install 'sheetkin[parquet]'). csv, json and parquet are computed and "
                        "written in blocks of 16384 positions: millions stream at bounded memory")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--at", metavar="DEG", type=_finite_float, action="append",
                       help="crank angle in degrees; repeatable; replaces the scene's positions")
    where.add_argument("--range", metavar="START:STOP:STEP",
                       help="crank angles START, START+STEP, ... in degrees, STOP excluded (as "
                            "numpy's arange: 0:360:0.5 is 720 positions); STEP may be negative; "
                            "decimal steps are exact (0:1:0.1 gives 0.3); a negative START "
                            "needs '=': --range=-90:90:1")
    where.add_argument("--at-file", metavar="FILE[:COLUMN]",
                       help="crank angles in degrees from FILE: one a line (blank lines and # "
                            "comments skipped), or a CSV file with a header, its column phi_1 "
                            "or the one named after ':' (e.g. angles.csv:phi)")
    p.add_argument("--analogs", action="store_true",
                   help="add the velocity and acceleration analogs d/dphi, d2/dphi2 "
                        "(columns vqx_A, vq_A, aqx_A, omegaq_2, epsq_2, vqs_B, ...)")
    p.add_argument("--dynamics", action="store_true",
                   help="add the energy and force analysis: kinetic and potential energy, inertia "
                        "forces, energy rates, power of the external forces, joint reactions, the "
                        "balancing moment M_bal and the energy balance (needs [[mass]]/[[force]])")
    p.add_argument("--allow-gaps", action="store_true",
                   help="where a group cannot assemble, mark those positions (assembled = "
                        "false, empty values) and compute the rest instead of failing")
    p.add_argument("--toggle-threshold", type=_positive_float, default=TOGGLE_THRESHOLD,
                   metavar="X", help="flag positions whose normalised group determinant "
                   f"(sine of the transmission angle for RRR) is below X (default {TOGGLE_THRESHOLD})")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")


def _add_workbook_parser(sub) -> None:
    """`sheetkin workbook`: the lecture's workbook with live formulas."""
    w = sub.add_parser(
        "workbook", help="the lecture's Excel workbook with live formulas",
        description="Write the lecture's row-structured workbook (the lecture's steps 7-10) for "
                    "each scene: title rows, input block, crank block, a kinematic-constraint "
                    "block per group (intermediate variables, every branch, checks, accepted "
                    "values), driven points, check rows with a summary, and charts. Every "
                    "computed cell is a formula; the scene is embedded in a hidden sheet. "
                    "Without -o, SCENE.toml is written to SCENE.xlsx beside it "
                    "(SCENE-exercise.xlsx with --exercise).")
    w.add_argument("scenes", metavar="SCENE.toml", nargs="+", help="scene file(s)")
    w.add_argument("-o", "--output", metavar="FILE.xlsx", help="where to write (one scene only)")
    w.add_argument("--lang", choices=["ru", "uk", "en"], default="ru",
                   help="the book's language: every word, unit and chart title (default ru, as the course; "
                        "uk Ukrainian; en English)")
    w.add_argument("--exercise", action="store_true",
                   help="leave the computed rows empty for students to fill (inputs, names, "
                        "units and check rows kept)")
    w.add_argument("--positions", type=_positive_int, metavar="N",
                   help="number of crank positions (columns), instead of the scene's")
    w.add_argument("--step-deg", type=_finite_float, metavar="DEG", help="crank angle step, instead of the scene's")
    w.add_argument("--phi0-deg", type=_finite_float, metavar="DEG", help="first crank angle, instead of the scene's")
    w.add_argument("--synthesis", action="store_true",
                   help="require the synthesis sheet (the course's synthesis method): exit 2 if the scene has no "
                        "[synthesis] table (`synth crank-rocker -o` writes one). Without this "
                        "option the sheet is added whenever the scene has the table")
    w.add_argument("--check", action="store_true",
                   help="write nothing: exit 1 if an existing workbook differs from what would be "
                        "written (stale) or is missing")


def _add_evaluate_parser(sub) -> None:
    """`sheetkin evaluate`: a workbook's formulas computed headlessly."""
    e = sub.add_parser(
        "evaluate", help="compute a workbook's formulas without a spreadsheet program",
        description="Evaluate every formula of an .xlsx workbook headlessly (numpy) and print "
                    "its named rows (column A) against its position columns (E onwards).")
    e.add_argument("book", metavar="BOOK.xlsx")
    e.add_argument("--format", choices=["table", "csv", "json"], default="table")
    e.add_argument("--sheet", help="the sheet to print (default: the first)")
    e.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")


def _add_validate_parser(sub) -> None:
    """`sheetkin validate`: students' workbooks graded row by row."""
    v = sub.add_parser(
        "validate", help="check students' workbooks against the reference solver",
        description="Validate filled workbooks (made by `sheetkin workbook` or `sheetkin "
                    "variants`): the given data are checked against the issued variant (the "
                    "roster, or the scene embedded in the book; a change fails); every named row "
                    "is compared with the reference, each row is also judged on the student's own "
                    "inputs, and the report names the wrong rows, the likely causes (rows wrong "
                    "on their own inputs, rounded typed numbers) and the rows wrong only because "
                    "of them. Exit 0 all correct, 1 mistakes found, 2 unusable input.")
    v.add_argument("paths", metavar="FILE|FOLDER|ZIP", nargs="+",
                   help=".xlsx, .xlsm, .xls, .ods or .fods files, folders searched for them (recursively), "
                        "or the zip of Moodle's \"download all submissions\"; a file given twice is "
                        "validated once")
    v.add_argument("--json", action="store_true", help="print the reports as JSON")
    v.add_argument("--html", metavar="REPORT.html", help="also write a readable HTML page")
    v.add_argument("--lang", choices=["ru", "uk", "en"], default=None,
                   help="language of the reports (text, HTML, grades.csv's headers and words, the JSON's "
                        "notes), the validator's messages included (default: the books' own language); "
                        "grades.csv's identifier column keeps Moodle's name, the command's own errors "
                        "stay English")
    v.add_argument("--grades", metavar="GRADES.csv",
                   help="also write one line per submission: student, group, variant, file, rows "
                        "correct, checks passing, given data changed, likely causes, possible copies "
                        "and a score (see `sheetkin docs class`); a CSV file Moodle's gradebook imports")
    v.add_argument("--class-list", metavar="STUDENTS.csv",
                   help="with --grades: the class as Moodle exports it (First name, Last name, Email "
                        "address or ID number); fills grades.csv's identifier column from the Moodle "
                        "folder each book came in, else the name the student typed (Russian forms: "
                        "'Иванов И.', 'Петрова Анна Сергеевна'); one grade per student (the newest file)")
    v.add_argument("--copies", choices=["hold", "keep", "zero"], default="hold",
                   help="with --grades: the grade of a possible copy (both books of a pair): hold "
                        "(default: the score left empty, status 'held for review', the teacher decides), "
                        "keep (its score), zero (0)")
    v.add_argument("--out-of", type=float, metavar="N",
                   help="with --grades: also the grade out of N points (the Moodle grade item's maximum), "
                        "beside the 0..100 score")
    v.add_argument("--scale", nargs="?", const="", metavar="NAME=LEAST,...",
                   help="with --grades: also the mark on a scale, beside the score; alone: the Russian "
                        "five-point scale (отлично 85, хорошо 70, удовлетворительно 50, "
                        "неудовлетворительно below), in the report's language; or your own thresholds: "
                        "'отлично=90,хорошо=75,удовлетворительно=60,неудовлетворительно=0'")
    v.add_argument("--grades-format", choices=["csv", "csv-excel", "xlsx"], default="csv",
                   help="with --grades: csv (default: what Moodle's import reads: ',' between fields, "
                        "'.' decimals, UTF-8), csv-excel (';' and ',' decimals, UTF-8 with a BOM: a Russian Excel "
                        "opens it in columns by a double click) or xlsx (a workbook)")
    v.add_argument("--worksheet", metavar="WORKSHEET.csv",
                   help="with --grades: Moodle's offline grading worksheet of the assignment (Download "
                        "grading worksheet); --grades then writes it back with its own columns and each "
                        "participant's Grade filled in (scaled to its Maximum grade), to upload as it is")
    v.add_argument("--progress", choices=["auto", "always", "never"], default="auto",
                   help="progress bar on stderr for several files (auto: when stderr is a terminal)")
    v.add_argument("--jobs", type=_capped_int(MAX_JOBS, "two processes per core; each holds a workbook"),
                   metavar="N",
                   help="validate in N processes (default: one per core, here "
                        f"{os.cpu_count() or 1}; at most {MAX_JOBS}); 1: in this process. Reports come "
                        "in the order of the files either way; a process that dies (out of memory) "
                        "costs its file only")
    v.add_argument("--roster", metavar="roster.csv",
                   help="the issued variants (written by `sheetkin variants`): each book's input "
                        "block is compared with its variant's row (found by the variant id in the "
                        "book); a changed given value is reported first, fails the book, and its "
                        "rows are graded against the issued values. Without --roster a book is "
                        "checked against the scene embedded in it")
    v.add_argument("--key", metavar="FILE",
                   help="the teacher's key file (default: .sheetkin-key next to --roster): checks "
                        "each issued book's seal, so an edited hidden scene sheet is reported")
    v.add_argument("--accept-changed-inputs", action="store_true",
                   help="grade each book against the student's own input block even where it "
                        "differs from the issued variant (still reported, no longer a failure)")
    v.add_argument("--scene", metavar="SCENE.toml",
                   help="the variant of a workbook built from scratch (no sheetkin template): its table is "
                        "found by value on any sheet, in either orientation, and graded by the lecture's "
                        "required quantities (see `sheetkin docs grading`); with --roster, assignment.csv "
                        "beside it names each student's variant instead")
    v.add_argument("--accept-typed", action="store_true",
                   help="let a number typed where a formula belongs earn credit when it is right "
                        "to its last digit (default: a computed row earns credit only where it "
                        "computes; still reported as typed, not computed; see `sheetkin docs grading`)")
    v.add_argument("--no-libreoffice", action="store_true",
                   help="do not let LibreOffice compute the cells sheetkin cannot (a function it "
                        "lacks): what reads them is \"not judged: check by hand\" (default: "
                        "recalculated by soffice when it is installed)")


def _add_bench_parser(sub) -> None:
    """`sheetkin bench`: speed against accuracy of each method."""
    b = sub.add_parser(
        "bench", help="time and accuracy of each way of computing a scene",
        description="For each method (the closed-form solver; Newton on the loop-closure "
                    "equations, warm-started; finite differences of the positions for steps "
                    "1e-1..1e-8 rad; the workbook's formulas through sheetkin's evaluator; "
                    "LibreOffice's recalculation of the workbook, when installed) measure the "
                    "time per crank position and the largest error of positions, velocities "
                    "and accelerations against an independent mpmath solution at 50 digits. "
                    "Writes DIR/bench.csv and DIR/bench.png (error against time, log-log) and "
                    "prints the table; a warning names the positions where a method fails or flags "
                    "itself (the solver near a toggle, Newton at a nearly singular Jacobian, a "
                    "finite-difference step whose answer changes by more than 1e-6 when the step "
                    "is doubled); bench.csv counts and names them (flagged, flagged_deg) and gives "
                    "the finite differences' step-doubling estimate (est_vel, est_acc).")
    b.add_argument("scene", metavar="SCENE.toml", nargs="?",
                   help="the scene file (none with --stability)")
    b.add_argument("--out", metavar="DIR", required=True,
                   help="folder for bench.csv and bench.png (stability.csv, stability.png)")
    b.add_argument("--stability", action="store_true",
                   help="instead of a scene, the stability study: each group kind's own scenes "
                        "walked towards where it degenerates (a toggle, a change point, just past "
                        "the edge of a non-assembling interval, two lines turning parallel), "
                        "1e-2..1e-10 rad away; each method's error, time and status (ok, flagged, "
                        "refused, diverged, branch jump, NaN) at each distance; writes "
                        "DIR/stability.csv and DIR/stability.png")
    b.add_argument("--positions", type=_positive_int, metavar="N",
                   help="N crank positions over one revolution from phi0 (default: the scene's)")
    b.add_argument("--no-libreoffice", action="store_true",
                   help="skip the LibreOffice recalculation (the slowest method)")


def _add_synth_parser(sub) -> None:
    """`sheetkin synth KIND`: a mechanism from its design data."""
    s = sub.add_parser(
        "synth", help="synthesize a mechanism from design data (the course's synthesis method)",
        description="Synthesize a mechanism from its design data and print its dimensions; "
                    "with -o, write a scene file ready for `compute` and `workbook`.")
    ssub = s.add_subparsers(dest="kind", metavar="KIND", required=True)
    _add_crank_rocker_parser(ssub)


def _add_crank_rocker_parser(ssub) -> None:
    """`sheetkin synth crank-rocker`: the four-bar from its time-ratio coefficient."""
    cr = ssub.add_parser(
        "crank-rocker", help="crank-rocker four-bar from the time-ratio coefficient K_w",
        description="The course's synthesis of a crank-rocker: from the time-ratio coefficient K_w "
                    "(overlap angle theta = "
                    "180 (K_w - 1)/(K_w + 1) deg), the rocker length l3, the rocker pivot's "
                    "Y_D and the rocker's extreme angles gamma1 < gamma2, find the crank l1, "
                    "the coupler l2, the crank angle phi1H of the extended dead position and "
                    "the rocker pivot's X_D (crank pivot at the origin, crank turning "
                    "counterclockwise). Prints l1, l2, phi1H_deg, X_D. Refuses data with no "
                    "crank-rocker (K_w < 1, Grashof violated, crank not the shortest link).")
    cr.add_argument("--kw", type=_finite_float, required=True, metavar="K_W",
                    help="time-ratio coefficient K_w >= 1 (working stroke time / return time)")
    cr.add_argument("--l3", type=_positive_float, required=True, metavar="L3",
                    help="rocker length |DB|, m")
    cr.add_argument("--yd", type=_finite_float, required=True, metavar="Y_D",
                    help="ordinate of the rocker pivot D, m")
    cr.add_argument("--gamma1-deg", type=_finite_float, required=True, metavar="DEG",
                    help="rocker angle (direction D->B) at the extended dead position")
    cr.add_argument("--gamma2-deg", type=_finite_float, required=True, metavar="DEG",
                    help="rocker angle at the folded dead position (gamma1 < gamma2)")
    cr.add_argument("--format", choices=["table", "json"], default="table",
                    help="table: one line per unknown (default); json: an object")
    cr.add_argument("-o", "--output", metavar="SCENE.toml",
                    help="also write the synthesized mechanism as a scene file, with a [synthesis] "
                         "table of the given data (`sheetkin workbook SCENE.toml` then adds the "
                         "synthesis sheet to the scene's workbook)")
    cr.add_argument("--workbook", metavar="OUT.xlsx",
                    help="also write a workbook with a synthesis sheet: the given data (editable), "
                         "theta, the closed-form solution as live formulas, the four equations' "
                         "residuals, the dead positions' points and a chart of them with the "
                         "rocker's arc")
    cr.add_argument("--lang", choices=["ru", "uk", "en"], default="ru",
                    help="language of the synthesis workbook (default ru)")
    cr.add_argument("--omega", type=_finite_float, default=10.0, metavar="RAD_S",
                    help="crank angular velocity in the written scene, rad/s (default 10; "
                         "positive: the working stroke is gamma1 -> gamma2)")
    cr.add_argument("--positions", type=_positive_int, default=13, metavar="N",
                    help="crank positions in the written scene (default 13)")
    cr.add_argument("--step-deg", type=_finite_float, default=30.0, metavar="DEG",
                    help="crank angle step in the written scene (default 30)")


def _add_animate_parser(sub):
    a = sub.add_parser(
        "animate", help="the mechanism over a revolution: a GIF or an offline HTML page",
        description="Draw the mechanism at FRAMES positions over one crank revolution (from "
                    "phi0, the way the crank turns): the frame with its ground signs and guides, "
                    "every link as a segment (a polygon for a link with three or more points), "
                    "sliders as blocks on their guides, the paths of the points, labels of "
                    "joints and links, toggle positions and the parts of the revolution where a "
                    "group cannot assemble. -o decides the format: .gif (matplotlib + Pillow), "
                    ".html (one self-contained page with play/pause, a speed choice and a position "
                    "slider) or "
                    ".png (the first position).")
    a.add_argument("scene", metavar="SCENE.toml", help="the scene file")
    a.add_argument("-o", "--output", metavar="OUT", required=True,
                   help="mechanism.gif, mechanism.html or mechanism.png")
    a.add_argument("--frames", type=_capped_int(MAX_FRAMES, "every 0.1 deg"), default=36,
                   metavar="N", help="positions over the revolution (default 36, every 10 deg; at most "
                                     f"{MAX_FRAMES:,})")
    a.add_argument("--fps", type=_fps, default=12.0,
                   help=f"frames per second (default 12; {FPS_RANGE[0]:g} to {FPS_RANGE[1]:g})")
    a.add_argument("--size", type=_capped_int(MAX_SIZE, "pixels"), default=320, metavar="PX",
                   help="width of the drawing in pixels (default 320, at most "
                        f"{MAX_SIZE:,}); the height follows at equal scale, "
                        f"at most {MAX_SIZE:,} too (the width shrinks for a tall mechanism)")
    a.add_argument("--vectors", action="store_true",
                   help="draw the points' velocity vectors (one scale for the whole revolution)")
    a.add_argument("--no-labels", action="store_true", help="leave out the names of joints and links")
    a.add_argument("--lang", choices=["ru", "uk", "en"], default="ru",
                   help="language of the page's controls, captions and notes, and of the GIF's captions "
                        "(default ru, as the books)")
    a.add_argument("--allow-gaps", action="store_true",
                   help="draw a mechanism that cannot assemble somewhere on the revolution (those "
                        "positions show the crank alone and say so) instead of failing")
    a.add_argument("--toggle-threshold", type=_positive_float, default=TOGGLE_THRESHOLD, metavar="X",
                   help=f"mark positions whose |det_g<i>| is below X (default {TOGGLE_THRESHOLD})")
    a.add_argument("--progress", choices=["auto", "always", "never"], default="auto",
                   help="frame counter on stderr while a GIF is written (auto: when stderr is a terminal)")


# sheetkin.course.variants' BAND, MIN_DET, MARGIN, TRIES, REVOLUTION_DEG, without importing openpyxl
# for --help (tests/course/test_variants.py checks they are equal)
VARIANTS_DEFAULTS = (0.10, 0.25, 0.10, 200, 1.0)


def _add_variants_parser(sub):
    BAND, MIN_DET, MARGIN, TRIES, REVOLUTION_DEG = VARIANTS_DEFAULTS
    x = sub.add_parser(
        "variants", help="N distinct variants of a scheme for a class: exercise and key workbooks, roster.csv",
        description="Make N variants of the scheme for N students. By default every length, "
                    "coordinate and offset (the input rows in metres) whose scene value is not zero "
                    f"varies within +-{BAND:.0%} of it, rounded to the millimetre; --vary sets a "
                    "range for any given value of the scene. A variant is kept when every group "
                    "assembles at every position of the sheet and over a whole revolution "
                    f"({REVOLUTION_DEG:g} deg apart: the crank turns fully), every link keeps its kind "
                    "of motion (turns or rocks: a crank-rocker stays a crank-rocker), every group's "
                    f"|det| (toggle measure) is >= --min-det at all those positions, and it differs from "
                    f"every other variant in some given value by {MARGIN:.0%} of that value's range "
                    "(at least one grid step). Writes in DIR, per variant ID: ID.toml (its scene), "
                    "ID-exercise.xlsx (computed rows empty, student and group cells blank), "
                    "ID-key.xlsx (the answer key); and roster.csv (variant, exercise, key, scene, "
                    f"then every given value) and the teacher's key {'.sheetkin-key'} (never put in a "
                    "workbook: `validate --roster` uses it to check the books' seals). "
                    f"Refuses, with one line, a scheme with fewer than N acceptable variants in {TRIES}*N "
                    "tries.")
    x.add_argument("scene", metavar="SCENE.toml", help="the scheme's scene file")
    x.add_argument("-n", type=_positive_int, default=None, metavar="N",
                   help="number of variants (default: one per student of --class-list, else 30)")
    x.add_argument("--class-list", metavar="STUDENTS.csv",
                   help="the class as Moodle exports it (First name, Last name, Email address or ID "
                        "number; comma or semicolon; UTF-8 or Windows-1251): the k-th student of the "
                        "list (from 0) gets variant k mod N, so more students than variants is allowed; "
                        "each student's exercise ID-NAME-exercise.xlsx has their name in their cell and "
                        "their identifier sealed in it; assignment.csv lists who got what")
    x.add_argument("--out", metavar="DIR", required=True, help="folder for the variants (created if missing)")
    x.add_argument("--seed", type=int, metavar="S",
                   help="random seed: the same seed gives byte-identical scenes and roster.csv "
                        "(default: a random one, printed)")
    x.add_argument("--vary", metavar="NAME=LO..HI", action="append", default=[],
                   help="range of a given value, named as in the input block (L1, L2, x_D, Fi_t0, "
                        "gamma_g2 ...), instead of the default band; repeatable; e.g. --vary L2=0.45..0.55")
    x.add_argument("--min-det", type=_positive_float, default=MIN_DET, metavar="X",
                   help=f"least |det| of every group at every position (default {MIN_DET:g}: for RRR "
                        "the transmission angle stays above 14.5 deg)")
    x.add_argument("--lang", choices=["ru", "uk", "en"], default="ru", help="language of the workbooks (default ru)")
    x.add_argument("--force", action="store_true",
                   help="overwrite the workbooks already in DIR; an issued roster.csv, .sheetkin-key and "
                        "assignment.csv are kept beside the new ones, dated (validate still checks the "
                        "books sealed with the older key)")


def _add_examples_parser(sub) -> None:
    x = sub.add_parser(
        "examples", help="write the bundled example scenes to a folder",
        description="Write the example scenes that come with sheetkin (the course's four-bar, "
                    "shaper, crank-slider, slotted levers, kulisas, chains) to DIR, and list "
                    "them with their titles. An existing file is never overwritten.")
    x.add_argument("dir", metavar="DIR", nargs="?", default=".",
                   help="the folder to write them to (made if missing; default: the current folder)")


def _add_docs_parser(sub) -> None:
    x = sub.add_parser(
        "docs", help="list the documentation pages, or print one",
        description="The documentation that comes with sheetkin, as Markdown pages: without "
                    "PAGE, their names and titles; with PAGE (e.g. scene-format, tutorial, class), "
                    "that page printed.")
    x.add_argument("page", metavar="PAGE", nargs="?", help="the page's name (as listed)")
    x.add_argument("--lang", choices=["ru", "uk", "en"], default=None,
                   help="for a page written in several languages (student-guide): which one "
                        "(default: the locale's, LANG or LC_ALL; else Russian, the course's)")
