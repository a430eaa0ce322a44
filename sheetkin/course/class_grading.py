"""Grading a whole class: every book validated (sheetkin.course.batch), each matched with
its student (sheetkin.course.identity), possible copies found among them and against the
issued variants (sheetkin.course.copies), and the warnings that concern the class rather
than one book (a key or roster that is another class's, a roster re-written).

`grade_class` is what `sheetkin validate` runs; the command line parses the options, calls
it, prints and writes."""
from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from sheetkin.files import shown
from sheetkin.messages import message

from .batch import validate_many
from .classlist import ClassList
from .copies import Copies, file_digest, possible_copies, roster_variants
from .identity import Identity, file_mtime, find_assignment, identify
from .issued import Options
from .report_model import Report


@dataclass
class GradedClass:
    """The class's reports (in the files' order), who each one is, the possible copies,
    the class list grades.csv names (--class-list, or the assignment's students), and the
    one-line warnings about the class as a whole."""
    reports: list[Report]
    identities: list[Identity]
    copies: Copies
    class_list: ClassList | None
    warnings: list[str] = field(default_factory=list)

    def identity_warnings(self) -> list[str]:
        """The identity flags a teacher must see even without grades.csv: a book issued to
        another student, found in another's folder, not graded."""
        return [f"{self.reports[i].path}: {flag}" for i, me in enumerate(self.identities) for flag in me.flags
                if flag.startswith(("issued to", "found in", "not graded"))]


def grade_class(files: list[Path], shown_as: Callable[[Path], str], options: Options, *,
                jobs: int | None = None, progress: Callable | None = None, class_list: ClassList | None = None,
                roster_path: str | None = None, for_grades: bool = False,
                each: Callable[[Report], None] | None = None) -> GradedClass:
    """Validate `files` and grade them as a class. shown_as(path): the name the teacher
    knows a file by (inside a zip); each(report): called as each report comes (the text
    report printed while the others are validated); for_grades: grades.csv will be
    written (the assignment's students then stand for a missing class list)."""
    reports, real = [], []
    # closing(): an interruption while a report is printed also stops the workers at once
    with contextlib.closing(validate_many(files, jobs, progress, options)) as reports_of:
        for path, rep in zip(files, reports_of, strict=False):
            real.append(str(path))
            show_as(rep, str(path), shown_as(path))
            reports.append(printable_report(rep))
            if each is not None:
                each(rep)
    assignment = find_assignment(roster_path)
    if class_list is None and assignment is not None and for_grades:
        class_list = assignment.as_class_list()
    identities = identify(reports, class_list, assignment, [file_mtime(p) for p in real])
    for rep, me in zip(reports, identities, strict=True):
        rep.notes += [f"identity: {flag}" for flag in me.flags]      # --json carries them
    digests = [None if r.error else file_digest(p) for r, p in zip(reports, real, strict=True)]
    variants = roster_variants(options.roster, assignment) if options.roster is not None else None
    copies = possible_copies(reports, digests, [m.who for m in identities],
                             assignment.assigned() if assignment else None, variants) if reports else Copies()
    warnings = [w for w in (_mismatched_key(reports, options), _roster_contradicts(reports, options)) if w]
    return GradedClass(reports, identities, copies, class_list, warnings)


def show_as(rep: Report, real: str, name: str) -> None:
    """A report of a file unpacked from a zip names it as the teacher knows it."""
    if name == real:
        return
    rep.path = name
    if rep.error and rep.error.startswith(real):
        rep.error = name + rep.error[len(real):]


def printable_report(rep: Report) -> Report:
    """The report with every text fit for UTF-8 output: a file name that is not UTF-8 (made
    on another system) shown with \\xNN escapes (sheetkin.files.shown) in the text, JSON,
    HTML and grades alike."""
    import dataclasses
    for f in dataclasses.fields(rep):
        v = getattr(rep, f.name)
        if isinstance(v, str):
            setattr(rep, f.name, shown(v))
        elif isinstance(v, list) and v and all(isinstance(x, str) for x in v):
            setattr(rep, f.name, [shown(x) for x in v])
    return rep


def _roster_contradicts(reports: list[Report], options: Options) -> str:
    """One warning when most sealed books' seals check but the roster gives other data for
    them: a roster re-written (`variants --force` before this version) or another class's.
    Each such book was graded against its sealed data."""
    sealed = [r for r in reports if not r.error and r.variant and r.seal == "ok"]
    differ = [r for r in sealed if r.roster_differs]
    if options.roster is None or not differ or 2 * len(differ) < len(sealed):
        return ""
    return message("roster_contradicts_seals", f=options.roster.path, n=len(differ), m=len(sealed))


def _mismatched_key(reports: list[Report], options: Options) -> str:
    """One warning when no issued book's seal matches the key, or no book's variant is in
    the roster: a teacher who gave another class's key or roster, rather than a class of
    students who all edited their scene sheets (each book still says so on its own)."""
    issued = [r for r in reports if not r.error and r.variant]
    if len(issued) < 2:
        return ""
    if options.key is not None and not any(r.seal == "ok" for r in issued):
        return message("key_matches_no_seal", n=len(issued))
    if options.roster is not None and all("is not in" in r.seal for r in issued):
        return message("roster_has_no_variant", n=len(issued), f=options.roster.path)
    return ""
