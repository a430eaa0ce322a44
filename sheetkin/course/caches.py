"""The caches of grading: a variant's reference and its template sheet (sheetkin.course.
reference), the local judgement's parsed rows (sheetkin.course.localjudge), a scene's sheet
rows (scene_rows). Each is a Kept of bounded size, the oldest entry forgotten first;
clear_caches() empties them all (tests, a long-running process that reads new scenes)."""
from __future__ import annotations

from typing import Any

from sheetkin.groups.rows import Row
from sheetkin.kinematics.scene import Scene
from sheetkin.sheet.workbook import sheet_rows

_ALL: list[Kept] = []


class Kept(dict):
    """A dict of at most `size` entries: keep() forgets the oldest when it is full."""

    def __init__(self, size: int):
        super().__init__()
        self.size = size
        _ALL.append(self)

    def keep(self, key: Any, value: Any) -> Any:
        if len(self) >= self.size:
            del self[next(iter(self))]
        self[key] = value
        return value


def clear_caches() -> None:
    """Forget every kept reference, template sheet and parsed row."""
    for kept in _ALL:
        kept.clear()


_ROWS = Kept(8)     # id(scene) -> (scene, its rows): a scene object is asked about many times


def scene_rows(scene: Scene) -> tuple[Row, ...]:
    """sheet_rows(scene).rows, built once per scene object: grading one book asks about its
    issued scene seven times (the seal, the given data, the row graph, the reference, its
    check statuses, the nudges, the rows graded), ~5 ms a time for a four-bar. The rows are
    read, never changed."""
    kept = _ROWS.get(id(scene))
    if kept is not None and kept[0] is scene:
        return kept[1]
    return _ROWS.keep(id(scene), (scene, tuple(sheet_rows(scene).rows)))[1]
