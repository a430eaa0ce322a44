"""The report of one graded book: its rows (RowReport) and every fact the reports, the
grades and copy detection read about it (Report). The facts only: what they add up to
(a verdict, a score, "all correct", the --json dict) is the grading rule's, in grades.py,
which reads this model; the model imports nothing of it."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from sheetkin.kinematics.scene import Scene

from .layout import Layout

INTERNAL = {"to_dict": False}     # a Report field's metadata: not in --json (grades.report_dict)

# The named states of a graded row; the strings are what --json writes (and tests read).
# A row of the sheet against the reference for the student's variant:
RowStatus = Literal["correct", "wrong", "missing", "empty"]
# the reference's kind of a graded row ("" before it is known): sheetkin.sheet.workbook's kinds
RowKind = Literal["", "calc", "accepted", "guard", "derived"]
# where its graded value comes from: its formula, a typed number, the cached value of a
# formula sheetkin cannot evaluate; "empty" a row with neither (behaviour.py)
RowSource = Literal["formula", "typed", "cached", "empty"]
# judged on the student's own inputs (localjudge.py): "" not judged (it reads a missing row)
LocalJudgement = Literal["right", "wrong", ""]
# a row's verdict in the grade (grades.row_verdict)
RowVerdict = Literal["correct", "typed", "wrong", "missing"]
MISSING_STATUSES: tuple[RowStatus, ...] = ("missing", "empty")


@dataclass
class RowReport:
    name: str
    row: int | None                  # the student's row number
    status: RowStatus
    max_error: float = 0.0
    first_wrong: int | None = None   # position number (1-based) of the first wrong cell
    wrong_cells: list[int] = field(default_factory=list)   # position numbers
    expected: object = None          # at the first wrong cell
    got: object = None
    cause: bool = False              # wrong, and no ancestor is wrong
    because_of: list[str] = field(default_factory=list)    # the causes it depends on
    kind: RowKind = ""               # the reference's kind of row
    source: RowSource = "formula"
    local: LocalJudgement = ""       # on the student's own inputs
    note: str = ""                   # for a cause: one line why (a typed number: cell, digits, error below)
    # issue 21: positions (1-based) where the row holds a typed value, no formula: a computed
    # row earns credit only where it computes (sheetkin/course/grades.py)
    typed_cells: list[int] = field(default_factory=list)
    formula_cells: int = 0           # cells holding a formula (their own, or an array's)
    # positions (1-based, among typed_cells) whose formula reads only typed numbers: none of
    # the given data, through any formulas (a number pasted elsewhere, then "=Лист2!E5")
    reads_typed: list[int] = field(default_factory=list)
    # issue 31 (sheetkin/course/behaviour.py): positions (1-based) right on the issued data but
    # not on nudged given data (also in typed_cells: they earn nothing); a row sheetkin cannot
    # evaluate is not judged (out of the rows graded)
    not_following: list[int] = field(default_factory=list)
    not_judged: bool = False

    @property
    def is_typed(self) -> bool:
        """A typed value where a formula belongs: at some position, or (a derived row) its
        value in column D."""
        return bool(self.typed_cells) or (self.kind == "derived" and self.source == "typed")


@dataclass
class Report:
    path: str
    author: str = ""
    title: str = ""
    rows: list[RowReport] = field(default_factory=list)
    cache_mismatch: list[str] = field(default_factory=list)   # cells: formula != cached value
    failing_checks: list[str] = field(default_factory=list)   # the student's check rows that fail
    problems: list[str] = field(default_factory=list)         # unsupported functions ...
    positions: int = 0
    error: str | None = None         # unusable input: the one-line reason
    # (i, phi_1) of each position column, as the sheet's rows i and phi_1 name it (the
    # reference for the student's variant); the reports name positions this way
    position_names: list[tuple[float, float]] = field(default_factory=list)
    # issue 13: who filled it in (their own input rows; A2 is the scheme's author), the
    # issued variant, the given data the student changed, the scene sheet's seal (issued.py)
    student: str = ""
    group: str = ""
    variant: str = ""
    given_changed: list[dict] = field(default_factory=list)
    seal: str = ""                   # "" not checked | "ok" | why it fails
    accepted_changes: bool = False   # --accept-changed-inputs: graded on the student's inputs
    accepted_typed: bool = False     # --accept-typed: typed numbers right to their digits earn credit
    # issue 21: the issued check rows deleted from the sheet, and those whose status (column
    # D) is typed over its formula: they lose their share of the grade
    checks_deleted: list[str] = field(default_factory=list)
    checks_typed: list[str] = field(default_factory=list)
    checks_issued: int = 0
    issued_to: str = ""              # the identifier sealed in it by `variants --class-list`
    notes: list[str] = field(default_factory=list)
    checks_not_judged: list[str] = field(default_factory=list)   # status not evaluable (behaviour.py)
    # Facts of a usable book that the reports, grades and copy detection read but --json
    # leaves out (INTERNAL): their defaults are what a report that stopped early says.
    layout: Layout | None = field(default=None, metadata=INTERNAL)       # the student's cells (report texts)
    roster_differs: bool = field(default=False, metadata=INTERNAL)       # one warning for the class
    lang: str = field(default="", metadata=INTERNAL)                     # the reports' default language
    variant_scene: Scene | None = field(default=None, metadata=INTERNAL)  # the report's picture
    marks: dict | None = field(default=None, metadata=INTERNAL)          # the raw cells copy detection compares
    checks_total: int | None = field(default=None, metadata=INTERNAL)    # check rows in the sheet
    checks_apply: int | None = field(default=None, metadata=INTERNAL)    # issued check rows with a number somewhere
    checks_passing: int | None = field(default=None, metadata=INTERNAL)
    checks_na: int = field(default=0, metadata=INTERNAL)
    checks_unfilled: int = field(default=0, metadata=INTERNAL)
    # the share of the graded rows' cells filled in (behaviour.py): unfilled check rows lose
    # only the rest of their share
    filled_share: float = field(default=0.0, metadata=INTERNAL)
    issued_by: str = field(default="", metadata=INTERNAL)   # the version that wrote the book ("" before 0.3)

    @property
    def wrong(self) -> list[RowReport]:
        return [r for r in self.rows if r.status == "wrong"]

    @property
    def missing(self) -> list[RowReport]:
        return [r for r in self.rows if r.status in ("missing", "empty")]

    @property
    def causes(self) -> list[RowReport]:
        return [r for r in self.rows if r.cause]

    @property
    def reason(self) -> str:
        """The unusable file's reason without its leading "path: " (the tables name the
        file in a column of their own); "" for a usable file."""
        if not self.error:
            return ""
        return self.error[len(self.path) + 2:] if self.error.startswith(self.path + ": ") else self.error

    @property
    def typed(self) -> list[RowReport]:
        """Rows holding typed values where formulas belong ("typed, not computed")."""
        return [r for r in self.rows if r.is_typed and r.status not in ("missing", "empty")]
