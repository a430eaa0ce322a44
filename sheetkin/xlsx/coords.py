"""Column letters and openpyxl's formula tokenizer, without importing openpyxl.

Why: `import openpyxl` costs 0.1-0.3 s on this machine (its package `__init__` loads the
workbook, cell, chart and writer modules), while `evaluate` and the reading half of
`validate` need only two pure functions of it: column letters <-> numbers, and the formula
tokenizer, a self-contained module (it imports only `re`). The letters are computed here
with openpyxl's rules (A..ZZZ, ValueError outside); the tokenizer is openpyxl's own file,
loaded on its own when openpyxl itself is not imported yet (tests/xlsx/test_evaluator.py
compares both with openpyxl's).
"""
from __future__ import annotations

import importlib.util
import sys
from functools import cache
from types import ModuleType

_LETTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
_INDEX = {ch: k for k, ch in enumerate(_LETTERS, 1)}


@cache
def get_column_letter(col_idx: int) -> str:
    """1 -> "A", 27 -> "AA", 18278 -> "ZZZ" (openpyxl.utils.get_column_letter)."""
    if not 1 <= col_idx <= 18278:
        raise ValueError(f"Invalid column index {col_idx}")
    out = ""
    while col_idx:
        col_idx, rem = divmod(col_idx - 1, 26)
        out = _LETTERS[rem] + out
    return out


@cache
def column_index_from_string(col: str) -> int:
    """"A" -> 1, "zz" -> 702 (openpyxl.utils.column_index_from_string: A..ZZZ, any case)."""
    if not 1 <= len(col) <= 3:
        raise ValueError(f"'{col}' is not a valid column name. Column names are from A to ZZZ")
    idx = 0
    for ch in col.upper():
        pos = _INDEX.get(ch)
        if pos is None:
            raise ValueError(f"'{col}' is not a valid column name. Column names are from A to ZZZ")
        idx = idx * 26 + pos
    return idx


def _tokenizer_module() -> ModuleType:
    """openpyxl.formula.tokenizer: the imported one if openpyxl is loaded, else its file
    loaded alone (it imports only `re`), so that parsing a formula does not import openpyxl."""
    loaded = sys.modules.get("openpyxl.formula.tokenizer")
    if loaded is not None:
        return loaded
    package = importlib.util.find_spec("openpyxl")
    if package is None or not package.submodule_search_locations:
        raise ImportError("openpyxl is not installed: sheetkin needs its formula tokenizer")
    path = f"{list(package.submodule_search_locations)[0]}/formula/tokenizer.py"
    spec = importlib.util.spec_from_file_location("sheetkin.xlsx._openpyxl_tokenizer", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_tok = _tokenizer_module()
Token = _tok.Token
Tokenizer = _tok.Tokenizer
TokenizerError = _tok.TokenizerError
