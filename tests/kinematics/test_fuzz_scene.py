"""Fuzzing the scene parser (issue 11, item 7): documents built from the scene's own keys
with random values (huge, tiny, NaN and inf numbers, integers of hundreds of digits, text
with control characters, wrong types, nesting, missing keys, unknown keys and group types),
and random snippets in the bundled scenes' text. Only two outcomes are allowed: a SceneError
of one line naming the file, or a valid scene; and `compute` on a valid scene gives finite
numbers (NaN only where a group cannot assemble or at a toggle) or our one-line errors.

Deterministic (derandomize=True); about 20 s. `python benchmarks/fuzz_scene.py` runs the same
checks on many more cases and counts the outcomes (README, "Reliability").
"""
from __future__ import annotations

import copy
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sheetkin.kinematics.scene import SceneError, parse_scene
from sheetkin.kinematics.table import AssemblyError, NumericOverflow, TooLarge, compute

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
TEXTS = [p.read_text(encoding="utf-8") for p in sorted(WORKBOOKS.glob("*.toml"))]
TEMPLATES = [tomllib.loads(t) for t in TEXTS]
SOURCE = "fuzz.toml"
SETTINGS = dict(deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


# --------------------------------------------------------------------------- the check
def check_document(text: str) -> str:
    """'refused' (a clean SceneError), 'computed' or 'compute refused' (a clean one-line
    error from compute); anything else fails the test."""
    try:
        scene = parse_scene(text, SOURCE)
    except SceneError as e:
        assert_one_line(str(e))
        return "refused"
    angles = [scene.crank.phi0_deg + i * scene.crank.step_deg for i in range(min(scene.crank.positions, 6))]
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # numpy's warnings would be errors here
        try:
            df = compute(scene, angles, dynamics=scene.has_dynamics, allow_gaps=True)
        except (AssemblyError, NumericOverflow, TooLarge) as e:
            assert_one_line(str(e))
            return "compute refused"
    num = df.select_dtypes("number").to_numpy(dtype=float)
    assert not np.isinf(num).any(), "inf in compute's table"
    nan_rows = np.isnan(num).any(axis=1)
    explained = (~df["assembled"].to_numpy(dtype=bool) if "assembled" in df else np.zeros(len(df), bool)) \
        | (df["near_toggle"].astype(str).to_numpy() != "")
    assert not (nan_rows & ~explained).any(), "NaN at an assembled position away from toggles"
    return "computed"


def assert_one_line(msg: str):
    assert msg and "\n" not in msg and "\r" not in msg, repr(msg)
    assert msg.startswith(SOURCE), msg
    assert "Traceback" not in msg and len(msg) <= 1000, msg


# --------------------------------------------------------------------------- random values
def toml_string(s: str) -> str:
    out = []
    for ch in s:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else toml_string(k)


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if v != v else ("inf" if v == float("inf") else "-inf" if v == -float("inf") else repr(v))
    if isinstance(v, str):
        return toml_string(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{toml_key(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def toml_document(doc: dict) -> str:
    """Top-level values first, then [table]s and [[array]]s of tables (their own nested
    tables inline)."""
    head, tail = [], []
    for k, v in doc.items():
        if isinstance(v, dict):
            tail.append(f"[{toml_key(k)}]")
            tail += [f"{toml_key(kk)} = {toml_value(vv)}" for kk, vv in v.items()]
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for item in v:
                tail.append(f"[[{toml_key(k)}]]")
                tail += [f"{toml_key(kk)} = {toml_value(vv)}" for kk, vv in item.items()]
        else:
            head.append(f"{toml_key(k)} = {toml_value(v)}")
    return "\n".join(head + tail) + "\n"


NAMES = ["O", "O1", "A", "B", "C", "D", "S2", "S3", "E", "frame", "x", ""]
KEYS = ["title", "author", "frame", "crank", "group", "point", "gravity", "mass", "force", "synthesis",
        "pivot", "joint", "length", "lengths", "phi0_deg", "step_deg", "positions", "omega", "epsilon",
        "type", "links", "joints", "branch", "guide", "through", "angle_deg", "offset", "name", "link",
        "from", "along", "across", "inertia", "centre", "at", "force", "moment", "from_deg", "to_deg",
        "kw", "l3", "lenght", "Type", "a b", "\n", "\u0000"]
special_numbers = st.sampled_from([
    0, 0.0, -0.0, 1, -1, 2, 3, 13, 1e-300, 5e-324, -5e-324, 1e-12, 1e12, 1e12 + 1, -1e12, 1e13, 1e154, 1e308,
    -1e308, 1.7976931348623157e308, float("nan"), float("inf"), -float("inf"), 10 ** 400, -(10 ** 400),
    2 ** 63, 2 ** 64 + 1, 10 ** 12, 10 ** 8, 10 ** 8 + 1, 16_381, 360.0, 720.0, 1e-9, 0.5, 0.34, 0.14, 20.0])
numbers = st.one_of(special_numbers,
                    st.floats(allow_nan=True, allow_infinity=True),
                    st.floats(min_value=-2.0, max_value=2.0),
                    st.integers(-(10 ** 420), 10 ** 420),
                    st.integers(-5, 20))
texts = st.one_of(st.sampled_from(NAMES + ["RRR", "RRP", "RPR", "PRP", "rrr", "=1+1", "@SUM(1)", "-2"]),
                  st.text(max_size=12),
                  st.text(alphabet=st.characters(max_codepoint=0x9F), max_size=8))
scalars = st.one_of(numbers, texts, st.booleans())
values = st.recursive(scalars, lambda inner: st.one_of(
    st.lists(inner, max_size=4), st.dictionaries(st.sampled_from(KEYS), inner, max_size=3)), max_leaves=12)


def _paths(doc) -> list[tuple[object, object]]:
    """(container, key) of every value in the document, iteratively."""
    out, stack = [], [doc]
    while stack:
        node = stack.pop()
        items = node.items() if isinstance(node, dict) else enumerate(node)
        for k, v in list(items):
            out.append((node, k))
            if isinstance(v, (dict, list)):
                stack.append(v)
    return out


@st.composite
def documents(draw):
    doc = copy.deepcopy(draw(st.sampled_from(TEMPLATES)))
    for _ in range(draw(st.integers(1, 4))):
        paths = _paths(doc)
        if not paths:
            break
        node, key = draw(st.sampled_from(paths))
        op = draw(st.sampled_from(["replace", "replace", "number", "scale", "scale", "scale", "delete",
                                   "add", "nest", "type"]))
        if op == "scale":           # valid but extreme: tiny and huge mechanisms, mixed scales
            number = [(n, k) for n, k in paths if isinstance(n[k], (int, float)) and not isinstance(n[k], bool)
                      and abs(n[k]) < 1e300]
            if number:
                node, key = draw(st.sampled_from(number))
                node[key] = node[key] * draw(st.sampled_from([1e-12, 1e-9, 1e-6, 1e-3, -1, 0.5, 2, 1e3, 1e6,
                                                              1e9, 1e11, 1e12]))
        elif op == "replace":
            node[key] = draw(values)
        elif op == "number":
            node[key] = draw(numbers)
        elif op == "delete":
            if isinstance(node, dict):
                del node[key]
            else:
                node.pop(key)
        elif op == "add" and isinstance(node, dict):
            node[draw(st.sampled_from(KEYS))] = draw(values)
        elif op == "nest":
            v = node[key]
            for _ in range(draw(st.integers(1, 12))):
                v = [v]
            node[key] = v
        elif op == "type":
            group = draw(st.sampled_from(doc.get("group") or [{}])) if isinstance(doc.get("group"), list) else {}
            if isinstance(group, dict):
                group["type"] = draw(st.sampled_from(["RRR", "RRP", "RPR", "PRP", "", "rrr", 3]))
    return toml_document(doc)


SNIPPETS = ["nan", "x = inf", "omega = nan", "[[group]]", "[crank]", "[frame]", "positions = 99999999999",
            "positions = " + "9" * 400, "length = " + "1" * 5000, "= = =", "a = [[[[[[[[[[1]]]]]]]]]]",
            "a = " + "[" * 3000 + "]" * 3000, '"\\u0000" = 1', "step_deg = 0", "\x00", "\x1b", "\r", "\ufeff",
            "length = -0.0", "omega = 1e-320", "omega = 1e308", "title = '''=cmd'''", '[[point]]\nname = "Q"',
            "[group.guide]", "links = [2, 3]", "branch = 0", "[[mass]]\nlink = 2\nmass = 1e12",
            "gravity = [0, -1e12]", "epsilon = -inf", "phi0_deg = 1e12", "[synthesis]\nkw = nan"]


# --------------------------------------------------------------------------- the tests
@settings(max_examples=250, **SETTINGS)
@given(documents())
def test_random_documents_give_a_scene_or_one_line(text):
    check_document(text)


@settings(max_examples=150, **SETTINGS)
@given(st.sampled_from(TEXTS), st.integers(0, 10 ** 6),
       st.one_of(st.sampled_from(SNIPPETS), st.text(max_size=30)), st.booleans())
def test_random_snippets_in_real_scenes(text, where, snippet, replace):
    lines = text.splitlines()
    k = where % (len(lines) + 1)
    if replace and k < len(lines):
        lines[k] = snippet
    else:
        lines.insert(k, snippet)
    check_document("\n".join(lines) + "\n")


def test_the_fuzzer_reaches_both_outcomes():
    """The documents strategy is not all refusals: the bundled scenes computed through the
    same check, and a few known mutations of each kind refused."""
    assert {check_document(toml_document(t)) for t in TEMPLATES} == {"computed"}
    for snippet in ("positions = 0", "omega = nan", "a = 1"):
        assert check_document(TEXTS[0].replace("epsilon", snippet + "\nepsilon", 1)) == "refused"
