"""sheetkin.xlsx.package: untrusted .xlsx input is refused with one line, never a traceback.

Every bad input is built here, in tmp_path, from an openpyxl workbook, zipfile and raw bytes.
"""
from __future__ import annotations

import io
import os
import struct
import zipfile
import zlib
from pathlib import Path

import openpyxl
import pytest

from sheetkin.xlsx.package import (
    Limits,
    Package,
    SheetPart,
    UnusableWorkbook,
    check_dimension,
    check_openpyxl_safe,
    open_package,
    sheet_dimension,
    sheet_parts,
)

REPO = Path(__file__).resolve().parents[2]
SHEET = "xl/worksheets/sheet1.xml"
BILLION_LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>
<row r="1"><c r="A1" t="inlineStr"><is><t>&lol9;</t></is></c></row></sheetData></worksheet>
"""
SST_BOMB = BILLION_LAUGHS.replace(
    b'<worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>\n'
    b'<row r="1"><c r="A1" t="inlineStr"><is><t>&lol9;</t></is></c></row></sheetData></worksheet>',
    b'<sst xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" count="1" '
    b'uniqueCount="1"><si><t>&lol9;</t></si></sst>')
REL_NS = "http://schemas.openxmlformats.org/officeDocument/2006/relationships"


# -- builders ---------------------------------------------------------------------------------
def good_workbook(path: Path) -> Path:
    """A normal openpyxl workbook: three sheets (one hidden, non-ASCII names), strings, formulas."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Кинематика"
    ws.append(["phi, deg", "x_A, m"])
    for r in range(2, 12):
        ws.cell(r, 1, 10 * (r - 2))
        ws.cell(r, 2, f"=0.14*COS(RADIANS(A{r}))")
    hidden = wb.create_sheet("scene")
    hidden["A1"] = "l1 = 0.14"
    hidden.sheet_state = "hidden"
    wb.create_sheet("Графики")["A1"] = "chart here"
    wb.save(path)
    return path


def rewrite(src: Path, dst: Path, *, add: dict | None = None, replace: dict | None = None,
            drop: tuple = (), compression=zipfile.ZIP_DEFLATED) -> Path:
    """Copy the zip `src` to `dst`, dropping, replacing and adding members."""
    add, replace = add or {}, replace or {}
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w", compression) as zout:
        for info in zin.infolist():
            if info.filename in drop:
                continue
            data = replace.get(info.filename, zin.read(info.filename))
            if callable(data):
                data = data(zin.read(info.filename))
            zout.writestr(info.filename, data)
        for name, data in add.items():
            zout.writestr(name, data)
    return dst


def patch_central(data: bytes, name: str, **fields) -> bytes:
    """`data` with fields (flags, crc, file_size) of `name`'s central directory entry patched."""
    offsets = {"flags": (8, "<H"), "crc": (16, "<L"), "file_size": (24, "<L")}
    buf = bytearray(data)
    pos = buf.find(b"PK\x01\x02")
    while pos >= 0:
        nlen = struct.unpack_from("<H", buf, pos + 28)[0]
        if buf[pos + 46:pos + 46 + nlen].decode() == name:
            for field, value in fields.items():
                off, fmt = offsets[field]
                struct.pack_into(fmt, buf, pos + off, value)
            return bytes(buf)
        pos = buf.find(b"PK\x01\x02", pos + 4)
    raise AssertionError(f"{name} not in the central directory")


def refused(path, *words: str, limits: Limits = Limits()) -> str:
    """The message open_package gives for `path`: one line, the path first, naming `words`."""
    with pytest.raises(UnusableWorkbook) as info:
        open_package(path, limits)
    return assert_message(info.value, path, *words)


def assert_message(err: UnusableWorkbook, path, *words: str) -> str:
    msg = str(err)
    assert isinstance(err, ValueError)
    assert "\n" not in msg and "\r" not in msg and "Traceback" not in msg, msg
    assert msg.startswith(f"{path}: "), msg
    assert "; " in msg, msg  # <what is wrong>; <what was expected>
    for w in words:
        assert w.lower() in msg.lower(), (w, msg)
    return msg


@pytest.fixture
def good(tmp_path) -> Path:
    return good_workbook(tmp_path / "good.xlsx")


# -- usable workbooks -------------------------------------------------------------------------
def test_normal_workbook_opens_and_lists_sheets_in_order(good):
    pkg = open_package(good)
    assert isinstance(pkg, Package)
    assert "[Content_Types].xml" in pkg.names and "xl/workbook.xml" in pkg.names
    assert pkg.workbook_part == "xl/workbook.xml"
    assert sheet_parts(pkg) == [
        SheetPart("Кинематика", "xl/worksheets/sheet1.xml", "visible", "worksheet"),
        SheetPart("scene", "xl/worksheets/sheet2.xml", "hidden", "worksheet"),
        SheetPart("Графики", "xl/worksheets/sheet3.xml", "visible", "worksheet"),
    ]
    name, part, *_ = sheet_parts(pkg)[0]
    assert (name, part) == ("Кинематика", SHEET)
    assert sheet_dimension(pkg, SHEET) == (11, 2)


def test_xml_parses_a_sheet_and_iterparse_streams_it(good):
    pkg = open_package(good)
    root = pkg.xml(SHEET)
    ns = "{http://schemas.openxmlformats.org/spreadsheetml/2006/main}"
    formulas = [f.text for f in root.iter(ns + "f")]
    assert formulas[0] == "0.14*COS(RADIANS(A2))" and len(formulas) == 10
    cells = [el.get("r") for _ev, el in pkg.iterparse(SHEET) if el.tag == ns + "c"]
    assert cells[:3] == ["A1", "B1", "A2"] and len(cells) == 22
    assert pkg.read(SHEET) == zipfile.ZipFile(good).read(SHEET)


def test_relative_and_absolute_relationship_targets(good, tmp_path):
    # openpyxl writes absolute targets (/xl/worksheets/...); Excel writes relative ones.
    rels = "xl/_rels/workbook.xml.rels"
    assert b'Target="/xl/worksheets/sheet1.xml"' in zipfile.ZipFile(good).read(rels)
    relative = rewrite(good, tmp_path / "relative.xlsx", replace={
        rels: lambda b: b.replace(b'Target="/xl/worksheets/', b'Target="worksheets/')})
    assert [s.part for s in sheet_parts(open_package(relative))] == [
        "xl/worksheets/sheet1.xml", "xl/worksheets/sheet2.xml", "xl/worksheets/sheet3.xml"]


@pytest.mark.parametrize("name", ["fourbar.xlsx", "shaper.xlsx"])
def test_sheetkins_own_workbooks_open(name):
    pkg = open_package(REPO / "workbooks" / name)
    assert [s.name for s in sheet_parts(pkg)][0] == "Кинематика"


def test_hyperlinks_are_not_external_links(good, tmp_path):
    wb = openpyxl.load_workbook(good)
    wb.active["C1"].hyperlink = "https://example.org/course"
    wb.save(tmp_path / "link.xlsx")
    open_package(tmp_path / "link.xlsx")


def test_openpyxl_uses_defusedxml():
    assert check_openpyxl_safe() is True


def test_openpyxl_can_load_the_checked_bytes(good):
    pkg = open_package(good)
    wb = openpyxl.load_workbook(io.BytesIO(pkg.data))
    assert wb.sheetnames == ["Кинематика", "scene", "Графики"]


def test_input_never_modified(good):
    os.chmod(good, 0o444)  # read-only is enough
    before, mtime = good.read_bytes(), good.stat().st_mtime_ns
    pkg = open_package(good)
    for name in pkg.names:
        pkg.read(name)
    pkg.xml(SHEET)
    list(pkg.iterparse(SHEET))
    sheet_parts(pkg)
    openpyxl.load_workbook(io.BytesIO(pkg.data))
    assert good.read_bytes() == before
    assert good.stat().st_mtime_ns == mtime


# -- not a workbook at all --------------------------------------------------------------------
def test_missing_path_and_directory(tmp_path):
    refused(tmp_path / "nope.xlsx", "no such file")
    refused(tmp_path, "is a directory")
    with pytest.raises(UnusableWorkbook, match=r"^bad\\x00name\.xlsx: cannot be read"):
        open_package("bad\0name.xlsx")


def test_control_characters_in_the_path_are_escaped(tmp_path):
    p = tmp_path / "two\nlines.xlsx"
    p.write_text("not a workbook")
    with pytest.raises(UnusableWorkbook) as info:
        open_package(p)
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith(str(p).replace("\n", "\\n") + ": not an .xlsx file")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_fifo_is_not_read(tmp_path):
    os.mkfifo(tmp_path / "pipe.xlsx")
    refused(tmp_path / "pipe.xlsx", "not a regular file")


def test_text_file_renamed_xlsx(tmp_path):
    p = tmp_path / "answers.xlsx"
    p.write_text("phi;x_A\n0;0.14\n", encoding="utf-8")
    refused(p, "not an .xlsx file", "not a zip archive", "plain text")


def test_html_renamed_xlsx(tmp_path):
    p = tmp_path / "page.xlsx"
    p.write_text("<html><body><table></table></body></html>")
    refused(p, "not an .xlsx file", "XML or HTML")


def test_empty_file(tmp_path):
    p = tmp_path / "empty.xlsx"
    p.write_bytes(b"")
    refused(p, "empty file")


def test_old_binary_xls(tmp_path):
    p = tmp_path / "old.xlsx"
    p.write_bytes(b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + bytes(4096))
    refused(p, "not an .xlsx file", ".xls")


def test_password_protected_workbook_is_an_ole_file(tmp_path):
    # Excel's "Encrypt with password" writes an OLE compound file holding "EncryptedPackage".
    p = tmp_path / "secret.xlsx"
    p.write_bytes(b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + bytes(600)
                  + "EncryptedPackage".encode("utf-16-le") + bytes(600))
    refused(p, "password-protected")


def test_ods_like_zip(tmp_path):
    p = tmp_path / "lab.xlsx"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("mimetype", "application/vnd.oasis.opendocument.spreadsheet",
                   compress_type=zipfile.ZIP_STORED)
        z.writestr("content.xml", "<office:document-content/>")
        z.writestr("META-INF/manifest.xml", "<manifest/>")
    refused(p, "not an .xlsx file", "OpenDocument", ".ods")


def test_plain_zip_and_zip_without_workbook(good, tmp_path):
    p = tmp_path / "plain.xlsx"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("answers.txt", "42")
    refused(p, "not a spreadsheet package", "[Content_Types].xml")
    no_wb = rewrite(good, tmp_path / "nowb.xlsx", drop=("xl/workbook.xml", "_rels/.rels"))
    refused(no_wb, "not a spreadsheet package", "workbook")
    no_wb2 = rewrite(good, tmp_path / "nowb2.xlsx", drop=("xl/workbook.xml",))
    refused(no_wb2, "not a spreadsheet package", "workbook")


def test_word_document(tmp_path):
    p = tmp_path / "report.xlsx"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("[Content_Types].xml", "<Types/>")
        z.writestr("word/document.xml", "<w:document/>")
    refused(p, "not a spreadsheet", "Word")


def test_file_too_big(good):
    refused(good, "file is", "at most 1000 bytes", limits=Limits(max_file_bytes=1000))


# -- corrupt zips -----------------------------------------------------------------------------
def test_truncated_xlsx(good, tmp_path):
    p = tmp_path / "cut.xlsx"
    data = good.read_bytes()
    p.write_bytes(data[:len(data) // 2])
    refused(p, "corrupt or truncated zip")


def test_bad_crc_in_a_stored_member(good, tmp_path):
    p = rewrite(good, tmp_path / "stored.xlsx", compression=zipfile.ZIP_STORED)
    open_package(p)  # stored members are fine
    data = bytearray(p.read_bytes())
    info = zipfile.ZipFile(p).getinfo(SHEET)
    nlen, xlen = struct.unpack_from("<HH", data, info.header_offset + 26)
    start = info.header_offset + 30 + nlen + xlen
    data[start + info.compress_size // 2] ^= 0x01  # one flipped bit inside the sheet's XML
    p.write_bytes(bytes(data))
    refused(p, "corrupt zip", "CRC", SHEET)


def test_bad_deflate_data(good, tmp_path):
    data = bytearray(good.read_bytes())
    info = zipfile.ZipFile(good).getinfo(SHEET)
    nlen, xlen = struct.unpack_from("<HH", data, info.header_offset + 26)
    start = info.header_offset + 30 + nlen + xlen
    data[start:start + 40] = b"\xff" * 40
    p = tmp_path / "garbled.xlsx"
    p.write_bytes(bytes(data))
    refused(p, "corrupt zip", SHEET)


def test_encrypted_entries(good, tmp_path):
    p = tmp_path / "enc.xlsx"
    p.write_bytes(patch_central(good.read_bytes(), SHEET, flags=0x1))
    refused(p, "encrypted")


def _big_part_workbook(good, tmp_path, size=2_000_000) -> tuple[Path, bytes]:
    """The good workbook plus a deflated XML part of `size` bytes (compresses ~50:1)."""
    body = b"".join(b'<r n="%d"/>' % i for i in range(size // 8))[:size - 7]
    body = b"<a>" + body + b"</a>"
    body = body + b" " * (size - len(body))
    return rewrite(good, tmp_path / "big.xlsx", add={"customXml/item1.xml": body}), body


def test_header_that_lies_about_size(good, tmp_path):
    p, body = _big_part_workbook(good, tmp_path)
    open_package(p)
    liar = tmp_path / "liar.xlsx"
    liar.write_bytes(patch_central(p.read_bytes(), "customXml/item1.xml", file_size=1000))
    refused(liar, "corrupt zip", "customXml/item1.xml", "more than the 1000 bytes its header says")
    # zipfile itself stops at the declared size; with the CRC of that prefix patched in too,
    # it returns the 1000 bytes silently. Inflating independently still catches the lie.
    crafty = tmp_path / "crafty.xlsx"
    crafty.write_bytes(patch_central(p.read_bytes(), "customXml/item1.xml", file_size=1000,
                                     crc=zlib.crc32(body[:1000])))
    refused(crafty, "corrupt zip", "customXml/item1.xml", "its header says")


def test_header_that_claims_more_than_it_holds(good, tmp_path):
    p, body = _big_part_workbook(good, tmp_path)
    inflated = tmp_path / "inflated.xlsx"
    inflated.write_bytes(patch_central(p.read_bytes(), "customXml/item1.xml",
                                       file_size=len(body) + 10))
    refused(inflated, "corrupt zip", "customXml/item1.xml")


# -- macros and external links ----------------------------------------------------------------
def test_xlsm_with_vba_project(good, tmp_path):
    p = rewrite(good, tmp_path / "lab.xlsm", add={"xl/vbaProject.bin": b"\xd0\xcf\x11\xe0" + bytes(512)})
    msg = refused(p, "contains macros", "never runs macros", ".xlsx")
    assert "vbaProject.bin" in msg


def test_xlsm_extension_without_vba(good, tmp_path):
    p = tmp_path / "lab.xlsm"
    p.write_bytes(good.read_bytes())
    refused(p, "macro-enabled", ".xlsm", "never runs macros")


def test_xlsx_extension_but_vba_inside(good, tmp_path):
    p = rewrite(good, tmp_path / "sneaky.xlsx", add={"xl/vbaProject.bin": bytes(512)})
    refused(p, "contains macros", "vbaProject.bin")


def test_macro_enabled_content_type(good, tmp_path):
    p = rewrite(good, tmp_path / "ct.xlsx", replace={"[Content_Types].xml": lambda b: b.replace(
        b"application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml",
        b"application/vnd.ms-excel.sheet.macroEnabled.main+xml")})
    assert b"macroEnabled" in zipfile.ZipFile(p).read("[Content_Types].xml")
    refused(p, "macro-enabled", "content type")


def test_excel4_macro_sheet(good, tmp_path):
    p = rewrite(good, tmp_path / "xlm.xlsx", add={"xl/macrosheets/sheet1.xml": b"<xm:macrosheet/>"})
    refused(p, "contains macros", "macrosheets")


def test_external_link_part(good, tmp_path):
    p = rewrite(good, tmp_path / "ext.xlsx", add={
        "xl/externalLinks/externalLink1.xml":
            b'<externalLink xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main">'
            b'<externalBook r:id="rId1" xmlns:r="' + REL_NS.encode() + b'"/></externalLink>',
        "xl/externalLinks/_rels/externalLink1.xml.rels":
            b'<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            b'<Relationship Id="rId1" Type="' + REL_NS.encode() + b'/externalLinkPath" '
            b'Target="file:///C:/students/other.xlsx" TargetMode="External"/></Relationships>'})
    refused(p, "links to other files", "external links", "xl/externalLinks/externalLink1.xml")


def test_external_link_relationship_only(good, tmp_path):
    rel = (f'<Relationship Id="rId99" Type="{REL_NS}/externalLink" '
           'Target="externalLinks/externalLink1.xml"/></Relationships>').encode()
    p = rewrite(good, tmp_path / "rel.xlsx", replace={
        "xl/_rels/workbook.xml.rels": lambda b: b.replace(b"</Relationships>", rel)})
    refused(p, "links to other files", "externalLink")


def test_linked_ole_object(good, tmp_path):
    rels = (b'<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            b'<Relationship Id="rId1" Type="' + REL_NS.encode() + b'/oleObject" '
            b'Target="file:///\\\\server\\share\\data.xls" TargetMode="External"/></Relationships>')
    p = rewrite(good, tmp_path / "ole.xlsx", add={"xl/worksheets/_rels/sheet1.xml.rels": rels})
    refused(p, "links to other files", "oleObject")


# -- entity bombs -----------------------------------------------------------------------------
@pytest.mark.parametrize("part", [SHEET, "xl/sharedStrings.xml"])
def test_billion_laughs(good, tmp_path, part):
    if part == SHEET:
        p = rewrite(good, tmp_path / "bomb.xlsx", replace={SHEET: BILLION_LAUGHS})
    else:  # openpyxl writes no shared strings: add them as Excel and LibreOffice do
        sst_rel = (f'<Relationship Id="rId99" Type="{REL_NS}/sharedStrings" '
                   'Target="sharedStrings.xml"/></Relationships>').encode()
        sst_ct = (b'<Override PartName="/xl/sharedStrings.xml" ContentType="application/'
                  b'vnd.openxmlformats-officedocument.spreadsheetml.sharedStrings+xml"/></Types>')
        p = rewrite(good, tmp_path / "bomb.xlsx", add={part: SST_BOMB}, replace={
            "xl/_rels/workbook.xml.rels": lambda b: b.replace(b"</Relationships>", sst_rel),
            "[Content_Types].xml": lambda b: b.replace(b"</Types>", sst_ct)})
    refused(p, part, "DTD or entity declarations", "entity bomb")


def test_billion_laughs_in_utf16(good, tmp_path):
    bomb = BILLION_LAUGHS.replace(b'<?xml version="1.0"?>', b'<?xml version="1.0" encoding="UTF-16"?>')
    bomb = b"\xff\xfe" + bomb.decode().encode("utf-16-le")
    p = rewrite(good, tmp_path / "bomb16.xlsx", replace={SHEET: bomb})
    refused(p, SHEET, "entity bomb")


def test_billion_laughs_in_utf16_big_endian_after_a_megabyte(good, tmp_path):
    # the scan looks for a "!" first (issue 32): in UTF-16BE too, and past the first
    # inflated chunk (1 MB), where the window is the chunk and the last one's tail
    import random

    from sheetkin.xlsx.package import _DTD_MARKERS
    assert all(b"!" in m for m in _DTD_MARKERS)
    head, rest = BILLION_LAUGHS.split(b"<!DOCTYPE", 1)
    padding = random.Random(32).randbytes(1 << 19).hex()    # incompressible: no zip-bomb ratio
    text = (head.decode() + "<!--" + padding + "-->" + "<!DOCTYPE" + rest.decode())
    text = text.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="UTF-16"?>')
    p = rewrite(good, tmp_path / "bomb16be.xlsx", replace={SHEET: b"\xfe\xff" + text.encode("utf-16-be")})
    refused(p, SHEET, "entity bomb")


@pytest.mark.parametrize("encoding", ["UTF-32", "windows-1251"])
def test_xml_in_other_encodings(good, tmp_path, encoding):
    # The standard allows UTF-8 and UTF-16 only. Stdlib ElementTree would read windows-1251
    # through Python's codecs, and raises ValueError, not ParseError, on UTF-32.
    p = rewrite(good, tmp_path / "enc.xlsx", replace={SHEET: lambda b: (
        f'<?xml version="1.0" encoding="{encoding}"?>'.encode() + b.split(b"?>", 1)[-1])})
    refused(p, SHEET, f"encoding '{encoding.lower()}'", "UTF-8 or UTF-16")


def test_utf16_xml_is_fine(good, tmp_path):
    def utf16(b: bytes) -> bytes:
        text = '<?xml version="1.0" encoding="UTF-16"?>' + b.decode().split("?>", 1)[-1]
        return text.encode("utf-16")
    p = rewrite(good, tmp_path / "utf16.xlsx", replace={SHEET: utf16})
    pkg = open_package(p)
    assert pkg.read(SHEET).startswith(b"\xff\xfe")
    assert len(list(pkg.xml(SHEET).iter())) > 20


def test_dtd_in_relationships(good, tmp_path):
    p = rewrite(good, tmp_path / "relbomb.xlsx", replace={
        "_rels/.rels": lambda b: b'<!DOCTYPE r [<!ENTITY x "y">]>' + b})
    refused(p, "_rels/.rels", "entity")


def test_xml_refuses_dtds_and_broken_xml_at_parse_time(good, tmp_path):
    # A part nobody parses at open time (not XML by name or content type) is not pre-scanned,
    # but Package.xml still refuses its DTD; broken XML is one line too.
    p = rewrite(good, tmp_path / "odd.xlsx", add={"xl/embeddings/blob.bin": BILLION_LAUGHS},
                replace={SHEET: lambda b: b[:len(b) // 2]})
    pkg = open_package(p)
    with pytest.raises(UnusableWorkbook) as info:
        pkg.xml("xl/embeddings/blob.bin")
    assert_message(info.value, p, "xl/embeddings/blob.bin", "DTD", "entity bomb")
    with pytest.raises(UnusableWorkbook) as info:
        pkg.xml(SHEET)
    assert_message(info.value, p, SHEET, "not well-formed XML")
    with pytest.raises(UnusableWorkbook) as info:
        list(pkg.iterparse(SHEET))
    assert_message(info.value, p, SHEET, "not well-formed XML")


def test_control_characters_in_names_stay_on_one_line(good, tmp_path):
    p = rewrite(good, tmp_path / "evil.xlsx", add={"xl/evil\nname.xml": BILLION_LAUGHS})
    msg = refused(p, "entity bomb")
    assert "evil\\nname.xml" in msg


# -- sizes and zip bombs ----------------------------------------------------------------------
def _zeros_workbook(good, tmp_path, megabytes=10) -> Path:
    p = rewrite(good, tmp_path / "zeros.xlsx", drop=(SHEET,))
    with zipfile.ZipFile(p, "a", zipfile.ZIP_DEFLATED) as z, z.open(SHEET, "w") as f:
        for _ in range(megabytes):
            f.write(bytes(1_000_000))
    return p


def test_zip_bomb_part_too_big(good, tmp_path):
    p = _zeros_workbook(good, tmp_path)
    assert p.stat().st_size < 100_000
    refused(p, SHEET, "10 MB uncompressed", "at most 5 MB per part",
            limits=Limits(max_part_bytes=5_000_000))


def test_zip_bomb_ratio(good, tmp_path):
    p = _zeros_workbook(good, tmp_path)
    refused(p, SHEET, "zip bomb", "at most 200:1")


def test_total_uncompressed_size(good, tmp_path):
    p, _ = _big_part_workbook(good, tmp_path)
    refused(p, "uncompressed in all", "at most 1 MB", limits=Limits(max_total_bytes=1_000_000))


def test_too_many_parts(good, tmp_path):
    p = rewrite(good, tmp_path / "many.xlsx",
                add={f"customXml/item{i}.xml": b"<a/>" for i in range(2000)})
    refused(p, "parts", "at most 2000")


def test_duplicate_part_names(good, tmp_path):
    p = rewrite(good, tmp_path / "dup.xlsx")
    with pytest.warns(UserWarning), zipfile.ZipFile(p, "a") as z:
        z.writestr(SHEET, b"<worksheet/>")
    refused(p, "corrupt zip", "two parts with this name")


def test_a_cell_that_holds_something_past_the_limits_is_refused(tmp_path):
    """The <dimension ref> is only the writer's claim (LibreOffice writes A1:XFD1048576 for
    styled empty rows): the gate lets it through, the reader refuses a cell that holds
    something past the limits."""
    from sheetkin.xlsx.cells import read_book
    wb = openpyxl.Workbook()
    wb.active.title = "Лист1"
    wb.active["A1"] = 1
    wb.active["XFD1048576"] = 2  # two cells, a sheet claiming every row and column
    wb.save(tmp_path / "huge.xlsx")
    open_package(tmp_path / "huge.xlsx")
    with pytest.raises(UnusableWorkbook) as info:
        read_book(tmp_path / "huge.xlsx")
    assert_message(info.value, tmp_path / "huge.xlsx", "sheet 'Лист1'", "XFD1048576",
                   "at most 100000 rows and 4000 columns")


def test_check_dimension(tmp_path):
    check_dimension("a.xlsx", "S", 100_000, 4_000)
    with pytest.raises(UnusableWorkbook) as info:
        check_dimension("a.xlsx", "S", 100_001, 1)
    assert_message(info.value, "a.xlsx", "sheet 'S'", "100001 rows")
    with pytest.raises(UnusableWorkbook):
        check_dimension("a.xlsx", "S", 10, 11, Limits(max_cols=10))


def test_limits_must_be_positive():
    with pytest.raises(ValueError):
        Limits(max_parts=0)


def test_dtd_markers_found_across_every_seam():
    """The gate's scan (_has_dtd) finds a DTD or entity marker in the part's bytes without
    joining the last chunk's tail to the next chunk (issue 32): a marker in UTF-8, UTF-16 LE
    or BE, whole in a chunk or cut at any of its bytes between two chunks, is found; text
    with "!" and "<" but no marker is not; as looking in tail + chunk would answer."""
    import random

    from sheetkin.xlsx.package import _DTD_MARKERS, _DTD_OVERLAP, _has_dtd

    def reference(tail: bytes, chunk: bytes) -> bool:
        return any(m in tail + chunk for m in _DTD_MARKERS)

    rng = random.Random(7)
    filler = bytes(rng.choice(b"ab<!-x\x00 ") for _ in range(200))
    for m in _DTD_MARKERS:
        for cut in range(len(m) + 1):
            previous = filler[:50] + m[:cut]
            tail, chunk = previous[-_DTD_OVERLAP:], m[cut:] + filler[:40]
            assert _has_dtd(tail, chunk) == reference(tail, chunk), (m, cut)
            if cut < len(m) - _DTD_OVERLAP or cut == 0:
                assert _has_dtd(tail, chunk), (m, cut)
        assert _has_dtd(b"", filler + m + filler) and _has_dtd(filler[-_DTD_OVERLAP:], filler + m)
    for _ in range(2000):
        tail = bytes(rng.choice(b"<!DOCTYPENTI\x00 a") for _ in range(_DTD_OVERLAP))
        chunk = bytes(rng.choice(b"<!DOCTYPENTI\x00 a") for _ in range(rng.randrange(1, 40)))
        assert _has_dtd(tail, chunk) == reference(tail, chunk), (tail, chunk)
