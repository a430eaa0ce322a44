"""Scene files: parse and validate a TOML scene (the format: docs/scene-format.md).

A scene is one planar linkage: frame points, the driving crank, the Assur groups (dyads)
attached one after another, and points fixed on links. This module turns the file into
frozen dataclasses and a *plan*: the order in which the solver may place each joint and
point. Every mistake raises SceneError with one line: file, line, key, what was expected.
"""
from __future__ import annotations

import heapq
import math
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import NoReturn

from sheetkin.errors import InputError
from sheetkin.files import read_text
from sheetkin.groups import KINDS, kind_of
from sheetkin.groups.group import Group, Guide, slide_names

from .caps import (
    MAX_POSITIONS,
    MAX_SCENE_BYTES,
    WORKBOOK_MAX_POSITIONS,
    SceneError,
    check_values,
    load_toml,
    one_line,
    shown,
)

GROUP_TYPES = tuple(KINDS)
NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")

# How a Scene draws itself in a notebook (Scene._repr_svg_): the drawing lives in
# sheetkin.views, above this stage, so the package offers it (sheetkin/__init__.py's
# _draw_scene, found through sys.modules) rather than the scene importing a view; setting
# this replaces it.
draw_in_notebook: Callable[[Scene], str] | None = None


class AssemblyError(InputError):
    """The mechanism cannot be assembled at some requested crank positions (raised by
    sheetkin.compute; defined here, with no numpy, so the command line can catch it
    without importing the solver). The user's to mend (the scene's lengths, the angles
    asked for, or allow_gaps=True), so an InputError; the command line gives it its own
    exit code (3), since the scene itself is valid."""


@dataclass(frozen=True)
class Crank:
    pivot: str
    joint: str
    length: float
    phi0_deg: float
    step_deg: float
    positions: int
    omega: float
    epsilon: float


@dataclass(frozen=True)
class Point:
    name: str
    link: int
    origin: str      # the scene key `from`: a joint (or earlier point) of that link
    along: float
    across: float


@dataclass(frozen=True)
class Mass:
    """A link's mass (kg), its moment of inertia about its centre of mass (kg m^2), and the
    point that is that centre (a joint or [[point]] of the link)."""
    link: int
    mass: float
    inertia: float
    centre: str


@dataclass(frozen=True)
class Force:
    """An external force (N) at a point of a link and/or a moment (N m, + counterclockwise)
    on the link, acting while the crank angle is in [from_deg, to_deg] (mod 360), or always
    when the interval is None (e.g. the cutting resistance on a shaper's ram over its
    working stroke)."""
    index: int
    name: str
    link: int
    at: str | None
    force: tuple[float, float]
    moment: float
    interval_deg: tuple[float, float] | None = None


@dataclass(frozen=True)
class Scene:
    """A checked scene: the frame's points, the crank, the Assur groups in the order they are
    solved, the points on links, and (for the dynamics) gravity, masses and forces.

    Made by `parse_scene(text)` or `load_scene(path)`, never by hand; `sheetkin.compute(scene)`
    computes it. In a notebook it draws itself (an SVG of the mechanism at its first position)."""

    title: str
    author: str
    frame: dict[str, tuple[float, float]]
    crank: Crank
    groups: tuple[Group, ...]
    points: tuple[Point, ...]
    plan: tuple[tuple[str, object], ...]   # ("crank", Crank) | ("group", Group) | ("point", Point)
    source: str = "<scene>"
    gravity: tuple[float, float] = (0.0, 0.0)    # m/s^2; (0, -9.81) when y points up
    masses: tuple[Mass, ...] = ()
    forces: tuple[Force, ...] = ()

    def _repr_svg_(self) -> str | None:
        """Jupyter shows a Scene as its mechanism at the first crank position. The drawing
        is a view above this stage: `draw_in_notebook` if set, else the package's
        (sheetkin/__init__.py: `import sheetkin` no longer loads this module to install it);
        without one, Jupyter shows the repr."""
        draw = draw_in_notebook or getattr(sys.modules.get("sheetkin"), "_draw_scene", None)
        return draw(self) if draw is not None else None

    @property
    def has_dynamics(self) -> bool:
        """The scene has something for the energy and force analysis to work on."""
        return bool(self.masses or self.forces)

    @property
    def links(self) -> list[int]:
        """Moving links after the crank, in number order (2, 3, ...)."""
        return [k for g in self.groups for k in g.links]

    @property
    def moving_joints(self) -> list[str]:
        return [self.crank.joint] + [n for g in self.groups for n in kind_of(g).new_joints(g)]

    @property
    def sliders(self) -> list[str]:
        """Slide tags in group order (`sheetkin.groups.group.slide_names` gives `s_*`, `vs_*`, `as_*`)."""
        return [t for g in self.groups for t in kind_of(g).sliders(g)]

    def crank_angles_deg(self) -> list[float]:
        c = self.crank
        return [c.phi0_deg + i * c.step_deg for i in range(c.positions)]


# --------------------------------------------------------------------------- locating keys
class KeyLocator:
    """Finds the line of a key in the TOML text (tomllib keeps no positions)."""

    def __init__(self, text: str):
        self.lines = text.splitlines()
        self.tables: dict[tuple[str, int], int] = {}   # (table, occurrence) -> header line
        counts: dict[str, int] = {}
        for no, line in enumerate(self.lines, 1):
            m = re.match(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\"]+)\s*\]\]?", line)
            if m:
                name = m.group(2)
                i = counts.get(name, 0)
                counts[name] = i + 1
                self.tables[(name, i)] = no

    def line(self, table: str | None, index: int = 0, key: str | None = None) -> int | None:
        """Line of `key` inside the index-th `table` ([table] or [[table]]); for a dotted
        key a.b: the line `a = {...}`, `a.b = ...`, or `b = ...` under a [table.a] header.
        With table None, a top-level key: `key = ...` or a [key] / [[key]] header."""
        start = self.tables.get((table, index), 0) if table else 0
        if table and not start:
            return None
        if key is None:
            return start or None
        head, _, rest = key.partition(".")
        found = self._key_line(start, head) or (rest and self._key_line(start, key))
        if not found and rest and table:
            sub = next((no for (name, i), no in sorted(self.tables.items(), key=lambda t: t[1])
                        if name == f"{table}.{head}" and no > start), None)
            found = sub and (self._key_line(sub, rest) or sub)
        if not found and not table:
            found = self.tables.get((key, 0))
        return found or start or None

    def _key_line(self, start: int, key: str) -> int | None:
        pat = re.compile(rf"^\s*{re.escape(key)}\s*=")
        for no in range(start + 1, len(self.lines) + 1):
            text = self.lines[no - 1]
            if no > start + 1 and re.match(r"^\s*\[", text):
                return None    # the table (or the top level, before any header) ended
            if pat.match(text):
                return no
        return None


class SceneContext:
    """Where we are in the file, to build one-line errors."""

    def __init__(self, source: str, loc: KeyLocator | str):
        # the locator is built on the first error only (its line scan is most of the cost
        # of a long valid file): `loc` may be the scene's text
        self.source, self._loc = source, loc

    @property
    def loc(self) -> KeyLocator:
        if isinstance(self._loc, str):
            self._loc = KeyLocator(self._loc)
        return self._loc

    def fail(self, where: str, table: str | None, index: int, key: str | None, msg: str) -> NoReturn:
        no = self.loc.line(table, index, key)
        pos = f"{self.source}:{no}" if no else self.source
        what = f"{where} key '{key}'" if key else where
        raise SceneError(one_line(f"{pos}: {what}: {msg}"))


def _type_name(v) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
            list: "an array", dict: "a table"}.get(type(v), type(v).__name__)


_CHECKS = {
    "a number": lambda x: isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x),
    "an integer": lambda x: isinstance(x, int) and not isinstance(x, bool),
    "a string": lambda x: isinstance(x, str),
}


class SceneTable:
    """One TOML table with typed getters that raise SceneError naming the key."""

    def __init__(self, ctx: SceneContext, data, where: str, table: str | None, index: int = 0):
        self.ctx, self.where, self.table, self.index = ctx, where, table, index
        if not isinstance(data, dict):
            # e.g. `frame = 5`: point at that line (there is no [frame] header to find)
            ctx.fail("scene", None, 0, table, f"expected a [{table}] table, got {_type_name(data)}")
        self.data = data

    # set by `reporting_through`: a nested table names its keys under its parent's
    _redirect: Callable[[str | None, str], NoReturn] | None = None

    def fail(self, key: str | None, msg: str) -> NoReturn:
        if self._redirect is not None:
            self._redirect(key, msg)
        self.ctx.fail(self.where, self.table, self.index, key, msg)

    def reporting_through(self, fail: Callable[[str | None, str], NoReturn]) -> SceneTable:
        """This table, reporting its mistakes through `fail` (e.g. `guide.through` named
        under the group that holds the inline guide table)."""
        self._redirect = fail
        return self

    def check_keys(self, allowed):
        for k in self.data:
            if k not in allowed:
                self.fail(k, f"unknown key; expected one of: {', '.join(allowed)}")

    def get(self, key, kind, default=...):
        if key not in self.data:
            if default is ...:
                self.fail(key, f"missing; expected {kind}")
            return default
        v = self.data[key]
        if not _CHECKS[kind](v):
            if isinstance(v, float) and not math.isfinite(v):
                self.fail(key, f"expected a finite number, got {shown(v)}")
            self.fail(key, f"expected {kind}, got {_type_name(v)} {shown(v)}")
        return float(v) if kind == "a number" else v

    def positive(self, key):
        v = self.get(key, "a number")
        if v <= 0:
            self.fail(key, f"expected a positive length in metres, got {v:g}")
        return v

    def name(self, key):
        v = self.get(key, "a string")
        if not NAME_RE.match(v):
            self.fail(key, f"expected a name of letters, digits and _ starting with a letter, got {shown(v)}")
        return v

    def guide(self, key, frame) -> Guide:
        """The guide table `key` (see _parse_guide)."""
        return _parse_guide(self, key, frame)

    def guides(self, key, n, frame) -> tuple[Guide, ...]:
        """An array of exactly n guide tables (PRP: `guides = [guide_a, guide_b]`)."""
        v = self.data.get(key, ...)
        if v is ... or not isinstance(v, list) or len(v) != n:
            self.fail(key, f"expected an array of {n} guides {{through = ..., angle_deg = ..., link = ...}}, "
                           f"got {'nothing' if v is ... else _type_name(v)}")
        return tuple(_parse_guide(self, key, frame, i) for i in range(n))

    def array(self, key, n, kind):
        v = self.data.get(key, ...)
        if v is ...:
            self.fail(key, f"missing; expected an array of {n} {kind}s")
        if not isinstance(v, list) or len(v) != n:
            self.fail(key, f"expected an array of {n} {kind}s, got {shown(v)}")
        ok = {"number": lambda x: isinstance(x, (int, float)) and not isinstance(x, bool)
              and math.isfinite(x),
              "name": lambda x: isinstance(x, str) and bool(NAME_RE.match(x)),
              "integer": lambda x: isinstance(x, int) and not isinstance(x, bool)}[kind]
        if not all(ok(x) for x in v):
            self.fail(key, f"expected an array of {n} {kind}s, got {shown(v)}")
        return tuple(float(x) for x in v) if kind == "number" else tuple(v)


# --------------------------------------------------------------------------- parsing
def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file; raises SceneError (one line) on any mistake."""
    if isinstance(path, str) and "\n" in path:
        raise SceneError("load_scene takes a scene file's path; for a scene's text use "
                         "sheetkin.parse_scene(text) (compute() takes either)")
    path = Path(path)
    try:
        # bounded and non-blocking: /dev/zero or a FIFO is refused before a byte is read
        text = read_text(path, MAX_SCENE_BYTES, "scene .toml file")   # utf-8-sig: Notepad's byte-order mark
    except FileNotFoundError:
        raise SceneError(one_line(f"{path}: no such file")) from None
    except IsADirectoryError:
        raise SceneError(one_line(f"{path}: is a directory, expected a scene .toml file")) from None
    except UnicodeDecodeError:
        raise SceneError(one_line(f"{path}: not a UTF-8 text file, expected a scene .toml file")) from None
    except OSError as e:
        raise SceneError(one_line(f"{path}: cannot read: {e.strerror}")) from None
    if len(text) > MAX_SCENE_BYTES:
        raise SceneError(one_line(f"{path}: {len(text):,} characters; a scene file may hold at most "
                                  f"{MAX_SCENE_BYTES:,} (a scene is a few KB)"))
    return parse_scene(text, str(path))


def _fail_at(ctx: SceneContext, data: dict, path: tuple, msg: str):
    """SceneError at a value's path in the document: [table] key, [[table]] #i key, or a
    top-level key, located as the typed getters locate theirs."""
    head = path[0]
    keys = [k for k in path[1:] if isinstance(k, str)]
    top = data.get(head)
    if len(path) > 2 and isinstance(top, list) and isinstance(path[1], int) and isinstance(top[path[1]], dict):
        ctx.fail(f"[[{head}]] #{path[1] + 1}", head, path[1], ".".join(map(str, path[2:3] + tuple(keys[1:2]))), msg)
    if len(path) > 1 and isinstance(top, dict):
        ctx.fail(f"[{head}]", head, 0, ".".join(keys[:2]), msg)
    ctx.fail("scene", None, 0, head, msg)


def as_scene(scene: Scene | str | Path) -> Scene:
    """A Scene from a Scene, a scene file's path, or a scene's TOML text: the Python API's
    `compute(...)`, `result(...)` take any of them. Text is told from a path by its line
    breaks or its `=` (a scene holds both; a file name neither), so a path is never parsed
    as text and a text never looked for on disk (it used to be, echoed whole in "no such file")."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str) and ("\n" in scene or ("=" in scene and not _is_file(scene))):
        return parse_scene(scene, "<scene text>")
    return load_scene(scene)


def _is_file(name: str) -> bool:
    try:
        return Path(name).is_file()
    except (OSError, ValueError):       # too long for a file name, or a NUL in it
        return False


def parse_scene(text: str, source: str = "<scene>") -> Scene:
    """The scene in `text` (TOML, the scene format: `sheetkin docs scene-format`), checked.

    `source` names it in errors. A mistake raises `SceneError` with one line that names the
    source, the line and the key; `load_scene(path)` reads a file the same way."""
    data = load_toml(text, source)
    ctx = SceneContext(source, text)
    check_values(data, lambda path, msg: _fail_at(ctx, data, path, msg))
    top = SceneTable(ctx, data, "scene", None)
    top.check_keys(["title", "author", "frame", "crank", "group", "point", "gravity", "mass",
                    "force", "synthesis"])
    # [synthesis] (the data a crank-rocker was synthesized from) is read and checked by
    # sheetkin.studies.synthesis when a workbook gets its synthesis sheet
    title = top.get("title", "a string", Path(source).stem)
    author = top.get("author", "a string", "")

    known: dict[str, str] = {}     # name -> what defined it (for "defined twice")

    def define(tbl: SceneTable, key: str, name: str, what: str):
        if name in known:
            tbl.fail(key, f"name '{name}' is defined twice (already {known[name]})")
        known[name] = what

    frame = _parse_frame(ctx, data, define)
    crank = _parse_crank(ctx, data, frame, define)
    groups = _parse_groups(ctx, data, frame, define)
    points = _parse_points(ctx, data, define)
    plan = _make_plan(ctx, frame, crank, groups, points)
    _check_slides(ctx, groups)
    gravity = top.array("gravity", 2, "number") if "gravity" in data else (0.0, 0.0)
    on_link = link_joints(crank, groups)
    for p in points:
        on_link[p.link].append(p.name)
    masses = _parse_masses(ctx, data, on_link)
    forces = _parse_forces(ctx, data, on_link)
    return Scene(title, author, frame, crank, tuple(groups), tuple(points), plan, source,
                 gravity, masses, forces)


def _parse_frame(ctx, data, define):
    if "frame" not in data:
        ctx.fail("scene", None, 0, "frame", "missing; expected a [frame] table of fixed points")
    tbl = SceneTable(ctx, data["frame"], "[frame]", "frame")
    frame = {}
    for name in tbl.data:
        if not NAME_RE.match(name):
            tbl.fail(name, "expected a point name of letters, digits and _ starting with a letter")
        frame[name] = tbl.array(name, 2, "number")
        define(tbl, name, name, "a frame point")
    if not frame:
        tbl.fail(None, "expected at least one fixed point, e.g. O = [0.0, 0.0]")
    return frame


def _parse_crank(ctx, data, frame, define):
    if "crank" not in data:
        ctx.fail("scene", None, 0, "crank", "missing; expected a [crank] table")
    tbl = SceneTable(ctx, data["crank"], "[crank]", "crank")
    tbl.check_keys(["pivot", "joint", "length", "phi0_deg", "step_deg", "positions",
                    "omega", "epsilon"])
    pivot = tbl.name("pivot")
    if pivot not in frame:
        tbl.fail("pivot", f"expected a frame point ({', '.join(frame)}), got '{pivot}'")
    joint = tbl.name("joint")
    define(tbl, "joint", joint, "the crank's joint")
    positions = tbl.get("positions", "an integer", 13)
    if not 1 <= positions <= MAX_POSITIONS:
        tbl.fail("positions", f"expected an integer >= 1 and at most {MAX_POSITIONS:,} (the compute cap; a "
                              f"workbook holds at most {WORKBOOK_MAX_POSITIONS:,}), got {positions:,}")
    step = tbl.get("step_deg", "a number", 30.0)
    if step == 0 and positions > 1:
        tbl.fail("step_deg", f"expected a nonzero step: with step 0 all {positions} positions are "
                             "the same crank angle (use positions = 1 for one angle)")
    return Crank(pivot, joint, tbl.positive("length"), tbl.get("phi0_deg", "a number", 0.0),
                 step, positions, tbl.get("omega", "a number"),
                 tbl.get("epsilon", "a number", 0.0))


def _parse_groups(ctx, data, frame, define):
    raw = data.get("group", [])
    if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
        ctx.fail("scene", None, 0, "group", "expected [[group]] tables (double brackets: one per group)")
    groups, next_link = [], 2
    for i, g in enumerate(raw):
        tbl = SceneTable(ctx, g, f"[[group]] #{i + 1}", "group", i)
        if "type" not in tbl.data:
            tbl.fail("type", f"missing; expected one of {', '.join(GROUP_TYPES)}")
        kind = tbl.get("type", "a string")
        if kind not in KINDS:
            tbl.fail("type", f"unknown group type '{kind}'; expected one of {', '.join(GROUP_TYPES)}")
        mod = KINDS[kind]
        tbl.check_keys(mod.KEYS)
        links = tbl.array("links", 2, "integer")
        if links != (next_link, next_link + 1):
            tbl.fail("links", f"expected [{next_link}, {next_link + 1}] (links are numbered 0 frame, "
                              f"1 crank, then each group's links in file order), got {list(links)}")
        next_link += 2
        joints, params = mod.parse(tbl, frame)
        group = Group(i + 1, kind, links, joints, params)
        for n in mod.new_joints(group):
            define(tbl, "joints", n, f"the new joint of group {i + 1}")
        groups.append(group)
    return groups


def _check_slides(ctx, groups):
    """One name, one quantity: two groups may not both define s_P."""
    slides: dict[str, int] = {}
    for g in groups:
        for tag in kind_of(g).sliders(g):
            if tag in slides:
                ctx.fail(f"[[group]] #{g.index}", "group", g.index - 1, "joints",
                         f"group {slides[tag]} already defines the slide of '{tag}' "
                         f"({slide_names(tag)[0]}); a slider quantity is named once")
            slides[tag] = g.index


def _parse_guide(tbl: SceneTable, key: str, frame, index: int | None = None) -> Guide:
    """A guide `{through = POINT or [x, y], angle_deg = A, link = k}` (the contract's
    "Group types"): on the frame (link 0, the default) `through` is a frame point or [x, y];
    on a moving link k it names a point of link k (checked when the scene is planned).
    With `index`, the index-th element of the array `key` (PRP's `guides`)."""
    expected = "{through = POINT or [x, y], angle_deg = ..., link = k}"
    value = tbl.data.get(key, ...)
    where = key
    if index is not None:
        if not isinstance(value, list):
            tbl.fail(key, f"expected an array of guides [{expected}, ...], got {_type_name(value)}")
        value, where = value[index], f"{key}[{index}]"
    if value is ...:
        tbl.fail(key, f"missing; expected {key} = {expected}")
    if not isinstance(value, dict):
        tbl.fail(key, f"expected {where} = {expected}, got {_type_name(value)}")
    guide = SceneTable(tbl.ctx, value, tbl.where, tbl.table, tbl.index)
    guide.reporting_through(lambda k, msg: tbl.fail(f"{where}.{k}" if k else where, msg))
    guide.check_keys(["through", "angle_deg", "link"])
    link = guide.get("link", "an integer", 0)
    if link < 0:
        guide.fail("link", f"expected 0 (the frame) or a moving link's number, got {link}")
    angle = guide.get("angle_deg", "a number", 0.0)
    through = guide.data.get("through", ...)
    if through is ...:
        guide.fail("through", "missing; expected a point's name" + (" or [x, y]" if link == 0 else ""))
    if isinstance(through, str):
        name = guide.name("through")
        if link == 0:
            if name not in frame:
                guide.fail("through", f"expected a frame point ({', '.join(frame)}) or [x, y], got '{name}'")
            return Guide(name, tuple(frame[name]), angle, 0)
        return Guide(name, None, angle, link)
    if link != 0:
        guide.fail("through", f"a guide on moving link {link} passes through a point of that link: "
                              f"expected its name, got {through!r}")
    return Guide(None, tuple(guide.array("through", 2, "number")), angle, 0)


def _parse_points(ctx, data, define):
    raw = data.get("point", [])
    if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
        ctx.fail("scene", None, 0, "point", "expected [[point]] tables (double brackets: one per point)")
    points = []
    for i, p in enumerate(raw):
        tbl = SceneTable(ctx, p, f"[[point]] #{i + 1}", "point", i)
        tbl.check_keys(["name", "link", "from", "along", "across"])
        name = tbl.name("name")
        define(tbl, "name", name, f"point #{i + 1}")
        points.append(Point(name, tbl.get("link", "an integer"), tbl.name("from"),
                            tbl.get("along", "a number", 0.0), tbl.get("across", "a number", 0.0)))
    return points


def _array_of_tables(ctx, data, key: str):
    raw = data.get(key, [])
    if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
        ctx.fail("scene", None, 0, key, f"expected [[{key}]] tables (double brackets: one per {key})")
    return raw


def _link_and_point(tbl: SceneTable, on_link: dict[int, list[str]], point_key: str, required: bool):
    """`link` (a moving link) and a point of it named by `point_key`, for [[mass]]/[[force]]."""
    link = tbl.get("link", "an integer")
    if link not in on_link:
        tbl.fail("link", f"expected a moving link 1..{max(on_link)}, got {link}")
    if point_key not in tbl.data:
        if not required:
            return link, None
        tbl.fail(point_key, f"missing; expected a joint or point of link {link} ({', '.join(on_link[link])})")
    name = tbl.name(point_key)
    if name not in on_link[link]:
        tbl.fail(point_key, f"expected a joint or point of link {link} "
                            f"({', '.join(on_link[link])}), got '{name}'")
    return link, name


def _parse_masses(ctx, data, on_link) -> tuple[Mass, ...]:
    masses: dict[int, Mass] = {}
    for i, m in enumerate(_array_of_tables(ctx, data, "mass")):
        tbl = SceneTable(ctx, m, f"[[mass]] #{i + 1}", "mass", i)
        tbl.check_keys(["link", "mass", "inertia", "centre"])
        link, centre = _link_and_point(tbl, on_link, "centre", True)
        if link in masses:
            tbl.fail("link", f"link {link} already has a [[mass]]; give each link one")
        inertia = tbl.get("inertia", "a number", 0.0)
        if inertia < 0:
            tbl.fail("inertia", f"expected a moment of inertia >= 0 in kg m^2, got {inertia:g}")
        mass = tbl.get("mass", "a number")
        if mass <= 0:
            tbl.fail("mass", f"expected a positive mass in kg, got {mass:g}")
        masses[link] = Mass(link, mass, inertia, centre)
    return tuple(sorted(masses.values(), key=lambda m: m.link))


def _parse_forces(ctx, data, on_link) -> tuple[Force, ...]:
    forces = []
    names: set[str] = set()
    for i, f in enumerate(_array_of_tables(ctx, data, "force")):
        tbl = SceneTable(ctx, f, f"[[force]] #{i + 1}", "force", i)
        tbl.check_keys(["name", "link", "at", "force", "moment", "from_deg", "to_deg"])
        name = tbl.name("name") if "name" in tbl.data else f"F{i + 1}"
        if name in ("ext", "bal"):
            # P_<name> is the load's power row; P_ext and P_bal are the totals'
            tbl.fail("name", f"'{name}' is reserved (P_{name} names a total); choose another name")
        if name in names:
            tbl.fail("name", f"name '{name}' is used by another [[force]]")
        names.add(name)
        has_force = "force" in tbl.data
        if not has_force and "moment" not in tbl.data:
            tbl.fail(None, "expected `force = [Fx, Fy]` (N, with `at`) and/or `moment` (N m)")
        link, at = _link_and_point(tbl, on_link, "at", has_force)
        force = tbl.array("force", 2, "number") if has_force else (0.0, 0.0)
        interval = None
        if "from_deg" in tbl.data or "to_deg" in tbl.data:
            lo, hi = tbl.get("from_deg", "a number"), tbl.get("to_deg", "a number")
            if not 0.0 < hi - lo < 360.0:
                tbl.fail("to_deg", f"expected from_deg < to_deg < from_deg + 360 (the crank angles, "
                                   f"degrees, while the force acts), got {lo:g}..{hi:g}")
            interval = (lo, hi)
        forces.append(Force(i + 1, name, link, at, force, tbl.get("moment", "a number", 0.0), interval))
    return tuple(forces)


def link_joints(crank: Crank, groups) -> dict[int, list[str]]:
    """The joints each moving link carries (where a point on it may be measured from)."""
    out = {1: [crank.pivot, crank.joint]}
    for g in groups:
        out.update(kind_of(g).carries(g))
    return out


def _check_points(ctx, points, on_link, on_link_set, n_links: int) -> None:
    """Each point on a moving link, measured from a joint or another point of its link:
    checked before placement, so a bad `from` is blamed on the point, not on a group that
    needs the point (a point that its own link's group uses as a joint is circular: the
    group's `joints` is the mistake, reported during placement)."""
    names_on: dict[int, set[str]] = {}   # link -> names of the points on it
    for p in points:
        names_on.setdefault(p.link, set()).add(p.name)
    for i, p in enumerate(points):
        if not 1 <= p.link <= n_links:
            ctx.fail(f"[[point]] #{i + 1}", "point", i, "link",
                     f"expected a moving link 1..{n_links}, got {p.link}")
        if not (p.origin in on_link_set[p.link] or (p.origin in names_on[p.link] and p.origin != p.name)
                or p.name in on_link_set[p.link]):
            allowed = on_link[p.link] + [q.name for q in points if q.link == p.link and q is not p]
            ctx.fail(f"[[point]] #{i + 1}", "point", i, "from",
                     f"expected a joint or point of link {p.link} ({', '.join(allowed)}), got '{p.origin}'")


def _check_group(ctx, g, known: set, on_link: dict, placer: dict) -> None:
    """A group's joints placed before it, its guides on earlier links and named there."""
    kind = kind_of(g)
    where = (f"[[group]] #{g.index}", "group", g.index - 1)
    for name in kind.needs(g):
        if name not in known:
            ctx.fail(*where, "joints", f"'{name}' {_not_yet(name, g, placer)}")
    for key, name, link in kind.on_links(g):
        if link >= g.links[0]:
            ctx.fail(*where, key.split(".")[0],
                     f"link {link} is not placed before group {g.index} (its links are {list(g.links)}); "
                     f"a guide may be on the frame (0), the crank (1) or an earlier group's link")
        if name not in on_link.get(link, []):
            ctx.fail(*where, key, f"'{name}' is not a point of link {link} "
                                  f"(expected one of {', '.join(on_link.get(link, []))})")


def _make_plan(ctx, frame, crank, groups, points):
    """Order of placement: crank, then each group; a point as soon as its link is placed.

    TOML keeps no order between [[group]] and [[point]] arrays, and a group may need a
    point on an earlier link (seed 001: C on the slotted lever drives the coupler), so
    points are placed by dependency, not by file order.
    """
    on_link = link_joints(crank, groups)
    on_link_set = {k: set(v) for k, v in on_link.items()}
    _check_points(ctx, points, on_link, on_link_set, 1 + 2 * len(groups))
    known = set(frame) | {crank.joint}
    plan: list[tuple[str, object]] = [("crank", crank)]
    # Points go in the order of repeated passes over the file's points (a point whose
    # `from` was placed earlier in the same pass goes in that pass, else in the next).
    # Emulated with a heap of (pass, index) and, per (link, name), the points waiting
    # for that name: linear in the number of points, as 20,000 of them must parse in
    # well under a second (the passes themselves were quadratic).
    waiting: dict[tuple[int, str], list[int]] = {}
    by_link: dict[int, list[int]] = {}
    for i, p in enumerate(points):
        waiting.setdefault((p.link, p.origin), []).append(i)
        by_link.setdefault(p.link, []).append(i)
    placed = [False] * len(points)

    def place_points(new_links):
        heap = [(1, i) for k in new_links for i in by_link.get(k, ())
                if points[i].origin in on_link_set[k]]
        heapq.heapify(heap)
        while heap:
            pass_no, i = heapq.heappop(heap)
            p = points[i]
            if placed[i]:
                continue
            placed[i] = True
            plan.append(("point", p))
            known.add(p.name)
            on_link[p.link].append(p.name)
            on_link_set[p.link].add(p.name)
            for j in waiting.get((p.link, p.name), ()):
                if not placed[j]:
                    heapq.heappush(heap, (pass_no if j > i else pass_no + 1, j))

    place_points([1])
    placer = {n: g for g in groups for n in kind_of(g).new_joints(g)}
    placer.update({p.name: p for p in points})
    for g in groups:
        _check_group(ctx, g, known, on_link, placer)
        plan.append(("group", g))
        known.update(kind_of(g).new_joints(g))
        place_points(g.links)
    pending = [(i, p) for i, p in enumerate(points) if not placed[i]]
    for i, p in pending:   # only points measured from each other in a circle remain
        ctx.fail(f"[[point]] #{i + 1}", "point", i, "from",
                 f"'{p.origin}' is measured, directly or through other points, from '{p.name}' itself")
    return tuple(plan)


def key_line(text: str, table: str | None, key: str) -> int | None:
    """Line number of `key` in [table] of a scene's text (for messages about a valid
    scene's values, e.g. a workbook's column cap)."""
    return KeyLocator(text).line(table, 0, key)


def _not_yet(name: str, g: Group, placer: dict) -> str:
    """Why a group cannot use `name` yet: naming what defines it later, or that nothing does."""
    by = placer.get(name)
    if by is None:
        return "is not defined anywhere (no frame point, joint or [[point]] of that name)"
    what = (f"{by.label}, later in the file" if isinstance(by, Group)
            else f"[[point]] '{by.name}' on link {by.link}, known only after link {by.link} is placed")
    return (f"is used by {g.label} before it is known: it is placed by {what}; a group may use "
            "frame points, the crank's joint, joints of earlier groups and points on earlier links")


def override_crank(text: str, source: str = "<scene>", **values) -> tuple[str, Scene]:
    """The scene text with some [crank] keys replaced (positions, step_deg, phi0_deg ...),
    and the scene it parses to. The text is patched, not regenerated, so comments stay and
    a workbook can embed exactly the scene it was made from."""
    lines = text.splitlines()
    loc = KeyLocator(text)
    header = loc.line("crank")
    if header is None:
        raise SceneError(f"{source}: no [crank] table to change")
    for key, value in values.items():
        literal = repr(value) if isinstance(value, (int, float)) else f'"{value}"'
        no = loc._key_line(header, key)
        if no:
            def keep_comment(m: re.Match[str], literal: str = literal) -> str:
                return f"{m.group(1)}{literal}{m.group(2) or ''}"
            lines[no - 1] = re.sub(rf"^(\s*{key}\s*=\s*)[^#]*?(\s*(#.*)?)$", keep_comment, lines[no - 1])
        else:
            lines.insert(header, f"{key} = {literal}")
            loc = KeyLocator("\n".join(lines))
    new = "\n".join(lines) + "\n"
    return new, parse_scene(new, source)
