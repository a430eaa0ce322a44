"""Run by /usr/bin/python3 (Debian's python3-uno), not by the tests' Python: edits workbooks in
LibreOffice through UNO the way a student does in Calc, and saves them. tests/helpers/studentbooks.py
writes the jobs (JSON) and starts this script; it starts its own soffice (private profile,
--accept on a socket), so nothing is shared with another test.

usage: /usr/bin/python3 studentbooks_uno.py JOBS.json PORT PROFILE_DIR
JOBS.json: [{"src": path, "dst": path, "ops": [[op, args...], ...]}, ...]
ops (rows and columns from 1, as the sheet shows them; "main" is the exercise's first sheet
as issued, found by name before any op moves it):
  ["formulas", sheet, [[row, col, "=..."], ...]]   type formulas (Excel syntax, English names)
  ["values", sheet, [[row, col, value], ...]]      type numbers or text (None clears)
  ["formula_lines", sheet, [[r0, c0, r1, c1, ["=...", ...]], ...]]   a row or column of formulas
  ["insert_sheet", name, position]                 a new sheet at `position` (0: first)
  ["move_sheet", name, position]                   drag a tab
  ["insert_columns", sheet, col, count]            insert before column `col`
  ["delete_rows", sheet, row, count]
  ["name_range", name, sheet, "$E$31:$Q$31"]       a named range (Insert > Names > Define)
"""
import contextlib
import json
import subprocess
import sys
import time

import uno
from com.sun.star.beans import PropertyValue


def prop(name, value):
    p = PropertyValue()
    p.Name, p.Value = name, value
    return p


def connect(port):
    local = uno.getComponentContext()
    resolver = local.ServiceManager.createInstanceWithContext("com.sun.star.bridge.UnoUrlResolver", local)
    for _ in range(120):
        try:
            ctx = resolver.resolve(f"uno:socket,host=127.0.0.1,port={port};urp;StarOffice.ComponentContext")
            return ctx.ServiceManager.createInstanceWithContext("com.sun.star.frame.Desktop", ctx)
        except Exception:
            time.sleep(0.5)
    raise SystemExit("cannot connect to soffice")


def sheet_of(doc, name, main):
    sheets = doc.Sheets
    return sheets.getByName(main if name == "main" else name)


FILTERS = {".xlsx": "Calc MS Excel 2007 XML", ".ods": "calc8", ".xls": "MS Excel 97"}


def run_job(desktop, job):
    url = uno.systemPathToFileUrl(job["src"])
    doc = desktop.loadComponentFromURL(url, "_blank", 0, (prop("Hidden", True),))
    main = doc.Sheets.ElementNames[0]
    for op in job["ops"]:
        kind, args = op[0], op[1:]
        if kind == "formulas":
            sh = sheet_of(doc, args[0], main)
            for r, c, f in args[1]:
                # setFormula takes the English names and ';' between arguments
                sh.getCellByPosition(c - 1, r - 1).setFormula(f.replace(",", ";"))
        elif kind == "formula_lines":
            # a line of formulas at once (a row or a column the student fills by dragging its
            # first cell): one UNO call per line instead of one per cell
            sh = sheet_of(doc, args[0], main)
            for r0, c0, r1, c1, texts in args[1]:
                cells = [t.replace(",", ";") for t in texts]
                rows = (tuple(cells),) if r0 == r1 else tuple((t,) for t in cells)
                sh.getCellRangeByPosition(c0 - 1, r0 - 1, c1 - 1, r1 - 1).setFormulaArray(rows)
        elif kind == "values":
            sh = sheet_of(doc, args[0], main)
            for r, c, v in args[1]:
                cell = sh.getCellByPosition(c - 1, r - 1)
                if v is None:
                    cell.setString("")
                elif isinstance(v, str):
                    cell.setString(v)
                else:
                    cell.setValue(float(v))
        elif kind == "insert_sheet":
            doc.Sheets.insertNewByName(args[0], args[1])
        elif kind == "move_sheet":
            doc.Sheets.moveByName(args[0], args[1])
        elif kind == "insert_columns":
            sh = sheet_of(doc, args[0], main)
            sh.unprotect("")        # the issued sheet is protected without a password (language merge)
            sh.Columns.insertByIndex(args[1] - 1, args[2])
        elif kind == "delete_rows":
            sh = sheet_of(doc, args[0], main)
            sh.unprotect("")        # as a student does before deleting rows of the protected sheet
            sh.Rows.removeByIndex(args[1] - 1, args[2])
        elif kind == "name_range":
            sh = sheet_of(doc, args[1], main)
            addr = sh.getCellByPosition(0, 0).CellAddress
            doc.NamedRanges.addNewByName(args[0], f"${sh.Name}.{args[2]}", addr, 0)
        else:
            raise SystemExit(f"unknown op {kind}")
    doc.calculateAll()
    dst = job["dst"]
    ext = dst[dst.rfind("."):].lower()
    doc.storeToURL(uno.systemPathToFileUrl(dst), (prop("FilterName", FILTERS[ext]), prop("Overwrite", True)))
    doc.close(True)


def main():
    jobs_path, port, profile = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(jobs_path, encoding="utf-8") as f:
        jobs = json.load(f)
    proc = subprocess.Popen(["soffice", f"-env:UserInstallation=file://{profile}", "--headless", "--invisible",
                             "--norestore", "--nologo", "--nolockcheck",
                             f"--accept=socket,host=127.0.0.1,port={port};urp;"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        desktop = connect(port)
        for job in jobs:
            run_job(desktop, job)
        with contextlib.suppress(Exception):       # soffice may close the bridge while quitting
            desktop.terminate()
    finally:
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()


if __name__ == "__main__":
    main()
