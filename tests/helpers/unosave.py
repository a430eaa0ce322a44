"""Save a workbook the way a student's LibreOffice does, through UNO: in another format
(.xls, .ods), with a password. Debian's python3-uno works with /usr/bin/python3 only, so
the UNO part runs there as a subprocess, with its own LibreOffice and a temporary profile."""
from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
from pathlib import Path

FILTERS = {".xls": "MS Excel 97", ".ods": "calc8", ".xlsx": "Calc MS Excel 2007 XML"}

_SCRIPT = r'''
import json, os, subprocess, sys, time
import uno
from com.sun.star.beans import PropertyValue
jobs, soffice, profile = json.loads(sys.argv[1]), sys.argv[2], sys.argv[3]
pipe = "sheetkin_uno_%d" % os.getpid()
proc = subprocess.Popen([soffice, "-env:UserInstallation=" + profile, "--headless", "--norestore",
                         "--nologo", "--nolockcheck", "--accept=pipe,name=%s;urp;" % pipe],
                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
def prop(name, value):
    p = PropertyValue(); p.Name, p.Value = name, value; return p
try:
    local = uno.getComponentContext()
    resolver = local.ServiceManager.createInstanceWithContext("com.sun.star.bridge.UnoUrlResolver", local)
    for _ in range(240):
        try:
            ctx = resolver.resolve("uno:pipe,name=%s;urp;StarOffice.ComponentContext" % pipe)
            break
        except Exception:
            time.sleep(0.25)
    desktop = ctx.ServiceManager.createInstanceWithContext("com.sun.star.frame.Desktop", ctx)
    for src, dst, filt, password in jobs:
        doc = desktop.loadComponentFromURL(uno.systemPathToFileUrl(src), "_blank", 0, (prop("Hidden", True),))
        args = [prop("FilterName", filt), prop("Overwrite", True)]
        if password:
            args.append(prop("Password", password))
        doc.storeToURL(uno.systemPathToFileUrl(dst), tuple(args))
        doc.close(True)
    try:
        desktop.terminate()
    except Exception:
        pass
finally:
    try:
        proc.wait(timeout=20)
    except Exception:
        os.killpg(proc.pid, 9)
'''


def save_as(jobs: list[tuple[Path, Path, str | None]], timeout: float = 240) -> None:
    """Each (source, target, password or None): the source opened in LibreOffice and saved
    as the target's format (by its suffix), with the password if one is given."""
    soffice = shutil.which("soffice")
    if soffice is None or not Path("/usr/bin/python3").exists():
        raise RuntimeError("LibreOffice or /usr/bin/python3 (python3-uno) missing")
    spec = [[str(Path(s).resolve()), str(Path(d).resolve()), FILTERS[Path(d).suffix.lower()], p]
            for s, d, p in jobs]
    with tempfile.TemporaryDirectory(prefix="sheetkin-uno-") as profile:
        done = subprocess.run(["/usr/bin/python3", "-c", _SCRIPT, json.dumps(spec), soffice, Path(profile).as_uri()],
                              timeout=timeout, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"the UNO script failed ({done.returncode}): {done.stderr[-2000:]}")
    for _, d, _ in jobs:
        if not Path(d).is_file():
            raise RuntimeError(f"LibreOffice did not write {d}")
