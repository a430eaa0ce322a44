"""The mechanism as a picture: pure functions from compute()'s table to shapes, and SVG.

A picture of a scene at one crank position is a list of `Shape`s in the scene's own
coordinates (metres, y up): the frame (ground hatches at the frame pivots, fixed guides),
every link as a segment (a polygon for a link with three or more points), sliders as
rectangles on their guides, slots as lines, joints as dots, labels, optional velocity
vectors; behind them the paths of the points over a revolution, toggle positions and the
parts of the revolution where a group cannot assemble. The GIF and HTML animation
(sheetkin.views.animate), the notebook pictures (sheetkin.result, Scene._repr_svg_) and the
validation report all draw these same shapes.

Everything is drawn from the computed points (columns x_P, y_P, phi_k) and from the parts
each kind declares (`parts(g)`, sheetkin.groups.parts): which links hold which points, the
guides and slots, and the blocks that slide on them (sheetkin.kinematics.geometry, which the
workbook's charts sheet shares). Nothing here knows a kind.
"""
from __future__ import annotations

import html
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from sheetkin.kinematics.geometry import (
    FINE_POSITIONS,
    Structure,
    bounds,
    guide_frame,
    guide_span,
    moving_points,
    point_xy,
    revolution,
    structure,
)
from sheetkin.kinematics.scene import Scene
from sheetkin.kinematics.table import assembly_gaps, compute
from sheetkin.messages import message

# what a shape is, and what it stands for in the drawing (its role picks the style, STYLES)
ShapeKind = Literal["line", "polygon", "dot", "text", "arrow"]
Role = Literal["trace", "trace_gap", "toggle", "ground", "hatch", "guide", "slot", "link", "block",
               "joint", "point", "vector", "label", "link_label"]


@dataclass(frozen=True)
class Shape:
    """One drawn item in scene coordinates. kind: line (open polyline), polygon (closed),
    dot, text, arrow (xy: tail, head). role picks the style (see STYLES)."""
    kind: ShapeKind
    xy: np.ndarray
    role: Role
    text: str = ""


@dataclass
class Picture:
    """Everything the renderers need: the bounds (equal scale), the shapes that stay
    (paths, frame, toggles) and one list of shapes plus a caption per position."""
    bounds: tuple[float, float, float, float]        # xmin, ymin, xmax, ymax
    background: list[Shape]
    frames: list[list[Shape]]
    captions: list[str]
    title: str = ""
    notes: list[str] = field(default_factory=list)   # gaps, toggles, vector scale


# role -> stroke colour, stroke width (px), fill, dash
STYLES: dict[Role, tuple[str, float, str | None, str | None]] = {
    "trace": ("#9bb7d4", 1.0, None, None),
    "trace_gap": ("#d62728", 1.2, None, "3,2"),
    "toggle": ("#d62728", 1.5, None, None),
    "ground": ("#555555", 1.0, "#dddddd", None),
    "hatch": ("#555555", 0.8, None, None),
    "guide": ("#555555", 1.2, None, None),
    "slot": ("#1f4e79", 1.0, None, "4,2"),
    "link": ("#1f4e79", 2.5, "#cfe0f1", None),
    "block": ("#1f4e79", 1.5, "#f6d58b", None),
    "joint": ("#1f4e79", 1.2, "#ffffff", None),
    "point": ("#1f4e79", 1.0, "#1f4e79", None),
    "vector": ("#2ca02c", 1.5, None, None),
    "label": ("#222222", 0.0, None, None),
    "link_label": ("#7f3f00", 0.0, None, None),
}


# --------------------------------------------------------------------------- shapes
def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _hull(pts: np.ndarray) -> np.ndarray:
    """Convex hull (monotone chain), counterclockwise; 1 or 2 points come back as they are."""
    pts = np.unique(pts, axis=0)
    if len(pts) < 3:
        return pts
    def half(seq):
        out: list[np.ndarray] = []
        for p in seq:
            while len(out) >= 2 and _cross(out[-1] - out[-2], p - out[-2]) <= 1e-15:
                out.pop()
            out.append(p)
        return out
    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _ground(x: float, y: float, r: float) -> list[Shape]:
    """The lecture's fixed-pivot sign: a triangle under the pivot on a hatched base."""
    tri = np.array([[x, y], [x - r, y - 1.6 * r], [x + r, y - 1.6 * r]])
    base = np.array([[x - 1.6 * r, y - 1.6 * r], [x + 1.6 * r, y - 1.6 * r]])
    out = [Shape("polygon", tri, "ground"), Shape("line", base, "hatch")]
    for k in range(5):
        x1 = x - 1.4 * r + k * 0.7 * r
        out.append(Shape("line", np.array([[x1, y - 1.6 * r], [x1 - 0.6 * r, y - 2.3 * r]]), "hatch"))
    return out


def _hatched_line(a: np.ndarray, b: np.ndarray, r: float) -> list[Shape]:
    """A fixed guide: the line and short hatches on its right-hand side."""
    out = [Shape("line", np.array([a, b]), "guide")]
    d = b - a
    length = float(np.hypot(*d))
    if length <= 0:
        return out
    u = d / length
    n = np.array([-u[1], u[0]])
    for t in np.arange(0.0, length, 1.2 * r):
        p = a + t * u
        out.append(Shape("line", np.array([p, p - 0.7 * r * n - 0.5 * r * u]), "hatch"))
    return out


def _runs(xy: np.ndarray, ok: np.ndarray):
    """Consecutive runs of rows where ok (a path broken at the gaps)."""
    idx = np.flatnonzero(ok)
    if idx.size == 0:
        return []
    cuts = np.flatnonzero(np.diff(idx) > 1) + 1
    return [xy[r] for r in np.split(idx, cuts) if r.size >= 2]


def background(scene: Scene, fine, st: Structure, spans, r: float, threshold: float) -> list[Shape]:
    """Paths of the moving points, the frame (ground signs, fixed guides), toggle marks."""
    out: list[Shape] = []
    for p in moving_points(scene):
        xy = point_xy(scene, fine, p)
        for run in _runs(xy, np.isfinite(xy).all(axis=1)):
            out.append(Shape("line", run, "trace"))
    if "assembled" in fine:
        # where the mechanism cannot assemble, the crank still turns: its path there in red
        bad = ~fine["assembled"].to_numpy(bool)
        a = point_xy(scene, fine, scene.crank.joint)
        for run in _runs(a, bad):
            out.append(Shape("line", run, "trace_gap"))
    for g, (t0, t1) in zip(st.guides, spans, strict=False):
        if g.link == 0:
            base, u = guide_frame(scene, fine.iloc[:1], g)
            out += _hatched_line(base[0] + (t0 - 1.5 * r) * u[0], base[0] + (t1 + 1.5 * r) * u[0], r)
    for f in st.pivots:
        out += _ground(*scene.frame[f], r)
    for i, joints in st.groups.items():
        col = f"det_g{i}"
        if col not in fine:
            continue
        det = fine[col].to_numpy(float)
        near = np.abs(det) < threshold
        sign_change = np.zeros_like(near)
        ok = np.isfinite(det)
        sign_change[1:] = ok[1:] & ok[:-1] & (np.sign(det[1:]) != np.sign(det[:-1]))
        for row in np.flatnonzero(near | sign_change):
            for j in joints:
                xy = point_xy(scene, fine.iloc[row:row + 1], j)[0]
                if np.isfinite(xy).all() and j not in scene.frame:
                    out.append(Shape("dot", xy[None, :], "toggle", f"toggle g{i}"))
    return out


def _rect(c: np.ndarray, u: np.ndarray, half_l: float, half_w: float) -> np.ndarray:
    n = np.array([-u[1], u[0]])
    return np.array([c - half_l * u - half_w * n, c + half_l * u - half_w * n,
                     c + half_l * u + half_w * n, c - half_l * u + half_w * n])


def frame_shapes(scene: Scene, row, st: Structure, spans, r: float, *, vectors: float = 0.0,
                 labels: bool = True) -> list[Shape]:
    """The mechanism at one position: `row` is a one-row DataFrame of compute()'s table.
    vectors > 0 draws each point's velocity, `vectors` metres of drawing per m/s."""
    at = {}
    for pts in st.members.values():
        for p in pts:
            if p not in at:
                at[p] = point_xy(scene, row, p)[0]
    out = _moving_guides(scene, row, st, spans, r) + _links(st, at) + _blocks(scene, row, st, at, r)
    joints = set(scene.moving_joints) | set(st.pivots)
    for p, xy in at.items():
        if np.isfinite(xy).all():
            out.append(Shape("dot", xy[None, :], "joint" if p in joints else "point"))
    if vectors:
        out += _velocities(scene, row, at, vectors, r)
    if labels:
        out += _labels(st, at, r)
    return out


def _moving_guides(scene: Scene, row, st: Structure, spans, r: float) -> list[Shape]:
    """A slot or a guide on a moving link moves with it (the fixed ones are background)."""
    out = []
    for g, (t0, t1) in zip(st.guides, spans, strict=False):
        if g.link != 0:
            base, u = guide_frame(scene, row, g)
            if np.isfinite(base).all() and np.isfinite(u).all():
                out.append(Shape("line", np.array([base[0] + (t0 - r) * u[0], base[0] + (t1 + r) * u[0]]), "slot"))
    return out


def _links(st: Structure, at: dict[str, np.ndarray]) -> list[Shape]:
    """Each link as the convex hull of its points (a segment for two)."""
    out = []
    for pts in st.members.values():
        xy = np.array([at[p] for p in pts])
        if not np.isfinite(xy).all() or len(xy) < 2:
            continue
        hull = _hull(xy)
        out.append(Shape("polygon" if len(hull) >= 3 else "line", hull, "link"))
    return out


def _blocks(scene: Scene, row, st: Structure, at: dict[str, np.ndarray], r: float) -> list[Shape]:
    """The sliders: a rectangle on its guide's direction, centred on its point."""
    out = []
    for b in st.blocks:
        _, u = guide_frame(scene, row, b.guide)
        c = at.get(b.at, point_xy(scene, row, b.at)[0])
        if np.isfinite(c).all() and np.isfinite(u).all():
            out.append(Shape("polygon", _rect(c, u[0], 1.3 * r, 0.75 * r), "block"))
    return out


def _velocities(scene: Scene, row, at: dict[str, np.ndarray], vectors: float, r: float) -> list[Shape]:
    """Each moving point's velocity as an arrow, `vectors` metres of drawing per m/s (a
    speed too small to see is left out)."""
    out = []
    for p in moving_points(scene):
        tail = at.get(p)
        if tail is None or not np.isfinite(tail).all():
            continue
        v = np.array([float(row[f"vx_{p}"].iloc[0]), float(row[f"vy_{p}"].iloc[0])])
        if np.isfinite(v).all() and np.hypot(*v) * vectors > 0.2 * r:
            out.append(Shape("arrow", np.array([tail, tail + vectors * v]), "vector", f"v_{p}"))
    return out


def _labels(st: Structure, at: dict[str, np.ndarray], r: float) -> list[Shape]:
    """The points' names beside them, and each link's number at its middle."""
    out = []
    for p, xy in at.items():
        if np.isfinite(xy).all():
            out.append(Shape("text", xy[None, :] + np.array([[0.9 * r, 0.6 * r]]), "label", p))
    for k, pts in st.members.items():
        xy = np.array([at[p] for p in pts])
        if np.isfinite(xy).all():
            c = xy.mean(axis=0) if len(xy) > 1 else xy[0] + np.array([-1.8 * r, 1.2 * r])
            out.append(Shape("text", c[None, :] + np.array([[-0.4 * r, -1.4 * r]]), "link_label", str(k)))
    return out


# --------------------------------------------------------------------------- the picture
def picture(scene: Scene, frames=None, *, fine=None, vectors: bool = False, labels: bool = True,
            allow_gaps: bool = True, toggle_threshold: float = 0.01) -> Picture:
    """The shapes of `scene` at the crank angles `frames` (degrees; a DataFrame of
    compute() is taken as it is), with the paths over a revolution (`fine`, 360 positions
    unless given). Without allow_gaps, a scene that cannot assemble somewhere on the
    revolution raises compute's AssemblyError."""
    import pandas as pd
    if fine is None:
        fine = compute(scene, revolution(scene, FINE_POSITIONS), allow_gaps=allow_gaps,
                       toggle_threshold=toggle_threshold)
    if frames is None:
        frames = scene.crank_angles_deg()
    table = frames if isinstance(frames, pd.DataFrame) else compute(
        scene, np.asarray(frames, dtype=float), allow_gaps=True, toggle_threshold=toggle_threshold)
    st = structure(scene)
    spans = [guide_span(scene, fine, g) for g in st.guides]
    box = bounds(scene, fine, st, spans)
    r = 0.022 * max(box[2] - box[0], box[3] - box[1])
    scale = 0.0
    notes = []
    if vectors:
        speeds = [fine[f"v_{p}"].to_numpy(float) for p in moving_points(scene)]
        vmax = np.nanmax(np.concatenate(speeds)) if speeds else 0.0
        if np.isfinite(vmax) and vmax > 0:
            scale = 0.25 * max(box[2] - box[0], box[3] - box[1]) / vmax
            notes.append(message("velocity_scale", x=f"{scale:.3g}"))
    if "assembled" in fine and not fine["assembled"].all():
        notes += [str(g) for g in assembly_gaps(scene, fine["phi_1"].to_numpy())]
    flagged = [message("near_toggle_at", g=i, h=i, t=f"{toggle_threshold:g}", a=", ".join(
        f"{v:.0f}" for v in fine["phi_1"][fine[f"det_g{i}"].abs() < toggle_threshold].iloc[:6] % 360))
               for i in st.groups if (fine[f"det_g{i}"].abs() < toggle_threshold).any()]
    notes += flagged
    shapes, captions = [], []
    for i in range(len(table)):
        row = table.iloc[i:i + 1]
        shapes.append(frame_shapes(scene, row, st, spans, r, vectors=scale, labels=labels))
        captions.append(caption(scene, row))
    return Picture(box, background(scene, fine, st, spans, r, toggle_threshold), shapes, captions,
                   scene.title, notes)


def caption(scene: Scene, row) -> str:
    """'phi_1 = 30 deg', with what is wrong at that position."""
    phi = float(row["phi_1"].iloc[0])
    text = f"phi_1 = {phi:.4g} deg"
    if "assembled" in row and not bool(row["assembled"].iloc[0]):
        text += message("cannot_assemble")
    flag = str(row["near_toggle"].iloc[0]) if "near_toggle" in row else ""
    if flag:
        text += message("near_toggle", g=flag)
    return text


# --------------------------------------------------------------------------- SVG
class _Px:
    """Scene coordinates -> pixels (equal scale, y down)."""

    def __init__(self, box, width: int):
        x0, y0, x1, y1 = box
        self.s = width / (x1 - x0)
        self.x0, self.y1 = x0, y1
        self.width, self.height = width, max(1, int(round((y1 - y0) * self.s)))

    def __call__(self, xy: np.ndarray) -> np.ndarray:
        return np.column_stack([(xy[:, 0] - self.x0) * self.s, (self.y1 - xy[:, 1]) * self.s])


def _svg_shape(s: Shape, px: _Px) -> str:
    stroke, width, fill, dash = STYLES[s.role]
    p = px(s.xy)
    dash_attr = f" stroke-dasharray='{dash}'" if dash else ""
    if s.kind == "text":
        weight = " font-style='italic'" if s.role == "link_label" else ""
        return (f"<text x='{p[0, 0]:.1f}' y='{p[0, 1]:.1f}' fill='{stroke}' font-size='11'{weight}>"
                f"{html.escape(s.text)}</text>")
    if s.kind == "dot":
        rad = 3.5 if s.role in ("joint", "toggle") else 2.5
        f = "none" if s.role == "toggle" else fill
        return (f"<circle cx='{p[0, 0]:.1f}' cy='{p[0, 1]:.1f}' r='{rad}' fill='{f}' stroke='{stroke}' "
                f"stroke-width='{width}'><title>{html.escape(s.text)}</title></circle>" if s.text else
                f"<circle cx='{p[0, 0]:.1f}' cy='{p[0, 1]:.1f}' r='{rad}' fill='{f}' stroke='{stroke}' "
                f"stroke-width='{width}'/>")
    pts = " ".join(f"{x:.1f},{y:.1f}" for x, y in p)
    if s.kind == "polygon":
        return f"<polygon points='{pts}' fill='{fill or 'none'}' stroke='{stroke}' stroke-width='{width}'{dash_attr}/>"
    if s.kind == "arrow":
        return (f"<line x1='{p[0, 0]:.1f}' y1='{p[0, 1]:.1f}' x2='{p[1, 0]:.1f}' y2='{p[1, 1]:.1f}' "
                f"stroke='{stroke}' stroke-width='{width}' marker-end='url(#arrow)'/>")
    return f"<polyline points='{pts}' fill='none' stroke='{stroke}' stroke-width='{width}'{dash_attr}/>"


def svg(pic: Picture, position: int = 0, width: int = 480) -> str:
    """One position of a Picture as a standalone SVG document (equal scale)."""
    px = _Px(pic.bounds, width)
    body = [_svg_shape(s, px) for s in pic.background + (pic.frames[position] if pic.frames else [])]
    cap = html.escape(pic.captions[position] if pic.captions else "")
    title = html.escape(pic.title)
    h = px.height + 36
    return (f"<svg xmlns='http://www.w3.org/2000/svg' width='{px.width}' height='{h}' "
            f"viewBox='0 0 {px.width} {h}' font-family='sans-serif'>"
            "<defs><marker id='arrow' viewBox='0 0 10 10' refX='9' refY='5' markerWidth='6' "
            "markerHeight='6' orient='auto'><path d='M0,0L10,5L0,10z' fill='#2ca02c'/></marker></defs>"
            f"<rect width='100%' height='100%' fill='white'/><g transform='translate(0,18)'>"
            + "".join(body) + "</g>"
            f"<text x='4' y='13' font-size='12' fill='#222'>{title}</text>"
            f"<text x='4' y='{h - 5}' font-size='11' fill='#444'>{cap}</text></svg>")


def scene_svg(scene: Scene, position: int = 0, width: int = 480) -> str:
    """The scene at its first crank position with the paths over a revolution."""
    return svg(picture(scene, [scene.crank_angles_deg()[position]]), 0, width)
