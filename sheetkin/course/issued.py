"""Issued variants: the given data a student received, and whether they are still the same.

`sheetkin variants` (sheetkin/course/variants.py) gives each student a variant of a scheme: a
scene whose given data (lengths, coordinates, ...) differ from the others'. The workbook
carries the variant's id and scene (hidden sheet `scene`, workbook.ISSUED_LABELS), and a
seal: HMAC-SHA256, under the teacher's key, of the id and the scene's text. The key is a
file the teacher keeps (DIR/.sheetkin-key, written by `variants`), never in a workbook, so a
student who edits the hidden sheet cannot make a matching seal. A book issued to one
student (`variants --class-list`) holds their identifier in C3 (label in B3), under the
same seal. A book whose seal checks is graded against its sealed data; keys of earlier
issues, kept dated beside the key by `variants --force`, still check their books.

The validator asks `check_given` which values were issued (from roster.csv, or else from
the embedded scene) and which of them the student's input block changed. A leaf below the
validator: it imports only the scene and the workbook's row list.
"""
from __future__ import annotations

import csv
import hashlib
import hmac
import io
import math
import secrets
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

from sheetkin.errors import InputError
from sheetkin.files import MAX_KEY_BYTES, read_bytes, read_text
from sheetkin.kinematics.scene import Scene, one_line
from sheetkin.messages import message
from sheetkin.sheet.workbook import IDENTITY_ROWS, ISSUED_LABELS, VERSION_LABEL, VERSION_ROW
from sheetkin.untrusted import csv_cell, from_csv_cell

from .caches import scene_rows
from .tolerance import RTOL

KEY_FILE = ".sheetkin-key"          # written by `variants` in its --out folder
ROSTER_FILE = "roster.csv"
ROSTER_FIXED = ("variant", "exercise", "key", "scene")   # roster.csv's first columns; given data follow
MAX_ROSTER_BYTES = 5_000_000        # a class of 30 is a few KB
_IDENTITY = {name for name, _, _ in IDENTITY_ROWS}
STUDENT_LABEL, STUDENT_ROW = "student", len(ISSUED_LABELS) + 1   # scene!B3: the student it was issued to
OLDER_KEYS = ".sheetkin-key-*"      # earlier keys kept dated by `variants --force`
OTHER_CLASS_VALUES = 3              # given values unlike the roster's row, seal failing: another class's book


class RosterError(InputError):
    """roster.csv or the key file cannot be used; str() is one line naming file:line:column.
    Not a SceneError: a roster is not a scene (the command line reports both the same way)."""


# --------------------------------------------------------------------------- the given data
def given_values(scene: Scene) -> dict[str, float]:
    """The scene's input block as the workbook writes it (name -> value), without the
    student's identity rows: the given data of the variant, in the sheet's order."""
    # every input row but the identity rows is written with the scene's number
    return {r.name: cast(float, r.value) for r in scene_rows(scene)
            if r.kind == "input" and r.name not in _IDENTITY}


def _same(issued, got) -> bool:
    if isinstance(got, bool) or not isinstance(got, (int, float)):
        return False
    return math.isfinite(got) and abs(float(got) - float(issued)) <= RTOL * max(1.0, abs(float(issued)))


def changes(issued: dict[str, float], got: dict[str, object], where: dict[str, str]) -> list[dict]:
    """The given values the student's input block does not hold as issued: each
    {"name", "cell", "issued", "got"} (got None: the cell is empty)."""
    out = []
    for name, value in issued.items():
        v = got.get(name)
        if not _same(value, v):
            out.append({"name": name, "cell": where.get(name, "?"), "issued": value,
                        "got": float(v) if isinstance(v, int) and not isinstance(v, bool) else v})
    return out


def _show(v) -> str:
    if isinstance(v, float):
        return f"{v:g}" if v == float(f"{v:g}") else repr(v)
    return "empty" if v is None else repr(v)


def changed_line(changed: list[dict]) -> str:
    """`given data changed: L1 0.14 -> 0.05, Fi_t0 20 -> 1` (the report's first line)."""
    return message("given_data_changed", list=", ".join(f"{c['name']} {_show(c['issued'])} -> {_show(c['got'])}"
                                                        for c in changed))


# --------------------------------------------------------------------------- the seal
def _canonical(scene_text: str) -> str:
    """The scene's text as the hidden sheet gives it back: one line a cell, empty cells
    empty lines, trailing empty lines dropped (a spreadsheet program keeps no empty tail)."""
    lines = scene_text.splitlines()
    while lines and not lines[-1].strip():
        lines.pop()
    return "\n".join(lines)


def seal(key: bytes, variant: str, scene_text: str, student: str = "") -> str:
    """HMAC-SHA256 of the issued data (variant id, scene text and, for a book issued to one
    student by `variants --class-list`, their identifier) under the teacher's key. Without a
    student the message is the one books were sealed with before: they still check."""
    msg = f"sheetkin variant\0{variant}\0{_canonical(scene_text)}"
    if student:
        msg += f"\0student\0{student}"
    return hmac.new(key, msg.encode(), hashlib.sha256).hexdigest()


def seal_status(key: bytes | None, variant: str, scene_text: str, found: str, student: str = "",
                older: tuple[bytes, ...] = ()) -> str:
    """"" (no key: not checked), "ok", or the one-line reason the seal fails. `older`: the
    keys of earlier issues kept beside the key (`variants --force`): a book issued then
    still checks."""
    if key is None:
        return ""
    if not found:
        return message("seal_missing")
    for k in (key, *older):
        if hmac.compare_digest(seal(k, variant, scene_text, student), found.strip().lower()):
            return "ok"
    return message("seal_mismatch")


def new_key() -> str:
    """A fresh key: 32 random bytes, as the hex text the key file holds."""
    return secrets.token_hex(32)


def read_key(path) -> bytes:
    """The teacher's key from its file (64 hex digits); one-line errors."""
    path = Path(path)
    try:
        text = read_text(path, MAX_KEY_BYTES, "key file", "utf-8").strip()
    except FileNotFoundError:
        raise RosterError(one_line(message("no_such_key_file", f=path))) from None
    except (OSError, UnicodeDecodeError) as e:
        raise RosterError(one_line(f"{path}: cannot read the key file ({getattr(e, 'strerror', None) or e})")) from None
    try:
        key = bytes.fromhex(text)
    except ValueError:
        key = b""
    if len(key) < 16:
        raise RosterError(one_line(f"{path}:1:1: expected a key of 32-64 hex digits (as `sheetkin variants` "
                                   "writes it)"))
    return key


def marks(consts: dict) -> tuple[str, str]:
    """(variant id, seal) from the scene sheet's cells {(row, col): value} (C1, C2 when B1,
    B2 hold their labels); ("", "") for a book made by `sheetkin workbook`."""
    out = []
    for r, label in enumerate(ISSUED_LABELS, 1):
        v = consts.get((r, 3)) if consts.get((r, 2)) == label else None
        out.append("" if v is None else (str(int(v)) if isinstance(v, float) and v.is_integer() else str(v)).strip())
    return out[0], out[1]


def student_mark(consts: dict) -> str:
    """The identifier sealed in a book issued to one student (scene!C3 beside its label
    STUDENT_LABEL in B3; `variants --class-list`); "" otherwise."""
    if consts.get((STUDENT_ROW, 2)) != STUDENT_LABEL:
        return ""
    v = consts.get((STUDENT_ROW, 3))
    return "" if v is None else " ".join(str(v).split())


def version_mark(consts: dict) -> str:
    """The version of sheetkin that wrote the book (scene!C4 beside its label in B4; every
    book since issue 31); "" for a book written before (0.2.0 or earlier)."""
    if consts.get((VERSION_ROW, 2)) != VERSION_LABEL:
        return ""
    v = consts.get((VERSION_ROW, 3))
    return "" if v is None else str(v).strip()


# --------------------------------------------------------------------------- roster.csv
@dataclass(frozen=True)
class Roster:
    path: str
    names: tuple[str, ...]                      # the given data's names (columns after ROSTER_FIXED)
    rows: dict[str, dict[str, float]]           # variant id -> given values
    files: dict[str, dict[str, str]] = field(default_factory=dict)   # variant id -> exercise, key, scene


def roster_text(names: list[str], rows: list[tuple[str, dict[str, str], dict[str, float]]]) -> str:
    """roster.csv: variant, exercise, key, scene, then every given value (repr: reads back
    as the same number)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(list(ROSTER_FIXED) + list(names))
    for vid, files, values in rows:
        # the texts neutralized for a spreadsheet (issue 30); the numbers stay numbers
        w.writerow([csv_cell(vid)] + [csv_cell(files[k]) for k in ROSTER_FIXED[1:]] + [_cell(values[n]) for n in names])
    return buf.getvalue()


def _cell(v) -> str:
    return str(int(v)) if isinstance(v, int) or (isinstance(v, float) and v.is_integer() and abs(v) < 1e15) else repr(v)


def read_roster(path) -> Roster:
    """roster.csv as `variants` writes it; every mistake one line naming file:line:column."""
    p = str(path)
    try:
        raw = read_bytes(path, MAX_ROSTER_BYTES, "roster")
    except FileNotFoundError:
        moved = Path(p).parent / "teacher" / ROSTER_FILE    # variants.TEACHER_FOLDER (issue 34)
        if moved.is_file():
            raise RosterError(one_line(message("no_roster_file_moved", f=p, moved=moved))) from None
        raise RosterError(one_line(message("no_roster_file", f=p))) from None
    except OSError as e:
        raise RosterError(one_line(f"{p}: cannot read the roster ({e.strerror or e})")) from None
    if len(raw) > MAX_ROSTER_BYTES:
        raise RosterError(one_line(f"{p}: {len(raw):,} bytes; a roster holds at most {MAX_ROSTER_BYTES:,}"))
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        try:
            text = raw.decode("cp1251")          # re-saved by a Russian Excel ("CSV (разделители - запятые)")
        except UnicodeDecodeError:
            line = raw[:e.start].count(b"\n") + 1
            raise RosterError(one_line(f"{p}:{line}: not UTF-8 (nor Windows-1251) text; expected roster.csv "
                                       "as `sheetkin variants` writes it")) from None
    return parse_roster(text, p)


def parse_roster(text: str, p: str = "roster.csv") -> Roster:
    if "\0" in text:
        line = text[:text.index("\0")].count("\n") + 1
        raise RosterError(one_line(f"{p}:{line}: a NUL character; expected a CSV text file"))
    # a Russian Excel saves CSV with ";" between fields and "," as the decimal point
    delim = ";" if text.split("\n", 1)[0].count(";") > text.split("\n", 1)[0].count(",") else ","
    reader = csv.reader(io.StringIO(text, newline=""), delimiter=delim)
    try:
        header = _roster_header(next(reader, None), p)
        names = header[len(ROSTER_FIXED):]
        rows: dict[str, dict[str, float]] = {}
        files: dict[str, dict[str, str]] = {}
        for fields in reader:
            line = reader.line_num
            if not fields or all(not f.strip() for f in fields):
                continue
            while len(fields) > len(header) and not fields[-1].strip():
                fields = fields[:-1]          # Excel pads a row with empty fields (";;;")
            if len(fields) != len(header):
                raise RosterError(one_line(f"{p}:{line}:{min(len(fields), len(header)) + 1}: {len(fields)} "
                                           f"fields, expected {len(header)} (as the header)"))
            vid = from_csv_cell(fields[0].strip())
            if not vid:
                raise RosterError(one_line(f"{p}:{line}:1: empty variant id"))
            if vid in rows:
                raise RosterError(one_line(f"{p}:{line}:1: variant {vid!r} appears twice"))
            rows[vid] = _roster_values(names, fields[len(ROSTER_FIXED):], delim == ";", f"{p}:{line}")
            files[vid] = dict(zip(ROSTER_FIXED[1:], (from_csv_cell(f.strip()) for f in fields[1:len(ROSTER_FIXED)]),
                                   strict=False))
    except csv.Error as e:
        raise RosterError(one_line(f"{p}:{reader.line_num}: not a valid CSV file ({e})")) from None
    if not rows:
        raise RosterError(one_line(f"{p}:2: no variants (a header only)"))
    return Roster(p, tuple(names), rows, files)


def _roster_header(header: list[str] | None, p: str) -> list[str]:
    """roster.csv's header, stripped of Excel's empty trailing columns: the fixed columns,
    then the given data's names (each once)."""
    if not header or not any(h.strip() for h in header):
        raise RosterError(one_line(f"{p}:1:1: empty; expected a header: {','.join(ROSTER_FIXED)},<given data>..."))
    header = [h.strip() for h in header]
    while len(header) > len(ROSTER_FIXED) and not header[-1]:
        header.pop()                  # Excel's empty trailing columns
    for k, want in enumerate(ROSTER_FIXED):
        if k >= len(header) or header[k] != want:
            got = header[k] if k < len(header) else "nothing"
            raise RosterError(one_line(f"{p}:1:{k + 1}: expected column '{want}', got {got!r}"))
    seen: set[str] = set()
    for k, n in enumerate(header[len(ROSTER_FIXED):], len(ROSTER_FIXED) + 1):
        if not n or n in seen or n in ROSTER_FIXED:
            raise RosterError(one_line(f"{p}:1:{k}: column name {n!r} is empty or repeated"))
        seen.add(n)
    return header


def _roster_values(names: list[str], fields: list[str], decimal_comma: bool, where: str) -> dict[str, float]:
    """One variant's given data (name -> number); where: "file:line"."""
    values = {}
    for k, (n, f) in enumerate(zip(names, fields, strict=False), len(ROSTER_FIXED) + 1):
        try:
            v = float(f.strip().replace(",", ".") if decimal_comma else f)
        except ValueError:
            v = math.nan
        if not math.isfinite(v):
            raise RosterError(one_line(f"{where}:{k}: {n}: expected a number, got {f!r}", 400))
        values[n] = v
    return values


# --------------------------------------------------------------------------- for the validator
@dataclass(frozen=True)
class Options:
    """What `validate` knows about the issued variants (picklable: the process pool)."""
    roster: Roster | None = None
    key: bytes | None = None
    accept_changed: bool = False
    accept_typed: bool = False       # --accept-typed (sheetkin/course/grades.py)
    older_keys: tuple[bytes, ...] = ()          # earlier issues' keys (dated, beside the key)
    libreoffice: bool = True         # cells sheetkin cannot compute, by LibreOffice (--no-libreoffice)


@dataclass
class Given:
    variant: str = ""
    issued: dict[str, float] = field(default_factory=dict)   # {} : the book's inputs are its variant
    changed: list[dict] = field(default_factory=list)
    seal: str = ""
    notes: list[str] = field(default_factory=list)
    student: str = ""                    # the identifier sealed in it (variants --class-list)
    roster_differs: bool = False         # its seal checks, the roster's row says other data


def check_given(scene: Scene, scene_text: str, consts: dict, inputs: dict[str, object],
                where: dict[str, str], opts: Options | None) -> Given:
    """Which given data were issued for this book and which of them the student changed.

    A book with a variant id (made by `variants`) is checked against its roster row (with
    --roster) or else against its embedded scene. A book made by `sheetkin workbook` has no
    id (and no seal): its given data are the scene embedded at generation, so a student who
    edits L1 there is told so and graded against the embedded values (issue 13: "with
    L1 = 0.05 the validator said all correct"); --accept-changed-inputs grades a student's
    own variant, as before issue 13."""
    opts = opts or Options()
    vid, found = marks(consts)
    out = Given(variant=vid, student=student_mark(consts))
    roster = opts.roster
    if not vid:
        if roster is not None:
            out.seal = "scene sheet edited: it names no variant (scene!C1), so the roster row is unknown"
            return out
        out.issued = given_values(scene)
        out.changed = changes(out.issued, inputs, where)
        return out
    out.seal = seal_status(opts.key, vid, scene_text, found, out.student, opts.older_keys)
    embedded = given_values(scene)
    out.issued = embedded
    if roster is not None and out.seal == "ok":
        # the seal proves the embedded data were issued: they are graded, whatever the roster
        # says (a roster re-written by `variants --force`, or another class's: one warning)
        row = roster.rows.get(vid)
        out.roster_differs = row is None or any(n in row and not _same(row[n], v) for n, v in embedded.items())
    elif roster is not None:
        if vid not in roster.rows:
            out.seal = out.seal if out.seal in (message("seal_missing"), message("seal_mismatch")) else \
                message("variant_not_in_roster", v=repr(vid), roster=roster.path)
        else:
            out.issued = {n: roster.rows[vid][n] for n in roster.names if n in embedded}
            missing = [n for n in embedded if n not in roster.rows[vid]]
            if missing:
                out.notes.append(message("has_no_column_for", roster=roster.path, names=", ".join(missing)))
                out.issued.update({n: embedded[n] for n in missing})
    if roster is not None and (out.seal == message("seal_mismatch")
                               or not out.seal and set(embedded) - set(roster.names)):
        # without a key only another scheme is told: the data of this scheme stay the roster's
        other = _other_class(roster, vid, embedded)
        if other:
            # said first, before any word of tampering (issue 31): a book handed in to the
            # wrong class is the likelier story, and its given data are its own class's
            out.seal = f"{other}; {out.seal}" if out.seal else other
            out.issued = embedded
    out.changed = changes(out.issued, inputs, where)
    _text_numbers(out)
    return out


def _other_class(roster: Roster, vid: str, embedded: dict[str, float]) -> str:
    """Why a book whose seal fails under this class's key looks like another class's: its
    scheme's given data are not the roster's columns, or its variant's data are not the
    roster's row; "" when it looks like this class's."""
    mine, theirs = set(embedded), set(roster.names)
    if mine - theirs:
        return message("book_of_another_scheme", roster=roster.path, names=", ".join(sorted(mine - theirs)[:4]))
    row = roster.rows.get(vid)
    # another class's variant differs in most of the drawn data (every length, offset ...); a
    # student who edits a value or two in the input block and the hidden sheet alike is
    # told "given data changed" as before
    if row is None or sum(n in row and not _same(row[n], v) for n, v in embedded.items()) >= OTHER_CLASS_VALUES:
        return message("book_of_another_roster_not_in" if row is None else "book_of_another_roster_row",
                       roster=roster.path, v=vid)
    return ""


def as_text_number(v) -> float | None:
    """The number a text such as "0,144" (a Russian spreadsheet's decimal comma) or "0.144"
    reads as; None for any other text."""
    if not isinstance(v, str):
        return None
    t = v.strip().replace("\u00a0", "").replace(" ", "")
    try:
        x = float(t.replace(",", ".", 1)) if t.count(",") <= 1 and "." not in t or "," not in t else None
    except ValueError:
        return None
    return x if x is not None and math.isfinite(x) else None


def _text_numbers(out: Given) -> None:
    """A given value stored as text that reads as the issued number ("0,144": a Russian
    Calc computes with it) is not changed data (issue 31): a remark, not a zero."""
    kept = []
    for c in out.changed:
        x = as_text_number(c["got"])
        if x is not None and _same(c["issued"], x):
            out.notes.append(f"given {c['name']} ({c['cell']}) is the text {c['got']!r}, not a number: it is the "
                             f"issued {_show(c['issued'])} (a spreadsheet may read it so; type it as a number)")
        else:
            kept.append(c)
    out.changed = kept
