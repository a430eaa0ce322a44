"""Formula text to expression trees: openpyxl's tokenizer, then precedence climbing, after
Excel's limits for one formula (length, nesting). A
tree is nested tuples: ("const", value), ("ref", Ref), ("name", NAME), ("fn", NAME, args),
("bin", op, left, right), ("neg", x), ("pct", x), ("missing",), ("array", rows); a Ref's relative parts are
offsets from the host cell, so one tree serves every cell of a run.

Separate from evaluator.py because parsing needs no values and no workbook: the evaluator,
its hostile-input checks (limits.py) and the fuzz tests use it on its own. Its
errors are ParseError (a formula that cannot be read) and Note (a cell's problem, with the
error value the cell gets).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

from sheetkin.messages import message

from .cells import MAX_COL, MAX_ROW
from .coords import Token, Tokenizer, TokenizerError, column_index_from_string
from .errors import SpreadsheetError
from .functions import ERRORS, XlError
from .package import shorten

CELL_REF = re.compile(r"^(\$?)([A-Za-z]{1,3})(\$?)(\d+)$")


# the characters openpyxl's tokenizer treats one by one as part of an operand: none starts
# a string, a bracket, an error, a space, an operator, a bracket pair or a separator
_ORDINARY = re.compile(r"""[^"'\[# \n+\-*/^&=><%{}();,]+""")

# _Tokenizer._plain's pieces: what most formulas are made of, one match each; anything else
# (', [, #, a line break, {, }, ;) is left to openpyxl's loop
_PLAIN = re.compile(r"""(?P<word>[^"'\[# \n+\-*/^&=><%{}();,]+)|(?P<string>"(?:[^"]*"")*[^"]*"(?!"))"""
                    r"""|(?P<space> +)|(?P<op>[<>]=|<>|[%*/^&=><+\-])|(?P<open>\()|(?P<close>\))|(?P<comma>,)"""
                    r"""|(?P<other>.)""", re.S)
_INFIX_AFTER = frozenset({Token.OPERAND, Token.OP_POST})
_FLOAT_WORDS = frozenset({"inf", "infinity", "nan"})       # the words float() reads as numbers


def _operand_token(value: str) -> Token:
    """Token.make_operand(value) without its float() where the text cannot be a number (a
    reference or a name: a "$" or a letter first, no word float() reads): the ValueError it
    raised and caught for each was 4 % of parsing the shaper's formulas (issue 32)."""
    first = value[0]
    if (first == "$" or first.isalpha()) and value not in ("TRUE", "FALSE") \
            and value.lower().strip() not in _FLOAT_WORDS:         # (float() strips: "inf<tab>" is a number)
        return Token(value, Token.OPERAND, Token.RANGE)
    return Token.make_operand(value)


class _Tokenizer(Tokenizer):
    """openpyxl's tokenizer, knowing Excel 365's newer error literals (=ISERROR(#SPILL!)
    was "not a formula"): every error of sheetkin.xlsx.functions.ERRORS; and faster: its
    loop appends an operand's characters one at a time (its own TODO says a regex would
    do), here a run of them at once, and its strings, spaces and errors are matched in
    place instead of on a copy of the formula's rest: parse_formula of the 360-column
    shaper's 167 runs 0.042 -> 0.039 s (issue 32, item 5; most of the time is in its tokens,
    7,813, not its characters); and most formulas are read by _plain, a regex match a piece.
    The tokens and errors are openpyxl's, compared in tests/xlsx/test_tokenizer.py."""
    ERROR_CODES = tuple(ERRORS)
    offset: int                     # set by openpyxl's __init__: the characters read so far

    def _parse(self):
        if self.offset or not self.formula:
            return
        if self.formula[0] != "=":
            self.items.append(Token(self.formula, Token.LITERAL))
            return
        if self._plain():
            return
        self.offset = 1
        consumers = (("\"'", self._parse_string), ("[", self._parse_brackets), ("#", self._parse_error),
                     (" \n", self._parse_whitespace), ("+-*/^&=><%", self._parse_operator),
                     ("{(", self._parse_opener), (")}", self._parse_closer), (";,", self._parse_separator))
        dispatcher = {ch: consumer for chars, consumer in consumers for ch in chars}
        formula, enders, n = self.formula, self.TOKEN_ENDERS, len(self.formula)
        while self.offset < n:
            if self.check_scientific_notation():        # may consume a + or -
                continue
            char = formula[self.offset]
            if char in enders:
                self.save_token()
            consumer = dispatcher.get(char)
            if consumer is not None:
                self.offset += consumer()
            else:                                       # ordinary characters: all of them at once
                run = _ORDINARY.match(formula, self.offset)
                assert run is not None                  # char is one
                self.token.append(run.group())
                self.offset = run.end()
        self.save_token()

    def _plain(self) -> bool:
        """The tokens of a formula made of words, strings, spaces, operators, parentheses and
        commas only, as openpyxl's loop makes them (compared in tests/xlsx/test_tokenizer.py),
        one regex match a piece instead of a method call a character: parsing the
        360-column shaper's 167 formulas took 0.87 of the instructions (issue 32). False,
        with nothing changed, for anything else: the loop then reads the formula."""
        items: list = []
        stack: list = []
        word = ""                                   # the operand being read (openpyxl's self.token)
        sn_re, make_operand = self.SN_RE, _operand_token
        for m in _PLAIN.finditer(self.formula, 1):
            kind, text = m.lastgroup, m.group()
            if kind == "word":
                word += text
                continue
            if kind == "op" and text in "+-" and word and sn_re.match(word):
                word += text                        # 1E+3: the sign is the exponent's
                continue
            if kind == "string":
                if word:
                    return False                    # (openpyxl's loop says what that is)
                items.append(make_operand(text))
                continue
            if kind == "other":
                return False
            if word and kind != "open":             # the characters that end an operand
                items.append(make_operand(word))
                word = ""
            if kind == "space":
                items.append(Token(" ", Token.WSPACE))
            elif kind == "op":
                if len(text) == 2 or text in "*/^&=><":
                    items.append(Token(text, Token.OP_IN))
                elif text == "%":
                    items.append(Token(text, Token.OP_POST))
                else:                               # + or -: infix after an operand, a ")" or a %
                    prev = next((t for t in reversed(items) if t.type != Token.WSPACE), None)
                    infix = prev is not None and (prev.subtype == Token.CLOSE or prev.type in _INFIX_AFTER)
                    items.append(Token(text, Token.OP_IN if infix else Token.OP_PRE))
            elif kind == "open":
                token = Token.make_subexp(word + "(" if word else "(")
                word = ""
                items.append(token)
                stack.append(token)
            elif kind == "close":
                if not stack:
                    return False
                items.append(stack.pop().get_closer())
            elif not stack or stack[-1].type == Token.PAREN:     # a comma: the union operator
                items.append(Token(",", Token.OP_IN))
            else:                                   # between a function's arguments
                items.append(Token.make_separator(","))
        if word:
            items.append(make_operand(word))
        self.items, self.token_stack, self.offset = items, stack, len(self.formula)
        return True

    def assert_empty_token(self, can_follow=()):
        # the token's last character, as openpyxl's one-character pieces have it
        if self.token and self.token[-1][-1:] not in can_follow:
            raise TokenizerError(f"Unexpected character at position {self.offset} in '{self.formula}'")

    def _parse_string(self):
        self.assert_empty_token(can_follow=":")
        delim = self.formula[self.offset]
        match = self.STRING_REGEXES[delim].match(self.formula, self.offset)
        if match is None:
            subtype = "string" if delim == '"' else "link"
            raise TokenizerError(f"Reached end of formula while parsing {subtype} in {self.formula}")
        text = match.group(0)
        if delim == '"':
            self.items.append(Token.make_operand(text))
        else:
            self.token.append(text)
        return len(text)

    def _parse_whitespace(self):
        self.items.append(Token(self.formula[self.offset], Token.WSPACE))
        return self.WSPACE_RE.match(self.formula, self.offset).end() - self.offset

    def _parse_error(self):
        self.assert_empty_token(can_follow="!")
        for err in self.ERROR_CODES:
            if self.formula.startswith(err, self.offset):
                self.items.append(Token.make_operand("".join(self.token) + err))
                del self.token[:]
                return len(err)
        raise TokenizerError(f"Invalid error code at position {self.offset} in '{self.formula}'")


@dataclass(frozen=True)
class Ref:
    """A cell or range reference; relative parts are offsets from the host cell."""
    sheet: str | None
    r1: int
    c1: int
    r2: int
    c2: int
    r1_abs: bool
    c1_abs: bool
    r2_abs: bool
    c2_abs: bool

    @property
    def is_range(self):
        return (self.r1, self.c1, self.r1_abs, self.c1_abs) != (self.r2, self.c2, self.r2_abs, self.c2_abs)


class ParseError(SpreadsheetError):
    """A formula that cannot be read; `code` is the error its cell gets."""

    def __init__(self, message: str, code: str = "#NAME?"):
        super().__init__(message)
        self.code = code


class Note(str):
    """A cell's problem as one line of text (Book.notes); `code` is the error value the
    cell gets (#NAME? for an unknown function, #VALUE! for a wrong number of arguments...)."""
    code: str

    def __new__(cls, text: str, code: str = "#NAME?"):
        self = super().__new__(cls, " ".join(str(text).split("\n")))
        self.code = code
        return self


def _split_sheet(text: str) -> tuple[str | None, str]:
    if "!" not in text:
        return None, text
    sheet, ref = text.rsplit("!", 1)
    if sheet.startswith("'") and sheet.endswith("'"):
        sheet = sheet[1:-1].replace("''", "'")
    if sheet.startswith("["):
        raise ParseError(f"a reference to another file ({text})")
    return sheet, ref


def _cell(text: str, host_r: int, host_c: int):
    m = CELL_REF.match(text)
    if not m:
        return None
    cabs, col, rabs, row = m.groups()
    r, c = int(row), column_index_from_string(col.upper())
    if not (1 <= r <= 1048576 and c <= 16384):     # past Excel's grid: a name (Excel: #NAME?)
        return None
    return (r if rabs else r - host_r, c if cabs else c - host_c, bool(rabs), bool(cabs))


def _operand_ref(text: str, host_r: int, host_c: int, names: dict):
    if text.upper().endswith("!#REF!"):     # Sheet1!#REF!: a reference to deleted cells
        return ("const", XlError("#REF!"))
    sheet, ref = _split_sheet(text)
    parts = ref.split(":")
    if len(parts) > 2:
        raise ParseError(f"unsupported reference {text}")
    ends = [_cell(p, host_r, host_c) for p in parts]
    if all(e is not None for e in ends):
        a, b = ends[0], ends[-1]
        return Ref(sheet, a[0], a[1], b[0], b[1], a[2], a[3], b[2], b[3])
    if sheet is None and len(parts) == 1 and ref.upper() in names:
        return ("name", ref.upper())
    if len(parts) == 2:
        whole = _whole(parts, host_r, host_c)
        if whole is None:
            raise ParseError(f"unsupported reference {text}")
        return Ref(sheet, *whole)
    return ("name", ref.upper())


_WHOLE_COL = re.compile(r"^(\$?)([A-Za-z]{1,3})$")
_WHOLE_ROW = re.compile(r"^(\$?)(\d{1,7})$")


def _whole(parts: list[str], host_r: int, host_c: int):
    """A whole-column (A:C, $A:$A) or whole-row (2:2) reference as the range of every row
    (column) of the sheet: r1 c1 r2 c2 and their absolute flags, like a Ref. The evaluator
    bounds it by the workbook's used range (_bound_whole)."""
    a, b = _WHOLE_COL.match(parts[0]), _WHOLE_COL.match(parts[1])
    if a and b:
        c1, c2 = column_index_from_string(a[2].upper()), column_index_from_string(b[2].upper())
        if max(c1, c2) > MAX_COL:
            return None
        return (1, c1 if a[1] else c1 - host_c, MAX_ROW, c2 if b[1] else c2 - host_c,
                True, bool(a[1]), True, bool(b[1]))
    a, b = _WHOLE_ROW.match(parts[0]), _WHOLE_ROW.match(parts[1])
    if a and b:
        r1, r2 = int(a[2]), int(b[2])
        if not (1 <= r1 <= MAX_ROW and 1 <= r2 <= MAX_ROW):
            return None
        return (r1 if a[1] else r1 - host_r, 1, r2 if b[1] else r2 - host_r, MAX_COL,
                bool(a[1]), True, bool(b[1]), True)
    return None


# how Excel stores a function newer than Excel 2007 (_xlfn.IFS, _xlfn.ACOT, _xlfn._xlws.SORT)
FUNCTION_PREFIXES = ("_XLFN._XLWS.", "_XLFN.", "_XLWS.")


def function_name(text: str) -> str:
    """A function's name as the table knows it: upper case, without Excel's storage prefixes."""
    name = text.upper()
    for prefix in FUNCTION_PREFIXES:
        if name.startswith(prefix):
            return name[len(prefix):]
    return name


# the functions whose value is a reference, which a range may start or end at (A1:INDEX(A1:A9,3),
# A1:IF(B1>0,A5,A9) and A1:CHOOSE(2,A3,A5), whose chosen argument is one, as in Excel);
# ":" is the range operator between them, a node ("fn", ":", [start, end]) of the tree
CHOOSERS = frozenset({"IF", "CHOOSE"})        # they pick an argument: its reference (Context._choice)
RANGE_ENDS = frozenset({"INDEX", "OFFSET", "INDIRECT", ":"}) | CHOOSERS
_PREC = {"=": 1, "<>": 1, "<": 1, ">": 1, "<=": 1, ">=": 1, "&": 2, "+": 3, "-": 3, "*": 4, "/": 4, "^": 5}


# Excel's own limits for a formula (Microsoft, "Excel specifications and limits"): a cell
# whose formula exceeds one gets an error and a note. They also keep the parser (recursive
# descent, about 3 Python frames a level) and the evaluation (about 2) below Python's
# recursion limit: a sum of 4000 terms is a left-leaning chain, walked iteratively.
MAX_FORMULA_CHARS = 8192          # characters of a formula's text
MAX_NESTING = 64                  # nested functions and parentheses (and runs of + - %)
MAX_ARGS = 255                    # arguments of one function

def _check_limits(tokens: list) -> None:
    """Refuse, before parsing, a formula nested deeper than MAX_NESTING levels (functions,
    parentheses, array braces, and runs of prefix or postfix operators, which the parser
    and the tree also nest)."""
    depth = run = 0
    for t in tokens:
        typ = t.type
        if typ in (Token.OP_PRE, Token.OP_POST):
            run += 1
            if depth + run > MAX_NESTING:
                raise ParseError(f"nesting deeper than {MAX_NESTING} levels (Excel's limit)", "#VALUE!")
            continue
        run = 0
        if t.subtype == Token.OPEN:
            depth += 1
            if depth > MAX_NESTING:
                raise ParseError(f"nesting deeper than {MAX_NESTING} levels (Excel's limit)", "#VALUE!")
        elif t.subtype == Token.CLOSE:
            depth -= 1


_SIMPLE_OPERAND = re.compile(r"^=((?:'[^'!]+'!|[A-Za-z_][\w.]*!)?\$?[A-Za-z_][\w.]*(?::\$?[A-Za-z]{1,3}\$?\d+)?)$")
_MANTISSA_E = re.compile(r"^(\d+\.?\d*|\.\d+)[Ee]$")


def _merge_exponents(tokens: list) -> list:
    """openpyxl's tokenizer reads =12.5E-1 as the name '12.5E', '-', 1: glue such a
    mantissa, its exponent's sign and digits back into one number."""
    out, i = [], 0
    while i < len(tokens):
        t = tokens[i]
        if (t.type == Token.OPERAND and _MANTISSA_E.match(t.value) and i + 2 < len(tokens)
                and tokens[i + 1].type == Token.OP_IN and tokens[i + 1].value in "+-"
                and tokens[i + 2].type == Token.OPERAND and tokens[i + 2].subtype == Token.NUMBER
                and tokens[i + 2].value.isdigit()):
            out.append(Token(t.value + tokens[i + 1].value + tokens[i + 2].value, Token.OPERAND, Token.NUMBER))
            i += 3
            continue
        out.append(t)
        i += 1
    return out


def parse_formula(formula: str, host_r: int, host_c: int, names: dict):
    """Expression tree of a formula (openpyxl's tokenizer, then precedence climbing).
    Excel's limits are enforced first (see _check_limits), so the recursive descent and
    every walk of the tree stay far from Python's recursion limit; anything unreadable is
    a ParseError."""
    if len(formula) > MAX_FORMULA_CHARS + 1:              # + 1: the "="
        raise ParseError(f"longer than {MAX_FORMULA_CHARS} characters (Excel's limit)", "#VALUE!")
    simple = _SIMPLE_OPERAND.match(formula)
    if simple and simple.group(1).upper() not in ("TRUE", "FALSE"):
        # one reference or name (=$A$1, =Data!B2:C9, =dfi): the tree without the tokenizer, as
        # defined names mostly are (30,000 names read in a tenth of the time, issue 30)
        node = _operand_ref(simple.group(1), host_r, host_c, names)
        return ("ref", node) if isinstance(node, Ref) else node
    try:
        tokens = _merge_exponents([t for t in _Tokenizer(formula).items if t.type != Token.WSPACE])
    except Exception as e:      # noqa: BLE001 - the tokenizer's own errors (TokenizerError, IndexError...)
        raise ParseError(f"not a formula ({type(e).__name__}: {shorten(e, 100)})") from None
    _check_limits(tokens)
    parser = _Parser(tokens, host_r, host_c, names)
    tree = parser.expression(0)
    if parser.pos != parser.end:
        raise ParseError(message("unexpected", t=repr(tokens[parser.pos].value)))
    return tree


def _operand(t, host_r: int, host_c: int, names: dict):
    """The tree of one operand token: a number, a text, a boolean, an error, a reference or a name."""
    if t.subtype == Token.NUMBER:
        x = float(t.value)
        return ("const", x if math.isfinite(x) else XlError("#NUM!"))   # =1e999: past the largest double
    if t.subtype == Token.TEXT:
        return ("const", t.value[1:-1].replace('""', '"'))
    if t.subtype == Token.LOGICAL:
        return ("const", t.value.upper() == "TRUE")
    if t.subtype == Token.ERROR:
        return ("const", XlError(t.value.upper()))
    node = _operand_ref(t.value, host_r, host_c, names)
    return ("ref", node) if isinstance(node, Ref) else node


class _Parser:
    """Precedence climbing over a formula's tokens; the host cell and the names decide
    what a reference or a word is."""

    def __init__(self, tokens: list, host_r: int, host_c: int, names: dict):
        # one None after the last token: peek() is an index, not a bounds check (25,000
        # peeks in the 360-column shaper's 167 formulas, issue 32)
        self.tokens, self.pos, self.end = [*tokens, None], 0, len(tokens)
        self.host_r, self.host_c, self.names = host_r, host_c, names

    def peek(self):
        return self.tokens[self.pos]

    def take(self):
        """The next token, or None at the end (where it stays)."""
        t = self.tokens[self.pos]
        if t is not None:
            self.pos += 1
        return t

    def primary(self):
        t = self.take()
        if t is None:
            raise ParseError(message("formula_ends_too_early"))
        if t.type == Token.OP_PRE:
            # unary minus binds tighter than ^ in Excel: -2^2 = 4
            node = ("neg", self.primary()) if t.value == "-" else self.primary()
            return self.postfix(node)
        if t.type == Token.OPERAND:
            return self.postfix(_operand(t, self.host_r, self.host_c, self.names))
        if t.type == Token.PAREN and t.subtype == Token.OPEN:
            node = self.expression(0)
            close = self.take()
            if close is None or close.type != Token.PAREN:
                raise ParseError(message("unbalanced_parentheses"))
            return self.postfix(node)
        if t.type == Token.FUNC and t.subtype == Token.OPEN:
            start, colon, name = t.value[:-1].rpartition(":")
            if colon and start and function_name(name) in RANGE_ENDS:
                # A1:INDEX(...): the tokenizer keeps a range's start with the function it ends in
                left = _operand_ref(start, self.host_r, self.host_c, self.names)
                left = ("ref", left) if isinstance(left, Ref) else left
                return self.postfix(("fn", ":", [left, self.function(function_name(name))]))
            return self.postfix(self.function(function_name(t.value[:-1])))
        if t.type == Token.ARRAY and t.subtype == Token.OPEN:
            return self.postfix(self.array_constant())
        raise ParseError(message("unexpected", t=repr(t.value)))

    def array_constant(self):
        """An array constant after its "{": ("array", rows of values); "," between the values
        of a row, ";" between rows, constants only (a number, optionally negative, a text, a
        boolean, an error), every row as long as the first, as Excel requires."""
        rows: list[list] = [[]]
        sign = 1.0
        while True:
            t = self.take()
            if t is None:
                raise ParseError("{ is not closed")
            if t.type == Token.ARRAY and t.subtype == Token.CLOSE:
                break
            if t.type == Token.SEP:
                rows.append([]) if t.subtype == Token.ROW else None
                continue
            if t.type == Token.OP_PRE and t.value in "+-":
                sign = -sign if t.value == "-" else sign
                continue
            node = _operand(t, self.host_r, self.host_c, {}) if t.type == Token.OPERAND else None
            if node is None or node[0] != "const" or (sign < 0 and not isinstance(node[1], float)):
                raise ParseError(f"{t.value!r} in an array constant (constants only)")
            rows[-1].append(sign * node[1] if sign < 0 else node[1])
            sign = 1.0
        if not rows[0] or any(len(r) != len(rows[0]) for r in rows):
            raise ParseError("an array constant's rows differ in length")
        return ("array", tuple(tuple(r) for r in rows))

    def function(self, name: str):
        """A function's arguments, after its opening token, up to its closing one."""
        args: list[tuple] = []
        nxt = self.peek()
        if nxt and nxt.type == Token.FUNC and nxt.subtype == Token.CLOSE:
            self.take()
            return ("fn", name, args)
        while True:
            nxt = self.peek()
            if nxt and (nxt.type == Token.SEP or (nxt.type == Token.FUNC and nxt.subtype == Token.CLOSE)):
                args.append(("missing",))      # =ROUND(2.5,) : an empty argument
            else:
                args.append(self.expression(0))
            sep = self.take()
            if sep is None:
                raise ParseError(message("not_closed", f=name))
            if sep.type == Token.FUNC and sep.subtype == Token.CLOSE:
                return ("fn", name, args)
            if not (sep.type == Token.SEP and sep.subtype == Token.ARG):
                raise ParseError(message("unexpected_in", t=repr(sep.value), f=name))

    def postfix(self, node):
        while (nxt := self.peek()) is not None:
            if nxt.type == Token.OP_POST:
                self.take()
                node = ("pct", node)
                continue
            if not (node[0] == "fn" and node[1] in RANGE_ENDS and nxt.value.startswith(":") and len(nxt.value) > 1):
                break
            # INDEX(...):A5 and OFFSET(...):INDEX(...): a range that starts at a function's reference
            if nxt.type == Token.OPERAND:
                self.take()
                right = _operand_ref(nxt.value[1:], self.host_r, self.host_c, self.names)
                node = ("fn", ":", [node, ("ref", right) if isinstance(right, Ref) else right])
            elif nxt.type == Token.FUNC and nxt.subtype == Token.OPEN and function_name(nxt.value[1:-1]) in RANGE_ENDS:
                self.take()
                node = ("fn", ":", [node, self.function(function_name(nxt.value[1:-1]))])
            else:
                break
        return node

    def expression(self, min_prec: int):
        left = self.primary()
        tokens = self.tokens
        while (t := tokens[self.pos]) is not None and t.type == Token.OP_IN and _PREC.get(t.value, 0) > min_prec:
            self.pos += 1
            right = self.expression(_PREC[t.value])
            left = ("bin", t.value, left, right)
        return left


def tree_nodes(tree):
    """Every node of a tree, parents first, left to right; iterative (a 4000-term sum is a
    tree 4000 deep)."""
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node
        kind = node[0]
        if kind == "fn":
            stack.extend(reversed(node[2]))
        elif kind in ("neg", "pct"):
            stack.append(node[1])
        elif kind == "bin":
            stack.append(node[3])
            stack.append(node[2])


def functions_of(tree) -> set[str]:
    return {node[1] for node in tree_nodes(tree) if node[0] == "fn"}


def refs_of(tree) -> list[Ref]:
    return [node[1] for node in tree_nodes(tree) if node[0] == "ref"]


def names_of(tree) -> list[str]:
    """The defined names a formula reads (every unknown word is one: parse with names={})."""
    return [node[1] for node in tree_nodes(tree) if node[0] == "name"]
