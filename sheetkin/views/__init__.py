"""Views beside the pipeline: what a user reads or looks at.

It owns the output formats of `compute` (`output`: CSV, JSON, parquet in bounded blocks;
`floatfmt`: shortest round-trip number text), the drawing of a mechanism (`drawing`),
animations (`animate`: GIF, HTML, PNG) and notebook display (`notebook`).
"""
from __future__ import annotations

from sheetkin.lazy import exports

# public name -> the module that defines it, imported on first use (sheetkin.lazy)
_EXPORTS = {
    "write_compute": "output",
    "scene_svg": "drawing",
    "picture": "drawing",
    "result": "notebook",
    "Result": "notebook",
}

__getattr__, __dir__ = exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
