"""The command line as the tests call it: `run(capsys, "compute", path, ...)` gives (exit code,
stdout, stderr), an argparse exit (SystemExit) taken as its code."""
from __future__ import annotations

from sheetkin.cli.commands import main


def run(capsys, *argv):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as e:
        code = e.code
    out, err = capsys.readouterr()
    return code, out, err
