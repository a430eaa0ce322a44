"""The engine's memos, one type: a class's books share their formulas, so parsed formulas,
run templates, constants and the cells a run reads are kept for the rest of the process,
each memo bounded (cleared whole when full: simpler than eviction, and a class's formulas
fit). `clear_caches()` empties them all (benchmarks measure a cold start with it; a
long-lived process may call it between classes)."""
from __future__ import annotations

from typing import Any

_ALL: list[Cache] = []


class Cache(dict):
    """A bounded memo: `put` clears it first when it holds `limit` entries."""

    def __init__(self, what: str, limit: int):
        super().__init__()
        self.what, self.limit = what, limit
        _ALL.append(self)

    def put(self, key: Any, value: Any) -> Any:
        if len(self) >= self.limit:
            self.clear()
        self[key] = value
        return value


def clear_caches() -> None:
    """Empty every memo of the engine (parsed formulas, templates, constants, reads ...)."""
    for cache in _ALL:
        cache.clear()
