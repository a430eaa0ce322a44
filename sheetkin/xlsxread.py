"""Reading a workbook's cells: constants, formulas and the values the spreadsheet cached.

The sheet XML is read directly (an .xlsx is a zip of XML parts), through the input gate
(xlsxsafe): never modified, never trusted. Shared formulas (LibreOffice, Excel) are expanded.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from xml.etree import ElementTree

from openpyxl.utils import get_column_letter

from .xlsxsafe import Limits, UnusableWorkbook, open_package, sheet_parts

_LETTERS = [""] + [get_column_letter(c) for c in range(1, 16385)]   # Excel's last column is XFD
_COLUMN_INDEX = {letters: c for c, letters in enumerate(_LETTERS) if c}


@dataclass
class Sheet:
    name: str
    state: str
    consts: dict = field(default_factory=dict)    # (r, c) -> value (number, str, bool, error text)
    formulas: dict = field(default_factory=dict)  # (r, c) -> formula text (without "=")
    cached: dict = field(default_factory=dict)    # (r, c) -> cached value of a formula cell
    max_row: int = 0
    max_col: int = 0



def _read_sheet(pkg, name: str, part: str, state: str, shared: list[str], limits: Limits) -> Sheet:
    sh = Sheet(name, state)
    # The C parser directly, not defusedxml's (which calls back into Python for every
    # element, 4x slower here): safe because open_package refused every part that declares
    # a DTD or an entity, the only way to an entity bomb or an external entity.
    if not part.lower().endswith(".xml"):           # only .xml parts were pre-scanned
        root = pkg.xml(part)
    else:
        try:
            root = ElementTree.fromstring(pkg.read(part))
        except ElementTree.ParseError as e:
            raise UnusableWorkbook(pkg.path, f"not well-formed XML ({e})", "a sheet saved by Excel or LibreOffice",
                                   part=part) from None
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    shared_f: dict[str, tuple[str, int, int]] = {}
    f_tag, v_tag, is_tag, t_tag = f"{ns}f", f"{ns}v", f"{ns}is", f"{ns}t"
    col_of = _COLUMN_INDEX
    for c in root.iter(f"{ns}c"):
        ref = c.get("r") or ""
        letters = ref.rstrip("0123456789")
        col = col_of.get(letters)
        if col is None or not ref[len(letters):].isdigit():
            raise UnusableWorkbook(pkg.path, f"a cell without a valid reference ({ref!r})",
                                   "cells named like A1", part=part)
        row = int(ref[len(letters):])
        if row > limits.max_rows or col > limits.max_cols:
            raise UnusableWorkbook(pkg.path, f"sheet '{name}' has a cell at {ref}",
                                   f"at most {limits.max_rows} rows and {limits.max_cols} columns")
        if row > sh.max_row:
            sh.max_row = row
        if col > sh.max_col:
            sh.max_col = col
        f = v = inline = None
        for child in c:                    # one pass over <f>, <v>, <is>
            tag = child.tag
            if tag == v_tag:
                v = child
            elif tag == f_tag:
                f = child
            elif tag == is_tag:
                inline = child
        t = c.get("t", "n")
        vtext = v.text if v is not None else None
        if t == "s" and vtext is not None:
            value = shared[int(vtext)]
        elif t == "inlineStr" and inline is not None:
            value = "".join(x.text or "" for x in inline.iter(t_tag))
        elif t == "b" and vtext is not None:
            value = vtext.strip() == "1"
        elif t in ("e", "str") and vtext is not None:
            value = vtext
        elif vtext is not None:
            value = float(vtext)
        else:
            value = None
        if f is not None:
            text = f.text
            if f.get("t") == "shared":
                si = f.get("si")
                if text:
                    shared_f[si] = (text, row, col)
                elif si in shared_f:
                    master, mr, mc = shared_f[si]
                    text = _shift_formula(master, row - mr, col - mc)
            if text:
                sh.formulas[(row, col)] = text
                if value is not None:
                    sh.cached[(row, col)] = value
                continue
        if value is not None:
            sh.consts[(row, col)] = value
    return sh


def _shift_formula(formula: str, dr: int, dc: int) -> str:
    from openpyxl.formula.translate import Translator
    return Translator("=" + formula, origin="A1").translate_formula(
        f"{get_column_letter(1 + dc)}{1 + dr}")[1:] if (dr >= 0 and dc >= 0) else formula


def _shared_strings(pkg) -> list[str]:
    if "xl/sharedStrings.xml" not in pkg.names:
        return []
    root = pkg.xml("xl/sharedStrings.xml")
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    return ["".join(t.text or "" for t in si.iter(f"{ns}t")) for si in root.iter(f"{ns}si")]


def _defined_names(pkg) -> dict[str, str]:
    root = pkg.xml("xl/workbook.xml")
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    return {d.get("name"): (d.text or "") for d in root.iter(f"{ns}definedName")
            if d.get("localSheetId") is None}


# --------------------------------------------------------------------------- evaluation

@dataclass
class RawBook:
    """A workbook as read: constants, formulas and cached values of every sheet."""
    path: str
    sheets: dict[str, Sheet]
    order: list[str]
    names: dict[str, str]


def read_book(path: str | Path, limits: Limits = Limits()) -> RawBook:
    """Read an .xlsx safely (xlsxsafe): never modified, never trusted."""
    pkg = open_package(path, limits)
    shared = _shared_strings(pkg)
    names = _defined_names(pkg)
    sheets, order = {}, []
    for info in sheet_parts(pkg):
        sheets[info.name] = _read_sheet(pkg, info.name, info.part, info.state, shared, limits)
        order.append(info.name)
    return RawBook(str(path), sheets, order, names)


