"""The workbook writer: the lecture's row-structured sheet with live formulas.

It owns the kinematics sheet (`workbook`: the input block, the crank block, a block per
group written by the group's kind, the points, "accepted values"), the check rows and
their summary (`checks`), the dynamics sheet (`dynamics`), the charts and the drawing of
the mechanism (`charts`), and the page set-up for printing (`printing`).
"""
from __future__ import annotations

from sheetkin.lazy import exports

# public name -> the module that defines it, imported on first use (sheetkin.lazy)
_EXPORTS = {
    "build_workbook": "workbook",
    "write_workbook": "workbook",
    "sheet_rows": "workbook",
    "existing_fingerprint": "workbook",
    "built_fingerprint": "workbook",
    "embedded_scene_text": "workbook",
}

__getattr__, __dir__ = exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
