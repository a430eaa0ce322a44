"""The surface of a group kind, as a typed Protocol (checked by mypy, not at run time).

A kind is a module (sheetkin.groups.rrr ...), and mypy checks a module against a Protocol
when it is assigned to a variable of the Protocol's type: sheetkin.groups types its table
`KINDS` and `kind_of` with `KindModule`, and assigns every bundled kind to it in a
typing-only block, so a kind that misses a member, or gives one the wrong signature, fails
`mypy`. At run time `sheetkin.groups.register` checks that the members are there.

The members, in the order a kind module declares them (groups/__init__.py says what each
one means; docs/adding-a-kind.md shows a whole kind):

  what it is          KIND, LECTURE, SLIDES, TITLE, KEYS
  scene keys          Params, parse, needs, on_links, new_joints, carries, sliders, fourbar
  the drawing         parts (links, guides and slots, blocks; the guides' input rows)
  positions, rates    solve
  the workbook        TEXTS, input_rows, with_inputs, rows
  kinetostatics       pin_owner, pairs, reactions, reaction_rows
  loop equations      loop, side_ok, discriminant, unknowns
  stability families  STABILITY

Constants are read-only properties here, so that a module's `KIND = "RRR"` (a str) and
`STABILITY = (Family(...), ...)` (a tuple of any length) match them.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:       # motion imports numpy; `sheetkin --help` imports this module
    from .group import Family, Group
    from .motion import GroupMotion, Motion, Pair, Rotation
    from .parts import Parts
    from .rows import Builder, InputRow, LoadRows, Text

# every member a kind module must define (register checks them at run time)
MEMBERS = ("KIND", "LECTURE", "SLIDES", "TITLE", "KEYS", "Params", "parse", "needs", "on_links", "new_joints",
           "carries", "sliders", "fourbar", "parts", "solve", "TEXTS", "input_rows", "with_inputs", "rows", "pin_owner",
           "pairs", "reactions", "reaction_rows", "loop", "side_ok", "discriminant", "unknowns", "STABILITY")


class KindModule(Protocol):
    """One Assur group kind (a module). g is always a Group of this kind."""

    # --- what it is
    @property
    def KIND(self) -> str: ...          # the scene's `type`
    @property
    def LECTURE(self) -> str: ...       # the course's code (section titles)
    @property
    def SLIDES(self) -> str: ...
    @property
    def TITLE(self) -> Text: ...        # one line in the course's words, ru, uk, en
    @property
    def KEYS(self) -> tuple[str, ...]: ...      # allowed scene keys, "type" and "links" included

    # --- scene keys
    @property
    def Params(self) -> type: ...       # frozen dataclass of the kind's own fields (g.params)

    def parse(self, tbl: Any, frame: Mapping[str, Any]) -> tuple[tuple[str, ...], Any]: ...
    def needs(self, g: Group) -> list[str]: ...
    def on_links(self, g: Group) -> list[tuple[str, str, int]]: ...
    def new_joints(self, g: Group) -> list[str]: ...
    def carries(self, g: Group) -> dict[int, list[str]]: ...
    def sliders(self, g: Group) -> list[str]: ...
    def fourbar(self, g: Group, crank_joint: str, frame: Any) -> tuple[float, float, str, int] | None: ...

    # --- the drawing (sheetkin.views.drawing, the charts sheet)
    def parts(self, g: Group) -> Parts: ...

    # --- positions, velocities, accelerations
    def solve(self, g: Group, known: dict[str, Motion], rot: dict[int, Rotation], scale: float) -> GroupMotion: ...

    # --- the workbook: the rows' texts, {"ru": {key: template}, "uk": {...}, "en": {...}} (one table
    # per language, the same keys and format fields in each; rows.Texts(TEXTS)(key, **fields) is a Text)
    @property
    def TEXTS(self) -> Mapping[str, Mapping[str, str]]: ...
    def input_rows(self, g: Group) -> list[InputRow]: ...
    def with_inputs(self, g: Group, num: Any) -> Group: ...
    def rows(self, b: Builder, g: Group) -> None: ...

    # --- kinetostatics
    def pin_owner(self, g: Group) -> dict[str, int]: ...
    def pairs(self, g: Group, owner: dict[str, int]) -> list[Pair]: ...
    def reactions(self, g: Group, known: Any, links: Any, loads: Any, owner: Any) -> dict[str, tuple]: ...
    def reaction_rows(self, b: Builder, g: Group, owner: dict[str, int], k: LoadRows) -> None: ...

    # --- loop equations (Newton, the mpmath reference)
    def loop(self, lib: Any, g: Group, known: Any, links: Any) -> Any: ...
    def side_ok(self, lib: Any, g: Group, known: Any, links: Any, q: Any, joints: Any) -> bool: ...
    def discriminant(self, lib: Any, g: Group, known: Any, links: Any) -> Any: ...
    def unknowns(self, g: Group, sol: Any) -> tuple[Any, Any]: ...

    # --- stability families (sheetkin bench --stability)
    @property
    def STABILITY(self) -> tuple[Family, ...]: ...
