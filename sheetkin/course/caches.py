"""The caches of grading: a variant's reference and its template sheet (sheetkin.course.
reference), the local judgement's parsed rows (sheetkin.course.localjudge). Each is a Kept
of bounded size, the oldest entry forgotten first; clear_caches() empties them all (tests,
a long-running process that reads new scenes)."""
from __future__ import annotations

from typing import Any

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
