"""The spreadsheet engine: reads an .xlsx (or, through LibreOffice, .ods/.fods/.xls) book and
computes its formulas headlessly, within Excel's limits.

It owns the package gate (`package`: zip bombs, part sizes, `Limits`, `UnusableWorkbook`),
the cell reader (`cells`), the formula parser (`parse`), values and functions (`values`,
`functions`), the function table (`table`: every worksheet function one entry, its kernels
in `mathstat`, `textinfo`, `lookup` and `cellwise`), runs of like formulas (`runs`), the
evaluator with its context and limits (`evaluator`, `context`, `limits`), the cells not
computed here (`uncomputed`), the memos (`caches`, `clear_caches()`), what a file that
is not an .xlsx is and its conversion (`convert`: password sniffing, .ods/.fods/.xls, the
OpenDocument gate), and LibreOffice itself (`libreoffice`). It imports nothing else of
sheetkin: the course package grades with it, and it knows nothing of mechanisms.
"""
from __future__ import annotations

import sys
from importlib import import_module
from typing import Any

# public name -> the module that defines it, imported on first use (sheetkin.lazy)
_EXPORTS = {
    "evaluate": "evaluator",
    "evaluate_frame": "evaluator",
    "rows_frame": "evaluator",
    "Book": "evaluator",
    "EvaluationError": "runs",
    "Limits": "package",
    "UnusableWorkbook": "package",
    "open_package": "package",
    "read_book": "cells",
    "convert_opendocument": "convert",
    "check_opendocument": "convert",
    "password_protected": "convert",
    "parse_formula": "parse",
    "ParseError": "parse",
    "XlError": "functions",
    "clear_caches": "caches",
}


def __getattr__(name: str) -> Any:
    # the engine stands alone (no sheetkin import), so it carries its own PEP 562 hook
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    setattr(sys.modules[__name__], name, value)
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))

__all__ = sorted(_EXPORTS)
