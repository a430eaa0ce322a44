"""The class list (Moodle's participants or grades export) and who a name is in it.

A student types their name as people in Russia write it: "Иванов И.", "Иванов И.И.",
"Петрова Анна Сергеевна" (with the patronymic the list does not hold), "СИДОРОВ П.",
"Пётр Сидоров" (any order, case, ё for е). `ClassList.match(text)` finds the people whose
name it can be (docs/teacher-guide.md, "Running a class"):
  * the surname is one of the typed words;
  * every other typed word is one of the person's given names (first name, patronymic
    when the list has it), or looks like a patronymic (-вич, -вна, -ична, -ич, -оглы,
    -кызы) when the list has none;
  * each typed initial ("И.", "И.С.") is the first letter of the person's given names, in
    order (first name, then patronymic);
  * a lone surname matches every person of that surname.
Exactly one person: matched; none or several: listed for the teacher (`validate` says so).

A Moodle download's folder ("Иван Иванов_12345_assignsubmission_file_") gives the name
Moodle shows and the participant number (moodle_submitter).
"""
from __future__ import annotations

import contextlib
import csv
import io
import re
from dataclasses import dataclass, field
from pathlib import Path

from sheetkin.errors import InputError
from sheetkin.messages import message
from sheetkin.untrusted import plain_text

MAX_CLASS_LIST_BYTES = 5_000_000       # a year's class is a few hundred KB
ID_HEADERS = ("Email address", "ID number", "Username")      # Moodle's export names them so
_NAME_HEADERS = {"first": ("first name", "имя"), "last": ("last name", "surname", "фамилия"),
                 "full": ("full name", "student", "фио", "студент", "полное имя")}
_ID_ALIASES = {"Email address": ("email address", "email", "e-mail", "адрес электронной почты",
                                 "электронная почта"),
               "ID number": ("id number", "idnumber", "индивидуальный номер", "идентификационный номер"),
               "Username": ("username", "логин", "имя пользователя")}
_PATRONYMIC = re.compile(r"(вич|вна|ична|инична|ич|оглы|кызы)$")
NAME_WORD = re.compile(r"[^\W\d_]+(?:[-'][^\W\d_]+)*\.?")


class ClassListError(InputError):
    """--class-list cannot be used: one line naming the file and line."""


def fold_name(text: str) -> str:
    # without the invisible characters a student can hide in a name ("Ива\u200bнов"), and in
    # NFKC ("Ｉｖａｎｏｖ" is "Ivanov"): look-alike names compare equal (issue 30)
    return plain_text(text).casefold().replace("ё", "е")


def name_key(text: str) -> frozenset:
    """A name in any word order, case, with or without commas, ё as е: 'Иванов, Иван' ==
    'иван иванов'."""
    return frozenset(w.rstrip(".") for w in NAME_WORD.findall(fold_name(text)))


def _tokens(text: str) -> list[str]:
    """A typed name's words and initials in order: "Иванов И.С." -> ["иванов", "и.", "с."]."""
    out = []
    for tok in NAME_WORD.findall(fold_name(text).replace(".", ". ")):
        bare = tok.rstrip(".")
        out.append(bare[0] + "." if len(bare) == 1 or (tok.endswith(".") and len(bare) <= 2) else bare)
    return out


@dataclass(frozen=True)
class Person:
    name: str                      # as the list writes it: "Иванов Иван"
    ident: str                     # the identifier column's value
    surname: str                   # folded
    given: tuple[str, ...]         # folded: first name, then patronymic if the list has it
    line: int = 0

    def fits(self, tokens: list[str]) -> bool:
        """Whether the typed tokens (_tokens) can name this person (the module's rules)."""
        surnames = set(self.surname.split())
        if not any(t in surnames for t in tokens):
            return False
        rest = [t for t in tokens if t not in surnames]
        for k, tok in enumerate(rest):
            initial = tok.endswith(".")
            if k < len(self.given):
                if not (self.given[k].startswith(tok[0]) if initial else self.given[k] == tok):
                    return False
            elif k != 1 or not (initial or _PATRONYMIC.search(tok)):
                return False         # a patronymic the list does not hold, nothing more
        return True


@dataclass
class ClassList:
    id_header: str                       # Moodle's name of the identifier column
    ids: dict                            # name key -> identifier (the whole name, any order)
    ambiguous: set                       # name keys of two people or more
    people: list[Person] = field(default_factory=list)
    path: str = ""

    def match(self, text: str) -> list[Person]:
        """Everyone `text` can name (the module's rules): one person, or none, or several."""
        text = str(text or "").strip()
        if not text:
            return []
        by_key, by_surname, _ = self._index()
        exact = by_key.get(name_key(text))
        if exact:
            return [p for _, p in exact]
        tokens = _tokens(text)
        # only a person one of whose surname words is typed can fit (Person.fits)
        found = {k: p for t in set(tokens) for k, p in by_surname.get(t, ())}
        return [found[k] for k in sorted(found) if found[k].fits(tokens)]

    def _index(self) -> tuple[dict, dict, dict]:
        """The people (with their places in the list) by whole-name key, by surname word and
        by identifier, made once per list: comparing every book's name with every line took
        94 s for 800 books and a 100,000-line list. Remade when people were added since."""
        cached = self.__dict__.get("_indexed")
        if cached is not None and cached[0] == len(self.people):
            return cached[1]
        by_key: dict[frozenset, list] = {}
        by_surname: dict[str, list] = {}
        by_ident: dict[str, Person] = {}
        for k, p in enumerate(self.people):
            by_key.setdefault(name_key(p.name), []).append((k, p))
            for w in set(p.surname.split()):
                by_surname.setdefault(w, []).append((k, p))
            by_ident.setdefault(p.ident, p)
        self.__dict__["_indexed"] = (len(self.people), (by_key, by_surname, by_ident))
        return by_key, by_surname, by_ident

    def ident_of(self, text: str) -> str:
        """The identifier of the one person `text` names; "" for none or several."""
        found = {p.ident for p in self.match(text)}
        return found.pop() if len(found) == 1 else ""

    def by_ident(self, ident: str) -> Person | None:
        return self._index()[2].get(ident)


def decode_table(raw: bytes, path: str, what: str) -> str:
    """A CSV file's text: UTF-8 (with or without a byte-order mark), else Windows-1251 (what
    a Russian Excel saves as "CSV (разделители - запятые)")."""
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        pass
    if b"\0" in raw or raw.startswith(b"PK\x03\x04"):
        raise ClassListError(message("binary_not_csv", f=path, opt=what)) from None
    try:
        return raw.decode("cp1251")
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        raise ClassListError(message("not_utf8_csv", f=path, line=line, opt=what) + "save it as CSV UTF-8") from None


def delimiter(header_line: str) -> str:
    """The separator a header line uses: ",", ";" (a Russian Excel) or a tab."""
    return max((",", ";", "\t"), key=header_line.count)


def read_bounded(path: str, limit: int, what: str) -> bytes:
    """At most `limit` bytes of a regular file: a FIFO or device is refused before reading,
    a larger file refused as it is read (never read whole first)."""
    import errno

    from sheetkin.files import RefusedFile, read_bytes
    # the capped reader every input goes through (reliability): it names what the path is
    # ("a character device, not a regular file") and never blocks on a FIFO
    try:
        return read_bytes(path, limit, what.lstrip("-").replace("-", " "))
    except FileNotFoundError:
        raise ClassListError(message("no_such_csv", f=path, opt=what)) from None
    except RefusedFile as e:
        if e.errno == errno.EFBIG:
            raise ClassListError(f"{path}: {what}: more than {limit:,} bytes; a class list is a few KB") from None
        raise ClassListError(f"{path}: {what}: {e.strerror}") from None
    except OSError as e:
        raise ClassListError(f"{path}: {what}: cannot read it ({e.strerror or e})") from None


_BLANK = " \t\r\n\u00a0\u200b;,"      # what a line of no student may hold


def read_class_list(path: str) -> ClassList:
    """The teacher's list of students: a CSV file with a header, its name columns ("First
    name" and "Last name"/"Surname", or "Full name") and an identifier column ("Email
    address", "ID number" or "Username"), as Moodle exports them; comma, semicolon or tab;
    UTF-8 or Windows-1251."""
    text = decode_table(read_bounded(path, MAX_CLASS_LIST_BYTES, "--class-list"), path, "--class-list")
    # a stray byte-order mark (a second one, or one inside after files were joined) is no
    # text of any name (issue 31): dropped wherever it is
    text = text.replace("\ufeff", "")
    delim = delimiter(text.split("\n", 1)[0])
    try:
        rows = list(csv.reader(io.StringIO(text, newline=""), delimiter=delim))
    except csv.Error as e:
        raise ClassListError(f"{path}: --class-list: not a CSV file this reads ({e})") from None
    if not rows:
        raise ClassListError(message("class_list_empty", f=path))
    head = [h.strip().casefold() for h in rows[0]]

    def column(aliases):
        return next((k for k, h in enumerate(head) if h in aliases), None)
    id_header, id_col = next(((h, column(a)) for h, a in _ID_ALIASES.items() if column(a) is not None), (None, None))
    first_col, last_col, full_col = (column(_NAME_HEADERS[k]) for k in ("first", "last", "full"))
    if id_col is None or (full_col is None and (first_col is None or last_col is None)):
        raise ClassListError(message("class_list_columns", f=path, ids=", ".join(repr(h) for h in ID_HEADERS),
                                     got=", ".join(repr(h) for h in rows[0]))[:600])
    out = ClassList(id_header or ID_HEADERS[0], {}, set(), [], path)
    for line, row in enumerate(rows[1:], 2):
        if not any(c.strip(_BLANK) for c in row):
            continue      # a blank-looking line: spaces, a lone ';' or ',' (another delimiter's empty line)

        def cell(k, row=row):
            return " ".join(row[k].split()) if k is not None and k < len(row) else ""
        ident = cell(id_col)
        if full_col is not None:
            name = cell(full_col)
            words = [w.rstrip(".") for w in NAME_WORD.findall(fold_name(name))]
            surname, given = (words[0], tuple(words[1:])) if words else ("", ())
        else:
            name = f"{cell(last_col)} {cell(first_col)}".strip()
            surname = " ".join(w.rstrip(".") for w in NAME_WORD.findall(fold_name(cell(last_col))))
            given = tuple(w.rstrip(".") for w in NAME_WORD.findall(fold_name(cell(first_col))))
        key = name_key(name)
        if not key or not ident:
            raise ClassListError(message("class_list_line_without", f=path, line=line, id=id_header))
        if key in out.ids and out.ids[key] != ident:
            out.ambiguous.add(key)
        out.ids[key] = ident
        out.people.append(Person(name, ident, surname, given, line))
    return out


# --------------------------------------------------------------------------- Moodle's download
# A folder's participant number is read from its last fields only: the full name before it
# is the student's own (editable in many profiles), and a name "Петров_102_assignsubmission_file_x"
# must not make the folder Петров's (issue 30). A flat file's name ends with the student's
# file name, so there the number follows the first "_": Moodle writes the full name with
# its underscores replaced by spaces; a flat name that holds the pattern twice names no one.
_MOODLE_FOLDER = re.compile(r"^(?P<name>.*)_(?P<pid>\d+)_assign(?:submission|feedback)_[a-z]+_$", re.S)
_MOODLE_FLAT = re.compile(r"^(?P<name>[^_]*)_(?P<pid>\d+)_assign(?:submission|feedback)_[a-z]+_(?P<rest>.*)$", re.S)


@dataclass(frozen=True)
class Submitter:
    name: str            # the full name Moodle shows ("Participant" under blind marking)
    participant: str     # the assignment's participant number
    where: str           # the folder (or flat file) name it came from


def moodle_submitter(path: str | Path, root: str | Path | None = None) -> Submitter | None:
    """Who handed in `path`, from Moodle's "download all submissions" names: a folder
    `{full name}_{participant id}_assignsubmission_file_` above it (below `root`), or a
    flat file `{full name}_{participant id}_assignsubmission_file_{original name}`."""
    p = Path(path)
    parts = list(p.parts)
    if root is not None:
        with contextlib.suppress(ValueError):
            parts = list(p.relative_to(root).parts)
    # the outermost name is Moodle's; a file inside is named by the student, who could name
    # it after a classmate's folder ("Иван Иванов_5501_assignsubmission_file_lab.xlsx")
    for k, part in enumerate(parts):
        # a flat name's first `_id_assign..._` is Moodle's (it writes the full name's
        # underscores as spaces), whatever the original name after it says
        m = _MOODLE_FOLDER.match(part) if k < len(parts) - 1 else _MOODLE_FLAT.match(part)
        if m:
            return Submitter(" ".join(m.group("name").split()), m.group("pid"), part)
    return None
