"""The command line: `sheetkin COMMAND ...`.

It owns the argument parser with one small function per command (`args`), the commands
themselves and their dispatch (`commands`: each reads its inputs, calls the stage that
does the work, writes the outputs, and turns every expected failure into one line and an
exit code), and the crank angles of `--range` and `--at-file` (`angles`).
"""
from __future__ import annotations

from sheetkin.cli.commands import main

__all__ = ["main"]
