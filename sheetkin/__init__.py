"""sheetkin: kinematic analysis of planar linkages in the spreadsheet workflow of
Prof. Yu. A. Alyushin's course (MGGU). Pipeline: scene -> solver -> compute -> cli."""
__version__ = "0.1.0"

from .compute import AssemblyError, Gap, column_names, compute  # noqa: E402
from .scene import Scene, SceneError, load_scene, parse_scene  # noqa: E402
from .solver import solve  # noqa: E402


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
