"""Kinematics: the scene, the solver and the computed table.

It owns the scene reader (`scene`: the TOML contract of docs/scene-format.md, with its caps
in `caps`), the solver over a chain of Assur groups (`solver`: closed form, then Cramer's
rule for velocities and accelerations, all numpy over crank positions), the table that
`sheetkin.compute` returns (`table`: column names, gaps where a group cannot assemble,
blocks of positions at bounded memory), and the energy and force analysis (`dynamics`).
"""
from __future__ import annotations

from sheetkin.lazy import exports

# public name -> the module that defines it, imported on first use (sheetkin.lazy)
_EXPORTS = {
    "Scene": "scene",
    "SceneError": "caps",
    "AssemblyError": "scene",
    "load_scene": "scene",
    "parse_scene": "scene",
    "solve": "solver",
    "Solution": "solver",
    "compute": "table",
    "Gap": "table",
    "column_names": "table",
    "compute_blocks": "table",
    "AngleRange": "table",
}

__getattr__, __dir__ = exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
