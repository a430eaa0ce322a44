"""Schema validation of .xlsx books: every XML part against the ISO/IEC 29500-4 Transitional
schemas (tests/data/ooxml-xsd, copied from the ISO/ECMA publication; README there).

Excel is strict about element order and required elements where LibreOffice is lenient, so a
schema-valid part is the best check, without Excel, that a book opens with no repair prompt.
A part is validated against the schema of its root element's namespace; a namespace with no
schema here (none in sheetkin's books today) is reported as a problem, not skipped.
"""
from __future__ import annotations

import io
import zipfile
from functools import cache
from pathlib import Path

from lxml import etree

XSD = Path(__file__).resolve().parents[1] / "data" / "ooxml-xsd"
ISO = "ISO-IEC29500-4_2016"
# root namespace -> schema file
SCHEMAS = {
    "http://schemas.openxmlformats.org/spreadsheetml/2006/main": f"{ISO}/sml.xsd",
    "http://schemas.openxmlformats.org/drawingml/2006/chart": f"{ISO}/dml-chart.xsd",
    "http://schemas.openxmlformats.org/drawingml/2006/spreadsheetDrawing": f"{ISO}/dml-spreadsheetDrawing.xsd",
    "http://schemas.openxmlformats.org/drawingml/2006/main": f"{ISO}/dml-main.xsd",
    "http://schemas.openxmlformats.org/officeDocument/2006/extended-properties":
        f"{ISO}/shared-documentPropertiesExtended.xsd",
    "http://schemas.openxmlformats.org/package/2006/content-types": "ecma/opc-contentTypes.xsd",
    "http://schemas.openxmlformats.org/package/2006/relationships": "ecma/opc-relationships.xsd",
    "http://schemas.openxmlformats.org/package/2006/metadata/core-properties": "ecma/opc-coreProperties-local.xsd",
}


@cache
def schema(namespace: str) -> etree.XMLSchema:
    return etree.XMLSchema(etree.parse(str(XSD / SCHEMAS[namespace])))


def schema_errors(book) -> list[str]:
    """Every schema error of every XML part of `book` (a path, bytes or a file object), one
    line each: "part:line: message"."""
    if isinstance(book, bytes):
        book = io.BytesIO(book)
    errors = []
    with zipfile.ZipFile(book) as z:
        for name in z.namelist():
            if not (name.endswith(".xml") or name.endswith(".rels")):
                continue
            doc = etree.fromstring(z.read(name), etree.XMLParser(huge_tree=True)).getroottree()
            ns = etree.QName(doc.getroot()).namespace
            if ns not in SCHEMAS:
                errors.append(f"{name}: no schema here for the namespace {ns}")
                continue
            xs = schema(ns)
            if not xs.validate(doc):
                errors += [f"{name}:{e.line}: {e.message}" for e in xs.error_log]
    return errors
