"""The Assur group kinds: one module per kind, behind one explicit table.

`KINDS` maps a scene's `type` to the module that knows everything about that kind (the
contract's "Group types", docs/scene-format.md). The scene parser, the solver, the
workbook writer, the dynamics (numpy and sheet), the bench and the validator iterate over
a scene's groups and ask `kind_of(g)`; none of them tests a kind's name. Adding a kind is
one new module here, one line in `KINDS`, its tests (tests/helpers/kinds.py) and a bundled scene
(docs/adding-a-kind.md); a kind kept outside the package is one call to `register`. The
surface below is typed as `protocol.KindModule`, which mypy checks every kind against.

Every kind module provides the same surface, under banners in this order:

  # --- what it is
  KIND = "RPR"               the scene's `type`
  LECTURE = "ВПВ"            the course's code (section titles); SLIDES = "22-24"
  TITLE = Text(ru, uk, en)   one line in the course's words ("block on J1 in a kulisa ...")
  KEYS = (...)               the allowed scene keys, "type" and "links" included

  # --- scene keys
  Params                     frozen dataclass of the kind's own fields (g.params; read
                             through as g.branch, g.length, g.guide ...)
  parse(tbl, frame) -> (joints, Params)
        tbl is the [[group]] table (sheetkin.kinematics.scene's typed getters: get, array, positive,
        name, fail(key, msg), guide(key, frame) -> group.Guide); report every mistake with
        tbl.fail (one line naming file, line, key). `type`, `links` are checked before.
  needs(g) -> list[str]      points that must be known before the group is placed (J1,
                             J2, a moving guide's `through`), in the order to report them
  on_links(g) -> [(key, point, link)]  points that must belong to a given link (RRP: a
                             moving guide's `through` is a point of the guide's link)
  new_joints(g) -> list[str] joints the group places (RRR/RRP/PRP: N; RPP: K; RPR: none)
  carries(g) -> {link: [joints]}  the joints on each of its two links ([[point]] `from`,
                             [[mass]] `centre`, [[force]] `at` must be one of them)
  sliders(g) -> list[str]    slide tags, named by group.slide_names: "N" -> s_N, vs_N,
                             as_N; "2_N" -> s2_N, vs2_N, as2_N
  fourbar(g, crank_joint, frame) -> (coupler, rocker, pivot, branch) or None   the four-bar
                             the group closes with the crank (seed 002's synthesis designs
                             its lengths; only an RRR from the crank's joint to a frame point)
  parts(g) -> parts.Parts    what the drawing and the charts sheet draw: the points on each
                             link, the guides and slots (parts.GuidePart, with the input rows
                             of a guide's angle and point), the blocks on them

  # --- positions, velocities, accelerations (numpy over crank positions)
  solve(g, known, rot, scale) -> motion.GroupMotion
        known: name -> Motion of every known point; rot: link -> Rotation of every placed
        link (0 is motion.FRAME); scale: the crank's length. Closed form (the scene's
        branch), then the Cramer systems (same matrix for velocities and accelerations).
        GroupMotion(joints={N: Motion}, links={a: Rotation, b: Rotation},
                    slides={tag: Slide}, disc, toggle); toggle = det / (its lengths), free
                    of where the mechanism sits and of its size.

  # --- the workbook (sheetkin.groups.rows.Builder)
  TEXTS = {"ru": {...}, "uk": {...}, "en": {...}}   the rows' descriptions: format templates by
                             key, one table per language, the same keys and fields in each;
                             T = rows.Texts(TEXTS), T("phi_a", la=2) is a rows.Text (all three)
  input_rows(g) -> list[rows.InputRow]   the group's editable inputs; InputRow.early: written
                             with the lengths (before the frame points), else after them.
                             Names: L{k} lengths, gx_g{i} gy_g{i} gamma_g{i} a guide,
                             e_g{i} an offset, branch_g{i} the branch.
  with_inputs(g, num) -> Group   the group rebuilt from a student's inputs (validator):
                             num(name, default, choices=None) -> float
  rows(b, g)                 the block in the lecture's order: intermediate rows (P_g{i} ...),
                             the discriminant D_g{i} and rows.group_guard, every branch with
                             its checks, "accepted values" (contract names), Cramer rows for
                             velocities (Delta_g{i}, det_g{i}), f1_g{i}/f2_g{i}, Cramer rows for
                             accelerations, the new joint's motion (rows.motion_rows) and
                             checks (chk_*, at least one every 8 rows), each written by its
                             kind's builder: b.section, b.calc, b.accepted, b.check with a
                             T(key, ...) text. Sets b.rot[a], b.rot[b]
                             (cos, sin, omega, eps row names) and b.guard_of_link[a], [b].

  # --- kinetostatics
  pin_owner(g) -> {joint: link}   the link a later group hinges to at a new joint
  pairs(g, owner) -> list[motion.Pair]   the pairs whose reactions it computes (J1 side,
                             inner, J2 side); Pair(i, j, joint, sliding)
  reactions(g, known, links, loads, owner) -> {tag: (Rx, Ry, couple or None)}   numpy;
                             adds what it exerts on earlier links to `loads` (motion.Loads)
  reaction_rows(b, g, owner, k)   the same in the sheet; k is a rows.LoadRows (link_loads,
                             reaction, cramer_reaction, equilibrium, loads)

  # --- loop equations (Newton, the 50-digit mpmath reference, property tests)
  loop(lib, g, known, links) -> (F, J, b_v, b_a, place)
        lib: bench.MP or bench.FLOAT (cos, sin, pi, num, solve ...); known: name ->
        ((x, y), (vx, vy), (ax, ay)); links: k -> (phi, omega, eps). F(q) = 0 its vector
        loop-closure equation in two unknowns q; J q_t = b_v(q); J q_tt = b_a(q, q_t);
        place(q, q_t, q_tt) -> ({joint: motion tuple}, (link a, link b), {tag: (s, vs, as)})
  side_ok(lib, g, known, links, q, joints) -> bool   q is on the scene's branch
  discriminant(lib, g, known, links)   >= 0 where the group assembles, 0 at the edge of
                             its range (the stability study finds that edge in mpmath)
  unknowns(g, sol) -> (qa, qb)   the closed-form solution's q, arrays over positions

  # --- stability families (sheetkin bench --stability)
  STABILITY = (group.Family(...), ...)   scenes walked towards where the kind degenerates
                             (a toggle, the edge of its range, two lines turning parallel):
                             what the family varies and the function whose root is its
                             singular position; sheetkin.studies.stability runs them all
"""
from __future__ import annotations

from collections.abc import Iterator, Mapping
from importlib import import_module
from types import ModuleType
from typing import TYPE_CHECKING, Any, cast

from .protocol import MEMBERS, KindModule


class _Kinds(Mapping[str, KindModule]):
    """type -> kind module, each imported on first use: the kinds' kernels import numpy,
    and `sheetkin --help` or a scene's `type` check need none of it (tests/cli/test_startup.py)."""

    def __init__(self, modules: dict[str, str]):
        self._names: dict[str, str] = dict(modules)
        self._loaded: dict[str, KindModule] = {}

    def __getitem__(self, kind: str) -> KindModule:
        mod = self._loaded.get(kind)
        if mod is None:
            mod = self._loaded[kind] = cast(KindModule, import_module(f".{self._names[kind]}", __name__))
        return mod

    def __contains__(self, kind: object) -> bool:       # Mapping's would import the module
        return kind in self._names

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def add(self, module: ModuleType) -> str:
        kind = getattr(module, "KIND", None)
        missing = [m for m in MEMBERS if not hasattr(module, m)]
        if missing or not isinstance(kind, str):
            raise ValueError(f"{module.__name__}: not a group kind, it lacks {', '.join(missing) or 'KIND'} "
                             "(the surface: sheetkin.groups.protocol.KindModule)")
        if kind in self._names and self[kind] is not module:
            raise ValueError(f"{module.__name__}: group type '{kind}' is already {self._names[kind]}'s")
        self._names[kind], self._loaded[kind] = module.__name__, cast(KindModule, module)
        return kind

    def remove(self, kind: str) -> None:
        del self._names[kind]
        self._loaded.pop(kind, None)


# explicit, in the contract's order; `grep RPR` finds every use (no discovery, no decorators).
# A kind of this package is one line here; a kind kept elsewhere is one call to register().
KINDS = _Kinds({
    "RRR": "rrr",
    "RRP": "rrp",
    "RPR": "rpr",
    "PRP": "prp",
    "RPP": "rpp",
})

if TYPE_CHECKING:       # mypy checks each bundled kind module against the Protocol
    from . import prp, rpp, rpr, rrp, rrr
    _CHECKED: tuple[KindModule, ...] = (rrr, rrp, rpr, prp, rpp)


def register(module: ModuleType | str) -> str:
    """Add a kind kept outside this package (a module, or its import path): its `KIND`
    becomes a scene's `type` that every stage understands. Returns the type. Raises
    ValueError (one line) if the module lacks a member of the Protocol or its type is
    another module's. A kind of the package itself is a line in `KINDS` instead."""
    return KINDS.add(import_module(module) if isinstance(module, str) else module)


def unregister(kind: str) -> None:
    """Remove a type from the table (a test's kind, when the test is over)."""
    KINDS.remove(kind)


def kind_of(g: Any) -> KindModule:
    """The module of a group's kind (a Group, or its `type` string)."""
    return KINDS[g if isinstance(g, str) else g.type]


def families() -> list:
    """The stability study's families (group.Family), each kind's STABILITY in KINDS order."""
    return [f for kind in KINDS.values() for f in kind.STABILITY]
