"""The command line: `sheetkin COMMAND ...`.

It owns the argument parser with one small function per command (`args`), the commands
themselves and their dispatch (`commands`: each reads its inputs, calls the stage that
does the work, writes the outputs, and turns every expected failure into one line and an
exit code), and the crank angles of `--range` and `--at-file` (`angles`).
"""
from __future__ import annotations

import os
import sys
from typing import NoReturn

from sheetkin.cli.commands import main

__all__ = ["main", "run"]


def run() -> NoReturn:
    """The `sheetkin` program (the console script and `python -m sheetkin`): main() in a
    process of its own, which it ends without tearing the interpreter down."""
    # One BLAS thread, unless the user chose otherwise: numpy's OpenBLAS starts a worker
    # per core at import and they spin. On the course's 2-core machine `import numpy` took
    # 0.38 s of CPU with them and 0.24 s with one, `sheetkin evaluate` of the 360-column
    # shaper 0.10-0.14 s less (issue 32, item 5). Nothing sheetkin computes is a large
    # matrix product: the solver is elementwise, a student's MMULT/MINVERSE 2x2..4x4.
    # Set here, not at import, so that a notebook importing sheetkin keeps its numpy's.
    if "numpy" not in sys.modules:
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    # The cyclic collector every 100,000 new objects, not every 700, as mypy sets it: a
    # book read in one piece (tens of thousands of cells, formulas and parse trees, none of
    # them garbage) was scanned by 59 collections, 0.024-0.041 s of the shaper's evaluate
    # (issue 32, item 5); the garbage of a cycle still goes, later, and memory stayed the same.
    import gc
    gc.set_threshold(100_000, 30, 30)
    _quick_exit(main())


def _quick_exit(code: int) -> NoReturn:
    """End the process with `code` without the interpreter's teardown, as mypy does
    (`mypy.util.hard_exit`): freeing every module and object the command loaded took
    0.06-0.07 s of CPU after `sheetkin evaluate` (issue 32, item 5), for memory the system
    takes back anyway. What the teardown would still do for us is done first: the atexit
    functions (temporary folders' finalizers, logging) and the standard streams' flush;
    every output file is closed by the command itself (files.Output.commit). No collection:
    it took 0.036 s there, and Python promises no finalizer of an object left at exit
    either. With another thread alive, or a stream that cannot be flushed, the ordinary exit."""
    import atexit
    import threading
    if threading.active_count() > 1:
        sys.exit(code)                      # the interpreter joins them
    try:
        atexit._run_exitfuncs()
        sys.stdout.flush()
        sys.stderr.flush()
    except BaseException:                   # noqa: BLE001 - the ordinary exit says what it says
        sys.exit(code)
    os._exit(code)
