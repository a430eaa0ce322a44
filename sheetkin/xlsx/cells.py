"""Reading a workbook's cells: constants, formulas and the values the spreadsheet cached.

The sheet XML is read directly (an .xlsx is a zip of XML parts), through the input gate
(package.py): never modified, never trusted. Shared formulas (LibreOffice, Excel) are expanded.

Two paths, the same cells: a sheet part in the shape Excel, LibreOffice and openpyxl write
is read with one compiled regex over its <sheetData> bytes (no element tree; every byte
must be matched, texts are unescaped and decoded in one pass); anything else, and anything
the regex does not account for, goes through ElementTree (see _read_fast).
"""
from __future__ import annotations

import functools
import gc
import io
import math
import re
import sys
from collections.abc import Iterable
from dataclasses import dataclass, field
from itertools import compress, product, repeat
from operator import not_
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from sheetkin.messages import message

from .convert import check_opendocument as check_opendocument  # re-exported: cells was their home
from .convert import convert_opendocument as convert_opendocument
from .convert import converted, is_old_excel, is_opendocument
from .convert import password_protected as password_protected
from .coords import column_index_from_string
from .functions import ERRORS, XlError, capped
from .package import Limits, UnusableWorkbook, open_package, sheet_parts

MAX_COL = 16_384                         # XFD, Excel's last column


@functools.cache
def _columns() -> tuple[list[str], dict[str, int]]:
    """Every column's letters ("" for 0, then A ... XFD) and their numbers: built on first
    use, not at import (`sheetkin evaluate` starts faster, issue 32)."""
    abc = _ABC
    letters = ["", *abc, *map("".join, product(abc, abc)), *map("".join, product(abc, abc, abc))][:MAX_COL + 1]
    return letters, dict(zip(letters[1:], range(1, MAX_COL + 1), strict=True))


def _column_numbers(letters: list[bytes]) -> list[int]:
    """The column numbers of a sheet's cell references' letters (b"A" ... b"XFD", as _CELLS
    matches them: 1-3 capitals); KeyError past XFD. Each distinct column is worked out once
    (a book has a few hundred), not a table of all 16,384 built."""
    table = {}
    for b in set(letters):
        c = 0
        for ch in b:
            c = c * 26 + ch - 64
        if not 1 <= c <= MAX_COL:
            raise KeyError(b)
        table[b] = c
    return list(map(table.__getitem__, letters))


_ABC = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
MAX_ROW = 1_048_576                      # Excel's last row


@dataclass
class Sheet:
    name: str
    state: str
    consts: dict = field(default_factory=dict)    # (r, c) -> value (number, str, bool, XlError)
    formulas: dict = field(default_factory=dict)  # (r, c) -> formula text (without "=")
    cached: dict = field(default_factory=dict)    # (r, c) -> cached value of a formula cell
    max_row: int = 0                               # the used range: the last row and column
    max_col: int = 0                               # of a cell that holds something
    # array formulas (t="array": Ctrl+Shift+Enter, and Excel 365's dynamic-array spills):
    # the anchor (r, c), which holds the formula, -> the last cell (r2, c2) of its range; the
    # range's other cells hold no formula in the file, only the value saved (in `cached`)
    arrays: dict = field(default_factory=dict)
    names: dict = field(default_factory=dict)     # names scoped to this sheet (localSheetId)
    dangling: dict = field(default_factory=dict)  # (r, c) -> why a shared formula's cell has no text
    # the UTF-8 text of the formulas the file holds (the fast path's, as it decoded them),
    # kept for the sheet-name scan (_sheets_named) when asked; None: not kept, or some
    # formulas are not in it (a shared formula's cells, made by shifting its text)
    formula_bytes: list | None = None

    def computed(self, r: int, c: int) -> bool:
        """Whether the cell's value comes from a formula: its own, or an array formula's
        whose range holds it (a spilled cell), as opposed to a typed value."""
        if (r, c) in self.formulas:
            return True
        return any(r0 <= r <= r2 and c0 <= c <= c2 for (r0, c0), (r2, c2) in self.arrays.items())



def _read_sheet(pkg, name: str, part: str, state: str, shared: list[str], limits: Limits,
                budget: int | None = None, saved: bool = True, keep_text: bool = False) -> Sheet:
    """budget: cells that may still hold something (Limits.max_cells less the sheets before).
    saved: whether the values saved for formula cells are wanted (sh.cached); the fast path
    leaves them unread without (the evaluator computes them). keep_text: the fast path keeps
    the formulas' UTF-8 text in sh.formula_bytes."""
    if not part.lower().endswith(".xml"):           # only .xml parts were pre-scanned
        return _read_tree(pkg, pkg.xml(part), name, part, state, shared, limits, budget)
    data = pkg.read(part)
    sh = _read_fast(pkg, data, name, state, shared, limits, budget, saved, keep_text)
    if sh is not None:
        return sh
    return _read_tree(pkg, _streamed(pkg, data, part), name, part, state, shared, limits, budget)


def _streamed(pkg, data: bytes, part: str):
    """(namespace, the <c> elements one by one) of a sheet part, each row cleared once read:
    a 100 MB part never becomes a 1.5 GB element tree. The C parser directly, not
    defusedxml's (which calls back into Python for every element, 4x slower here): safe
    because open_package refused every part that declares a DTD or an entity, the only way
    to an entity bomb or an external entity."""
    def refuse(e):
        return UnusableWorkbook(pkg.path, f"not well-formed XML ({e})", "a sheet saved by Excel or LibreOffice",
                                part=part)
    events = ElementTree.iterparse(io.BytesIO(data), events=("start", "end"))
    try:
        _event, root = next(events)
    except (ElementTree.ParseError, StopIteration) as e:
        raise refuse(e) from None
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    c_tag, row_tag = f"{ns}c", f"{ns}row"

    def cells():
        try:
            for event, el in events:
                if event == "end":
                    if el.tag == c_tag:
                        yield el
                    elif el.tag == row_tag:
                        el.clear()
        except ElementTree.ParseError as e:
            raise refuse(e) from None
    return ns, cells()


def _check_cells(pkg, name: str, sh: Sheet, limits: Limits, budget: int | None) -> None:
    """Refuse a workbook in which more than limits.max_cells cells hold something (the
    reader's memory, about 150-300 bytes a cell, is what this bounds)."""
    held = len(sh.consts) + len(sh.formulas) + len(sh.dangling)
    if held > (limits.max_cells if budget is None else budget):
        raise UnusableWorkbook(pkg.path, f"more than {limits.max_cells:,} cells hold a value or a formula "
                               f"(counted up to sheet '{name}')",
                               message("at_most_limit", size=f"{limits.max_cells:,}"))


def _read_tree(pkg, root, name: str, part: str, state: str, shared: list[str], limits: Limits,
               budget: int | None = None) -> Sheet:
    """The general path: every well-formed sheet, through an element tree (root), or
    streamed ((namespace, cells) from _streamed)."""
    sh = Sheet(name, state)
    if isinstance(root, tuple):
        ns, cells = root
    else:
        ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
        cells = root.iter(f"{ns}c")
    shared_f: dict[str, _Shared] = {}
    f_tag, v_tag, is_tag, t_tag = f"{ns}f", f"{ns}v", f"{ns}is", f"{ns}t"
    pending: list = []                     # shared-formula cells met before their master
    col_of = _columns()[1]
    count = 0
    for c in cells:
        count += 1
        if count % 65536 == 0:
            _check_cells(pkg, name, sh, limits, budget)
        ref = c.get("r") or ""
        letters = ref.rstrip("0123456789")
        col = col_of.get(letters)
        if col is None or not ref[len(letters):].isdigit():
            raise UnusableWorkbook(pkg.path, f"a cell without a valid reference ({ref!r})",
                                   "cells named like A1", part=part)
        row = int(ref[len(letters):])
        f, v, inline = _children(c, f_tag, v_tag, is_tag)
        if f is None and (v is None or not v.text) and inline is None:
            continue                       # styled emptiness: no limit, not in the used range
        if row > limits.max_rows or col > limits.max_cols:
            raise UnusableWorkbook(pkg.path, f"sheet '{name}' has a cell at {ref}",
                                   f"at most {limits.max_rows} rows and {limits.max_cols} columns")
        if row > sh.max_row:
            sh.max_row = row
        if col > sh.max_col:
            sh.max_col = col
        try:
            value = _tree_value(c.get("t", "n"), v.text if v is not None else None, inline, t_tag, shared)
        except (ValueError, IndexError):
            raise UnusableWorkbook(pkg.path, f"sheet '{name}' cell {ref} has the value "
                                   f"{v.text if v is not None else None!r} of type {c.get('t', 'n')!r}",
                                   "a number, or an index into the shared strings", part=part) from None
        if f is not None and _place_formula(sh, f, value, row, col, shared_f, pending):
            continue
        if value is not None:
            sh.consts[(row, col)] = value
    _resolve_pending(sh, pending, shared_f, sh.formulas)
    _check_cells(pkg, name, sh, limits, budget)
    return _finish(sh, pkg, limits)


def _children(c, f_tag: str, v_tag: str, is_tag: str) -> tuple:
    """A cell element's <f>, <v> and <is> (None where absent), in one pass."""
    f = v = inline = None
    for child in c:
        tag = child.tag
        if tag == v_tag:
            v = child
        elif tag == f_tag:
            f = child
        elif tag == is_tag:
            inline = child
    return f, v, inline


def _place_formula(sh: Sheet, f, value, row: int, col: int, shared_f: dict, pending: list) -> bool:
    """A cell's <f> into the sheet (a shared formula's text shifted from its master, an array
    formula's range noted), its saved value into sh.cached; False for an empty <f> that is
    not shared (the cell is then a constant)."""
    text = f.text
    if f.get("t") == "shared":
        si = f.get("si")
        if text:
            shared_f[si] = _Shared(text, row, col)
        elif si in shared_f:
            text = _shifted(sh, shared_f[si], row, col, si)
            if text is None:               # cannot be shifted: dangling
                if value is not None:
                    sh.cached[(row, col)] = value
                return True
        else:                      # before its master (a block the master is inside), or no master
            pending.append((row, col, si))
            if value is not None:
                sh.cached[(row, col)] = value
            return True
    if not text:
        return False
    sh.formulas[(row, col)] = text
    if f.get("t") == "array":
        sh.arrays[(row, col)] = _array_end(f.get("ref"), row, col)
    if value is not None:
        sh.cached[(row, col)] = value
    return True


def _tree_value(t: str, vtext: str | None, inline, t_tag: str, shared: list[str]) -> float | str | bool | None:
    """A cell's value from its type t, the text of its <v> and its <is> element, as the
    element tree reads it (ValueError, IndexError: a value that does not fit its type)."""
    if t == "s" and vtext is not None:
        return shared[int(vtext)]
    if t == "inlineStr" and inline is not None:
        return capped("".join(x.text or "" for x in inline.iter(t_tag)))
    if t == "b" and vtext is not None:
        return vtext.strip() == "1"
    if t == "e" and vtext is not None:
        return saved_error(vtext)
    if t in ("str", "d") and vtext is not None:
        return capped(vtext)          # "d": an ISO 8601 date, text to a kinematics sheet
    if vtext is not None:
        return number(vtext)
    return None


def _array_end(ref: str | None, row: int, col: int) -> tuple[int, int]:
    """The last cell of an array formula's range (ref="B2:D4"), from its anchor B2; a
    missing or unreadable ref is the anchor alone."""
    last = (ref or "").split(":")[-1].replace("$", "")
    letters = last.rstrip("0123456789")
    c = _columns()[1].get(letters.upper())
    if c is None or not last[len(letters):].isdigit():
        return row, col
    return max(row, int(last[len(letters):])), max(col, c)


def _finish(sh: Sheet, pkg, limits: Limits) -> Sheet:
    """The cells of array ranges other than their anchors hold the anchor's values: what
    the spreadsheet saved there moves from the constants to the cached values (the
    evaluator computes them), and stays out of the formulas. An array range counts as
    cells that hold something: past the limits, the file is refused."""
    for (r, c), (r2, c2) in sh.arrays.items():
        if r2 > limits.max_rows or c2 > limits.max_cols:
            raise UnusableWorkbook(pkg.path, f"sheet '{sh.name}' has an array formula at "
                                   f"{_columns()[0][c]}{r} over {_columns()[0][c]}{r}:{_columns()[0][c2]}{r2}",
                                   f"at most {limits.max_rows} rows and {limits.max_cols} columns")
        if (r2 - r + 1) * (c2 - c + 1) <= len(sh.consts):
            cells = [(i, j) for i in range(r, r2 + 1) for j in range(c, c2 + 1)]
        else:
            cells = [k for k in sh.consts if r <= k[0] <= r2 and c <= k[1] <= c2]
        for key in cells:
            if key in sh.consts and key not in sh.formulas:
                sh.cached[key] = sh.consts.pop(key)
        sh.max_row, sh.max_col = max(sh.max_row, r2), max(sh.max_col, c2)
    return sh


def _shifted(sh: Sheet, master: _Shared, row: int, col: int, si) -> str | None:
    """A shared formula's text at (row, col), or None and the cell marked dangling when
    the master's text cannot be shifted (openpyxl's translator refuses it)."""
    try:
        return master.at(row, col)
    except Exception as e:      # noqa: BLE001 - the cell's problem: evaluated as #N/A with a note
        sh.dangling[(row, col)] = (f"a shared formula (si={str(si)[:20]}) whose text cannot be shifted "
                                   f"({type(e).__name__})")
        return None


def _resolve_pending(sh: Sheet, pending: list, masters: dict, formulas: dict) -> None:
    """Shared-formula cells listed before their master get its text now; those whose
    master is missing are dangling (the evaluator gives them #N/A and a note, never the
    value the file cached)."""
    for row, col, si in pending:
        text = _shifted(sh, masters[si], row, col, si) if si in masters else None
        if text:
            formulas[(row, col)] = text
        elif (row, col) not in sh.dangling:
            sh.dangling[(row, col)] = (f"a shared formula (si={str(si)[:20]}) without its first cell, "
                                       "which holds the text")


# ----------------------------------------------------------------- the fast path: one regex
# A sheet part as Excel, LibreOffice and openpyxl write it: an unprefixed <worksheet> (its
# namespace the default one), one <sheetData>, rows of cells <c r="A1" [s=".."] [t=".."] ...>
# with an optional <f>, <v> and <is><t>. One compiled regex must tile every byte of
# <sheetData> (re.split leaves nothing between its matches), so no byte goes unread. Any
# other shape (prefixed names, a namespace declared inside, t after other attributes,
# rich text, comments, CDATA, references in attributes, carriage returns, control
# characters, undefined entities, text that is not UTF-8, duplicate cells) goes to the
# element-tree path, which reads every well-formed sheet and refuses the rest. Either way
# the part was pre-scanned by open_package (no DTD, no entity declarations; limits).
_WS = rb"[ \t\n]"
_TEXT = rb"[^<]*+"                                      # character data (controls: _CONTROLS)
_VALUE = rb'"[^"<>&]*+"'                                # an attribute value without references
_NAME = rb"[A-Za-z_][\w.:-]*+"
# Every optional part is possessive: once it matched, skipping it cannot make the cell
# match (what follows it never starts the same way), so the engine keeps no state to go
# back to: 29 % fewer instructions for the split of a sheet, the same matches (issue 32).
# CPython 3.11.0-3.11.4 matched a possessive group wrongly (gh-106052, fixed in 3.11.5; on
# Debian 12's 3.11.2 a broken <row ... x<c ...> was read as a row): there the parts are
# atomic groups instead, correct and 8 % fewer instructions.
_POSSESSIVE_WORKS = sys.version_info >= (3, 11, 5)


def _cells_pattern(possessive: bool) -> bytes:
    def optional(part: bytes) -> bytes:
        return b"(?:" + part + b")?+" if possessive else b"(?>(?:" + part + b")?)"

    attribute = _WS + rb"++(?!xmlns)" + _NAME + b"=" + _VALUE
    return (_WS + rb"*+(?:"
            + optional(b"</row>" + _WS + b"*+")
            + optional(b"<row(?:" + attribute + rb")*+" + _WS + b"*+>" + _WS + b"*+")
            + rb'<c r="([A-Z]{1,3}+)([0-9]{1,7}+)"' + optional(b' s="[0-9]*+"') + optional(b' t="([A-Za-z]*+)"')
            + rb"(?:" + _WS + rb"++(?!t=|xmlns)" + _NAME + b"=" + _VALUE + rb")*+" + _WS + rb"*+"
            + rb"(?:/>|>"
            + optional(b"<f((?:" + attribute + rb")*+)" + _WS + rb"*+(?:/>|>(" + _TEXT + rb")</f>)")
            + optional(b"<v" + _WS + rb"*+(?:/>|>(" + _TEXT + rb")</v>)")
            + optional(b"<is><t" + optional(b' xml:space="[a-z]*+"') + _WS + rb"*+(>" + _TEXT + rb")</t></is>")
            + rb"</c>)"
            + rb"|<row(?:" + attribute + rb")*+" + _WS + rb"*+/?>"
            + rb"|</row>"
            + rb")" + _WS + rb"*+")


_CELLS = re.compile(_cells_pattern(_POSSESSIVE_WORKS))
# XML 1.0 allows no other control characters; a carriage return would need normalizing
_CONTROLS = bytes(range(0, 9)) + b"\x0b\x0c\x0d" + bytes(range(14, 32))
# each byte to 0 if it is one of _CONTROLS, else 1: a piece holds one if its translation holds
# a 0 (a table lookup per byte and one memchr: 25 % fewer instructions than deleting them)
_CONTROL_MAP = bytes(0 if b in _CONTROLS else 1 for b in range(256))


def _has_control(piece: bytes) -> bool:
    """Whether a piece of a sheet holds one of _CONTROLS. Its smallest byte first (numpy's
    minimum, 0.2 ms for 7.5 MB where the table took 6-13 ms, issue 32): every one of them
    lies below the space, and most sheets hold no byte below it at all (no line breaks,
    no tabs); only a piece that does is looked at through the table."""
    return bool(piece) and int(np.frombuffer(piece, np.uint8).min()) < 32 and 0 in piece.translate(_CONTROL_MAP)


_GROUPS = _CELLS.groups                                # letters, row, t, <f> attributes, <f>, <v>, ">" + <t>
_HEAD = re.compile(rb"(?:\xef\xbb\xbf)?(?:<\?xml[^<>?]*+\?>)?[ \t\r\n]*+<worksheet[ \t\r\n>]")
_SHARED = re.compile(rb'(?:^|[ \t\n])t="shared"')
_SI = re.compile(rb'(?:^|[ \t\n])si="([^"]*)"')
_ARRAY = re.compile(rb'(?:^|[ \t\n])t="array"')
_REF = re.compile(rb'(?:^|[ \t\n])ref="([^"]*)"')
_CHAR_REF = re.compile(rb"#[0-9]{1,7}|#x[0-9A-Fa-f]{1,6}")
_NAMED = {b"amp": b"&", b"lt": b"<", b"gt": b">", b"quot": b'"', b"apos": b"'"}


class _NotSimple(Exception):
    """Not the shape the fast path reads: the element tree decides."""


def _unescape(data: bytes) -> bytes:
    """XML's five named references and character references, replaced; anything else
    after a "&" is not for the fast path. One C-level regex pass with the replacements
    memoized (a formula sheet holds thousands of &lt; &gt; &quot; and, from some writers,
    its Cyrillic texts as &#1085;...: a Python loop per "&" was 5-7 ms a book)."""
    out, n = _ENTITY.subn(_entity, data)
    if n != data.count(b"&"):
        raise _NotSimple                            # an undefined entity, or a stray "&"
    return out


_ENTITY = re.compile(rb"&(amp|lt|gt|quot|apos|#[0-9]{1,7}|#x[0-9A-Fa-f]{1,6});")
_ENTITIES: dict[bytes, bytes] = {}


def _entity(m: re.Match) -> bytes:
    name = m.group(1)
    char = _NAMED.get(name) or _ENTITIES.get(name)
    if char is None:
        code = int(name[2:], 16) if name[1:2] == b"x" else int(name[1:])
        if not (code in (0x9, 0xA, 0xD) or 0x20 <= code <= 0xD7FF or 0xE000 <= code <= 0xFFFD
                or 0x10000 <= code <= 0x10FFFF):
            raise _NotSimple                        # a character XML does not allow
        char = _ENTITIES[name] = chr(code).encode("utf-8")
    return char


def _decoded(items: list[bytes]) -> tuple[list[str], bytes]:
    """(texts, their UTF-8 bytes joined by NUL): character data (bytes without markup),
    unescaped and decoded, all in one pass. With references in it, the text is cut at every
    '"' (no reference holds one): the pieces at odd places (a formula's string literals) are
    few distinct texts, each unescaped once; the others (the formulas' code, where references
    are few: &gt;, &lt;) are unescaped in one regex pass over them all (_unescape: an
    undefined entity or a character XML forbids is _NotSimple). openpyxl writes Cyrillic as
    &#1085;... (381,532 references in the 360-column shaper, all in 12 distinct literals), so
    this is several times faster than expat's pass over the whole text, which unescaped every
    reference each time (issue 32)."""
    if not items:
        return [], b""
    joined = b"\0".join(items)                     # NUL occurs neither raw nor as a reference
    if b"]]>" in joined:
        raise _NotSimple                            # not allowed in character data: the tree path says so
    if b"&" not in joined:
        return joined.decode("utf-8").split("\0"), joined
    pieces = joined.split(b'"')
    literals, code = pieces[1::2], pieces[::2]
    joined_code = b'"'.join(code)
    code_text = _unescape(joined_code).split(b'"') if b"&" in joined_code else code
    if len(code_text) == len(code):                 # (not so when a reference in the code spells '"')
        table = {p: _unescape(p) for p in set(literals) if b"&" in p}
        pieces[::2] = code_text
        pieces[1::2] = map(table.get, literals, literals)
    else:
        distinct = list(set(pieces))
        table = {p: _unescape(p) for p in compress(distinct, map(bytes.__contains__, distinct, repeat(ord("&"))))}
        pieces = list(map(table.get, pieces, pieces))
    joined = b'"'.join(pieces)
    texts = joined.decode("utf-8").split("\0")
    if len(texts) != len(items):
        raise _NotSimple                            # a reference to NUL (which _unescape refuses anyway)
    return texts, joined


def _text(b: bytes) -> str:
    if b"]]>" in b:
        raise _NotSimple                            # (as _decoded)
    return (_unescape(b) if b"&" in b else b).decode("utf-8")


_PIECE = 4 << 20        # bytes of <sheetData> split at a time (the split's lists cost ~10x)


def _read_fast(pkg, data: bytes, name: str, state: str, shared: list[str], limits: Limits,
               budget: int | None = None, saved: bool = True, keep_text: bool = False) -> Sheet | None:
    """The cells of a sheet part in the simple shape (see _CELLS), else None. Read in
    pieces of about _PIECE bytes ending at a </row>, so that the regex's lists stay small
    whatever the part's size."""
    if not _HEAD.match(data):
        return None
    start, end = data.find(b"<sheetData>"), data.find(b"</sheetData>")
    if start < 0 or end < start or data.count(b"<sheetData") != 1:
        return None
    gc_was = gc.isenabled()
    gc.disable()                # tens of thousands of small tuples, none of them cyclic
    try:
        masters: dict[str | None, _Shared]
        sh, masters, pos = Sheet(name, state, formula_bytes=[] if keep_text else None), {}, start + 11
        while pos < end:                            # pieces of <sheetData>, never a copy of all of it
            cut = end
            if cut - pos > _PIECE:
                cut = data.find(b"</row>", pos + _PIECE, end)
                cut = end if cut < 0 else cut + 6
            piece = data[pos:cut]
            if _has_control(piece):
                return None
            parts = _CELLS.split(piece)
            if any(parts[::_GROUPS + 1]):
                return None                         # bytes that no match accounts for
            _cells_of(pkg, parts, name, state, shared, limits, into=sh, masters=masters, saved=saved)
            _check_cells(pkg, name, sh, limits, budget)
            pos = cut
        return _finish(sh, pkg, limits)
    except UnusableWorkbook:
        raise
    except (_NotSimple, UnicodeDecodeError, ValueError, KeyError, IndexError):
        return None                                 # the element tree decides (or says what is wrong)
    finally:
        if gc_was:
            gc.enable()


def _cells_of(pkg, parts: list, name: str, state: str, shared: list[str], limits: Limits,
              into: Sheet | None = None, masters: dict | None = None, saved: bool = True) -> Sheet:
    """The cells of one piece of <sheetData> (split by _CELLS), added to `into`; masters:
    the shared formulas' first cells met so far (a block may span pieces); saved: whether
    the values saved for formula cells are read (into sh.cached)."""
    letters, rownums, types, fattrs, ftexts, vtexts, itexts = _columns_of(parts)
    sh = into if into is not None else Sheet(name, state)
    if not letters:
        return sh
    cols = _column_numbers(letters)                  # KeyError past XFD
    rows = list(map(int, rownums))
    keys = list(zip(rows, cols, strict=False))
    if len(set(keys)) != len(keys):
        raise _NotSimple                            # a cell listed twice
    # the used range and the limits: cells that hold something (a formula, a value), not
    # styled emptiness (<c r="XFD9" s="3"/>: LibreOffice styles whole rows and columns)
    held = list(map(any, zip(ftexts, fattrs, vtexts, itexts, strict=False)))
    if all(held):
        last_row, last_col = max(rows), max(cols)
    else:
        last_row = max(compress(rows, held), default=0)
        last_col = max(compress(cols, held), default=0)
    sh.max_row, sh.max_col = max(sh.max_row, last_row), max(sh.max_col, last_col)   # over the pieces
    if sh.max_row > limits.max_rows or sh.max_col > limits.max_cols:
        _refuse_far_cell(pkg, name, limits, rows, cols, letters, rownums, held)
    # formulas: the text of every <f> that has one, decoded in one pass
    texts, utf8 = _decoded(list(filter(None, ftexts)))
    formulas = dict(zip(compress(keys, ftexts), texts, strict=False))
    if sh.formula_bytes is not None:
        sh.formula_bytes.append(utf8)
    if any(fattrs):
        formulas = _shared_and_arrays(sh, keys, fattrs, ftexts, formulas, {} if masters is None else masters)
        if len(formulas) != len(texts):
            # a shared formula's other cells are its text shifted, which the file does not
            # hold: the sheet-name scan reads the texts that are evaluated (a shifter that
            # once moved Q1 of Q1!a1 as a cell named a sheet the file's text did not)
            sh.formula_bytes = None
    # values: constants, and the values saved for formula cells
    with_value: Iterable[int] = compress(range(len(keys)), vtexts)
    if any(itexts):
        with_value = sorted(set(with_value) | set(compress(range(len(keys)), itexts)))
    if not saved:                                   # constants only (and what dangling cells saved)
        with_value = list(with_value)
        is_formula = map(formulas.__contains__, map(keys.__getitem__, with_value))
        with_value = list(compress(with_value, map(not_, is_formula)))
    _store_values(sh, with_value, keys, types, vtexts, itexts, shared, formulas)
    sh.formulas.update(formulas)
    return sh


def _columns_of(parts: list) -> list[list]:
    """The regex's groups of a piece of <sheetData>, one list per group (letters, row, t,
    <f> attributes, <f>, <v>, <is>), the <row> and </row> matches left out."""
    k = _GROUPS + 1
    columns = [parts[g::k] for g in range(1, k)]
    if columns[0] and columns[0][-1] is None and columns[0].count(None) == 1:
        columns = [x[:-1] for x in columns]         # the last </row>
    elif None in columns[0]:                        # <row> or </row> matched alone
        keep = [x is not None for x in columns[0]]
        columns = [list(compress(x, keep)) for x in columns]
    return columns


def _refuse_far_cell(pkg, name: str, limits: Limits, rows, cols, letters, rownums, held) -> None:
    """One line naming the first cell that holds something past the rows or columns allowed."""
    for r, c, L, R, h in zip(rows, cols, letters, rownums, held, strict=False):
        if h and (r > limits.max_rows or c > limits.max_cols):
            raise UnusableWorkbook(pkg.path, f"sheet '{name}' has a cell at {(L + R).decode()}",
                                   f"at most {limits.max_rows} rows and {limits.max_cols} columns")


def _store_values(sh: Sheet, with_value: Iterable[int], keys: list, types: list, vtexts: list, itexts: list,
                  shared: list[str], formulas: dict) -> None:
    """Constants into sh.consts, the values saved for formula cells into sh.cached."""
    consts, cached = sh.consts, sh.cached
    for i in with_value:
        t, v = types[i], vtexts[i] or None
        if v is not None and (t is None or t == b"n"):
            value = number(v.decode())
        else:
            value = _value(t, v, itexts[i], shared)
            if value is None:
                continue
        key = keys[i]
        if key in formulas or key in sh.dangling:
            cached[key] = value
        else:
            consts[key] = value


def _shared_and_arrays(sh: Sheet, keys: list, fattrs: list, ftexts: list, formulas: dict, masters: dict) -> dict:
    """The formulas of a piece of <sheetData> with its shared formulas (Excel, LibreOffice)
    filled in, and its array formulas' ranges noted in sh.arrays: the first cell
    <f t="shared" si=".."> has the text, the block's other cells <f t="shared" si=".."/> are
    shifted from it (a block's master need not be its first cell: the masters are found
    first; a block may span pieces of the sheet: `masters` holds those met so far)."""
    children, pending = [], []
    for i in compress(range(len(keys)), fattrs):
        if not _SHARED.search(fattrs[i]):
            if _ARRAY.search(fattrs[i]) and keys[i] in formulas:
                ref = _REF.search(fattrs[i])
                sh.arrays[keys[i]] = _array_end(ref and ref.group(1).decode("ascii"), *keys[i])
            continue
        si_match = _SI.search(fattrs[i])
        si = si_match.group(1).decode("utf-8", "replace") if si_match else None
        if ftexts[i]:
            masters[si] = _Shared(formulas[keys[i]], *keys[i])
        else:
            children.append((i, si))
    for i, si in children:
        if si in masters:
            row, col = keys[i]
            text = _shifted(sh, masters[si], row, col, si)
            if text:
                formulas[keys[i]] = text
        else:
            pending.append((*keys[i], si))
    if pending:
        _resolve_pending(sh, pending, masters, formulas)
    formulas = {key: formulas[key] for key in keys if key in formulas}     # document order
    return formulas


def _value(t: bytes | None, v: bytes | None, inline: bytes | None, shared: list[str]):
    """A cell's value from its type and <v> or <is>, as _read_tree reads it."""
    t = b"n" if t is None else t
    if t == b"s" and v is not None:
        return shared[int(v.decode())]
    if t == b"inlineStr" and inline is not None:
        return capped(_text(inline[1:]))
    if t == b"b" and v is not None:
        return _text(v).strip() == "1"
    if t == b"e" and v is not None:
        return saved_error(_text(v))
    if t in (b"str", b"d") and v is not None:
        return capped(_text(v))
    if v is not None:
        return number(_text(v))
    return None


# ----------------------------------------------------------------- formulas shifted along a row
# References in either case (Excel's formulas read q1 as Q1; only a hand-edited file holds
# one): with capitals alone, Q1!a1 was shifted as the cell Q1 (to Q2!a1, another sheet).
_SHEET_PREFIX = r"(?:'(?:[^']|'')+'|[^\W\d][\w.]*)!"
_TEMPLATE_REF = re.compile(
    r'(?P<str>"(?:[^"]|"")*")'
    r"|(?<![\w.$!'])(?P<wsheet>" + _SHEET_PREFIX + r")?(?P<wca>\$?)(?P<wc1>[A-Za-z]{1,3}):"
    r"(?P<wcb>\$?)(?P<wc2>[A-Za-z]{1,3})"
    r"(?![\w(!])"                                               # a whole-column reference A:C
    r"|(?<![\w.$!'])(?P<rsheet>" + _SHEET_PREFIX + r")?(?P<wra>\$?)(?P<wr1>\d+):(?P<wrb>\$?)(?P<wr2>\d+)"
    r"(?![\w(.!])"                                              # a whole-row reference 2:5
    r"|(?<![\w.$!'])(?P<sheet>" + _SHEET_PREFIX + r")?(?P<cabs>\$?)(?P<col>[A-Za-z]{1,3})"
    r"(?P<rabs>\$?)(?P<row>\d+)(?![\w(!])")                        # (Q1! names a sheet, not a cell)


def _column_spans(m) -> list[tuple[int, int, str]]:
    """The relative column letters of one match of _TEMPLATE_REF: (start, end, letters)."""
    if m.group("col") is not None:
        return [] if m.group("cabs") else [(m.start("col"), m.end("col"), m.group("col"))]
    if m.group("wc1") is not None:
        return [(m.start(g), m.end(g), m.group(g)) for a, g in (("wca", "wc1"), ("wcb", "wc2"))
                if not m.group(a)]
    return []


class Template:
    """A formula as text with its relative columns left open: rendering it for the next
    columns and comparing strings tells whether those cells hold the same formula shifted."""

    def __init__(self, formula: str, host_c: int):
        offsets: list[int] = []           # one placeholder per distinct column offset
        pieces, slots, last = [], [], 0   # literal text between the placeholders
        for m in _TEMPLATE_REF.finditer(formula):
            for start, end, letters in _column_spans(m):
                o = column_index_from_string(letters) - host_c
                if o not in offsets:
                    offsets.append(o)
                pieces.append(formula[last:start])
                slots.append(offsets.index(o))
                last = end
        pieces.append(formula[last:])
        self.pieces, self.offsets, self.slots = pieces, offsets, slots
        # printf-style: 35 % faster than str.format for the 42,146 formulas of the 360-column
        # shaper compared with their row's first (issue 32)
        self.text = "".join(p.replace("%", "%%") + ("%s" if i < len(slots) else "") for i, p in enumerate(pieces))
        self.low = -min(offsets, default=0)
        self.high = MAX_COL - max(offsets, default=0)

    def render(self, col: int) -> str | None:
        if not self.low < col <= self.high:        # a reference left of column A or past XFD
            return None
        letters = [_columns()[0][col + o] for o in self.offsets]
        return self.text % tuple(letters[s] for s in self.slots)

    def render_many(self, col: int, n: int) -> list[str | None]:
        """The formulas of columns col ... col + n - 1."""
        if not (self.low < col and col + n - 1 <= self.high):
            return [self.render(c) for c in range(col, col + n)]
        if not self.offsets:
            return [self.pieces[0]] * n
        if len(self.offsets) == 1:                 # every relative column the same: join the letters in
            o = self.offsets[0]
            return list(map(str.join, _columns()[0][col + o:col + o + n], [self.pieces] * n))
        letters = [_columns()[0][col + o:col + o + n] for o in self.offsets]
        return list(map(self.text.__mod__, zip(*[letters[s] for s in self.slots], strict=True)))


class _Shared:
    """A shared formula's first cell; the texts of the block's other cells. Along the row
    (the way a formula is filled right) the text is the template rendered for the column,
    once the template gave openpyxl's translation for the first such cell; otherwise
    openpyxl's Translator."""

    def __init__(self, text: str, row: int, col: int):
        self.text, self.row, self.col = text, row, col
        self.template: Template | None = None
        self.agrees: bool | None = None

    def at(self, row: int, col: int) -> str:
        dr, dc = row - self.row, col - self.col
        if dr == 0 and dc > 0 and self.agrees is not False:
            if self.template is None:
                self.template = Template(self.text, self.col)
            text = self.template.render(col)
            if self.agrees and text is not None:
                return text
            translated = _shift_formula(self.text, dr, dc)
            self.agrees = text == translated
            return translated
        return _shift_formula(self.text, dr, dc)


def number(text: str) -> float | str:
    """A cell's number as the file holds it; NaN and infinities (no spreadsheet writes them,
    and 1e999 overflows) read as the error #NUM!, what a formula making them would give: a
    wrong row for the student, never a NaN reaching the validator."""
    x = float(text)
    return x if math.isfinite(x) else XlError("#NUM!")


def saved_error(text: str) -> XlError | str:
    """The value of a cell saved as an error (t="e"): the error, an XlError; a text that
    is no error Excel knows stays text (what the file says, shown as it is)."""
    return XlError(text) if text in ERRORS else text


def _shift_formula(formula: str, dr: int, dc: int) -> str:
    """The formula moved dr rows and dc columns (either may be negative: Excel writes a
    block ref="Y142:AR153" whose master cell is not its top-left corner). Absolute parts
    stay; a reference moved off the sheet becomes #REF!, as in Excel."""
    def col(abs_, letters):
        if abs_:
            return abs_ + letters
        c = _columns()[1][letters.upper()] + dc        # (references in any case: q1 is Q1)
        return _columns()[0][c] if 1 <= c <= MAX_COL else None

    def row(abs_, digits):
        if abs_:
            return abs_ + digits
        r = int(digits) + dr
        return str(r) if 1 <= r <= MAX_ROW else None

    def sub(m):
        if m.group("str") is not None:
            return m.group(0)
        if any(g is not None and g.upper() not in _columns()[1]
               for g in (m.group("col"), m.group("wc1"), m.group("wc2"))):
            return m.group(0)                 # past XFD (ZZZ9): a name, not a reference
        if any(g is not None and g.startswith("0") for g in (m.group("row"), m.group("wr1"), m.group("wr2"))):
            return m.group(0)                 # row 0 or a leading zero (A0, A01): no reference Excel writes
        if m.group("col") is not None:
            c, r = col(m.group("cabs"), m.group("col")), row(m.group("rabs"), m.group("row"))
            return "#REF!" if c is None or r is None else (m.group("sheet") or "") + c + r
        if m.group("wc1") is not None:
            a, b = col(m.group("wca"), m.group("wc1")), col(m.group("wcb"), m.group("wc2"))
            return "#REF!" if a is None or b is None else f"{m.group('wsheet') or ''}{a}:{b}"
        a, b = row(m.group("wra"), m.group("wr1")), row(m.group("wrb"), m.group("wr2"))
        return "#REF!" if a is None or b is None else f"{m.group('rsheet') or ''}{a}:{b}"

    out = _TEMPLATE_REF.sub(sub, formula)
    # a range one of whose ends left the sheet is #REF! as a whole
    return _BROKEN_RANGE.sub("#REF!", out) if "#REF!" in out else out


_BROKEN_RANGE = re.compile(r"#REF!:(?:#REF!|\$?[A-Za-z]{0,3}\$?\d*)|(?:\$?[A-Za-z]{1,3}\$?\d*|\$?\d+):#REF!")


def _shared_strings(pkg) -> list[str]:
    if "xl/sharedStrings.xml" not in pkg.names:
        return []
    root = pkg.xml("xl/sharedStrings.xml")
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    # the text is <si><t> or the <t> of each run <si><r><t>; a phonetic guide <si><rPh><t>
    # (furigana over Japanese text) is shown above the text, not part of it, as in Excel
    t, r = f"{ns}t", f"{ns}r"

    def text(si) -> str:
        parts = []
        for child in si:
            node = child if child.tag == t else child.find(t) if child.tag == r else None
            if node is not None:
                parts.append(node.text or "")
        return "".join(parts)
    return [capped(text(si)) for si in root.iter(f"{ns}si")]


def _defined_names(pkg) -> tuple[dict[str, str], dict[int, dict[str, str]]]:
    """The workbook's defined names: (workbook-scoped {name: text}, {sheet index: {name:
    text}} for the names scoped to one sheet, localSheetId). Excel's own hidden names
    (_xlnm.Print_Area ...) are kept: a formula cannot use them by that name anyway."""
    root = pkg.xml(pkg.workbook_part or "xl/workbook.xml")
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    glob: dict[str, str] = {}
    local: dict[int, dict[str, str]] = {}
    for d in root.iter(f"{ns}definedName"):
        name, text, scope = d.get("name"), d.text or "", d.get("localSheetId")
        if not name:
            continue
        if scope is None:
            glob[name] = text
        elif scope.strip().isdigit():
            local.setdefault(int(scope), {})[name] = text
    return glob, local


# --------------------------------------------------------------------------- evaluation

@dataclass
class RawBook:
    """A workbook as read: constants, formulas and cached values of every sheet."""
    path: str
    sheets: dict[str, Sheet]
    order: list[str]
    names: dict[str, str]


def read_book(path: str | Path, limits: Limits = Limits(), *, convert_timeout: float = 120,
              skip: frozenset[str] = frozenset(), needed_for: str | int | None = None,
              saved: bool = True) -> RawBook:
    """Read an .xlsx safely (package.py): never modified, never trusted. An OpenDocument
    spreadsheet (.ods, .fods) is converted to .xlsx by LibreOffice first (see
    `convert.converted`). skip: names of sheets the caller never reads (the validator's
    hidden `paths` sheet, 74% of a workbook's XML): listed, empty, their cells not parsed
    (the package gate has checked their part's size and shape all the same).
    needed_for: a sheet (its name, or 0 for the first) whose values alone the caller wants:
    only it and the sheets its formulas name, through each other, are read, the others
    listed empty as with skip (`sheetkin evaluate` prints one sheet); every sheet is read
    when the formulas' text cannot tell (see _sheets_named). saved=False: the values the
    file saved for formula cells (RawBook's Sheet.cached) may be left unread, as the
    evaluator computes them."""
    locked = password_protected(path)
    if locked:
        raise UnusableWorkbook(str(path), message("password_protected", what=locked),
                               message("workbook_saved_without_password"))
    if is_opendocument(path) or is_old_excel(path):
        with converted(path, limits, convert_timeout) as out:        # rare: read whole
            return _read_converted(out, str(path), limits)
    return _read_xlsx(path, limits, skip, needed_for, saved)


def _read_converted(out: Path, shown: str, limits: Limits) -> RawBook:
    try:
        raw = _read_xlsx(out, limits)
    except UnusableWorkbook as e:
        raise UnusableWorkbook(shown, f"(converted to .xlsx by LibreOffice) {e.problem}", e.expected,
                               e.part) from None
    raw.path = shown
    return raw



def _read_xlsx(path, limits: Limits, skip: frozenset[str] = frozenset(),
               needed_for: str | int | None = None, saved: bool = True) -> RawBook:
    pkg = open_package(path, limits)
    shared = _shared_strings(pkg)
    names, local = _defined_names(pkg)
    sheets: dict[str, Sheet] = {}
    order: list[str] = []
    held = 0
    infos = sheet_parts(pkg)
    if needed_for is not None and not _user_names(names, *local.values()):
        skip = skip | _not_needed(pkg, infos, needed_for, shared, limits, skip, sheets, saved)
    for i, info in enumerate(infos):
        if info.name in sheets:                     # read already (_not_needed)
            sh = sheets[info.name]
        elif info.name in skip:
            sh = sheets[info.name] = Sheet(info.name, info.state)
        else:
            sh = sheets[info.name] = _read_sheet(pkg, info.name, info.part, info.state, shared, limits,
                                                 limits.max_cells - held, saved)
        sh.names = local.get(i, {})
        held += len(sh.consts) + len(sh.formulas) + len(sh.dangling)
        order.append(info.name)
    return RawBook(str(path), {n: sheets[n] for n in order}, order, names)


def _user_names(*tables: dict[str, str]) -> bool:
    """Whether any defined name is the user's (a formula may read any sheet through it), not
    one of Excel's own (_xlnm.Print_Area ...: a formula cannot use them by that name)."""
    return any(not n.lower().startswith("_xlnm.") for table in tables for n in table)


def _not_needed(pkg, infos: list, needed_for: str | int, shared: list[str], limits: Limits,
                skip: frozenset[str], read: dict[str, Sheet], saved: bool = True) -> frozenset[str]:
    """The sheets that the sheet `needed_for` does not read, through its formulas and theirs
    (the sheets it reads are read here, into `read`); none when that cannot be told."""
    by_name = {info.name: info for info in infos if info.name not in skip}
    first = infos[0].name if needed_for == 0 and infos else needed_for
    if first not in by_name:
        return frozenset()
    todo, held = [first], 0
    while todo:
        info = by_name[todo.pop()]
        sh = read[info.name] = _read_sheet(pkg, info.name, info.part, info.state, shared, limits,
                                           limits.max_cells - held, saved, keep_text=True)
        held += len(sh.consts) + len(sh.formulas) + len(sh.dangling)
        named = _sheets_named(sh, list(by_name))
        sh.formula_bytes = None                     # (read for the scan only)
        if named is None:                           # every sheet read in order, as without needed_for
            for n in list(read):
                if n != infos[0].name or len(read) > 1:
                    del read[n]                     # (read again there, within the same caps)
            return frozenset()
        todo += [n for n in named if n not in read and n not in todo]
    return frozenset(by_name) - frozenset(read)


# What in a formula's text may read a sheet it does not name as Sheet! (or makes a sheet's
# used range matter: whole columns and rows end at the workbook's used range): a reference
# built from text (INDIRECT), the sheet functions, external and structured references
# ([..]); and after a colon, 3-D references (Sheet1:Sheet3!A1), whole columns (A:C) and
# rows (2:5). Looked for in the ASCII-lowercased UTF-8 text, strings included (a false alarm
# only reads every sheet). Each pattern with the literal it starts with, looked for first
# with `in`: a C search, 2-3x faster than the regex's own scan over the 360-column shaper's
# 3 MB of formulas, where only ":" occurs (issue 32).
_READS_UNNAMED = [(head, re.compile(p)) for head, p in (
    (b"indirect", rb"indirect"), (b"sheet", rb"sheets?\s*\("), (b"cell", rb"cell\s*\("),
    (b"info", rb"info\s*\("), (b"[", rb"\["),
    (b":", rb":\$?(?:[a-z]{1,3}|[0-9]+)(?![\w(.!$])|:'|:[^\W\d][\w.]*!"))]


def _sheets_named(sh: Sheet, sheet_names: list[str]) -> list[str] | None:
    """The sheets that sh's formulas may read: every sheet whose name, followed by "!"
    (quoted or not, in any case, as Excel compares sheet names), occurs in their text;
    None when the text does not tell (_READS_UNNAMED). A sheet without formulas reads none."""
    if not sh.formulas:
        return []
    if sh.formula_bytes is not None:
        # the reader's own UTF-8 text of the formulas, when they are all in the file as
        # they are (no shared formula's cells made by shifting: _cells_of): 5 MB in the
        # shaper, not joined and encoded again (issue 32)
        text = b"\0".join(sh.formula_bytes).lower()
    else:
        text = "\0".join(sh.formulas.values()).encode("utf-8").lower()
    if any(head in text and p.search(text) for head, p in _READS_UNNAMED):
        return None
    if b"!" not in text:                            # no sheet named (each name below looks for its "!")
        return []
    named, heads = [], None
    for name in sheet_names:
        low = name.encode("utf-8").lower()
        if low + b"!" in text or b"'" + low.replace(b"'", b"''") + b"'!" in text:
            named.append(name)
        elif not name.isascii():        # another case of its other letters: compared casefolded
            if heads is None:           # what precedes each "!", as long as a quoted name can be
                k = 4 * (2 * max(map(len, sheet_names)) + 2)       # 4: bytes of a character, at most
                heads = [b.decode("utf-8", "replace").casefold() for b in {p[-k:] for p in text.split(b"!")[:-1]}]
            n = name.casefold()
            if any(h.endswith(n) or h.endswith("'" + n.replace("'", "''") + "'") for h in heads):
                named.append(name)
    return named
