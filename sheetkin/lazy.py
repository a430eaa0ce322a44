"""Public names that load on first use (PEP 562), for the packages' `__init__` files.

Why: a package's `__init__` exports its public API, but importing it must not pull in what
only some of its modules need (numpy, pandas, openpyxl, matplotlib): `sheetkin --help`
loads no numpy, and `validate` no pandas (tests/cli/test_startup.py). A name that is also the
name of a submodule is not exported this way: the import system would rebind it to the
submodule.
"""
from __future__ import annotations

import sys
from collections.abc import Callable
from importlib import import_module
from typing import Any


def exports(package: str, table: dict[str, str]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """`__getattr__` and `__dir__` for `package`, whose public name N lives in the module
    `table[N]` (relative to the package, or absolute when it starts with "sheetkin.")."""

    def __getattr__(name: str) -> Any:
        if name not in table:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        where = table[name]
        module = import_module(where if where.startswith("sheetkin.") else f"{package}.{where}")
        value = getattr(module, name)
        setattr(sys.modules[package], name, value)   # once: later lookups are plain attributes
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(table))

    return __getattr__, __dir__
