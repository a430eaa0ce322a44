"""What a kind shows besides its rows: the parts a drawing is made of (a leaf module, no numpy).

Each kind's `parts(g)` answers, for one group: which points each of its links holds, the
straight lines its blocks slide on (guides fixed on a link, slots) and the blocks. The
drawing (sheetkin.views.drawing) and the charts sheet (sheetkin.sheet.charts) draw these
and never guess from a kind's parameters. A guide also names the workbook's input rows
that hold its angle and its point (the kind's `input_rows`), so that the charts sheet's
picture follows what a student types there.
"""
from __future__ import annotations

from dataclasses import dataclass

from .group import Guide


@dataclass(frozen=True)
class GuidePart:
    """A straight line fixed on link `link` (0: the frame) along which `slider` moves: it
    passes through `through` (a point name, or frame coordinates) shifted `offset` to the
    left, in the direction phi_link + angle_deg.

    foot_of       a slot: the line through `slider` along phi_link, based at the foot of
                  this point (the lever's pivot) on it (`through` is then not used);
    angle_input   the input row that holds angle_deg (on the frame the line's angle, on a
                  moving link its angle to phi_link), or None: the angle is fixed;
    point_inputs  the input rows (x, y) of the frame coordinates `through`, or None."""
    link: int
    through: str | tuple[float, float]
    angle_deg: float
    slider: str
    offset: float = 0.0
    group: int = 0          # the group that defines it (the charts sheet's helper labels)
    foot_of: str | None = None
    angle_input: str | None = None
    point_inputs: tuple[str, str] | None = None


@dataclass(frozen=True)
class BlockPart:
    """A slider block (its link) centred on a point, turned along a guide."""
    link: int
    at: str
    guide: GuidePart


@dataclass(frozen=True)
class Parts:
    """One group's drawing: the points on each of its links (link -> points, in drawing
    order), its guides and slots, and its blocks (each on one of `guides`)."""
    links: dict[int, tuple[str, ...]]
    guides: tuple[GuidePart, ...] = ()
    blocks: tuple[BlockPart, ...] = ()


def scene_guide(gd: Guide, slider: str, group: int, angle_input: str,
                point_inputs: tuple[str, str] | None) -> GuidePart:
    """A scene's guide (group.Guide) as drawn: through its frame coordinates on the frame
    (then `point_inputs` name their input rows), else through its point of the link."""
    on_frame = gd.link == 0 and gd.point is not None
    through: str | tuple[float, float] = gd.point if on_frame and gd.point is not None else str(gd.through)
    return GuidePart(gd.link, through, gd.angle_deg, slider, group=group, angle_input=angle_input,
                     point_inputs=point_inputs if on_frame else None)


def slot(link: int, slider: str, pivot: str, group: int) -> GuidePart:
    """A slot of link `link` (a kulisa): the line through the block's joint `slider`
    along phi_link, drawn from the foot of the lever's pivot `pivot`."""
    return GuidePart(link, slider, 0.0, slider, group=group, foot_of=pivot)
