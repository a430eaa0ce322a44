"""Validating many workbooks: a pool of worker processes, reports in the order given.

Each worker process keeps its own caches (the evaluator's parsed formulas, the validator's
generated sheet per structure and reference per variant), so a class's workbooks cost one
reference per variant and worker; the parent keeps only the reports (a Book of a 360-column
workbook is tens of MB and is dropped as soon as its report is made).

The pool is our own, not concurrent.futures': the parent hands each worker one file at a
time, so it always knows which file a worker holds. A worker that dies (the kernel's
out-of-memory killer, a crash in a library) costs that file only: it gets a one-line error,
a new worker takes the next file, and the class is graded. Workers ignore SIGINT (a Ctrl-C
in a terminal reaches the whole process group; the parent decides) and die on SIGTERM;
when the parent stops for any reason (done, an interrupt, an error) it terminates and
reaps every worker, and a worker whose parent vanished exits at its next read.
"""
from __future__ import annotations

import os
import signal
from collections import deque
from collections.abc import Callable, Iterator
from pathlib import Path

from sheetkin.files import child_ended, child_started

from .validator import Report
from .validator import validate as _validate_one

MAX_JOBS_PER_CORE = 2        # --jobs above this many per core only costs memory (docs/reliability.md)


def default_jobs() -> int:
    return os.cpu_count() or 1


def max_jobs() -> int:
    """The most worker processes --jobs may ask for: a few per core (each holds a workbook
    and its caches, ~100-300 MB; more than the cores only adds memory)."""
    return max(4, MAX_JOBS_PER_CORE * default_jobs())


def validate_many(paths: list[Path], jobs: int | None = None,
                  progress: Callable[[int, Path], None] | None = None, options=None) -> Iterator[Report]:
    """Yield validate(path) for every path, in order. jobs: processes (default: one per
    core; at most max_jobs()); 1, or a single file, validates in this process.
    progress(done, path) is called before each report is yielded. options: issued.Options
    (roster, key, ...). Close the generator (or let it finish) to stop the workers."""
    from functools import partial
    validate = partial(_validate_one, options=options)
    jobs = min(jobs or default_jobs(), max_jobs(), len(paths)) or 1
    if jobs == 1:
        for i, p in enumerate(paths, 1):
            rep = validate(p)
            if progress:
                progress(i, p)
            yield rep
        return
    yield from _pooled(paths, jobs, validate, progress)


def _worker(conn, validate) -> None:
    """A worker's loop: a path in, its report out, until the parent closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    while True:
        try:
            path = conn.recv()
        except (EOFError, OSError):
            return                     # the parent is done (or gone)
        conn.send(validate(path))


class _Worker:
    def __init__(self, ctx, validate):
        parent, child = ctx.Pipe()
        self.conn = parent
        self.process = ctx.Process(target=_worker, args=(child, validate), daemon=True)
        self.process.start()
        child_started(self.process.pid)
        child.close()
        self.index: int | None = None      # the file it holds

    def stop(self, hurry: bool) -> None:
        """Close its pipe (it exits at its next read) and reap it; terminate it if it is
        still busy (hurry: at once), kill it if SIGTERM did not end it."""
        self.conn.close()
        self.process.join(0 if hurry else 2)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join(2)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        child_ended(self.process.pid)


def died(path: Path, exitcode: int | None) -> str:
    """The one line of a file whose worker died while validating it."""
    if exitcode is not None and exitcode < 0:
        try:
            how = f"killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            how = f"killed by signal {-exitcode}"
        if -exitcode == signal.SIGKILL:
            how += " (the system's out-of-memory killer, or a kill -9)"
    else:
        how = f"ended with exit code {exitcode}"
    return (f"{path}: the process validating it was {how}; this file is not graded (try it alone: "
            "sheetkin validate FILE); the other files were validated")


def _pooled(paths: list[Path], jobs: int, validate, progress) -> Iterator[Report]:
    import multiprocessing
    from multiprocessing.connection import wait
    # fork: the workers start with sheetkin imported (spawn would re-import it in each);
    # where fork is missing (Windows, macOS default) the platform's method is used
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else None
    ctx = multiprocessing.get_context(method)
    # files of one variant next to each other (sorted names) mostly go to one worker in
    # turn and share its reference
    todo = deque(range(len(paths)))
    done: dict[int, Report] = {}
    workers: list[_Worker] = []
    shown = 0
    finished = False
    try:
        workers = [_Worker(ctx, validate) for _ in range(jobs)]
        while shown < len(paths):
            for w in workers:
                if w.index is None and todo:
                    w.index = todo.popleft()
                    w.conn.send(paths[w.index])
            busy = [w for w in workers if w.index is not None]
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            for k, w in enumerate(workers):
                if w.index is None or not (w.conn in ready or w.process.sentinel in ready):
                    continue
                rep = _receive(w)
                if rep is None:               # it died: this file's error, a fresh worker
                    w.stop(hurry=True)        # reaped: its exit code says how it died
                    rep = Report(str(paths[w.index]), error=died(paths[w.index], w.process.exitcode))
                    workers[k] = _Worker(ctx, validate) if todo else w
                done[w.index] = rep
                w.index = None
            while shown in done:
                rep = done.pop(shown)
                shown += 1
                if progress:
                    progress(shown, paths[shown - 1])
                yield rep
        finished = True
    finally:
        for w in workers:
            w.stop(hurry=not finished)


def _receive(w: _Worker) -> Report | None:
    """The worker's report, or None if it died (its pipe closed without one). wait() said
    its pipe or its sentinel is ready: alive, its pipe holds the report (or the EOF of a
    death just now); dead, a report it sent before dying may still be in the pipe."""
    try:
        if w.process.is_alive() or w.conn.poll(0.1):
            return w.conn.recv()
    except (EOFError, OSError):
        return None
    return None
