"""Text that a student (or a class list a student can edit) typed, made harmless for the
teacher (issue 30; docs/reliability.md, "What students type").

Three uses, three functions:

* `shown_text(text)` for a terminal, a report, an HTML page or a JSON string: every
  character that can move, hide or forge text is replaced by a visible escape
  (`\\u202e`, `\\x1b`, `\\r`, `\\n`): the bidirectional overrides and isolates
  (U+202A-202E, U+2066-2069, the marks U+200E, U+200F, U+061C), the zero-width characters
  (U+200B-200D, U+2060-2064, U+FEFF, U+180E), the line and paragraph separators
  (U+2028/9), the C0 controls (tab, CR, LF, ESC ...), DEL and the C1 controls
  (U+0080-009F, of which a terminal obeys CSI U+009B as it obeys ESC [). The escape *is*
  the mark that something was there: the teacher sees `Ива\\u200bнов`, not a name that only
  looks like a classmate's; nothing is dropped, so the raw text can be read back from it.
* `compare_key(text)` for comparing names: the same characters removed, NFKC (full-width
  and other compatibility forms folded: `Ｉｖａｎｏｖ` is `Ivanov`), case folded.
* `csv_cell(text)` for a CSV cell: `shown_text`, then an apostrophe before a leading `=`,
  `+`, `-`, `@`, tab or carriage return (also after leading spaces), as OWASP's CSV
  injection guidance says; Excel and LibreOffice show the text without the apostrophe.
  `from_csv_cell` undoes the apostrophe when sheetkin reads its own CSV back.

Only the standard library: every stage may import it (it sits beside sheetkin.files).
"""
from __future__ import annotations

import re
import unicodedata

FORMULA_START = ("=", "+", "-", "@", "\t", "\r")     # what a spreadsheet takes for a formula

# the characters shown_text escapes and compare_key removes
_HIDDEN = ("\u0000-\u001f\u007f-\u009f"          # C0 controls (ESC, CR, LF, tab ...), DEL, C1 controls
           "\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069"   # bidi marks, embeddings, overrides, isolates
           "\u200b-\u200d\u2060-\u2064\ufeff\u180e"         # zero-width and invisible characters
           "\u2028\u2029")                                  # line and paragraph separators
_HIDDEN_RE = re.compile(f"[{_HIDDEN}]")
_NAMED = {"\t": "\\t", "\r": "\\r", "\n": "\\n"}


def _escape(m: re.Match) -> str:
    c = m.group()
    return _NAMED.get(c) or (f"\\x{ord(c):02x}" if ord(c) < 0x100 else f"\\u{ord(c):04x}")


def has_hidden(text: str) -> bool:
    """Whether `text` holds a character shown_text escapes."""
    return bool(_HIDDEN_RE.search(text))


def shown_text(text: object) -> str:
    """`text` with every control, bidi and zero-width character as a visible escape."""
    s = "" if text is None else str(text)
    return _HIDDEN_RE.sub(_escape, s) if _HIDDEN_RE.search(s) else s


_ESCAPED_RE = re.compile(r"\\(x[0-9a-f]{2}|u[0-9a-f]{4}|[trn])")
_SPACES = "\t\r\n\u2028\u2029"


def _unescape_hidden(m: re.Match) -> str:
    code = m.group(1)
    c = {"t": "\t", "r": "\r", "n": "\n"}.get(code) or chr(int(code[1:], 16))
    return (" " if c in _SPACES else "") if _HIDDEN_RE.match(c) else m.group()


def plain_text(text: object) -> str:
    """`text` without those characters (a tab, CR or LF becomes a space), in NFKC. A text
    already passed through shown_text gives the same: its escapes of those characters are
    removed as they are (plain_text(shown_text(t)) == plain_text(t))."""
    s = "" if text is None else str(text)
    if "\\" in s:
        s = _ESCAPED_RE.sub(_unescape_hidden, s)
    s = re.sub(f"[{_SPACES}]", " ", s)
    return unicodedata.normalize("NFKC", _HIDDEN_RE.sub("", s))


def compare_key(text: object) -> str:
    """A text for comparing names: plain_text, case folded, spaces collapsed."""
    return " ".join(plain_text(text).casefold().split())


def csv_cell(text: object) -> str:
    """A CSV cell that a spreadsheet keeps as text and that shows no hidden character."""
    raw = "" if text is None else str(text)
    s = shown_text(raw)
    # judged on the text as typed (a leading tab is a formula's start for OWASP, also when
    # it is shown as \t) and as written
    formula = raw.lstrip(" ").startswith(FORMULA_START) or s.lstrip(" ").startswith(FORMULA_START)
    return "'" + s if formula else s


def from_csv_cell(text: str) -> str:
    """A cell of a CSV file csv_cell wrote, as it was typed (the apostrophe removed)."""
    starts = (*FORMULA_START, "\\t", "\\r")         # a tab or CR shown as its escape
    return text[1:] if text.startswith("'") and text[1:].lstrip(" ").startswith(starts) else text
