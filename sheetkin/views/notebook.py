"""Pictures in a notebook: a Scene and a computed result show themselves as the mechanism.

`sheetkin.result(scene, at=...)` is `compute()` with its scene kept: a `Result` whose
`.frame` is the very DataFrame compute() returns (compute() itself is unchanged), and whose
`_repr_svg_` draws the mechanism at the first computed position with the paths of its
points over a revolution, so Jupyter shows a picture. `Scene._repr_svg_` draws a loaded
scene at its first crank position through `scene_repr_svg` (the package sets it as the
scene's hook, sheetkin.kinematics.scene.draw_in_notebook, in sheetkin/__init__.py).
"""
from __future__ import annotations

from pathlib import Path

from sheetkin.kinematics.scene import Scene, as_scene
from sheetkin.kinematics.table import compute

from .drawing import picture, svg


class Result:
    """A computed table with the scene it came from.

    frame   compute()'s DataFrame, one row per position (unchanged)
    scene   the Scene
    svg(position=0, width=480)   the mechanism at that row, as an SVG document
    """

    def __init__(self, scene: Scene, frame):
        self.scene, self.frame = scene, frame

    def svg(self, position: int = 0, width: int = 480) -> str:
        pic = picture(self.scene, self.frame.iloc[position:position + 1])
        pic.captions[0] = f"position {position + 1} of {len(self.frame)}: {pic.captions[0]}"
        return svg(pic, 0, width)

    def _repr_svg_(self) -> str:
        return self.svg(0)

    def __repr__(self) -> str:
        return (f"<sheetkin.Result {self.scene.title!r}: {len(self.frame)} positions x "
                f"{self.frame.shape[1]} columns; .frame is the DataFrame>")


def result(scene: Scene | str | Path, at=None, **kwargs) -> Result:
    """compute(scene, at, **kwargs) with the scene kept, for a picture in a notebook."""
    scene = as_scene(scene)
    return Result(scene, compute(scene, at, **kwargs))


def scene_repr_svg(scene: Scene) -> str:
    """The scene at its first crank position (non-assembling parts left out and named)."""
    from .drawing import scene_svg
    return scene_svg(scene)
