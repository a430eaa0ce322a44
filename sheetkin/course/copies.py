"""Possible copies among a class's workbooks: what two submissions share that honest work
on two variants would not.

Every honest student writes the lecture's formulas (seed 003), so identical *correct*
formulas are expected and say nothing. What does signal a copy:
1. byte-identical files;
2. the same typed numbers (no formula) in the same computed cells, where the number is
   wrong in at least one of the two books, or the two books' given data (as typed) differ
   in what the row depends on: a number that is right for one variant and sits, typed, in
   another variant's book (a copy with the copier's given data typed in), or the same
   wrong number in both. At least COPY_TYPED_CELLS such cells (one number can agree by
   chance; a copied row brings a whole row of them);
3. the same wrong formula: a row wrong in both books whose formulas are not the lecture's
   (the reference workbook's) and are identical once written relative to their cell (the
   same text in every column, as dragging makes it).
4. the same name in the student's cell (a copy whose name was left, or a student handing
   in twice);
5. the same issued variant (its id, embedded by `sheetkin variants`) in two books, its
   given data changed in one: a book taken from its owner, the copier's data typed in;
6. numbers typed in one book, wrong there, that equal (to the digits typed) what another
   book's formulas computed in the same cells: the source is named by file and student;
7. one issued book handed in by two students (its sealed student, or with an assignment a
   variant issued to one student only); without an assignment, one variant from different
   students (listed for the teacher: nothing says who got which variant).
The answer is clusters (Copies): one per group of books linked by these rules, each rule
with the books it concerns, never every pair, so a report of 200 identical books is one
cluster, linear in the class (issue 23: 19,900 pairs were a 10.6 MB HTML page).
Honest students on different variants share only right formulas and typed numbers that
are right in both books (e.g. phi_1, which the variants share): never flagged. A copy
re-saved by a spreadsheet program, its name changed, every formula the lecture's and no
number typed, leaves nothing to find.

`submission_marks` runs inside the validation (sheetkin/course/validator.py) on the raw cells;
`possible_copies` compares the reports of a class.
"""
from __future__ import annotations

import hashlib
import re
from collections import defaultdict
from dataclasses import dataclass, field
from functools import lru_cache

from sheetkin.messages import message

from .reference import reference_book

COPY_RIGHT_DIGITS = 2      # a number right in both books with fewer digits (0, 1, 0.5) says nothing
COPY_TYPED_CELLS = 3       # shared typed numbers (wrong in one book at least) that flag a copy

# a cell reference (A1, $B$7) outside a string and not a function's name (LOG10( is a call)
_REF = re.compile(r'(?P<str>"[^"]*")|(?<![A-Za-z0-9_.$!])(?P<cabs>\$?)(?P<col>[A-Za-z]{1,3})'
                  r'(?P<rabs>\$?)(?P<row>\d+)(?![A-Za-z0-9_(])')


def _column_number(letters: str) -> int:
    n = 0
    for ch in letters.upper():
        n = 26 * n + ord(ch) - 64
    return n


@lru_cache(maxsize=1 << 18)
def relative_formula(formula: str, row: int, col: int) -> str:
    """The formula with its references written relative to its cell (R[-3]C[0]; absolute
    parts kept: R7C4), upper case, without spaces: the same text in every column of a
    row filled by dragging, and in every book with the same layout. Kept per (text, cell):
    a class's books repeat the layout, so each book after the first costs lookups (issue 24)."""
    def sub(m):
        if m.group("str") is not None:
            return m.group(0)
        c, r = _column_number(m.group("col")), int(m.group("row"))
        rr = f"R{r}" if m.group("rabs") else f"R[{r - row}]"
        cc = f"C{c}" if m.group("cabs") else f"C[{c - col}]"
        return rr + cc
    return _REF.sub(sub, "".join(formula.split())).upper()


def _row_formulas(sheet, r: int, first_col: int, positions: int) -> list[str | None]:
    return [None if (f := sheet.formulas.get((r, first_col + k))) is None else relative_formula(f, r, first_col + k)
            for k in range(positions)]


def _as_lecture(sheet, r: int, reference, rr: int, first_col: int, positions: int) -> bool:
    """Whether the row holds, on the reference's own row, the reference's formula texts
    (or nothing) in every position: then its relative formulas are the lecture's, which
    say nothing about copying; the honest book's common case, decided without a regex."""
    if r != rr:
        return False
    got, lecture = sheet.formulas, reference.formulas
    return all((f := got.get((r, c))) is None or f == lecture.get((rr, c))
               for c in range(first_col, first_col + positions))


def submission_marks(sheet, rows: dict[str, int], first_col: int, positions: int,
                     reference=None, ref_rows: dict[str, int] | None = None,
                     inputs: dict | None = None, ancestors: dict | None = None) -> dict:
    """What copy detection needs from a student's sheet (a sheetkin.xlsx.cells.Sheet): `typed`:
    {(row name, position 1..n): number} of the numbers typed in computed rows; `formulas`:
    {row name: digest of the row's relative formulas} of the rows whose formulas are not
    the lecture's (the reference sheet's, at ref_rows): the lecture's formulas are
    everybody's; `inputs`: the given data as typed, and `depends`: {row name with a typed
    number: the given data it depends on} (from `ancestors`, the validator's); `values`:
    {(row name, position): number} that the formulas computed, as the spreadsheet saved them
    (a classmate who typed them in is found by them)."""
    typed: dict[tuple[str, int], float] = {}
    formulas: dict[str, str] = {}
    values: dict[tuple[str, int], float] = {}
    for name, r in rows.items():
        _row_numbers(sheet, name, r, first_col, positions, typed, values)
        lecture_row = ref_rows.get(name) if reference is not None and ref_rows is not None else None
        digest = _own_formulas_digest(sheet, r, reference, lecture_row, first_col, positions)
        if digest is not None:
            formulas[name] = digest
    inputs = {n: v for n, v in (inputs or {}).items() if isinstance(v, (int, float, str)) and not isinstance(v, bool)}
    depends = {n: sorted((ancestors or {}).get(n, set()) & inputs.keys()) for n in {n for n, _ in typed}}
    return {"typed": typed, "formulas": formulas, "inputs": inputs, "depends": depends, "values": values}


def _row_numbers(sheet, name: str, r: int, first_col: int, positions: int,
                 typed: dict[tuple[str, int], float], values: dict[tuple[str, int], float]) -> None:
    """A row's typed numbers (into typed) and the finite numbers its formulas saved (into
    values), by (row name, position 1..n)."""
    cached = sheet.cached
    for k in range(positions):
        v = sheet.consts.get((r, first_col + k))
        if isinstance(v, (int, float)) and not isinstance(v, bool) and (r, first_col + k) not in sheet.formulas:
            typed[(name, k + 1)] = float(v)
        c = cached.get((r, first_col + k)) if (r, first_col + k) in sheet.formulas else None
        if isinstance(c, (int, float)) and not isinstance(c, bool) and c == c and abs(c) != float("inf"):
            values[(name, k + 1)] = float(c)


def _own_formulas_digest(sheet, r: int, reference, lecture_row: int | None, first_col: int,
                         positions: int) -> str | None:
    """The digest of a row's relative formulas, None if it has none or they are the
    lecture's (the reference's row lecture_row): the lecture's formulas are everybody's."""
    if lecture_row is not None and _as_lecture(sheet, r, reference, lecture_row, first_col, positions):
        return None                                 # the lecture's texts in the lecture's cells: nothing to hash
    texts = _row_formulas(sheet, r, first_col, positions)
    if not any(texts):
        return None
    if lecture_row is not None:
        lecture = _row_formulas(reference, lecture_row, first_col, positions)
        if all(t is None or t == l for t, l in zip(texts, lecture, strict=False)):
            return None
    return hashlib.sha256("\n".join(t or "" for t in texts).encode()).hexdigest()[:16]


def file_digest(path) -> str | None:
    """sha256 of the file's bytes; None when it cannot be read (an unusable submission)."""
    h = hashlib.sha256()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    except OSError:
        return None
    return h.hexdigest()


def _wrong_rows(rep) -> set[str]:
    """Rows wrong (against the reference) or locally wrong (on the student's own upstream
    values: issue 13, localjudge). Not only the likely causes: graded against the issued
    variant, a copier's retyped given data make the first rows the causes and the copied
    wrong formula one that depends on them."""
    return {r.name for r in rep.rows if r.status == "wrong" or r.local == "wrong"}


def _wrong_cells(rep) -> set[tuple[str, int]]:
    return {(r.name, k) for r in rep.rows for k in r.wrong_cells}


def _given_of(rep, row: str) -> tuple:
    """The given data (as typed) that `row` depends on in this book."""
    m = rep.marks
    return tuple((n, m["inputs"].get(n)) for n in m["depends"].get(row, ()))


def _given_differ(a, b, row: str) -> bool:
    """Whether the two books' given data (as typed) differ in what `row` depends on: the
    same number cannot then be right in both."""
    ma, mb = a.marks, b.marks
    return any(ma["inputs"].get(n) != mb["inputs"].get(n)
               for n in set(ma["depends"].get(row, ())) | set(mb["depends"].get(row, ())))


MAX_GROUP = 32             # books compared pair by pair within one shared number (the rest: with these)
MAX_LISTED = 3             # other members of a cluster a book's line names ("... and N more")


class _Union:
    """Union-find over report indices: the clusters of copies."""

    def __init__(self):
        self.parent: dict[int, int] = {}

    def find(self, i: int) -> int:
        self.parent.setdefault(i, i)
        while self.parent[i] != i:
            self.parent[i] = self.parent[self.parent[i]]
            i = self.parent[i]
        return i

    def join(self, members) -> None:
        members = list(members)
        for j in members[1:]:
            a, b = self.find(members[0]), self.find(j)
            if a != b:
                self.parent[max(a, b)] = min(a, b)


@dataclass
class Cluster:
    """Submissions that look copied from one another, and why: each reason is a text and
    the members it concerns (a group, never every pair: the report stays linear)."""
    members: list[int]
    reasons: list[tuple[str, list[int]]] = field(default_factory=list)     # one per text, merged
    links: list[tuple[str, list[int]]] = field(default_factory=list)       # as found (pairs_of)


class Copies(dict):
    """possible_copies' answer: {report index: its Cluster}, and `clusters` in order.
    Every consumer names a cluster once, and a book's line names at most MAX_LISTED others."""

    def __init__(self, clusters: list[Cluster] | tuple = ()):
        super().__init__()
        self.clusters = list(clusters)
        # {report index: [(file, student, why)]}: sources that are no submission (a variant's
        # key whose computed values a book holds typed); its cluster may name no other book
        self.sources: dict[int, list[tuple[str, str, str]]] = {}
        for c in self.clusters:
            for i in c.members:
                self[i] = c

    def others(self, i: int) -> list[int]:
        c = self.get(i)
        return [] if c is None else [j for j in c.members if j != i]

    def why(self, i: int) -> str:
        """The reasons that concern report i, "; "-joined."""
        c = self.get(i)
        return "" if c is None else "; ".join(dict.fromkeys(t for t, m in c.reasons if i in m))


def _by_key(keys) -> list[list[int]]:
    groups: dict = defaultdict(list)
    for i, k in enumerate(keys):
        if k:
            groups[k].append(i)
    return [g for g in groups.values() if len(g) > 1]


def _name_of(rep) -> str:
    return " ".join(str(rep.student or "").casefold().replace("ё", "е").split())


def _one_moodle_submitter(paths: list[str]) -> bool:
    """Whether every file came in the Moodle folder (or flat name) of one participant."""
    from .classlist import moodle_submitter
    subs = [moodle_submitter(p) for p in paths]
    found = [s for s in subs if s is not None]
    return len(found) == len(subs) and len({s.participant for s in found}) == 1


def _namesakes(a, b) -> bool:
    """Whether two books under one name are two students: sealed to different students
    (`variants --class-list`), or handed in from different Moodle participants' folders."""
    from .classlist import moodle_submitter
    if a.issued_to and b.issued_to and a.issued_to != b.issued_to:
        return True
    sa, sb = moodle_submitter(a.path), moodle_submitter(b.path)
    return sa is not None and sb is not None and sa.participant != sb.participant


def _identity_groups(reports, who, assigned) -> list[tuple[str, list[int]]]:
    """The same name typed in two files (a copy whose name was left, or one student handing
    in twice); one issued book handed in by two students (its sealed student, or a variant
    issued to one student only: `assigned` counts them); without an assignment, one variant
    from different students; one variant handed in twice, its given data retyped in one."""
    out = []
    usable = [not r.error for r in reports]
    for g in _by_key(_name_of(r) if ok else "" for r, ok in zip(reports, usable, strict=True)):
        if _one_moodle_submitter([reports[i].path for i in g]):
            continue          # one student's old and new versions (one grade is kept): not a copy
        # issue 31: namesakes (two "Иванов И.") are two students when their books are sealed
        # to different students or came in different Moodle folders: the name alone is no copy
        g = [i for i in g if any(j != i and not _namesakes(reports[i], reports[j])
                                 and not _one_moodle_submitter([reports[i].path, reports[j].path]) for j in g)]
        if len(g) > 1:
            out.append((message("same_student_name"), g))
    for g in _by_key((r.variant, r.issued_to) if ok and r.variant else ""
                     for r, ok in zip(reports, usable, strict=True)):
        rep = reports[g[0]]
        v, to = rep.variant, rep.issued_to
        hands = {who[i] for i in g if who[i]}
        if len(hands) > 1 and (to or (assigned is not None and assigned.get(v, 0) <= 1)):
            out.append((message("one_book_many_hands_to", v=v, to=to, n=len(hands)) if to else
                        message("one_book_many_hands", v=v, n=len(hands)), g))
        elif len(hands) > 1 and assigned is None:
            out.append((message("same_variant_unassigned", v=v, n=len(hands)), g))
        if any(reports[i].given_changed for i in g):
            out.append((message("same_variant_given_changed", v=v), g))
    return out


def _typed_pairs(reports, wrong) -> dict[tuple[int, int], int]:
    """{(i, j): shared typed numbers that are wrong in one book at least, or sit on given
    data that differ}; pairs counted within MAX_GROUP books per number (the others are
    counted against those): bounded by the class's size, not its square."""
    from .localjudge import typed_digits
    typed_at = defaultdict(list)
    for i, rep in enumerate(reports):
        marks = rep.marks
        if marks and not rep.error:
            for (name, k), v in marks["typed"].items():
                typed_at[name, k, v].append(i)
    shared: dict[tuple[int, int], int] = defaultdict(int)
    for (name, k, v), idx in typed_at.items():
        if len(idx) < 2 or (not any((name, k) in wrong[i] for i in idx)
                            and len({_given_of(reports[i], name) for i in idx[:MAX_GROUP]}) == 1):
            continue          # right in every book, on the same given data: a class on one variant
        # a one-digit number right in both books (0, 1, 0.5: sin 0, a dead-centre component)
        # is what any variant gives there, whatever given data it reads: no evidence
        short = typed_digits(v) < COPY_RIGHT_DIGITS
        for b, j in enumerate(idx[1:], 1):
            for i in idx[:min(b, MAX_GROUP)]:
                if (name, k) in wrong[i] or (name, k) in wrong[j] or (
                        not short and _given_differ(reports[i], reports[j], name)):
                    shared[i, j] += 1
    return shared


def _computed_sources(reports, wrong) -> dict[tuple[int, int], int]:
    """{(i, j): numbers typed in book i, wrong there, that equal (to the digits typed) what
    book j's formulas computed in the same cell}: i typed j's results."""
    import bisect

    from .localjudge import typed_digits, typed_tolerance
    computed = defaultdict(list)
    for j, rep in enumerate(reports):
        marks = rep.marks
        if marks and not rep.error:
            for cell, v in marks.get("values", {}).items():
                computed[cell].append((v, j))
    for lst in computed.values():
        lst.sort()
    found: dict[tuple[int, int], int] = defaultdict(int)
    for i, rep in enumerate(reports):
        marks = rep.marks
        if not marks or rep.error:
            continue
        for cell, v in marks["typed"].items():
            if cell not in wrong[i] or typed_digits(v) < 3 or cell not in computed:
                continue
            lst, tol = computed[cell], typed_tolerance(v)
            at = bisect.bisect_left(lst, (v - tol, -1))
            for c, j in lst[at:at + MAX_GROUP]:
                if c > v + tol:
                    break
                if j != i:
                    found[i, j] += 1
    return found


def _variant_sources(reports, wrong, variants: dict, linked: set[int],
                     sources: dict | None = None) -> list[tuple[str, list[int]]]:
    """Books whose typed numbers (wrong there) equal another variant's computed values (its
    key's): a classmate's results, or a key, typed in. variants: {variant id: (label, a
    function giving {(row, position): value}[, its key file, the students it was issued
    to])}, computed once each, only when needed; sources: {book: [(key file, students,
    why)]}, filled here (the source is no submission: Copies.sources)."""
    from .localjudge import typed_digits, typed_tolerance
    cache: dict = {}
    out = []
    for i, rep in enumerate(reports):
        marks = rep.marks
        if not marks or rep.error or i in linked:
            continue
        cells = {c: v for c, v in marks["typed"].items() if c in wrong[i] and typed_digits(v) >= 3}
        if len(cells) < COPY_TYPED_CELLS:
            continue
        for vid, (label, values, *key) in variants.items():
            if vid == rep.variant:
                continue
            if vid not in cache:
                try:
                    cache[vid] = values()
                except Exception:       # noqa: BLE001 - a variant that cannot be computed is no source
                    cache[vid] = {}
            got = cache[vid]
            n = sum(1 for c, v in cells.items() if c in got and abs(got[c] - v) <= typed_tolerance(v))
            if n >= COPY_TYPED_CELLS:
                why = message("typed_equal_variant", n=n, v=vid, what=label)
                out.append((why, [i]))
                if sources is not None:
                    sources.setdefault(i, []).append((*(key + ["", ""])[:2], why))
    return out


def roster_variants(roster, assignment=None) -> dict:
    """{variant id: (label, values)} for _variant_sources from the roster's scene files: the
    label names the variant's key file and the students it was issued to (assignment)."""
    from pathlib import Path
    folder = Path(roster.path).parent
    issued_to: dict[str, list[str]] = defaultdict(list)
    for name, vid, _ in (assignment.people.values() if assignment else ()):
        issued_to[vid].append(name)
    out = {}
    for vid, files in roster.files.items():
        scene_file = folder / files.get("scene", "")
        if not files.get("scene") or not scene_file.is_file():
            continue
        who = f", issued to {', '.join(issued_to[vid])}" if issued_to.get(vid) else ""
        key = str(folder / files.get("key", ""))
        out[vid] = (f"key {key}{who}", lambda p=scene_file: computed_values(p), key,
                    ", ".join(issued_to.get(vid, [])))
    return out


def computed_values(scene_file) -> dict:
    """{(row name, position): value} of the computed rows of a scene's reference sheet."""
    from sheetkin.kinematics.scene import load_scene
    from sheetkin.sheet.workbook import FIRST_COL

    from .caches import scene_rows

    scene = load_scene(scene_file)      # issue 30: read under the scene cap (8 MB), never whole
    book = reference_book(scene)
    sheet = book.order[0]
    rows = {book.sheets[sheet].consts.get((r, 1)): r for r in range(5, book.sheets[sheet].max_row + 1)}
    out = {}
    for row in scene_rows(scene):
        if row.kind in ("calc", "accepted", "guard") and row.name in rows:
            for k in range(scene.crank.positions):
                v = book.value(sheet, rows[row.name], FIRST_COL + k)
                if isinstance(v, float) and v == v:
                    out[(row.name, k + 1)] = v
    return out


def _label(reports, i: int) -> str:
    name = str(reports[i].student or "")
    return f"{reports[i].path}{f' ({name})' if name else ''}"


def possible_copies(reports, digests: list | None = None, who: list | None = None,
                    assigned: dict | None = None, variants: dict | None = None) -> Copies:
    """The clusters of submissions that look copied (the module's rules). digests:
    file_digest of each report's file (computed here when not given); who: each report's
    submitter (a Moodle identifier, or ""), for the identity rules; assigned: {variant:
    students it was issued to} from an assignment (None: no assignment); variants: the
    issued variants' computed values (roster_variants), for typed numbers taken from a
    variant no submission computed (a key, an absent classmate)."""
    if digests is None:
        digests = [None if r.error else file_digest(r.path) for r in reports]
    who = list(who) if who is not None else [_name_of(r) for r in reports]
    groups: list[tuple[str, list[int]]] = [(message("byte_identical_files"), g) for g in _by_key(digests)]
    wrong = [_wrong_cells(r) if r.marks else set() for r in reports]
    pairs = _typed_pairs(reports, wrong)
    links = defaultdict(list)
    for (i, j), n in pairs.items():
        if n >= COPY_TYPED_CELLS:
            links[i].append((j, n))
    for i, found in sorted(links.items()):          # one group per book: linear in the class
        most = max(n for _, n in found)
        groups.append((message("identical_typed_wrong", n=most), [i, *(j for j, _ in found)]))
    linked = set()
    for (i, j), n in sorted(_computed_sources(reports, wrong).items()):
        if n >= COPY_TYPED_CELLS:
            groups.append((message("typed_equal_computed", n=n, who=_label(reports, j)), [i, j]))
            linked.add(i)
    sources: dict[int, list[tuple[str, str, str]]] = {}
    if variants:
        groups += _variant_sources(reports, wrong, variants, linked, sources)
    groups += _identity_groups(reports, who, assigned)
    formula_at = defaultdict(list)
    for i, rep in enumerate(reports):
        marks = rep.marks
        if marks and not rep.error:
            bad = _wrong_rows(rep)
            for name, digest in marks["formulas"].items():
                if name in bad:
                    formula_at[name, digest].append(i)
    for (name, _), idx in sorted(formula_at.items()):
        if len(idx) > 1:
            groups.append((message("same_wrong_formula", name=name), idx))
    copies = _clusters(groups)
    copies.sources = sources
    return copies


def _clusters(groups: list[tuple[str, list[int]]]) -> Copies:
    union = _Union()
    for _, members in groups:
        union.join(members)
    by_root: dict[int, Cluster] = {}
    for text, members in groups:
        c = by_root.setdefault(union.find(members[0]), Cluster([]))
        c.links.append((text, members))
        merged = next((m for t, m in c.reasons if t == text), None)
        if merged is None:
            c.reasons.append((text, sorted(set(members))))
        else:
            merged[:] = sorted(set(merged) | set(members))
    for i in sorted(union.parent):
        by_root[union.find(i)].members.append(i)
    return Copies(sorted(by_root.values(), key=lambda c: c.members[0]))


def pairs_of(copies: Copies) -> dict[tuple[int, int], str]:
    """{(i, j): why} for i < j named together by a reason (tests and small classes only:
    quadratic). Two books in one cluster only through a third are not a pair."""
    out = {}
    for c in copies.clusters:
        for a, i in enumerate(c.members):
            for j in c.members[a + 1:]:
                why = [t for t, m in c.links if i in m and j in m]
                if why:
                    out[i, j] = "; ".join(dict.fromkeys(why))
    return out
