"""Writers for the real-file tests (test_real_files.py): spreadsheets in the two shapes
the evaluator meets in the wild, built by hand so that every feature is there on purpose.

* `fods(...)`: LibreOffice's flat ODF XML (.fods), written as a person would write it; the
  tests have LibreOffice convert it to .xlsx (its own XML: no shared formulas, `aca`
  attributes, styled empty cells, names with localSheetId).
* `xlsx(...)`: a package in Excel's own XML shape: shared formulas (`<f t="shared" ref=..
  si=..>`), array formulas (`<f t="array" ref=..>`), dynamic-array spills (`cm="1"` and
  xl/metadata.xml), defined names with localSheetId, cached values.
"""
from __future__ import annotations

import re
import zipfile
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from openpyxl.utils import column_index_from_string

MAIN_NS = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
REL_NS = "http://schemas.openxmlformats.org/officeDocument/2006/relationships"
PKG_REL_NS = "http://schemas.openxmlformats.org/package/2006/relationships"
_CT = "application/vnd.openxmlformats-officedocument.spreadsheetml"


# ------------------------------------------------------------------ Excel's shape
def cell(ref: str, value=None, f: str | None = None, fattrs: str = "", attrs: str = "") -> str:
    """One <c>: a value (number, bool, text, "#ERR!"), a formula with its <f> attributes
    (t="shared" ref=.. si=.., t="array" ref=..) and the value cached for it."""
    t = ""
    v = ""
    if isinstance(value, bool):
        t, v = ' t="b"', f"<v>{int(value)}</v>"
    elif isinstance(value, (int, float)):
        v = f"<v>{value!r}</v>"
    elif isinstance(value, str) and value.startswith("#"):
        t, v = ' t="e"', f"<v>{escape(value)}</v>"
    elif isinstance(value, str):
        if f is None:
            return f'<c r="{ref}" t="inlineStr"{attrs}><is><t>{escape(value)}</t></is></c>'
        t, v = ' t="str"', f"<v>{escape(value)}</v>"
    fx = ""
    if f is not None:
        fx = f"<f{fattrs}>{escape(f)}</f>" if f else f"<f{fattrs}/>"
    return f'<c r="{ref}"{t}{attrs}>{fx}{v}</c>'


def _row_of(ref: str) -> int:
    return int(re.sub(r"[^0-9]", "", ref))


def sheet_xml(cells: list[str], *, dimension: str | None = None, cols: str = "", rows: dict | None = None) -> str:
    """A worksheet part: the cells grouped into rows (extra row attributes by row number:
    `rows`), with an optional <dimension ref> and <cols>."""
    by_row: dict[int, list[str]] = {}
    for c in cells:
        by_row.setdefault(_row_of(re.search(r'r="([A-Z]+[0-9]+)"', c).group(1)), []).append(c)
    for r in rows or {}:
        by_row.setdefault(r, [])

    def col_key(c):
        return column_index_from_string(re.search(r'r="([A-Z]+)', c).group(1))
    body = "".join(f'<row r="{r}"{(rows or {}).get(r, "")}>{"".join(sorted(cs, key=col_key))}</row>'
                   for r, cs in sorted(by_row.items()))
    dim = f'<dimension ref="{dimension}"/>' if dimension else ""
    return (f'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<worksheet xmlns="{MAIN_NS}" '
            f'xmlns:r="{REL_NS}">{dim}{cols}<sheetData>{body}</sheetData></worksheet>')


def xlsx(path: Path, sheets: list[tuple[str, str]], names: list[tuple[str, str, int | None]] = (),
         dynamic: bool = False) -> Path:
    """An .xlsx of the given (name, sheet XML) and defined names (name, text, localSheetId
    or None); with `dynamic`, the xl/metadata.xml Excel 365 writes for cm="1" cells."""
    ct = [f'<Override PartName="/xl/workbook.xml" ContentType="{_CT}.sheet.main+xml"/>']
    rels = []
    for i, _ in enumerate(sheets, 1):
        ct.append(f'<Override PartName="/xl/worksheets/sheet{i}.xml" ContentType="{_CT}.worksheet+xml"/>')
        rels.append(f'<Relationship Id="rId{i}" Type="{REL_NS}/worksheet" Target="worksheets/sheet{i}.xml"/>')
    if dynamic:
        ct.append(f'<Override PartName="/xl/metadata.xml" ContentType="{_CT}.sheetMetadata+xml"/>')
        rels.append(f'<Relationship Id="rId90" Type="{REL_NS}/sheetMetadata" Target="metadata.xml"/>')
    sheet_list = "".join(f'<sheet name={quoteattr(n)} sheetId="{i}" r:id="rId{i}"/>'
                         for i, (n, _) in enumerate(sheets, 1))
    defined = "".join(f'<definedName name="{n}"{"" if s is None else f" localSheetId={chr(34)}{s}{chr(34)}"}>'
                      f"{escape(text)}</definedName>" for n, text, s in names)
    workbook = (f'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<workbook xmlns="{MAIN_NS}" '
                f'xmlns:r="{REL_NS}"><sheets>{sheet_list}</sheets>'
                + (f"<definedNames>{defined}</definedNames>" if defined else "") + "</workbook>")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml",
                   '<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<Types xmlns="http://schemas.'
                   'openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="'
                   'application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" '
                   f'ContentType="application/xml"/>{"".join(ct)}</Types>')
        z.writestr("_rels/.rels", f'<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="{PKG_REL_NS}">'
                   f'<Relationship Id="rId1" Type="{REL_NS}/officeDocument" Target="xl/workbook.xml"/>'
                   "</Relationships>")
        z.writestr("xl/workbook.xml", workbook)
        z.writestr("xl/_rels/workbook.xml.rels", f'<?xml version="1.0" encoding="UTF-8"?>\n<Relationships '
                   f'xmlns="{PKG_REL_NS}">{"".join(rels)}</Relationships>')
        for i, (_, xml) in enumerate(sheets, 1):
            z.writestr(f"xl/worksheets/sheet{i}.xml", xml)
        if dynamic:
            z.writestr("xl/metadata.xml", _METADATA)
    return path


# what Excel 365 writes for a dynamic-array formula (cell metadata 1 = XLDAPR, fDynamic)
_METADATA = (f'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n<metadata xmlns="{MAIN_NS}" '
             'xmlns:xda="http://schemas.microsoft.com/office/spreadsheetml/2017/dynamicarray">'
             '<metadataTypes count="1"><metadataType name="XLDAPR" minSupportedVersion="120000" copy="1" '
             'pasteAll="1" pasteValues="1" merge="1" splitFirst="1" rowColShift="1" clearFormats="1" '
             'clearComments="1" assign="1" coerce="1" cellMeta="1"/></metadataTypes><futureMetadata '
             'name="XLDAPR" count="1"><bk><extLst><ext uri="{bdbb8cdc-fa1e-496e-a857-3c3f30c029c3}">'
             '<xda:dynamicArrayProperties fDynamic="1" fCollapsed="0"/></ext></extLst></bk></futureMetadata>'
             '<cellMetadata count="1"><bk><rc t="1" v="0"/></bk></cellMetadata></metadata>')


# ------------------------------------------------------------------ LibreOffice's flat ODF
_FODS_HEAD = (
    '<?xml version="1.0" encoding="UTF-8"?>\n<office:document '
    'xmlns:office="urn:oasis:names:tc:opendocument:xmlns:office:1.0" '
    'xmlns:style="urn:oasis:names:tc:opendocument:xmlns:style:1.0" '
    'xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" '
    'xmlns:text="urn:oasis:names:tc:opendocument:xmlns:text:1.0" '
    'xmlns:fo="urn:oasis:names:tc:opendocument:xmlns:xsl-fo-compatible:1.0" '
    'xmlns:of="urn:oasis:names:tc:opendocument:xmlns:of:1.2" office:version="1.2" '
    'office:mimetype="application/vnd.oasis.opendocument.spreadsheet">'
    '<office:automatic-styles>'
    '<style:style style:name="ce1" style:family="table-cell"><style:table-cell-properties '
    'fo:background-color="#ffff00"/></style:style>'
    '<style:style style:name="ro1" style:family="table-row"><style:table-row-properties '
    'style:row-height="0.5cm"/></style:style></office:automatic-styles>')


def num(x) -> str:
    return f'<table:table-cell office:value-type="float" office:value="{x!r}"/>'


def text(s: str) -> str:
    return f'<table:table-cell office:value-type="string"><text:p>{escape(s)}</text:p></table:table-cell>'


def formula(f: str, matrix: tuple[int, int] | None = None) -> str:
    """A formula cell in ODF syntax (of:=[.A1]*2, arguments separated by ;); `matrix`
    (rows, columns) makes it an array formula over that many cells."""
    m = ("" if matrix is None else f' table:number-matrix-rows-spanned="{matrix[0]}" '
         f'table:number-matrix-columns-spanned="{matrix[1]}"')
    return f"<table:table-cell table:formula={quoteattr('of:=' + f)}{m}/>"


def empty(n: int = 1) -> str:
    return f'<table:table-cell table:number-columns-repeated="{n}"/>' if n > 1 else "<table:table-cell/>"


def named(name: str, target: str) -> str:
    """A named range (target in ODF syntax: $Calc.$B$1 or $Calc.$B$1:.$B$3)."""
    return (f'<table:named-range table:name="{name}" table:base-cell-address="$Calc.$A$1" '
            f'table:cell-range-address="{target}"/>')


def named_expression(name: str, expression: str) -> str:
    return (f'<table:named-expression table:name="{name}" table:base-cell-address="$Calc.$A$1" '
            f'table:expression="of:={escape(expression)}"/>')


def table(name: str, rows: list[list[str]], local_names: list[str] = (), styled: bool = False) -> str:
    """A sheet; with `styled`, every column and every row down to 1,048,576 has a style,
    as a sheet formatted by selecting whole columns looks."""
    cols = '<table:table-column table:default-cell-style-name="ce1" table:number-columns-repeated="1024"/>' \
        if styled else ""
    body = "".join(f'<table:table-row{" table:style-name=" + chr(34) + "ro1" + chr(34) if styled else ""}>'
                   f'{"".join(r)}</table:table-row>' for r in rows)
    if styled:
        body += (f'<table:table-row table:style-name="ro1" table:number-rows-repeated="{1048576 - len(rows)}">'
                 '<table:table-cell table:style-name="ce1" table:number-columns-repeated="1024"/>'
                 "</table:table-row>")
    names = f"<table:named-expressions>{''.join(local_names)}</table:named-expressions>" if local_names else ""
    return f'<table:table table:name="{name}">{cols}{body}{names}</table:table>'


def fods(path: Path, tables: list[str], names: list[str] = ()) -> Path:
    ne = f"<table:named-expressions>{''.join(names)}</table:named-expressions>" if names else ""
    path.write_text(f"{_FODS_HEAD}<office:body><office:spreadsheet>{''.join(tables)}{ne}"
                    "</office:spreadsheet></office:body></office:document>", "utf-8")
    return path


def ods(path: Path, fods_path: Path) -> Path:
    """The same spreadsheet as a zipped .ods (mimetype first, stored; content.xml)."""
    flat = fods_path.read_text("utf-8")
    content = flat.replace("<office:document ", "<office:document-content ", 1).replace(
        "</office:document>", "</office:document-content>")
    content = re.sub(r' office:mimetype="[^"]*"', "", content, count=1)
    manifest = ('<?xml version="1.0" encoding="UTF-8"?>\n<manifest:manifest xmlns:manifest="urn:oasis:names:'
                'tc:opendocument:xmlns:manifest:1.0" manifest:version="1.2"><manifest:file-entry '
                'manifest:full-path="/" manifest:media-type="application/vnd.oasis.opendocument.spreadsheet"/>'
                '<manifest:file-entry manifest:full-path="content.xml" manifest:media-type="text/xml"/>'
                "</manifest:manifest>")
    with zipfile.ZipFile(path, "w") as z:
        z.writestr(zipfile.ZipInfo("mimetype"), "application/vnd.oasis.opendocument.spreadsheet",
                   compress_type=zipfile.ZIP_STORED)
        z.writestr("content.xml", content, compress_type=zipfile.ZIP_DEFLATED)
        z.writestr("META-INF/manifest.xml", manifest, compress_type=zipfile.ZIP_DEFLATED)
    return path
