"""A scene's Assur group as data: the fields every kind has, a guide, and the names of a
slider's columns (a leaf module, no numpy: the scene reader and `--help` use it).

Each kind's own parameters (lengths, branch, guide, offset ...) are its module's frozen
`Params` (sheetkin.groups.<kind>), held in `Group.params`; `g.branch`, `g.lengths`, ...
read through to them, so a caller never needs to know which kind defines which field.
"""
from __future__ import annotations

from dataclasses import dataclass


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


def slide_names(tag: str) -> tuple[str, str, str]:
    """Contract names of a slide: tag 'N' -> (s_N, vs_N, as_N); a tag that starts with a
    digit is a further slide of the same point: '2_N' -> (s2_N, vs2_N, as2_N) (PRP)."""
    sep = "" if tag[:1].isdigit() else "_"
    return f"s{sep}{tag}", f"vs{sep}{tag}", f"as{sep}{tag}"
