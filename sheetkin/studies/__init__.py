"""Studies beside the pipeline: how accurate and how fast, and synthesis.

It owns the bench (`bench`: the closed form against Newton, finite differences, a 50-digit
mpmath reference and LibreOffice), the stability study near each kind's singular
positions (`stability`), and the crank-rocker synthesis of the course's seed (`synthesis`; its
sheet of live formulas: `synthesis_sheet`).
"""
from __future__ import annotations

from sheetkin.lazy import exports

# public name -> the module that defines it, imported on first use (sheetkin.lazy)
_EXPORTS = {
    "run_bench": "bench",
    "format_bench": "bench",
    "stability_study": "stability",
    "synthesize_crank_rocker": "synthesis",
    "build_synthesis_workbook": "synthesis_sheet",
}

__getattr__, __dir__ = exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
