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

__all__ = ["AssemblyError", "Gap", "Scene", "SceneError", "column_names", "compute", "evaluate_frame",
           "load_scene", "parse_scene", "solve", "__version__"]
