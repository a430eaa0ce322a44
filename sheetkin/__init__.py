"""sheetkin: kinematic analysis of planar linkages in the spreadsheet workflow of
Prof. Yu. A. Alyushin's course (MGGU). Pipeline: scene -> solver -> compute -> cli.

The public names load on first use (PEP 562): `import sheetkin` costs only the scene
reader, without numpy (the group kinds' registry imports a kind's numpy kernels when a
scene uses it), so `sheetkin --help` and small commands start quickly; the solver loads with sheetkin.solve / sheetkin.compute, pandas
with `compute()`'s DataFrame, openpyxl with the workbooks (tests/test_startup.py).
"""
import sys as _sys
import types as _types

__version__ = "0.1.0"

from .scene import AssemblyError, Scene, SceneError, load_scene, parse_scene  # noqa: E402

_LAZY = {"Gap": "compute", "column_names": "compute", "solve": "solver"}


def __getattr__(name):
    if name in _LAZY:
        from importlib import import_module
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value          # once: later lookups are plain attributes
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


class _Package(_types.ModuleType):
    """`sheetkin.compute` is the function, as before it loaded lazily: the import system
    sets a package's attribute to each submodule it loads, and the submodule
    sheetkin.compute would otherwise replace the function of the same name."""

    @property
    def compute(self):
        from .compute import compute
        return compute

    @compute.setter
    def compute(self, submodule):
        pass                                 # the submodule stays in sys.modules


_sys.modules[__name__].__class__ = _Package


def evaluate_frame(path, sheet=None):
    """Evaluate a workbook's formulas headlessly; rows = names, columns = positions."""
    from .evaluator import evaluate_frame as run     # imported on use: openpyxl's tokenizer
    return run(path, sheet)

def result(scene, at=None, **kwargs):
    """compute() with its scene kept: a Result (.frame is the DataFrame) that a notebook
    shows as a picture of the mechanism (sheetkin/notebook.py)."""
    from .notebook import result as run              # imported on use: the drawing
    return run(scene, at, **kwargs)


def _scene_repr_svg(self):
    """Jupyter shows a Scene as its mechanism at the first crank position."""
    from .notebook import scene_repr_svg
    return scene_repr_svg(self)


# the picture is wired here, at the top of the pipeline, so scene.py imports nothing above it
Scene._repr_svg_ = _scene_repr_svg

__all__ = ["AssemblyError", "Gap", "Scene", "SceneError", "column_names", "compute", "evaluate_frame",
           "load_scene", "parse_scene", "result", "solve", "__version__"]
