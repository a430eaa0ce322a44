"""A scene's Assur group as data: the fields every kind has, a guide, and the names of a
slider's columns (a leaf module, no numpy: the scene reader and `--help` use it).

Each kind's own parameters (lengths, branch, guide, offset ...) are its module's frozen
`Params` (sheetkin.groups.<kind>), held in `Group.params`; `g.branch`, `g.lengths`, ...
read through to them, so a caller never needs to know which kind defines which field.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Guide:
    """A straight line fixed on link `link` (0: the frame), the contract's
    `{through = POINT or [x, y], angle_deg = A, link = k}`: it passes through the point
    `through` of link k, or through `point` = (x, y) on the frame, and its direction is
    phi_k + A (on the frame: A itself). For a frame guide through a named frame point,
    `point` holds its coordinates too (the workbook's gx, gy inputs)."""
    through: str | None
    point: tuple[float, float] | None
    angle_deg: float
    link: int = 0

    @property
    def moving(self) -> bool:
        return self.link != 0


@dataclass(frozen=True)
class Group:
    """One Assur group (dyad). `index` counts groups from 1 in file order; `type` is the
    key of sheetkin.groups.KINDS; `joints` as the contract lists them for the kind."""
    index: int
    type: str
    links: tuple[int, int]
    joints: tuple[str, ...]
    params: object = None

    def __getattr__(self, name):
        # g.branch, g.lengths, g.guide, g.offset ...: the kind's own parameters
        params = self.__dict__.get("params")
        if params is not None and not name.startswith("__") and hasattr(params, name):
            return getattr(params, name)
        # self.__dict__, never self.type: while unpickling (a process pool) the fields are not set yet
        raise AttributeError(f"{self.__dict__.get('type', '?')} group has no field {name!r}")

    @property
    def label(self) -> str:
        return f"group {self.index} ({self.type} {'-'.join(self.joints)})"


@dataclass(frozen=True)
class Family:
    """One family of `sheetkin bench --stability` (sheetkin.studies.stability), declared by the kind
    module whose failure it approaches (its STABILITY tuple): a scene walked towards the
    place where the kind's closed form and Newton degenerate, at distances d (rad).

    name, title   the family's key and one line saying what degenerates;
    scene         TOML text; a family that varies a scene key instead of the crank angle
                  holds `{value}` where that key's value (degrees) goes;
    group         the index of the group that fails (the groups before it are placed as
                  usual);
    edge          what vanishes there: a function (lib, g, known, links) -> number of the
                  kind module whose simple root in the crank angle is the singular position
                  (the discriminant at the edge of a range, the sine of two lines' angle
                  ...), found by mpmath; or the singular value in degrees, exactly;
    near_deg      where mpmath's root finder starts (None: at the start of the first crank
                  interval where the float solver cannot assemble);
    side          -1: approached from below (edge - d); +1: from beyond (edge + d, where
                  no position may exist: Newton walks there from the points inside);
    start         None: the reference walks Newton in mpmath towards the edge from 0.05
                  rad away; else a function (lib, g, known, links) -> q or None giving the
                  group's closed form in mpmath at each distance (where the branches meet,
                  as at a change point, a walk cannot tell them apart; None: no position);
    vary          the scene key varied (its value edge + side * d, in degrees) at the
                  scene's one crank angle, or None: the crank angle is varied.
    """
    name: str
    title: str
    scene: str
    group: int
    edge: Any          # a function (lib, g, known, links) -> number, or the varied key's value
    near_deg: float | None = None
    side: int = -1
    start: Any = None  # None, or a function giving the unknowns where the walk starts
    vary: str | None = None


def crank_scene(title: str, groups: str, frame: str = "O = [0.0, 0.0]", length: float = 0.25,
                omega: float = 10.0, phi0_deg: float = 0.0) -> str:
    """A family's scene (TOML): a crank O A of `length` at one position phi0_deg, the frame
    points (TOML lines, O included) and the groups' tables."""
    return (f'title = "{title}"\nauthor = "sheetkin stability study"\n[frame]\n{frame}\n'
            f'[crank]\npivot = "O"\njoint = "A"\nlength = {length!r}\nphi0_deg = {phi0_deg!r}\n'
            f'positions = 1\nomega = {omega!r}\n{groups}')


def slide_names(tag: str) -> tuple[str, str, str]:
    """Contract names of a slide: tag 'N' -> (s_N, vs_N, as_N); a tag that starts with a
    digit is a further slide of the same point: '2_N' -> (s2_N, vs2_N, as2_N) (PRP)."""
    sep = "" if tag[:1].isdigit() else "_"
    return f"s{sep}{tag}", f"vs{sep}{tag}", f"as{sep}{tag}"
