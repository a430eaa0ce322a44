"""Who handed in each book, under which Moodle identifier it is graded, and what does not fit.

Three sources name a book's student (docs/teacher-guide.md, "Running a class"):
  * the Moodle folder (or flat file name) it came in: who handed it in;
  * the name typed in the book's student cell;
  * the identity sealed in it by `variants --class-list` (scene!C3, under the seal): whom
    it was issued to.
The grade goes to who handed it in: the folder's student, else the typed name's, else the
sealed one's; each name is matched with the class list (sheetkin/course/classlist.py). A
book issued to one student and handed in by another, or found in one student's folder with
another student's name typed in it, is flagged. One grade per Moodle user: of several
books of one student the newest file (its modification time, as Moodle's zip keeps it) is
graded and the others are listed, not graded.
"""
from __future__ import annotations

import csv
import io
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from sheetkin.messages import message
from sheetkin.untrusted import csv_cell, from_csv_cell

from .classlist import (
    ClassList,
    ClassListError,
    Person,
    decode_table,
    delimiter,
    moodle_submitter,
    name_key,
    read_bounded,
)

ASSIGNMENT_FILE = "assignment.csv"       # written by `variants --class-list` beside roster.csv
ASSIGNMENT_COLUMNS = ("student", "identifier", "variant", "exercise")
MAX_ASSIGNMENT_BYTES = 5_000_000


@dataclass
class Identity:
    ident: str = ""                  # the Moodle identifier the book is graded under ("": none)
    who: str = ""                    # a key for "the same submitter" (identifier, participant, or name)
    submitter: str = ""              # who handed it in, as the teacher reads it
    flags: list[str] = field(default_factory=list)
    unmatched: str = ""              # why the class list names no one (or several)
    superseded_by: int | None = None   # an older book of the same student: not graded
    participant: str = ""            # Moodle's participant number from the folder ("": not from Moodle)
    by_text: bool = False            # blind marking: the identifier came from a name typed in the book
    folder_name: str = ""            # the Moodle folder's full name ("": blind marking, or no folder)

    @property
    def moodle_user(self) -> str:
        """One grade per this key: Moodle's participant (one user per folder number), else
        whose grade it is."""
        return f"participant {self.participant}" if self.participant else self.student_key

    @property
    def student_key(self) -> str:
        """Whose grade this is: the identifier, else (blind marking, no class list) the
        Moodle participant; "" when nothing says."""
        return self.ident or (f"participant {self.participant}" if self.participant else "")


@dataclass
class Assignment:
    path: str
    id_header: str
    people: dict[str, tuple[str, str, str]]     # identifier -> (name, variant, exercise)

    def assigned(self) -> dict[str, int]:
        """{variant: how many students it was issued to}."""
        out: dict[str, int] = {}
        for _, v, _ in self.people.values():
            out[v] = out.get(v, 0) + 1
        return out

    def as_class_list(self) -> ClassList:
        """The students of the assignment as a class list (when --class-list is not given)."""
        from .classlist import NAME_WORD, fold_name, name_key
        cl = ClassList(self.id_header, {}, set(), [], self.path)
        for ident, (name, _, _) in self.people.items():
            words = [w.rstrip(".") for w in NAME_WORD.findall(fold_name(name))]
            cl.people.append(Person(name, ident, words[0] if words else "", tuple(words[1:])))
            cl.ids[name_key(name)] = ident
        return cl


def assignment_text(id_header: str, rows: list[tuple[str, str, str, str]]) -> str:
    """assignment.csv: student, identifier, variant, exercise; the identifier column's own
    name (Moodle's: Email address, ID number, Username) in its header, "identifier (Email
    address)" (issue 34: no comment line a spreadsheet shows as a stray row)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([ASSIGNMENT_COLUMNS[0], f"{ASSIGNMENT_COLUMNS[1]} ({csv_cell(id_header)})", *ASSIGNMENT_COLUMNS[2:]])
    # every cell came from the class list, which a student can edit (an e-mail "=cmd|..."
    # in a Moodle profile): neutralized, read back by from_csv_cell
    w.writerows([csv_cell(c) for c in row] for row in rows)
    return buf.getvalue()


def read_assignment(path) -> Assignment:
    """assignment.csv as `variants --class-list` writes it; one-line errors naming file:line."""
    p = str(path)
    text = decode_table(read_bounded(p, MAX_ASSIGNMENT_BYTES, "assignment"), p, "assignment")
    rows = list(csv.reader(io.StringIO(text, newline=""), delimiter=delimiter(text.split("\n", 1)[0])))
    head = [h.strip() for h in rows[0][:4]] if rows else []
    named = re.fullmatch(r"identifier(?: \((?P<name>.+)\))?", head[1]) if len(head) == 4 else None
    if named is None or (head[0], head[2], head[3]) != (ASSIGNMENT_COLUMNS[0], *ASSIGNMENT_COLUMNS[2:]):
        raise ClassListError(f"{p}:1: expected the header {','.join(ASSIGNMENT_COLUMNS)} (as `sheetkin variants "
                             "--class-list` writes it)")
    id_header, people = from_csv_cell(named.group("name") or "Email address"), {}
    for line, row in enumerate(rows[1:], 2):
        if row and row[0].startswith("# "):      # the identifier's name as files before issue 34 wrote it
            id_header = row[0][2:].strip() or id_header
            continue
        if not any(c.strip() for c in row):
            continue
        if len(row) < 4 or not row[1].strip() or not row[2].strip():
            raise ClassListError(f"{p}:{line}: expected a student, their identifier, a variant and an exercise")
        name, ident, variant, exercise = (from_csv_cell(c.strip()) for c in row[:4])
        people[ident] = (name, variant, exercise)
    return Assignment(p, id_header, people)


def _one(people: list[Person]) -> Person | None:
    return people[0] if len({p.ident for p in people}) == 1 else None


def _describe(text: str, people: list[Person], folder: str | None = None) -> str:
    """No one in the class list has the name, or who it can be; of a Moodle folder's name, the
    folder named first."""
    if not people:
        return (message("no_one_class_list", n=repr(text)) if folder is None else
                message("folder_no_one_class", f=repr(folder), n=repr(text)))
    who = ", ".join(f"{p.name} ({p.ident})" for p in people[:5])
    return (message("can_be", n=repr(text), who=who) if folder is None else
            message("folder_can_be", f=repr(folder), n=repr(text), who=who))


def identify(reports, class_list: ClassList | None = None, assignment: Assignment | None = None,
             mtimes: list[float] | None = None) -> list[Identity]:
    """Each report's Identity (the module's rules), in the reports' order. mtimes: each
    file's modification time (default: read from report.path)."""
    if class_list is None and assignment is not None:
        class_list = assignment.as_class_list()
    out = []
    for rep in reports:
        out.append(_identify_one(rep, class_list, assignment))
    _newest_only(reports, out, mtimes or [file_mtime(r.path) for r in reports])
    _one_line_per_identifier(reports, out)
    from sheetkin.files import shown  # the class list's names are students' too (a Moodle profile)
    for me in out:
        me.flags = [shown(f) for f in me.flags]
        me.submitter, me.unmatched = shown(me.submitter), shown(me.unmatched)
    return out


def _identify_one(rep, cl: ClassList | None, assignment: Assignment | None) -> Identity:
    me = Identity()
    typed = " ".join(str(rep.student or "").split())
    sealed = str(rep.issued_to or "")
    sub = moodle_submitter(rep.path)
    if sub is not None:
        me.participant = sub.participant
        if blind_marking(sub.name):
            # blind marking: the folder says "Participant" only; the number is the student's
            # identity in Moodle (its worksheet's Identifier), the name typed or sealed in
            # the book finds the class list's line
            return _identify_blind(me, rep, cl, assignment, sub.participant)
    sealed_name = ""
    if sealed:
        person = cl.by_ident(sealed) if cl else None
        sealed_name = person.name if person else (assignment.people.get(sealed, ("",))[0] if assignment else "")
    folder = typed_person = None
    if cl is not None:
        folder = _one(cl.match(sub.name)) if sub else None
        typed_person = _one(cl.match(typed)) if typed else None
    if sub is not None:
        me.submitter = f"{sub.name} " + message("moodle_participant", n=sub.participant)
        me.folder_name = sub.name
        me.who = folder.ident if folder else f"participant {sub.participant}"
        me.ident = folder.ident if folder else ""
        if cl is not None and folder is None:
            me.unmatched = _describe(sub.name, cl.match(sub.name), sub.where)
        if folder and typed and typed_person is not None and typed_person.ident != folder.ident:
            me.flags.append(message("found_folder_but_name", a=folder.name, b=typed_person.name))
        elif typed and typed_person is None and not same_name_loosely(typed, sub.name):
            # no class list (the README's path), or a typed name it does not hold: the
            # folder's name and the typed one share no word (issue 30)
            me.flags.append(message("found_folder_typed_other", a=sub.name, b=repr(typed)))
    elif typed:
        if typed_person is None and sealed and cl is not None:
            # a name two namesakes share ("Иванов И."): the book's seal says which of them
            mine = cl.by_ident(sealed)
            typed_person = mine if mine and any(p.ident == sealed for p in cl.match(typed)) else None
        me.submitter = typed
        me.who = typed_person.ident if typed_person else " ".join(sorted(name_key(typed)))
        me.ident = typed_person.ident if typed_person else ""
        if cl is not None and typed_person is None:
            me.unmatched = _describe(typed, cl.match(typed))
    elif sealed:
        me.submitter, me.who = sealed_name or sealed, sealed
        me.ident = sealed if cl is None or cl.by_ident(sealed) else ""
    if sealed and me.ident and sealed != me.ident:
        me.flags.append(message("issued_handed", a=f"{sealed_name or sealed} ({sealed})", b=me.submitter))
    elif (sealed and not me.ident and sub is not None and sealed_name and sub.name
          and name_key(sealed_name) != name_key(sub.name)):
            me.flags.append(message("issued_handed", a=f"{sealed_name} ({sealed})", b=me.submitter))
    return me


# Moodle's "Participant" (its string hiddenuser) in the site languages the course meets
BLIND_NAMES = ("participant", "участник", "учасник")


def blind_marking(folder_name: str) -> bool:
    """Whether a Moodle folder's full name is blind marking's "Participant"."""
    return folder_name.strip().casefold() in BLIND_NAMES


def _identify_blind(me: Identity, rep, cl: ClassList | None, assignment: Assignment | None,
                    participant: str) -> Identity:
    """A blind-marked submission: graded under the typed (else sealed) name's identifier;
    its submitter is "Participant N", whom no name can contradict."""
    plain = _identify_one(_without_folder(rep), cl, assignment)
    plain.participant = participant
    plain.submitter = f"Participant {participant}"
    # the Moodle user is the participant: a name typed in the book finds the class list's
    # line, but never merges this participant's books with another user's (issue 30)
    plain.who = f"participant {participant}"
    plain.by_text = bool(plain.ident)
    return plain


def _without_folder(rep):
    """The report as if handed in outside Moodle's folders (no path names a submitter)."""
    import copy
    flat = copy.copy(rep)
    flat.path = ""
    return flat


# Latin letters for Cyrillic ones (a Moodle profile may be in Latin, the typed name in Cyrillic)
_LATIN = dict(zip("абвгдеёжзийклмнопрстуфхцчшщъыьэюяіїєґ",
                  ["a", "b", "v", "g", "d", "e", "e", "zh", "z", "i", "i", "k", "l", "m", "n", "o", "p", "r", "s",
                   "t", "u", "f", "kh", "ts", "ch", "sh", "shch", "", "y", "", "e", "yu", "ya", "i", "yi", "ye", "g"],
                  strict=True))


def _skeleton(word: str) -> str:
    """A word's consonants in Latin letters, for comparing names across alphabets and
    transliterations ("Щукин", "Shchukin", "Schukin": "sckn")."""
    latin = "".join(_LATIN.get(c, c) for c in word)
    return "".join(c for c in latin if c not in "aeiouyhjw'-.")


def same_name_loosely(typed: str, folder_name: str) -> bool:
    """Whether a typed name can be the folder's student's, without a class list: some word
    of at least two letters is one of the folder name's words, in any alphabet or
    transliteration. True when it cannot tell (blind marking's "Participant", no words)."""
    from .classlist import NAME_WORD, fold_name
    typed_words = [w.rstrip(".") for w in NAME_WORD.findall(fold_name(typed)) if len(w.rstrip(".")) >= 2]
    folder_words = [w.rstrip(".") for w in NAME_WORD.findall(fold_name(folder_name)) if len(w.rstrip(".")) >= 2]
    if not typed_words or not folder_words or folder_words in (["participant"], ["участник"]):
        return True
    theirs = {_skeleton(w) for w in folder_words} - {""}
    for w in typed_words:
        mine = _skeleton(w)
        if mine and any(mine == t or (min(len(mine), len(t)) >= 3 and (mine.startswith(t) or t.startswith(mine)))
                        for t in theirs):
            return True
    return False


def file_mtime(path: str) -> float:
    try:
        return os.stat(path).st_mtime
    except (OSError, ValueError):           # a name with a NUL character
        return 0.0


def _newest_only(reports, ids: list[Identity], mtimes: list[float]) -> None:
    """One grade per Moodle user: the newest of a student's files is graded, the others
    point at it (superseded_by) and are listed."""
    by_ident: dict[str, list[int]] = {}
    for i, me in enumerate(ids):
        if me.moodle_user:
            by_ident.setdefault(me.moodle_user, []).append(i)
    for ident, idx in by_ident.items():
        if len(idx) < 2:
            continue
        # the student's own books first: a classmate's book found in the folder (flagged
        # above) is newer there by its upload, yet it is never this student's grade; then
        # the usable ones: a corrupt or locked re-upload must not replace a readable book
        foreign = {i for i in idx if ids[i].flags}
        newest = max(idx, key=lambda i: (i not in foreign, not reports[i].error, mtimes[i], i))
        for i in idx:
            if i != newest:
                ids[i].superseded_by = newest
                why = ("not_graded_newer" if mtimes[i] <= mtimes[newest] else
                       "not_graded_own_book" if i in foreign else "not_graded_usable")
                whom = ids[newest].student_key or ident          # the identifier a teacher knows
                ids[i].flags.append(message(why, who=whom, file=reports[newest].path))
        older = "graded_older_files" if all(mtimes[i] <= mtimes[newest] for i in idx) else "graded_other_files"
        ids[newest].flags.append(message(older, files=", ".join(reports[i].path for i in idx if i != newest)[:300]))


def _one_line_per_identifier(reports, ids: list[Identity]) -> None:
    """Two Moodle users' graded books under one identifier: a name typed in a blind-marked
    book never takes over the grade of the student whose own folder names them (issue 30);
    when no single folder settles it, none of them is graded under the identifier (the
    teacher decides, each book keeps its own line)."""
    claims: dict[str, list[int]] = {}
    for i, me in enumerate(ids):
        if me.ident and me.superseded_by is None:
            claims.setdefault(me.ident, []).append(i)
    for ident, idx in claims.items():
        if len({ids[i].moodle_user for i in idx}) < 2:
            continue
        by_folder = [i for i in idx if ids[i].participant and not ids[i].by_text]
        keep = by_folder[0] if len(by_folder) == 1 else None
        for i in idx:
            if i == keep:
                continue
            others = ", ".join(reports[j].path for j in idx if j != i)[:300]
            ids[i].unmatched = message("claimed_twice", ident=ident, a=ids[i].submitter or "this book", b=others)
            ids[i].flags.append(ids[i].unmatched)
            ids[i].ident = ""


def find_assignment(roster_path: str | None) -> Assignment | None:
    """assignment.csv beside --roster, when `variants --class-list` wrote one."""
    if not roster_path:
        return None
    p = Path(roster_path).parent / ASSIGNMENT_FILE
    return read_assignment(p) if p.is_file() else None
