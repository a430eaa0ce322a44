"""Every module or file that a docstring or comment of sheetkin/ names exists: a reader who
follows `sheetkin.xlsx.cells.read_book` or `tests/cli/test_startup.py` finds it there.

Three kinds of names are checked: dotted names under sheetkin (a module, or a name in one),
file names ending in .py (a path from the repository's root, or a file name found in it),
and the names of the old flat layout's modules (FORMER_MODULES), which old comments still
used after the modules moved into packages.
"""
from __future__ import annotations

import ast
import importlib
import io
import re
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "sheetkin"

# Modules of the flat layout before the packages (sheetkin/xlsxsafe.py, ...): distinctive
# names, none an English word, so a docstring naming one names a module that is gone.
FORMER_MODULES = {"xlsxsafe", "xlsxread", "scenecaps", "formula_values", "formula_parse", "formula_runs",
                  "evaluator_context", "evaluator_limits", "workbook_charts", "workbook_dynamics",
                  "workbook_print", "cli_args"}

# packages made of data folders (pyproject.toml: package-dir), not of modules in sheetkin/
DATA_PACKAGES = {"sheetkin.examples": ROOT / "workbooks", "sheetkin.docs": ROOT / "docs"}

DOTTED = re.compile(r"\bsheetkin(?:\.[A-Za-z_]\w*)+")
PY_FILE = re.compile(r"(?<![\w./-])((?:[\w-]+/)*[\w-]+\.py)\b")
FORMER = re.compile(r"\b(" + "|".join(sorted(FORMER_MODULES)) + r")\b")


def prose(path: Path) -> list[tuple[int, str]]:
    """(line, text) of every comment and docstring of a module."""
    source = path.read_text(encoding="utf-8")
    out = [(tok.start[0], tok.string) for tok in tokenize.generate_tokens(io.StringIO(source).readline)
           if tok.type == tokenize.COMMENT]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False)
            if doc is not None:
                out.append((node.body[0].lineno, doc))
    return out


def resolves(dotted: str) -> bool:
    """sheetkin.a.b.c is a module, or a name defined in one (a class's attribute too)."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        module = ".".join(parts[:k])
        if module in DATA_PACKAGES:
            return k == len(parts) and DATA_PACKAGES[module].is_dir()
        try:
            obj = importlib.import_module(module)
        except ModuleNotFoundError:
            continue
        for name in parts[k:]:
            if not hasattr(obj, name):
                return False
            obj = getattr(obj, name)
        return True
    return False


REPO_FILES = {p.name for p in ROOT.rglob("*.py") if ".git" not in p.parts}


def file_exists(name: str) -> bool:
    return (ROOT / name).is_file() or (PACKAGE / name).is_file() if "/" in name else name in REPO_FILES


def stale_names(path: Path) -> list[str]:
    out = []
    for line, text in prose(path):
        where = f"{path.relative_to(ROOT)}:{line}"
        out += [f"{where}: {d}" for d in DOTTED.findall(text) if not resolves(d)]
        out += [f"{where}: {f}" for f in PY_FILE.findall(text) if not file_exists(f)]
        out += [f"{where}: {m} (a module of the old layout)" for m in FORMER.findall(text)]
    return out


MODULES = sorted(PACKAGE.rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_every_module_a_docstring_or_comment_names_exists(path):
    stale = stale_names(path)
    assert not stale, "\n".join(stale)


def test_the_check_sees_names(tmp_path):
    """A stale name of each kind is found; live ones are not."""
    fake = tmp_path / "fake.py"
    fake.write_text('"""Reads through sheetkin.xlsx.cells.read_book and sheetkin.files (files.py),\n'
                    'as tests/cli/test_startup.py checks."""\n'
                    "# gone: sheetkin.xlsx.nothing_here, formula_values.py, tests/nothing.py, (xlsxsafe)\n")
    found = [line for _, text in prose(fake) for line in
             DOTTED.findall(text) + PY_FILE.findall(text) + FORMER.findall(text)]
    stale = [n for n in found if not (resolves(n) if n.startswith("sheetkin") else
                                      file_exists(n) if n.endswith(".py") else False)]
    assert stale == ["sheetkin.xlsx.nothing_here", "formula_values.py", "tests/nothing.py", "formula_values",
                     "xlsxsafe"], stale
