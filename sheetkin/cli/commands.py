"""Command line: `sheetkin compute SCENE.toml ...`, `sheetkin workbook SCENE.toml ...`,
`sheetkin bench SCENE.toml --out DIR`, `sheetkin synth crank-rocker ...`, ...

Exit codes: 0 done, 1 `workbook --check` found a stale or missing workbook, 2 unusable
input (an InputError of sheetkin.errors: a scene mistake, a refused workbook; a UsageError:
a bad option, an output option naming an input file) or unwritable output (an OSError: a
full disk, a closed pipe), 3 the mechanism cannot be assembled at some requested position
(AssemblyError; the message gives the intervals), 70 anything else: a bug (one line asking
to report it; SHEETKIN_DEBUG=1 shows the traceback).
Every error is one line on stderr; no traceback reaches the user. The commands' options
and their help texts are in sheetkin/cli/args.py; this module runs the commands.
"""
from __future__ import annotations

import functools
import io
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

# Only the standard library and the scene's caps here: `--help` and small commands start
# quickly, and each command imports what it needs (the scene reader, numpy, pandas,
# openpyxl, matplotlib) inside its function; `evaluate` loads no scene reader
# (tests/cli/test_startup.py checks which modules a command loads).
from sheetkin import __version__
from sheetkin.errors import InputError, UsageError
from sheetkin.files import read_text, shown, write_file
from sheetkin.kinematics.caps import (
    MAX_POSITIONS,
    MAX_SCENE_BYTES,
    WORKBOOK_MAX_POSITIONS,
    SceneError,
    one_line,
)

from .args import EXIT_INPUT, build_parser

if TYPE_CHECKING:                 # names for annotations only: the commands import on use
    from sheetkin.kinematics.table import AngleRange

EXIT_ASSEMBLY = 3
EXIT_BROKEN_PIPE = 141      # 128 + SIGPIPE: the reader of stdout left (`| head`), said quietly
EXIT_INTERNAL = 70          # a bug (BSD's EX_SOFTWARE): one line, and a request to report it


def cmd_variants(args) -> int:
    import secrets

    from sheetkin.course.variants import MAX_VARIANTS, make_variants, write_variants
    from sheetkin.kinematics.scene import load_scene
    load_scene(args.scene)                       # one line naming file, line and key
    class_list = None
    if getattr(args, "class_list", None):
        from sheetkin.course.classlist import read_class_list
        class_list = read_class_list(args.class_list)
        from sheetkin.course.variants import check_class_size  # issue 30: before any variant is made
        check_class_size(class_list)
    n = args.n or (min(len({p.ident for p in class_list.people}), MAX_VARIANTS) if class_list else 30)
    text = read_text(args.scene, MAX_SCENE_BYTES, "scene .toml file")
    seed = args.seed if args.seed is not None else secrets.randbelow(10 ** 6)
    # the scene's name goes into every variant's text: escaped if it is not UTF-8 (files.shown)
    variants = make_variants(text, shown(args.scene), max(n, 1), seed, args.vary, args.min_det)
    kept: list = []
    roster = write_variants(variants, args.out, force=args.force, lang=args.lang, class_list=class_list, kept=kept)
    for k in kept:
        print(f"sheetkin: {k}: the previous issue's {k.name.split('-2')[0].lstrip('.')} kept "
              "(validate still checks the books sealed with it)", file=sys.stderr)
    from sheetkin.messages import message, say
    who = message("assigned_students", n=len(class_list.people), f=args.class_list,
                  a=roster.parent / "assignment.csv") if class_list else ""
    teacher = getattr(args, "error_lang", None)      # the teacher's language, as the errors'
    print(say(message("variants_written", out=args.out, n=len(variants), scene=args.scene, seed=seed, who=who,
                      roster=roster, key=roster.parent / ".sheetkin-key"), teacher, "warnings", "report"),
          file=sys.stderr)
    if class_list:
        from sheetkin.course.variants import STUDENTS_FOLDER
        print("sheetkin: " + say(message("upload_moodle_one_book", s=Path(args.out) / STUDENTS_FOLDER,
                                         t=roster.parent, r=roster), teacher, "warnings", "report"), file=sys.stderr)
    return 0


def cmd_animate(args) -> int:
    from sheetkin.kinematics.scene import load_scene
    from sheetkin.views.animate import FORMATS, animate, stderr_progress
    scene = load_scene(args.scene)
    if Path(args.output).suffix.lower() not in FORMATS:
        raise UsageError(f"{args.output}: expected a file name ending in {', '.join(FORMATS)}")
    show = args.progress == "always" or (args.progress == "auto" and sys.stderr.isatty())
    pic = animate(scene, args.output, frames=args.frames, fps=args.fps, size=args.size,
                  vectors=args.vectors, labels=not args.no_labels, allow_gaps=args.allow_gaps,
                  toggle_threshold=args.toggle_threshold,
                  progress=stderr_progress(args.output) if show else None, lang=args.lang)
    if Path(args.output).suffix.lower() == ".png":      # one picture: the first position
        print(f"{args.output}: the mechanism at phi_1 = {scene.crank.phi0_deg:g} deg", file=sys.stderr)
    else:
        n = len(pic.frames)
        print(f"{args.output}: {n} position{'' if n == 1 else 's'}", file=sys.stderr)
    for note in pic.notes:
        if not note.startswith("velocity"):
            print(f"sheetkin: warning: {note}", file=sys.stderr)
    return 0


def cmd_examples(args) -> int:
    """The bundled scenes (package data `sheetkin.examples`) written to DIR and listed."""
    import tomllib
    from importlib.resources import files

    out = Path(args.dir)
    if out.exists() and not out.is_dir():
        raise UsageError(f"{out}: not a folder")
    out.mkdir(parents=True, exist_ok=True)
    scenes = sorted((p for p in files("sheetkin.examples").iterdir() if p.name.endswith(".toml")),
                    key=lambda p: p.name)
    # every file first, the list after: a reader that leaves early (`| head`) must not cut the writing
    listed, kept = [], []
    for src in scenes:
        text = src.read_text(encoding="utf-8")
        dest = out / src.name
        if dest.exists() and dest.read_text(encoding="utf-8", errors="replace") != text:
            kept.append(dest)
        elif not dest.exists():
            dest.write_text(text, encoding="utf-8")
        listed.append(f"{dest}  {tomllib.loads(text).get('title', '')}")
    for dest in kept:
        print(f"{dest}: kept (exists and differs; not overwritten)", file=sys.stderr)
    for line in listed:
        print(line)
    return 0


def _docs_folder() -> Path | None:
    """The documentation pages: package data `sheetkin.docs` in an installed wheel; in a
    checkout run from its source folder (not installed), the repository's docs/ beside it."""
    from importlib.resources import files
    try:
        return Path(str(files("sheetkin.docs")))
    except ModuleNotFoundError:
        here = Path(__file__).resolve().parents[2] / "docs"
        return here if (here / "index.md").is_file() else None


def _page_title(path: Path) -> str:
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return ""


def cmd_docs(args) -> int:
    """The documentation pages (docs/*.md, shipped as `sheetkin.docs`): listed, or one printed."""
    folder = _docs_folder()
    pages = {p.stem: p for p in sorted(folder.glob("*.md"), key=lambda p: p.stem)} if folder else {}
    if not pages:
        # an installation without its data: the user's to mend (reinstall), so one line, exit 2
        raise InputError("the documentation pages are not installed (sheetkin.docs is missing)")
    if args.page is None:
        width = max(map(len, pages))
        for name, path in pages.items():
            print(f"{name:<{width}}  {_page_title(path)}")
        print("\nsheetkin docs PAGE prints a page (Markdown), e.g. sheetkin docs scene-format")
        return 0
    name = args.page.removesuffix(".md")
    if name not in pages:
        # a page in several languages (student-guide.ru.md ...): the user's, else the course's
        from .platform import user_lang
        name = next((f"{name}.{lang}" for lang in (user_lang(getattr(args, "lang", None)), "ru", "en")
                     if f"{name}.{lang}" in pages), name)
    if name not in pages:
        raise UsageError(f"no documentation page {args.page!r}; the pages: {', '.join(pages)}")
    text = pages[name].read_text(encoding="utf-8")
    # the CLI reference is generated from the parser when the site is built; here, the same text
    text = text.replace("<!-- cli-reference -->", "See `sheetkin --help` and `sheetkin COMMAND --help`.")
    sys.stdout.write(_api_directives(text))
    return 0


def _api_directives(text: str) -> str:
    """The site's API page names objects (`::: sheetkin.kinematics.table.compute` and its
    indented options, for mkdocstrings); printed in a terminal, each becomes its heading,
    signature and docstring."""
    import importlib
    import inspect

    out: list[str] = []
    lines = iter(text.splitlines())
    for line in lines:
        if not line.startswith("::: "):
            out.append(line)
            continue
        module, _, name = line[4:].strip().rpartition(".")
        obj = getattr(importlib.import_module(module), name)
        try:
            signature = str(inspect.signature(obj))
        except (TypeError, ValueError):
            signature = ""
        out += [f"### `{name}{signature}`", "", inspect.getdoc(obj) or "", ""]
        for line in lines:                  # the directive's options: indented, up to a blank line
            if not line.startswith(" "):
                out.append(line)
                break
    return "\n".join(out) + "\n"


def cmd_compute(args) -> int:
    import numpy as np

    from sheetkin.kinematics.scene import load_scene
    from sheetkin.views.output import write_compute

    from .angles import parse_range, read_angles
    scene = load_scene(args.scene)
    if args.dynamics and not scene.has_dynamics:
        raise UsageError(f"{args.scene}: --dynamics needs [[mass]] and/or [[force]] tables in the "
                         "scene (and `gravity = [gx, gy]` for weight); see `sheetkin docs dynamics`")
    phi: AngleRange | np.ndarray     # a --range streams in blocks; other angles are one array
    if args.range is not None:
        phi = parse_range(args.range)
    elif args.at_file is not None:
        phi = read_angles(args.at_file)
    else:
        c = scene.crank       # the scene's angles as compute() makes them
        phi = (c.phi0_deg + np.arange(c.positions, dtype=float) * c.step_deg if args.at is None
               else np.array(args.at, dtype=float))
    warnings = write_compute(scene, phi, args.format, args.output, analogs=args.analogs,
                             dynamics=args.dynamics, allow_gaps=args.allow_gaps,
                             toggle_threshold=args.toggle_threshold)
    for w in warnings:
        print(f"sheetkin: warning: {w}", file=sys.stderr)
    return 0


def cmd_workbook(args) -> int:
    from sheetkin.kinematics.scene import load_scene, override_crank
    from sheetkin.sheet.workbook import (  # openpyxl only here
        WorkbookTooLarge,
        build_workbook,
        built_fingerprint,
        existing_fingerprint,
    )
    from sheetkin.studies.synthesis import parse_synthesis
    from sheetkin.studies.synthesis_sheet import add_scene_synthesis_sheet

    if args.output and len(args.scenes) > 1:
        raise UsageError(f"-o names one file, but {len(args.scenes)} scenes were given")
    overrides = {k: v for k, v in (("positions", args.positions), ("step_deg", args.step_deg),
                                   ("phi0_deg", args.phi0_deg)) if v is not None}
    stale = 0
    for path in args.scenes:
        scene = load_scene(path)        # validates, with the file's own line numbers
        text = read_text(path, MAX_SCENE_BYTES, "scene .toml file")
        if overrides:
            text, scene = override_crank(text, path, **overrides)
        check_workbook_positions(scene, text, path, "positions" in overrides)
        out = Path(args.output) if args.output else Path(path).with_name(
            Path(path).stem + ("-exercise" if args.exercise else "") + ".xlsx")
        synthesis = parse_synthesis(text, path)
        if synthesis is None and args.synthesis:
            raise UsageError(f"{path}: --synthesis: the scene has no [synthesis] table (the data "
                             "of `sheetkin synth crank-rocker`, which writes it with -o)")
        try:
            wb = build_workbook(scene, lang=args.lang, exercise=args.exercise, scene_text=text)
        except WorkbookTooLarge as e:
            raise InputError(f"{path}: {e}") from None
        if synthesis is not None:
            for w in add_scene_synthesis_sheet(wb, scene, synthesis, lang=args.lang):
                print(f"sheetkin: warning: {path}: {w}: the synthesis sheet's check rows "
                      "comparing it with the kinematics sheet fail", file=sys.stderr)
        if args.check:
            if not out.exists():
                print(f"sheetkin: {out}: missing (regenerate: sheetkin workbook {path})")
                stale += 1
            elif existing_fingerprint(out) != built_fingerprint(wb):
                print(f"sheetkin: {out}: stale, differs from {path} (regenerate: sheetkin workbook {path})")
                stale += 1
            else:
                print(f"{out}: up to date")
            continue
        if out.suffix.lower() != ".xlsx":
            raise UsageError(f"{out}: expected a file name ending in .xlsx")
        save_workbook(wb, out)
        print(f"{out}: {scene.crank.positions} positions, {len(scene.groups)} group(s), "
              f"{len(scene.points)} point(s)" + (", synthesis sheet" if synthesis else ""),
              file=sys.stderr)
    return 1 if stale else 0


def check_workbook_positions(scene, text: str, path: str, from_option: bool) -> None:
    """A workbook has one column per position after A-D: refuse more than a sheet holds
    (Excel's 16,384 columns) with a line naming the scene's key (or the option)."""
    from sheetkin.kinematics.scene import key_line
    n = scene.crank.positions
    if n <= WORKBOOK_MAX_POSITIONS:
        return
    what = "--positions" if from_option else (f"{path}:{key_line(text, 'crank', 'positions') or '?'}: "
                                              "[crank] key 'positions'")
    # --positions is an option that does not fit; [crank] positions a scene's value
    error = UsageError if from_option else SceneError
    raise error(f"{what}: {n:,} positions need {n:,} columns, but a workbook holds at most "
                f"{WORKBOOK_MAX_POSITIONS:,} (Excel's 16,384 columns less A-D); `sheetkin compute` "
                f"takes up to {MAX_POSITIONS:,}")


def cmd_evaluate(args) -> int:
    from sheetkin.xlsx.evaluator import evaluate, rows_csv, rows_table  # no pandas: rows_frame is the API's
    # only the printed sheet and those it reads (the others' XML is neither parsed nor
    # computed), and not the values the file saved for formula cells: they are computed
    book = _evaluate_one_line(functools.partial(evaluate, needed_for=args.sheet or 0, saved=False), args.book)
    if args.sheet and args.sheet not in book.sheets:
        raise UsageError(f"{args.book}: no sheet {args.sheet!r}; sheets: {', '.join(book.order)}")
    if args.format == "csv":
        text = rows_csv(book, args.sheet)
    else:
        names, data, _ = rows_table(book, args.sheet)
        if args.format == "json":
            rows, bad = strict_json_rows(names, data)
            # allow_nan=False: NaN and Infinity are not JSON (a strict reader refuses the file)
            text = json.dumps({"file": shown(args.book), "sheet": args.sheet or book.order[0], "rows": rows},
                              indent=1, ensure_ascii=False, allow_nan=False) + "\n"
            if bad:
                print(f"sheetkin: warning: {shown(args.book)}: {len(bad)} value(s) not finite (first: "
                      f"{', '.join(bad[:5])}) written as null", file=sys.stderr)
        else:
            from sheetkin.views.output import fmt_cell as _fmt  # the table only: it loads the solver
            text = "\n".join(f"{n:<16}" + "".join(f"{_fmt(v):>13}" for v in row)
                             for n, row in zip(names, data, strict=True)) + "\n"
    _write(args.output, text)
    return 0


def strict_json_rows(names: list[str], data: list[list]) -> tuple[dict, list[str]]:
    """{row name: values} with every non-finite number as None, and where they were."""
    import math
    rows: dict[str, list] = {}
    bad: list[str] = []
    for name, row in zip(names, data, strict=True):
        values = list(row)
        for k, v in enumerate(values):
            if isinstance(v, float) and not math.isfinite(v):
                values[k] = None
                bad.append(f"{name}[{k + 1}] = {v}")
        rows[str(name)] = values
    return rows, bad


def _evaluate_one_line(evaluate, path):
    """evaluate(path), every failure one line: the user's to mend (an InputError: a cell's
    problem with strict evaluation, a refused workbook; an OSError: a refused file) pass as
    they are; anything else (a bug of ours, memory) becomes an EvaluationError naming the
    file, never a traceback."""
    from sheetkin.xlsx.evaluator import EvaluationError
    try:
        return evaluate(path)
    except (InputError, OSError):
        raise
    except Exception as e:      # noqa: BLE001 - RecursionError, MemoryError, a bug: one line, exit 2
        raise EvaluationError(f"{path}: cannot be evaluated ({type(e).__name__}: {' '.join(str(e).split())[:200]}); "
                              "please report this file to sheetkin's authors") from None


def _write(path, text):
    """`text` to the file `path` (all or nothing: sheetkin.files.write_file), or stdout."""
    if path:
        with _writing(path):
            write_file(path, text)
    else:
        sys.stdout.write(text)


def save_workbook(wb, path) -> None:
    """Save an openpyxl workbook: built in memory first, then written in one go, so a
    full disk is one line naming the file (openpyxl writing to the file itself leaves an
    open zip whose clean-up prints a second error)."""
    buf = io.BytesIO()
    wb.save(buf)
    with _writing(path):
        write_file(path, buf.getvalue())


class _writing:
    """Context: an OSError while writing `path` (a full disk, /dev/full, no permission)
    comes out naming the file; a write error has no file name of its own."""

    def __init__(self, path):
        self.path = str(path)

    def __enter__(self):
        return self

    def __exit__(self, kind, e, tb):
        if isinstance(e, OSError) and not isinstance(e, BrokenPipeError) and not e.filename:
            raise OSError(e.errno, e.strerror or str(e), self.path) from None
        return False


# --------------------------------------------------------------------------- never overwrite input
def _command_files(args) -> tuple[list[tuple[str, str]], list[str]]:
    """(option, path) of every file the command writes, and the files it reads."""
    out = [(opt, getattr(args, dest)) for opt, dest in
           (("-o/--output", "output"), ("--html", "html"), ("--workbook", "workbook"), ("--grades", "grades"))
           if getattr(args, dest, None)]
    if args.command == "bench" and args.out:
        out += [("--out", str(Path(args.out) / f)) for f in
                ("bench.csv", "bench.png", "stability.csv", "stability.png")]
    inputs = [p for p in ([getattr(args, "scene", None), getattr(args, "book", None),
                           getattr(args, "class_list", None), getattr(args, "worksheet", None)] +
                          list(getattr(args, "scenes", None) or [])) if p]
    if args.command == "validate":
        inputs += [str(f) for f in _validation_files(args.paths, strict=False)]
        inputs += [p for p in (args.roster, args.key) if p]
        if args.roster and not args.key:        # the key beside the roster is read too
            from sheetkin.course.issued import KEY_FILE
            inputs.append(str(Path(args.roster).parent / KEY_FILE))
    from .inputs import more_inputs  # issue 30: zips in folders, assignment, the roster's scenes, keys
    inputs += more_inputs(args)
    if getattr(args, "at_file", None):
        from .angles import split_column
        inputs.append(str(split_column(args.at_file)[0]))
    return out, inputs


def _same_file(a: str, b: str) -> bool:
    """The same file, also through symlinks and hard links (os.path.samefile)."""
    try:
        return os.path.samefile(a, b)
    except OSError:          # one of them does not exist (yet): compare resolved names
        return Path(a).resolve() == Path(b).resolve()


def refuse_overwriting_inputs(args) -> None:
    """Raise UsageError (one line) if an output option names an input file of the command,
    or two outputs name one file: `evaluate b.xlsx -o b.xlsx` and `validate b.xlsx --html
    b.xlsx` used to overwrite the student's workbook."""
    outputs, inputs = _command_files(args)
    for k, (opt, path) in enumerate(outputs):
        for inp in inputs:
            if os.path.lexists(path) and _same_file(path, inp):
                raise UsageError(f"{path}: {opt} names the input file {inp}; refusing to overwrite it "
                                 "(choose another output name)")
        for opt2, other in outputs[k + 1:]:
            if opt2 != opt and _same_file(path, other):
                raise UsageError(f"{path}: both {opt} and {opt2} name this file; choose two names")
    from .inputs import check_outputs  # issue 30: a read-only output folder, before the work
    check_outputs(outputs)


def _validation_files(paths: list[str], strict: bool = True) -> list[Path]:
    """The files a validation reads as the user named them (a zip as itself: the input)."""
    from sheetkin.course.batch import submission_files
    return submission_files(paths, strict=strict, unpack=False).files


def _grades_first(args):
    """Before validating: --grades' folder writable, the class list read (its mistakes are
    one line now, not after the class is validated); returns the class list or None."""
    from sheetkin.messages import message
    if args.class_list and not args.grades:
        raise UsageError(message("class_list_without_grades"))
    if getattr(args, "worksheet", None) and not args.grades:
        raise UsageError("--worksheet is filled in and written as --grades: give --grades GRADES.csv too")
    if not args.grades:
        return None
    from sheetkin.course.grades import check_writable, read_class_list, read_worksheet
    check_writable(args.grades)
    # the worksheet's mistakes are one line now too (read again when written: it is small)
    if getattr(args, "worksheet", None):
        read_worksheet(args.worksheet)
    out_of = getattr(args, "out_of", None)
    if out_of is not None and not out_of > 0:
        raise UsageError(message("out_of_expected", v=f"{out_of:g}"))
    if getattr(args, "scale", None):
        from sheetkin.course.grades import five_point_scale
        five_point_scale("ru", args.scale)          # a mistake in the thresholds: one line now
    return read_class_list(args.class_list) if args.class_list else None


def _write_grades(args, reports, copies, class_list, identities=None, lang: str = "en") -> None:
    from sheetkin.messages import message, say

    from .help_texts import warning_line
    teacher = getattr(args, "error_lang", None)      # the teacher's language, as the errors'
    from sheetkin.course.grades import (
        COLUMNS,
        fill_worksheet,
        grade_lines,
        read_worksheet,
        worksheet_csv,
        write_grades,
    )
    lines, warnings = grade_lines(reports, copies, class_list,
                                  accept_changed=bool(getattr(args, "accept_changed_inputs", False)),
                                  identities=identities, lang=lang, copies_policy=getattr(args, "copies", "hold"))
    books = sum(1 for line in lines[1:] if line[2 + COLUMNS.index("file")])   # not "not handed in"
    out_of, scale_spec = getattr(args, "out_of", None), getattr(args, "scale", None)
    if out_of or scale_spec is not None:
        from sheetkin.course.grades import five_point_scale, with_course_grade
        scale = five_point_scale(lang, scale_spec) if scale_spec is not None else None
        lines = with_course_grade(lines, out_of, scale, lang)
    if getattr(args, "worksheet", None):
        sheet, more = fill_worksheet(read_worksheet(args.worksheet), lines)
        warnings += more
        write_grades(args.grades, worksheet_csv(sheet))
        print(say(message("worksheet_graded", f=args.grades, w=args.worksheet, n=books), teacher, "warnings",
                  "report"), file=sys.stderr)
    else:
        from sheetkin.course.grades import grades_data
        write_grades(args.grades, grades_data(lines, getattr(args, "grades_format", "csv")))
        print(say(message("submission_graded", f=args.grades, n=books), teacher, "warnings", "report"),
              file=sys.stderr)
    for w in warnings:
        print(warning_line(f"{args.grades}: {w}", teacher), file=sys.stderr)


def cmd_validate(args) -> int:
    from sheetkin.course.batch import submission_files
    from sheetkin.course.class_grading import grade_class
    from sheetkin.course.report import copies_lines, html_report, json_report, summary_table, text_report
    from sheetkin.course.report_texts import class_lang
    found = submission_files(args.paths)
    files = found.files
    class_list = _grades_first(args)
    for twice in found.twice:
        print(f"sheetkin: note: {twice}: given twice; validated once", file=sys.stderr)
    show = args.progress == "always" or (args.progress == "auto" and sys.stderr.isatty() and len(files) > 1)
    from sheetkin.xlsx.convert import convert_opendocument  # a class's .ods files: one LibreOffice run
    convert_opendocument(files, note=(lambda t: print(f"sheetkin: {t}", file=sys.stderr)) if show else None)
    # (converted before the pool starts: forked workers inherit the conversions)

    def progress(done, f):
        bar = int(30 * done / len(files))
        sys.stderr.write(f"\r[{'#' * bar}{'.' * (30 - bar)}] {done}/{len(files)} {f.name[:40]:<40}")
        sys.stderr.flush()

    def print_report(rep):
        if not args.json:
            sys.stdout.write(text_report(rep, args.lang or rep.lang or "ru"))
    options, keyless = _issued_options(args)
    from sheetkin.course.scratch import scratch_options  # hook (issue 33): books built from scratch
    options = scratch_options(options, getattr(args, "scene", None), args.roster)
    graded = grade_class(files, found.name, options, jobs=args.jobs, progress=progress if show else None,
                         class_list=class_list, roster_path=args.roster, for_grades=bool(args.grades),
                         each=print_report)
    reports, copies, identities = graded.reports, graded.copies, graded.identities
    if show:
        sys.stderr.write("\n")
    if keyless and any(r.variant for r in reports):
        print(f"sheetkin: note: {keyless}", file=sys.stderr)
    from .help_texts import warning_line
    teacher = getattr(args, "error_lang", None)      # the teacher's language, as the errors'
    for warning in graded.warnings:
        print(warning_line(warning, teacher), file=sys.stderr)
    lang = args.lang or class_lang(reports)
    if args.json:
        sys.stdout.write(json_report(reports, copies, lang))
    elif len(reports) > 1:
        sys.stdout.write("\n" + summary_table(reports, lang) + copies_lines(reports, copies, lang))
    if args.html:
        _write(args.html, html_report(reports, copies, lang, identities, getattr(args, "copies", "hold")))
    if args.grades:
        _write_grades(args, reports, copies, graded.class_list, identities, lang)
    else:
        for warning in graded.identity_warnings():
            print(warning_line(warning, teacher), file=sys.stderr)
    if any(r.error for r in reports):
        return EXIT_INPUT
    from sheetkin.course.grades import all_correct
    return 0 if all(all_correct(r) for r in reports) else 1


def _issued_options(args):
    """issued.Options from --roster, --key, --accept-changed-inputs, and the one-line note
    to give when there is no key (seals not checked)."""
    from sheetkin.course.issued import KEY_FILE, OLDER_KEYS, Options, read_key, read_roster
    roster = read_roster(args.roster) if args.roster else None
    key_path = args.key or (Path(args.roster).parent / KEY_FILE if args.roster else None)
    key: bytes | None = None
    older: tuple[bytes, ...] = ()
    if key_path is not None and (args.key or Path(key_path).exists()):
        key = read_key(key_path)
        # the keys of earlier issues, kept dated beside it by `variants --force`
        older = tuple(read_key(p) for p in sorted(Path(key_path).parent.glob(OLDER_KEYS)) if p.is_file())
    keyless = "" if key else ("no key (--key FILE, or .sheetkin-key next to --roster): the scene "
                              "sheets' seals are not checked")
    return Options(roster, key, args.accept_changed_inputs, bool(getattr(args, "accept_typed", False)),
                   older, libreoffice=not getattr(args, "no_libreoffice", False)), keyless


def cmd_bench(args) -> int:
    from sheetkin.studies.bench import format_bench, run_bench  # mpmath and matplotlib are needed only here
    if args.stability:
        return _cmd_stability(args)
    if args.scene is None:
        raise UsageError("bench: a SCENE.toml is needed (or --stability)")
    from sheetkin.kinematics.scene import load_scene
    scene = load_scene(args.scene)
    table, warnings = run_bench(scene, args.positions, args.out, libreoffice=not args.no_libreoffice)
    sys.stdout.write(format_bench(table))
    print(f"{Path(args.out) / 'bench.csv'}, {Path(args.out) / 'bench.png'}: written", file=sys.stderr)
    for w in warnings:
        print(f"sheetkin: warning: {w}", file=sys.stderr)
    return 0


def _cmd_stability(args) -> int:
    from sheetkin.studies.stability import format_stability, stability_study
    if args.scene is not None:
        raise UsageError("bench --stability builds its own scenes: give no SCENE.toml")
    table, warnings, _ = stability_study(args.out)
    sys.stdout.write(format_stability(table))
    print(f"{Path(args.out) / 'stability.csv'}, {Path(args.out) / 'stability.png'}: written",
          file=sys.stderr)
    for w in warnings:
        print(f"sheetkin: warning: {w}", file=sys.stderr)
    return 0


def cmd_synth(args) -> int:
    from sheetkin.kinematics.scene import parse_scene
    from sheetkin.studies.synthesis import parse_synthesis, synthesize_crank_rocker
    if args.omega <= 0:
        raise UsageError(f"--omega {args.omega:g}: expected a positive angular velocity (the "
                         "working stroke gamma1 -> gamma2 needs the crank turning counterclockwise)")
    mech = synthesize_crank_rocker(args.kw, args.l3, args.yd, args.gamma1_deg, args.gamma2_deg)
    res = mech.results()
    if args.format == "json":
        text = json.dumps(res, indent=1) + "\n"
    else:
        units = {"l1": "m", "l2": "m", "phi1H_deg": "deg", "X_D": "m"}
        text = "".join(f"{k:<11}{v:>14.6g}  {units[k]}\n" for k, v in res.items())
    if args.output:
        scene_text = mech.scene_toml(omega=args.omega, positions=args.positions,
                                     step_deg=args.step_deg, lang=args.lang)
        parse_scene(scene_text, args.output)          # what is written must load,
        parse_synthesis(scene_text, args.output)      # its [synthesis] table too
        _write(args.output, scene_text)
        print(f"{args.output}: written (crank-rocker, theta = {mech.theta_deg:.6g} deg)",
              file=sys.stderr)
    if args.workbook:
        from sheetkin.studies.synthesis_sheet import build_synthesis_workbook
        save_workbook(build_synthesis_workbook(args.kw, args.l3, args.yd, args.gamma1_deg,
                                               args.gamma2_deg, lang=args.lang), args.workbook)
        print(f"{args.workbook}: written (synthesis sheet)", file=sys.stderr)
    sys.stdout.write(text)
    return 0


class Terminated(KeyboardInterrupt):
    """SIGTERM (what `timeout` and `kill` send), raised where the program is, so that every
    clean-up on the way out runs (temporary files, workers, LibreOffice): exit 143. A
    KeyboardInterrupt, so that whatever lets a Ctrl-C through lets it through too."""


EXIT_SIGINT, EXIT_SIGTERM = 130, 143       # 128 + the signal's number, as a shell reports it


class _Signals:
    """Context: the first SIGINT raises KeyboardInterrupt and the first SIGTERM Terminated,
    so the command unwinds and cleans up; a second one (an impatient user, `timeout -k`)
    removes the temporary output files, kills the workers and exits at once. Only in the
    main thread (signal handlers cannot be set elsewhere); the old handlers come back."""

    def __enter__(self):
        import signal
        import threading
        self.old = {}
        if threading.current_thread() is not threading.main_thread():
            return self
        self.hit = False
        for sig in (signal.SIGINT, signal.SIGTERM):
            self.old[sig] = signal.signal(sig, self._handle)
        return self

    def _handle(self, signum, frame):
        import signal
        code = EXIT_SIGINT if signum == signal.SIGINT else EXIT_SIGTERM
        if self.hit:
            from sheetkin.files import kill_children, remove_temporaries
            remove_temporaries()
            kill_children()
            lo = sys.modules.get("sheetkin.xlsx.libreoffice")     # LibreOffice runs, if any started
            if lo is not None:
                lo.stop_all()
            os.write(2, b"sheetkin: interrupted again: stopped at once\n")
            os._exit(code)
        self.hit = True
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise Terminated

    def __exit__(self, *exc):
        import signal
        if getattr(self, "hit", False):
            # cleaned up, on the way out after a signal: a second one arriving now (or while
            # the interpreter shuts down) must not turn exit 130/143 into a death by signal
            for sig in self.old:
                signal.signal(sig, signal.SIG_IGN)
            return False
        for sig, old in self.old.items():
            signal.signal(sig, old)
        return False


def main(argv=None) -> int:
    # the help in the teacher's language (--lang, else the locale); the patterns Windows'
    # shells leave as typed (`class/*.xlsx`) expanded by sheetkin
    from .help_texts import ERROR_COMMANDS, error_parsers, help_lang
    from .platform import expand_patterns
    given = sys.argv[1:] if argv is None else [str(a) for a in argv]
    lang = help_lang(given)
    parser = build_parser(lang)
    # issue 34: the usage errors of validate and variants in the teacher's language too
    command = next((a for a in given if not a.startswith("-")), None)
    if command in ERROR_COMMANDS:
        for p in (parser, *error_parsers(parser)):
            setattr(p, "error_lang", lang)     # noqa: B010 (args._Parser's; mypy sees ArgumentParser)
    args = parser.parse_args(argv)
    args.error_lang = lang if args.command in ERROR_COMMANDS else None
    for many in ("paths", "scenes"):            # the commands that take many files
        if isinstance(getattr(args, many, None), list):
            setattr(args, many, expand_patterns(getattr(args, many)))
    try:
        with _Signals():
            return _run(args)
    except BrokenPipeError:
        # `sheetkin compute x.toml | head -1`: the reader has what it wanted. End quietly, as
        # command-line tools do (they die of SIGPIPE: 128 + 13, which a shell's pipefail sees)
        _detach_stdout()
        return EXIT_BROKEN_PIPE


def _detach_stdout():
    """Point stdout at /dev/null, so that the interpreter's last flush of the unwritable
    stream raises nothing ("Exception ignored ... BrokenPipeError")."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError, io.UnsupportedOperation):
        pass          # not a real file descriptor (a test's capture)


def _run(args) -> int:
    import warnings
    # a safety net: numpy's floating-point warnings never reach the user (the computing
    # functions run under np.errstate; this catches any that a thread would show)
    warnings.filterwarnings("ignore", category=RuntimeWarning,
                            message=r".*(overflow|invalid value|divide by zero|underflow) encountered")
    try:
        refuse_overwriting_inputs(args)
        code = {"compute": cmd_compute, "workbook": cmd_workbook, "evaluate": cmd_evaluate,
                "validate": cmd_validate, "bench": cmd_bench,
                "synth": cmd_synth, "animate": cmd_animate, "variants": cmd_variants,
                "examples": cmd_examples, "docs": cmd_docs}[args.command](args)
        _flush_stdout()
        return code
    except InputError as e:             # the user's to mend (UsageError among them): one line
        if _is_assembly_error(e):       # an InputError with its own exit code
            # the Python API says allow_gaps=True; on the command line it is the option
            said = str(e).replace("allow_gaps=True", "--allow-gaps")
            print(f"sheetkin: error: {getattr(args, 'scene', '')}: {said}", file=sys.stderr)
            return EXIT_ASSEMBLY
        from .help_texts import error_line  # validate's and variants': in the teacher's language
        print(one_line(error_line(str(e), getattr(args, "error_lang", None)), 2000), file=sys.stderr)
        return EXIT_INPUT
    except BrokenPipeError:
        raise
    except OSError as e:
        name = e.filename or "stdout"     # a write error without a name: ours name their files
        if not e.filename:
            _detach_stdout()
        print(one_line(f"sheetkin: error: {name}: {e.strerror or e}"), file=sys.stderr)
        return EXIT_INPUT
    except MemoryError:
        print("sheetkin: error: out of memory; use fewer positions (or smaller files)", file=sys.stderr)
        return EXIT_INPUT
    except Terminated:
        print("sheetkin: terminated", file=sys.stderr)
        return EXIT_SIGTERM
    except KeyboardInterrupt:
        print("sheetkin: interrupted", file=sys.stderr)
        return EXIT_SIGINT
    except Exception as e:              # outside the family (sheetkin.errors): a bug of ours
        if os.environ.get("SHEETKIN_DEBUG"):
            raise
        print(one_line(f"sheetkin: internal error: {type(e).__name__}: {e} (a bug in sheetkin "
                       f"{__version__}: please report it with the command and its files; "
                       "SHEETKIN_DEBUG=1 shows the traceback)", 2000), file=sys.stderr)
        return EXIT_INTERNAL


def _is_assembly_error(e: BaseException) -> bool:
    """Whether e is the scene's AssemblyError: only a command that loaded the scene reader
    can raise one, so it is looked up, not imported (`evaluate` loads no kinematics)."""
    scene = sys.modules.get("sheetkin.kinematics.scene")
    return scene is not None and isinstance(e, scene.AssemblyError)


def _flush_stdout():
    """Write out what is buffered now, while a failure (a closed pipe, a full disk) can
    still be reported in one line."""
    sys.stdout.flush()


if __name__ == "__main__":
    sys.exit(main())
