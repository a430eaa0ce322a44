"""The validator of student workbooks: which rows are right, which are wrong, and why.

For one workbook:
1. open it safely (sheetkin.xlsx.package) and read the scene embedded in its hidden sheet
   (sheetkin.course.book);
2. take the student's input block (column D of the input rows) as their variant: the
   scene with those lengths, coordinates, branches, Fi0, Fi_t, Fi_tt, Delta_Fi, and as many
   positions as the sheet has columns;
3. the reference for every named row: the workbook sheetkin generates for that variant,
   evaluated by the evaluator (its accepted values equal the solver, tested); so the
   intermediate rows (P, Q, F, ...) have references too;
4. the student's values: their formulas evaluated by the evaluator; where a cell has no
   formula, the number typed (checked to the precision it was typed with); where a formula
   cannot be evaluated, the value the spreadsheet cached; a formula that does not reach the
   given data through formulas (sheetkin.xlsx.precedents: it reads only typed numbers, such
   as values pasted on a scratch sheet) is typed, as the numbers it reads are;
5. row by row: correct / wrong (largest error, first wrong column) / missing / empty; each
   row is also judged on the student's own values of what it reads (sheetkin.course.localjudge):
   the likely causes are the rows wrong on their own inputs and the rounded typed numbers
   a wrong row below depends on; the others are wrong because they depend on a cause (in
   the lecture's dependency order). Cells whose formula disagrees with the value the
   spreadsheet cached are listed too.
"""
from __future__ import annotations

from pathlib import Path
from typing import cast

from sheetkin.kinematics.scene import SceneError
from sheetkin.messages import message
from sheetkin.sheet.charts import PATHS_SHEET
from sheetkin.sheet.workbook import (
    FIRST_COL,
    SCENE_SHEET,
)
from sheetkin.xlsx.cells import read_book
from sheetkin.xlsx.evaluator import Book, EvaluationError
from sheetkin.xlsx.package import Limits, UnusableWorkbook

from . import behaviour, by_libreoffice, issued, scratch
from .book import TITLE_AT, UnusableInput, book_lang, embedded_scene, evaluate_student, identity_text
from .caches import scene_rows
from .checks import read_checks
from .layout import VALUE_COL, find_layout, standard_view
from .reference import input_values, reference_book, variant_scene
from .report_model import Report
from .rows import Graded, from_given, grade_rows


# --------------------------------------------------------------------------- validation
def validate(path: str | Path, limits: Limits = Limits(), options: issued.Options | None = None) -> Report:
    """Validate one workbook; unusable input comes back as Report.error, not an exception.
    options: the roster, the teacher's key, --accept-changed-inputs (sheetkin/course/issued.py)."""
    path = str(path)
    try:
        return _validate(path, limits, options)
    except (UnusableWorkbook, UnusableInput, SceneError, EvaluationError) as e:
        msg = str(e)
        return Report(path, error=msg if msg.startswith(path) else f"{path}: {msg}")
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as e:     # RecursionError, MemoryError, a bug: this file's error only
        return Report(path, error=internal_error(path, e))


def internal_error(path: str, e: BaseException) -> str:
    """The one line for an unexpected exception while validating `path`: the batch goes
    on, and the teacher learns that this is sheetkin's fault, not the student's."""
    from sheetkin import __version__
    what = " ".join(str(e).split())[:200]
    return f"{path}: " + message("internal_error", what=f"{type(e).__name__}{': ' + what if what else ''}",
                                 v=__version__)


def _validate(path: str, limits: Limits, options: issued.Options | None = None) -> Report:
    book = read_book(path, limits, skip=frozenset({PATHS_SHEET}))    # never graded: not parsed
    if SCENE_SHEET not in book.sheets and scratch.applies(options):
        return scratch.grade_book(book, path, options)      # a book built from scratch, graded by value
    scene, scene_text = embedded_scene(book, path, options)
    # the graded sheet and its columns, found by their content (sheetkin/course/layout.py);
    # graded through a view in the issued layout (names A, value D, positions from E)
    ref_rows = scene_rows(scene)
    issued_positions = scene.crank.positions
    layout = find_layout(book.sheets, book.order, {r.name for r in ref_rows if r.kind != "section"}, "",
                         issued_positions, list(range(issued_positions)), {SCENE_SHEET, PATHS_SHEET})
    if layout is None:
        raise UnusableInput(f"{path}: " + message(
            "no_table_rows", names=", ".join(r.name for r in ref_rows if r.kind == "calc")[:60]))
    text_given = _given_as_text(book, layout, {r.name for r in ref_rows if r.kind == "input"})
    raw = evaluate_student(book, layout)
    # what sheetkin cannot compute (a function it lacks), computed by LibreOffice when installed
    by_libreoffice.fill_uncomputed(raw, path, options.libreoffice if options else True)
    evaluated, sh = standard_view(raw, layout)
    names: dict[str, int] = {}
    for r in range(5, sh.max_row + 1):
        v = sh.consts.get((r, 1))
        if isinstance(v, str) and v and v not in names:
            names[v] = r
    g = Graded(path, scene, ref_rows, layout, evaluated, sh, names)
    g.from_given = from_given(raw, g, issued_positions)
    report = _new_report(g, book, scene_text, options)
    report.notes[:0] = text_given
    # issue 31: the student's formulas evaluated again on nudged given data (behaviour.py)
    beh = (behaviour.prepare(g, raw, book.names, scene_text, options.libreoffice if options else True)
           if _judged_by_behaviour(report) else None)
    grade_rows(report, g)
    behaviour.judge_rows(report, g, beh)
    read_checks(report, evaluated, layout.sheet, sh, names, ref_rows, cast(Book, g.ref_book), g.ref_names)
    behaviour.judge_checks(report, g)
    behaviour.judge_held_checks(report, g, beh)
    return scratch.own_table(book, path, options, report)   # the issued sheet left empty: the student's own


def _given_as_text(book, layout, input_names: set[str]) -> list[str]:
    """Given data stored as text that reads as a number ("0,144": the decimal comma of a
    Russian spreadsheet, which computes with it) are read as that number, as that spreadsheet
    does (issue 31: a remark, not "given data changed" and every row wrong); one note each."""
    sheet = book.sheets[layout.sheet]
    name_col, value_col = layout.columns.get(1, 1), layout.columns.get(VALUE_COL, VALUE_COL)
    notes = []
    for (r, c), name in list(sheet.consts.items()):
        if c != name_col or name not in input_names:
            continue
        text = sheet.consts.get((r, value_col))
        x = issued.as_text_number(text)
        if x is not None and (r, value_col) not in sheet.formulas:
            sheet.consts[(r, value_col)] = x
            notes.append(message("given_as_text", name=name, cell=f"{layout.sheet}!{layout.cell(r, VALUE_COL)}",
                                 text=repr(text), x=f"{x:g}"))
    return notes


def _judged_by_behaviour(report: Report) -> bool:
    """A book graded 0 anyway (given data changed, seal broken) is not nudged."""
    from .grades import given_changed, seal_failed
    return not seal_failed(report) and not given_changed(report, report.accepted_changes)


def _new_report(g: Graded, book, scene_text: str, options: issued.Options | None) -> Report:
    """The report of a usable book before its rows are graded: the variant (the student's
    input block, checked against the issued one), its reference, who filled it in."""
    scene, ref_rows, layout, evaluated, sh, names, main = (g.scene, g.ref_rows, g.layout, g.evaluated, g.sh,
                                                          g.names, g.main)
    input_names = {r.name for r in ref_rows if r.kind == "input"}
    where = {n: f"{main}!{layout.cell(r, VALUE_COL)}" for n, r in names.items()}
    g.inputs = inputs = input_values(evaluated, main, {n: r for n, r in names.items() if n in input_names})
    positions = scene.crank.positions      # the issued ones, whatever lies right of the table
    # the given data: graded against the issued variant unless the changes are accepted
    given = issued.check_given(scene, scene_text, book.sheets[SCENE_SHEET].consts, inputs, where, options)
    accept = bool(options and options.accept_changed)
    g.student_scene = student_scene = variant_scene(scene, inputs if accept else {**inputs, **given.issued},
                                                    positions, where)
    g.ref_book = ref_book = reference_book(student_scene)
    ref_sheet = ref_book.order[0]
    g.ref_names = ref_names = {ref_book.sheets[ref_sheet].consts.get((r, 1)): r
                               for r in range(5, ref_book.sheets[ref_sheet].max_row + 1)}
    # who filled it in: D1, D2 (the lecture's rows 1-2); a book whose table has input rows
    # "student", "group" names them there (A1 its title, A2 the scheme's author)
    old = "student" in names
    position_names = [(ref_book.value(ref_sheet, ref_names["i"], FIRST_COL + k),
                       ref_book.value(ref_sheet, ref_names["phi_1"], FIRST_COL + k)) for k in range(positions)]
    return Report(g.path, author=scene.author or "",
                  title=str(sh.consts.get((1, 1) if old else TITLE_AT, "") or ""),
                  positions=positions, problems=list(evaluated.problems), position_names=position_names,
                  student=identity_text(evaluated, main, sh, names.get("student") if old else 1),
                  group=identity_text(evaluated, main, sh, names.get("group") if old else 2),
                  variant=given.variant, given_changed=given.changed, seal=given.seal,
                  accepted_changes=accept, accepted_typed=bool(options and options.accept_typed),
                  notes=given.notes + layout.notes + ([layout.outside_line()] if layout.outside else []),
                  issued_to=given.student, issued_by=issued.version_mark(book.sheets[SCENE_SHEET].consts),
                  layout=layout, roster_differs=given.roster_differs,
                  lang=book_lang(main), variant_scene=student_scene)
