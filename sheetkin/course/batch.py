"""Validating many workbooks: a process pool over every core, reports in the order given.

Each worker process keeps its own caches (the evaluator's parsed formulas, the validator's
generated sheet per structure and reference per variant), so a class's workbooks cost one
reference per variant and worker; the parent keeps only the reports (a Book of a 360-column
workbook is tens of MB and is dropped as soon as its report is made).
"""
from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from pathlib import Path

from .validator import Report
from .validator import validate as _validate_one


def default_jobs() -> int:
    return os.cpu_count() or 1


def validate_many(paths: list[Path], jobs: int | None = None,
                  progress: Callable[[int, Path], None] | None = None, options=None) -> Iterator[Report]:
    """Yield validate(path) for every path, in order. jobs: processes (default: one per
    core); 1, or a single file, validates in this process. progress(done, path) is called
    before each report is yielded. options: issued.Options (roster, key, ...)."""
    from functools import partial
    validate = partial(_validate_one, options=options)
    jobs = min(jobs or default_jobs(), len(paths)) or 1
    if jobs == 1:
        for i, p in enumerate(paths, 1):
            rep = validate(p)
            if progress:
                progress(i, p)
            yield rep
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    # fork: the workers start with sheetkin imported (spawn would re-import it in each);
    # where fork is missing (Windows, macOS default) the platform's method is used
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else None
    with ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context(method)) as pool:
        # small chunks keep the workers evenly busy; files of one variant next to each
        # other (sorted names) mostly land in one worker and share its reference
        for i, (p, rep) in enumerate(zip(paths, pool.map(validate, paths, chunksize=2), strict=False), 1):
            if progress:
                progress(i, p)
            yield rep
