"""sheetkin: kinematic analysis of planar linkages in the spreadsheet workflow of
Prof. Yu. A. Alyushin's course (MGGU).

The packages are the pipeline's stages, each importing only the ones before it:
groups (the Assur group kinds) -> kinematics (scene, solver, table) -> sheet (the
workbook writer) | xlsx (the spreadsheet engine, standing alone) -> course (validation,
grading, variants) -> cli; views (output, drawings) and studies (bench, synthesis) stand
beside them.

The public names load on first use (PEP 562): `import sheetkin` loads no stage, so
`sheetkin --help` and small commands start quickly; the scene reader loads with
`sheetkin.load_scene`, the solver with `sheetkin.solve` / `sheetkin.compute`, pandas with
`compute()`'s DataFrame, openpyxl with the workbooks.
"""
from __future__ import annotations

from importlib import import_module
from typing import Any

__version__ = "0.2.0"

# name -> the module that defines it, imported when the name is first used: `import
# sheetkin` (and so every command, `sheetkin evaluate` among them) loads no module of a stage
_LAZY = {"AssemblyError": "sheetkin.kinematics.scene", "Scene": "sheetkin.kinematics.scene",
         "SceneError": "sheetkin.kinematics.scene", "load_scene": "sheetkin.kinematics.scene",
         "parse_scene": "sheetkin.kinematics.scene",
         "Gap": "sheetkin.kinematics.table", "column_names": "sheetkin.kinematics.table",
         "compute": "sheetkin.kinematics.table", "solve": "sheetkin.kinematics.solver",
         "evaluate_frame": "sheetkin.xlsx.evaluator", "result": "sheetkin.views.notebook"}


def _draw_scene(scene) -> str:
    """A Scene in a notebook: the drawing (sheetkin.views, loaded on first use). The scene
    finds it here (kinematics.scene.draw_in_notebook's default): the package sits above
    every stage and offers the view to the scene, which never imports a view."""
    from sheetkin.views.notebook import scene_repr_svg
    return scene_repr_svg(scene)


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name]), name)
        globals()[name] = value          # once: later lookups are plain attributes
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = ["AssemblyError", "Gap", "Scene", "SceneError", "column_names", "compute", "evaluate_frame",
           "load_scene", "parse_scene", "result", "solve", "__version__"]
