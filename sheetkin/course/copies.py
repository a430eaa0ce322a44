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
   given data changed in one: a book taken from its owner, the copier's data typed in.
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
from functools import lru_cache

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
    """What copy detection needs from a student's sheet (an xlsxread.Sheet): `typed`:
    {(row name, position 1..n): number} of the numbers typed in computed rows; `formulas`:
    {row name: digest of the row's relative formulas} of the rows whose formulas are not
    the lecture's (the reference sheet's, at ref_rows): the lecture's formulas are
    everybody's; `inputs`: the given data as typed, and `depends`: {row name with a typed
    number: the given data it depends on} (from `ancestors`, the validator's)."""
    typed, formulas = {}, {}
    for name, r in rows.items():
        for k in range(positions):
            v = sheet.consts.get((r, first_col + k))
            if isinstance(v, (int, float)) and not isinstance(v, bool) and (r, first_col + k) not in sheet.formulas:
                typed[(name, k + 1)] = float(v)
        if reference is not None and name in (ref_rows or {}) and _as_lecture(sheet, r, reference, ref_rows[name],
                                                                           first_col, positions):
            continue                                # the lecture's texts in the lecture's cells: nothing to hash
        texts = _row_formulas(sheet, r, first_col, positions)
        if not any(texts):
            continue
        if reference is not None and name in (ref_rows or {}):
            lecture = _row_formulas(reference, ref_rows[name], first_col, positions)
            if all(t is None or t == l for t, l in zip(texts, lecture, strict=False)):
                continue
        formulas[name] = hashlib.sha256("\n".join(t or "" for t in texts).encode()).hexdigest()[:16]
    inputs = {n: v for n, v in (inputs or {}).items() if isinstance(v, (int, float, str)) and not isinstance(v, bool)}
    depends = {n: sorted((ancestors or {}).get(n, set()) & inputs.keys()) for n in {n for n, _ in typed}}
    return {"typed": typed, "formulas": formulas, "inputs": inputs, "depends": depends}


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
    return {r.name for r in rep.rows if r.status == "wrong" or getattr(r, "local", "") == "wrong"}


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


def _same_identity(reports, why) -> None:
    """The same name typed in the student's cell of two files (a copy whose name was left,
    or one student handing in twice); the same issued book (variant id) handed in twice,
    its given data retyped in one (a book taken from its owner, the copier's data typed)."""
    by_name, by_variant = defaultdict(list), defaultdict(list)
    for i, rep in enumerate(reports):
        if rep.error:
            continue
        name = " ".join(str(getattr(rep, "student", "") or "").casefold().split())
        if name:
            by_name[name].append(i)
        if getattr(rep, "variant", ""):
            by_variant[rep.variant].append(i)
    for idx in by_name.values():
        for a in range(len(idx)):
            for j in idx[a + 1:]:
                why[idx[a], j].append("the same student name")
    for variant, idx in by_variant.items():
        for a in range(len(idx)):
            for j in idx[a + 1:]:
                if getattr(reports[idx[a]], "given_changed", None) or getattr(reports[j], "given_changed", None):
                    why[idx[a], j].append(f"the same issued variant {variant}, its given data changed in one")


def possible_copies(reports, digests: list | None = None) -> dict[int, list[tuple[int, str]]]:
    """{index of a report: [(index of the other report, why), ...]} for every pair that
    looks copied (the module's rules), both ways. digests: file_digest of each report's
    file (computed here when not given)."""
    if digests is None:
        digests = [None if r.error else file_digest(r.path) for r in reports]
    why: dict[tuple[int, int], list[str]] = defaultdict(list)
    by_digest = defaultdict(list)
    for i, d in enumerate(digests):
        if d:
            by_digest[d].append(i)
    for same in by_digest.values():
        for a in range(len(same)):
            for b in same[a + 1:]:
                why[same[a], b].append("byte-identical files")
    # the same typed number at the same cell: index by (row, position, value)
    typed_at = defaultdict(list)
    formula_at = defaultdict(list)
    wrong = []
    for i, rep in enumerate(reports):
        marks = getattr(rep, "marks", None)
        wrong.append(_wrong_cells(rep) if marks else set())
        if not marks or rep.error:
            continue
        for (name, k), v in marks["typed"].items():
            typed_at[name, k, v].append(i)
        bad = _wrong_rows(rep)
        for name, digest in marks["formulas"].items():
            if name in bad:
                formula_at[name, digest].append(i)
    shared_typed = defaultdict(int)
    for (name, k, _), idx in typed_at.items():
        if len(idx) < 2 or (not any((name, k) in wrong[i] for i in idx)
                            and len({_given_of(reports[i], name) for i in idx}) == 1):
            continue          # right in every book, on the same given data: a class on one variant
        for a in range(len(idx)):
            for j in idx[a + 1:]:
                i = idx[a]
                if (name, k) in wrong[i] or (name, k) in wrong[j] or _given_differ(reports[i], reports[j], name):
                    shared_typed[i, j] += 1
    for (i, j), n in shared_typed.items():
        if n >= COPY_TYPED_CELLS:
            why[i, j].append(f"{n} identical typed numbers, wrong for one variant at least")
    _same_identity(reports, why)
    shared_formulas = defaultdict(list)
    for (name, _), idx in formula_at.items():
        for a in range(len(idx)):
            for b in idx[a + 1:]:
                shared_formulas[idx[a], b].append(name)
    for (i, j), names in shared_formulas.items():
        why[i, j].append(f"the same wrong formula in {', '.join(sorted(names))}")
    out: dict[int, list[tuple[int, str]]] = defaultdict(list)
    for (i, j), reasons in sorted(why.items()):
        text = "; ".join(reasons)
        out[i].append((j, text))
        out[j].append((i, text))
    return dict(out)
