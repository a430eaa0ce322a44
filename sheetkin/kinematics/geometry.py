"""The mechanism's geometry over a revolution, from compute()'s table: which points each
link holds, the guides and slots and the blocks on them (each kind's `parts(g)`,
sheetkin.groups.parts), the points' coordinates at every row, a slider's travel along its
guide and the bounds of everything. The drawing (sheetkin.views.drawing) and the workbook's
charts sheet (sheetkin.sheet.charts) both draw from it, so it lies below both.

Everything comes from the computed points (columns x_P, y_P, phi_k); nothing here knows a kind.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sheetkin.groups import kind_of
from sheetkin.groups.parts import BlockPart, GuidePart

from .scene import Group, Scene

FINE_POSITIONS = 360        # the paths: one point per degree of the crank


# a guide or slot and a block, as each kind declares them (sheetkin.groups.parts)
Guide = GuidePart
Block = BlockPart


@dataclass(frozen=True)
class Structure:
    """Which points belong to which link, and the guides and blocks: what a drawing needs
    from the scene besides the computed coordinates."""
    members: dict[int, tuple[str, ...]]
    guides: tuple[Guide, ...]
    blocks: tuple[Block, ...]
    pivots: tuple[str, ...]              # frame points that are joints (drawn grounded)
    groups: dict[int, tuple[str, ...]]   # group index -> its joints (toggle marks)


# --------------------------------------------------------------------------- structure
def group_parts(g: Group) -> tuple[dict[int, tuple[str, ...]], list[Guide], list[Block]]:
    """(members {link: points}, guides, blocks) of one group: the kind's own `parts(g)`."""
    parts = kind_of(g).parts(g)
    return dict(parts.links), list(parts.guides), list(parts.blocks)


def structure(scene: Scene) -> Structure:
    c = scene.crank
    members: dict[int, list[str]] = {1: [c.pivot, c.joint]}
    guides, blocks, groups = [], [], {}
    for g in scene.groups:
        m, gd, bl = group_parts(g)
        for k, pts in m.items():
            members.setdefault(k, [])
            members[k] += [p for p in pts if p not in members[k]]
        guides += gd
        blocks += bl
        groups[g.index] = tuple(g.joints)
    for p in scene.points:
        members.setdefault(p.link, [])
        members[p.link] += [q for q in (p.origin, p.name) if q not in members[p.link]]
    used = {p for pts in members.values() for p in pts}
    pivots = tuple(f for f in scene.frame if f in used)
    return Structure({k: tuple(v) for k, v in sorted(members.items())}, tuple(guides), tuple(blocks),
                     pivots, groups)


# --------------------------------------------------------------------------- coordinates
def point_xy(scene: Scene, df, name) -> np.ndarray:
    """(n, 2) coordinates of a point at every row of df (a frame point is constant)."""
    n = len(df)
    if isinstance(name, tuple):
        return np.tile(np.asarray(name, dtype=float), (n, 1))
    if name in scene.frame:
        return np.tile(np.asarray(scene.frame[name], dtype=float), (n, 1))
    return np.column_stack([df[f"x_{name}"].to_numpy(float), df[f"y_{name}"].to_numpy(float)])


def link_angle(df, k: int) -> np.ndarray:
    """phi_k in radians at every row (the frame: 0)."""
    if k == 0:
        return np.zeros(len(df))
    return np.radians(df[f"phi_{k}"].to_numpy(float))


def guide_frame(scene: Scene, df, g: Guide):
    """(base points (n, 2), unit directions (n, 2)) of a guide line at every row."""
    a = link_angle(df, g.link) + math.radians(g.angle_deg)
    u = np.column_stack([np.cos(a), np.sin(a)])
    nrm = np.column_stack([-u[:, 1], u[:, 0]])
    if g.foot_of is not None:          # a slot: the foot of the lever's joint on the line
        p = point_xy(scene, df, g.foot_of)
        d = np.einsum("ij,ij->i", point_xy(scene, df, g.slider) - p, nrm)
        return p + d[:, None] * nrm, u
    return point_xy(scene, df, g.through) + g.offset * nrm, u


def guide_span(scene: Scene, fine, g: Guide) -> tuple[float, float]:
    """The slider's travel along the guide over the revolution (in the guide's own frame),
    including the guide's base point (the slot's pivot, the guide's `through`)."""
    base, u = guide_frame(scene, fine, g)
    t = np.einsum("ij,ij->i", point_xy(scene, fine, g.slider) - base, u)
    t = t[np.isfinite(t)]
    return (min(0.0, t.min()), max(0.0, t.max())) if t.size else (0.0, 0.0)


def moving_points(scene: Scene) -> list[str]:
    """The joints that move and the points on links: every point that has a path."""
    return scene.moving_joints + [p.name for p in scene.points]


def bounds(scene: Scene, fine, st: Structure, spans) -> tuple[float, float, float, float]:
    """Bounds of everything drawn over the revolution, padded by 8 %."""
    xy = [np.asarray(list(scene.frame.values()), dtype=float).reshape(-1, 2)]
    xy += [point_xy(scene, fine, p) for p in moving_points(scene)]
    for g, (t0, t1) in zip(st.guides, spans, strict=False):
        base, u = guide_frame(scene, fine, g)
        xy += [base + t0 * u, base + t1 * u]
    pts = np.concatenate(xy)
    pts = pts[np.isfinite(pts).all(axis=1)]
    (x0, y0), (x1, y1) = pts.min(axis=0), pts.max(axis=0)
    size = max(x1 - x0, y1 - y0, 1e-9)
    pad = 0.08 * size
    return x0 - pad, y0 - pad, x1 + pad, y1 + pad



def revolution(scene: Scene, n: int) -> np.ndarray:
    """n crank angles over one revolution from phi0, turning the way the crank turns."""
    c = scene.crank
    sense = -1.0 if (c.omega < 0 or (c.omega == 0 and c.step_deg < 0)) else 1.0
    return c.phi0_deg + sense * 360.0 * np.arange(n) / n
