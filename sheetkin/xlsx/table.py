"""The function table: every worksheet function the evaluator computes, one entry each.

An entry says what the evaluator must know to call a function: its kernel, how many
arguments it takes (Excel's arity: a call outside it is #VALUE! and a note), whether its
arguments are read whole (`ranges`: a reference there is a block, text and booleans in it
skipped as SUM skips them; otherwise a range where one value is expected is intersected
with the formula's row or column, Excel's implicit intersection), whether it is lazy (the
kernel gets the argument trees and evaluates what it needs: IF, IFERROR, INDEX ...), and
its category, as Excel's function reference groups them. Adding a function is one entry
here (and one test); `sheetkin docs evaluator` lists this table (docs/evaluator.md, the
list between the markers, is `markdown()`; a test checks they agree).

Kernels: `kernel(*values)` for a function of single values, `kernel(values, is_reference)`
for one that reads ranges, `kernel(ctx, trees, run)` for a lazy one.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from importlib import import_module
from typing import Any

from . import functions as fx
from .parse import MAX_ARGS, tree_nodes
from .values import AGGREGATES, LAZY, SCALAR_FUNCS

CATEGORIES = ("Math & Trig", "Statistical", "Logical", "Information", "Lookup & Reference", "Text")
SYNTAX = "Excel 365 syntax"          # E1# and @, which files hold as functions, and the range operator
                                     # of A1:INDEX(...) (parse.RANGE_ENDS): not counted as functions


@dataclass(frozen=True)
class Function:
    """One worksheet function: see the module's docstring."""
    name: str
    category: str
    kernel: Callable[..., Any]
    arity: tuple[int, int]
    ranges: bool = False
    lazy: bool = False
    note: str = ""


FUNCTIONS: dict[str, Function] = {}


def _add(category: str, kernels: dict[str, Callable[..., Any]], arity: tuple[int, int], *,
         ranges: bool = False, lazy: bool = False, note: str = "") -> None:
    for name, kernel in kernels.items():
        if name in FUNCTIONS:
            raise ValueError(f"the function {name} is in the table twice")
        FUNCTIONS[name] = Function(name, category, kernel, arity, ranges, lazy, note)


class LazyModule:
    """The namespace of a module of kernels, each imported on its first call: the evaluator
    starts without the modules of functions a book does not call (issue 32, speed)."""

    def __init__(self, module: str):
        self.module = module

    def __getattr__(self, attr: str) -> Any:
        return LazyKernel(self.module, attr, None)

    def get(self, attr: str, key: str) -> Callable[..., Any]:
        return LazyKernel(self.module, attr, key)


class LazyKernel:
    """One kernel of a module imported on first use (see LazyModule)."""
    __slots__ = ("module", "attr", "key", "target")

    def __init__(self, module: str, attr: str, key: str | None):
        self.module, self.attr, self.key = module, attr, key
        self.target: Callable[..., Any] | None = None

    def __call__(self, *args: Any) -> Any:
        if self.target is None:
            obj = getattr(import_module(f"{__package__}.{self.module}"), self.attr)
            self.target = obj[self.key] if self.key is not None else obj
        return self.target(*args)


lookup, mathstat, textinfo = LazyModule("lookup"), LazyModule("mathstat"), LazyModule("textinfo")


def _whole(fn: Callable[..., Any]) -> Callable[..., Any]:
    """A kernel of arrays (MMULT, VLOOKUP ...) that needs no flags of which is a reference."""
    def kernel(vals, ranges):
        return fn(*vals)
    kernel.__doc__ = fn.__doc__
    return kernel


def _lazy(name: str) -> Callable[..., Any]:
    return LAZY[name].hook


MANY = (1, MAX_ARGS)
DYNAMIC = frozenset({"OFFSET", "INDIRECT", ":"})   # they make references while they run (Run.dynamic)
MATH, STAT, LOGIC, INFO, LOOKUP, TEXT = CATEGORIES

# ---------------------------------------------------------------- the generated sheets' own (values.py)
_add(MATH, {n: SCALAR_FUNCS[n] for n in ("SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "RADIANS",
                                         "DEGREES", "ABS", "SIGN", "EXP", "LN", "LOG10", "INT")}, (1, 1))
_add(MATH, {n: SCALAR_FUNCS[n] for n in ("ATAN2", "MOD", "POWER", "ROUND", "FLOOR", "CEILING")}, (2, 2))
_add(MATH, {"PI": _lazy("PI")}, (0, 0), lazy=True)
_add(MATH, {"TRUNC": _lazy("TRUNC")}, (1, 2), lazy=True)
_add(MATH, {n: _lazy(n) for n in fx.ROUNDING}, (1, 3), lazy=True)
_add(MATH, {n: AGGREGATES[n] for n in ("SUM", "SUMSQ", "PRODUCT", "SUMPRODUCT")}, MANY, ranges=True)
_add(STAT, {n: AGGREGATES[n] for n in ("AVERAGE", "MIN", "MAX", "COUNT")}, MANY, ranges=True)
_add(LOGIC, {n: AGGREGATES[n] for n in ("AND", "OR")}, MANY, ranges=True)
_add(LOGIC, {"IF": _lazy("IF")}, (1, 3), lazy=True)
_add(LOGIC, {"IFERROR": _lazy("IFERROR")}, (2, 2), lazy=True)
_add(LOGIC, {"NOT": _lazy("NOT")}, (1, 1), lazy=True)
_add(LOGIC, {"TRUE": _lazy("TRUE"), "FALSE": _lazy("FALSE")}, (0, 0), lazy=True)
_add(INFO, {n: _lazy(n) for n in ("ISNUMBER", "ISERROR", "ISTEXT", "ISERR", "ISNA", "ERROR.TYPE")}, (1, 1),
     lazy=True)
_add(INFO, {"NA": _lazy("NA")}, (0, 0), lazy=True)
_add(INFO, {"N": _lazy("N")}, (1, 1), ranges=True, lazy=True)
_add(LOOKUP, {"INDEX": _lazy("INDEX")}, (2, 4), ranges=True, lazy=True)
_add(LOOKUP, {"CHOOSE": _lazy("CHOOSE")}, (2, MAX_ARGS), ranges=True, lazy=True)
_add(LOOKUP, {"ROW": _lazy("ROW"), "COLUMN": _lazy("COLUMN")}, (0, 1), ranges=True, lazy=True)
_add(LOOKUP, {"ROWS": _lazy("ROWS"), "COLUMNS": _lazy("COLUMNS")}, (1, 1), ranges=True, lazy=True)
_add(TEXT, {"CONCATENATE": _lazy("CONCATENATE")}, (1, MAX_ARGS), lazy=True)
_add(TEXT, {"REPT": SCALAR_FUNCS["REPT"]}, (2, 2))
_add(TEXT, {"VALUE": _lazy("VALUE")}, (1, 1), ranges=True, lazy=True)
_add(SYNTAX, {"ANCHORARRAY": _lazy("ANCHORARRAY")}, (1, 1), ranges=True, lazy=True)
_add(SYNTAX, {"SINGLE": _lazy("SINGLE")}, (1, 1), ranges=True, lazy=True)
_add(SYNTAX, {":": _lazy(":")}, (2, 2), ranges=True, lazy=True)     # A1:INDEX(...), see parse.RANGE_ENDS

# ---------------------------------------------------------------- Math & Trig
_add(MATH, {n: mathstat.get("TRIG", n) for n in ("ACOT", "ACOTH", "COT", "CSC", "SEC", "COTH", "CSCH", "SECH", "SINH",
                                                  "COSH", "TANH", "ASINH", "ACOSH", "ATANH", "SQRTPI")}, (1, 1))
_add(MATH, {"ROUNDUP": mathstat.ROUNDUP, "ROUNDDOWN": mathstat.ROUNDDOWN}, (2, 2))
_add(MATH, {"LOG": mathstat.log}, (1, 2))
_add(MATH, {n: mathstat.get("MATH_SCALAR", n) for n in ("EVEN", "ODD", "FACT", "FACTDOUBLE", "ARABIC")}, (1, 1))
_add(MATH, {n: mathstat.get("MATH_SCALAR", n) for n in ("COMBIN", "COMBINA", "MROUND", "QUOTIENT", "DECIMAL")}, (2, 2))
_add(MATH, {"ROMAN": mathstat.get("MATH_SCALAR", "ROMAN")}, (1, 2),
     note="the classic form only (ROMAN(x, 0)); the concise forms 1-4 are #VALUE!")
_add(MATH, {"BASE": mathstat.get("MATH_SCALAR", "BASE")}, (2, 3))
_add(MATH, {"GCD": mathstat.get("MATH_RANGES", "GCD"), "LCM": mathstat.get("MATH_RANGES", "LCM"),
            "MULTINOMIAL": mathstat.get("MATH_RANGES", "MULTINOMIAL")}, MANY, ranges=True)
_add(MATH, {n: mathstat.get("MATH_RANGES", n) for n in ("SUMX2MY2", "SUMX2PY2", "SUMXMY2")}, (2, 2), ranges=True)
_add(MATH, {"SERIESSUM": mathstat.get("MATH_RANGES", "SERIESSUM")}, (4, 4), ranges=True)
_add(MATH, {"MDETERM": _whole(mathstat.mdeterm), "MINVERSE": _whole(mathstat.minverse),
            "MUNIT": _whole(mathstat.munit)}, (1, 1),
     ranges=True)
_add(MATH, {"MMULT": _whole(mathstat.mmult)}, (2, 2), ranges=True)
_add(MATH, {"SUMIF": lookup.get("CRITERIA", "SUMIF")}, (2, 3), ranges=True)
_add(MATH, {"SUMIFS": lookup.get("CRITERIA", "SUMIFS")}, (3, MAX_ARGS), ranges=True)

# ---------------------------------------------------------------- Statistical
_add(STAT, {n: mathstat.get("STATISTICAL", n) for n in (
    "MEDIAN", "STDEV", "STDEV.S", "STDEVP", "STDEV.P", "STDEVA", "STDEVPA", "VAR", "VAR.S", "VARP", "VAR.P",
    "VARA", "VARPA", "MODE", "MODE.SNGL", "AVERAGEA", "MAXA", "MINA", "AVEDEV", "DEVSQ", "GEOMEAN", "HARMEAN",
    "COUNTA", "COUNTBLANK")}, MANY, ranges=True)
_add(STAT, {n: mathstat.get("STATISTICAL", n) for n in (
    "LARGE", "SMALL", "PERCENTILE", "PERCENTILE.INC", "PERCENTILE.EXC", "QUARTILE", "QUARTILE.INC",
    "QUARTILE.EXC")}, (2, 2), ranges=True)
_add(STAT, {n: mathstat.get("STATISTICAL", n) for n in ("RANK", "RANK.EQ", "RANK.AVG")}, (2, 3), ranges=True)
_add(STAT, {"PERMUT": mathstat.get("MATH_SCALAR", "PERMUT")}, (2, 2))
_add(STAT, {"COUNTIF": lookup.get("CRITERIA", "COUNTIF"), "AVERAGEIF": lookup.get("CRITERIA", "AVERAGEIF")}, (2, 3),
     ranges=True)
_add(STAT, {"COUNTIFS": lookup.get("CRITERIA", "COUNTIFS")}, (2, MAX_ARGS), ranges=True)
_add(STAT, {n: lookup.get("CRITERIA", n) for n in ("AVERAGEIFS", "MAXIFS", "MINIFS")}, (3, MAX_ARGS), ranges=True)

# ---------------------------------------------------------------- Logical
_add(LOGIC, {"IFNA": textinfo.ifna}, (2, 2), lazy=True)
_add(LOGIC, {"IFS": textinfo.ifs}, (2, MAX_ARGS), lazy=True)
_add(LOGIC, {"SWITCH": textinfo.switch}, (3, MAX_ARGS), lazy=True)
_add(LOGIC, {"XOR": textinfo.xor}, MANY, ranges=True)

# ---------------------------------------------------------------- Information
_add(INFO, {n: textinfo.get("INFORMATION_LAZY", n) for n in ("ISBLANK", "ISLOGICAL", "ISNONTEXT")}, (1, 1),
     lazy=True)
_add(INFO, {"ISEVEN": mathstat.ISEVEN, "ISODD": mathstat.ISODD}, (1, 1))
_add(INFO, {"ISREF": textinfo.is_ref}, (1, 1), lazy=True)
_add(INFO, {"TYPE": textinfo.type_of}, (1, 1), ranges=True, lazy=True)

# ---------------------------------------------------------------- Lookup & Reference
_add(LOOKUP, {"MATCH": _whole(lookup.get("LOOKUPS", "MATCH"))}, (2, 3), ranges=True)
_add(LOOKUP, {n: _whole(lookup.get("LOOKUPS", n)) for n in ("VLOOKUP", "HLOOKUP")}, (3, 4), ranges=True)
_add(LOOKUP, {"LOOKUP": _whole(lookup.get("LOOKUPS", "LOOKUP"))}, (2, 3), ranges=True)
_add(LOOKUP, {"TRANSPOSE": _whole(mathstat.transpose)}, (1, 1), ranges=True)
_add(LOOKUP, {"ADDRESS": lookup.cellwise_address}, (2, 5))
_add(LOOKUP, {"OFFSET": lookup.offset}, (3, 5), ranges=True, lazy=True,
     note="evaluated after the cells it may read (a cell it reads that is computed later: not computed here)")
_add(LOOKUP, {"INDIRECT": lookup.indirect}, (1, 2), ranges=True, lazy=True,
     note="A1-style text only (R1C1 text is #REF!); evaluated after the cells it may read, as OFFSET")

# ---------------------------------------------------------------- Text
_add(TEXT, {n: textinfo.get("TEXT_SCALAR", n) for n in (
    "LEN", "TRIM", "UPPER", "LOWER", "PROPER", "CHAR", "CODE", "UNICHAR", "UNICODE", "CLEAN", "T")}, (1, 1))
_add(TEXT, {n: textinfo.get("TEXT_SCALAR", n) for n in ("LEFT", "RIGHT")}, (1, 2))
_add(TEXT, {"MID": textinfo.get("TEXT_SCALAR", "MID")}, (3, 3))
_add(TEXT, {"SUBSTITUTE": textinfo.get("TEXT_SCALAR", "SUBSTITUTE")}, (3, 4))
_add(TEXT, {"FIND": textinfo.get("TEXT_SCALAR", "FIND"), "SEARCH": textinfo.get("TEXT_SCALAR", "SEARCH")}, (2, 3))
_add(TEXT, {"REPLACE": textinfo.get("TEXT_SCALAR", "REPLACE")}, (4, 4))
_add(TEXT, {"EXACT": textinfo.get("TEXT_SCALAR", "EXACT"), "TEXT": textinfo.get("TEXT_SCALAR", "TEXT")}, (2, 2))
_add(TEXT, {"FIXED": textinfo.get("TEXT_SCALAR", "FIXED")}, (1, 3))
_add(TEXT, {"CONCAT": textinfo.get("TEXT_RANGES", "CONCAT")}, MANY, ranges=True)
_add(TEXT, {"TEXTJOIN": textinfo.get("TEXT_RANGES", "TEXTJOIN")}, (3, MAX_ARGS), ranges=True)


SUPPORTED = frozenset(FUNCTIONS)
# functions whose arguments are single values: a range there is intersected with the formula's row or column
SCALAR_CONTEXT = frozenset(n for n, f in FUNCTIONS.items() if not f.ranges)


def arity_problem(tree) -> str | None:
    """The first call with a wrong number of arguments, as a note, else None (an unknown
    function's arguments are not counted: the function is the problem)."""
    for node in tree_nodes(tree):
        if node[0] == "fn" and node[1] in FUNCTIONS:
            n = len(node[2])
            lo, hi = FUNCTIONS[node[1]].arity
            if not lo <= n <= hi:
                want = f"{lo}" if lo == hi else f"{lo} to {hi}"
                return f"{node[1]} takes {want} argument{'s' if hi != 1 else ''}, not {n}"
    return None


def by_category() -> dict[str, list[str]]:
    """The functions of each category (Excel's), sorted; the syntax entries left out."""
    out: dict[str, list[str]] = {c: [] for c in CATEGORIES}
    for name, f in FUNCTIONS.items():
        if f.category in out:
            out[f.category].append(name)
    return {c: sorted(names) for c, names in out.items()}


def markdown() -> str:
    """The supported functions by category, as docs/evaluator.md lists them."""
    groups = by_category()
    total = sum(len(v) for v in groups.values())
    lines = [f"{total} functions, by category (Excel's), from the function table (`sheetkin/xlsx/table.py`):", ""]
    for category, names in groups.items():
        lines.append(f"- **{category}** ({len(names)}): {' '.join(names)}")
    notes = [f"- {f.name}: {f.note}" for f in FUNCTIONS.values() if f.note]
    if notes:
        lines += ["", "Limits of some entries:", "", *notes]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":       # the docs' list: python -m sheetkin.xlsx.table
    print(markdown(), end="")
