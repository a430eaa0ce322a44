"""Draw every bundled scene (workbooks/*.toml) at one crank position: docs/img/<stem>.png.

    python tools/make_pictures.py            # all bundled scenes
    python tools/make_pictures.py fourbar    # some of them

The pictures in docs/scene-format.md and the README come from here. Links are drawn
between the joints each kind says they carry (sheetkin.groups: `carries`), frame points as
hatched triangles, sliders and blocks as squares, guides on the frame as dash-dotted lines,
[[point]]s as small circles; labels are the scene's names.
"""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sheetkin  # noqa: E402
from sheetkin.kinematics.scene import link_joints  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
COLORS = plt.rcParams["axes.prop_cycle"].by_key()["color"]


def draw(stem: str, out: Path, phi_deg: float = 120.0) -> Path:
    scene = sheetkin.load_scene(ROOT / "workbooks" / f"{stem}.toml")
    df = sheetkin.compute(scene, at=[phi_deg], allow_gaps=True)
    row = df.iloc[0]

    def xy(name):
        if name in scene.frame:
            return np.array(scene.frame[name], dtype=float)
        return np.array([row[f"x_{name}"], row[f"y_{name}"]])

    on = link_joints(scene.crank, scene.groups)
    for p in scene.points:
        on[p.link].append(p.name)
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    every = [xy(n) for names in on.values() for n in names] + [xy(n) for n in scene.frame]
    span = float(np.ptp(np.array(every), axis=0).max()) or 1.0
    size = 0.025 * span
    for g in scene.groups:                      # guides fixed on the frame
        for guide in [getattr(g, "guide", None), *getattr(g, "guides", ())]:
            if guide is not None and not guide.moving:
                u = np.array([np.cos(np.radians(guide.angle_deg)), np.sin(np.radians(guide.angle_deg))])
                p = np.array(guide.point)
                t = np.array([-1.5 * span, 1.5 * span])
                ax.plot(p[0] + t * u[0], p[1] + t * u[1], "-.", color="0.6", lw=1)
    for k, names in sorted(on.items()):
        pts = np.array([xy(n) for n in dict.fromkeys(names)])
        c = COLORS[k % len(COLORS)]
        if len(pts) > 1:
            ax.plot(pts[:, 0], pts[:, 1], "-", color=c, lw=3, solid_capstyle="round", label=f"link {k}")
        else:                                    # a block or slider: a square at its joint
            ax.add_patch(plt.Rectangle(pts[0] - 1.6 * size, 3.2 * size, 3.2 * size, fill=False, ec=c, lw=2,
                                       label=f"link {k}"))
        if k >= 2 and f"phi_{k}" in row:       # the line a block slides on: its direction
            th = np.radians(row[f"phi_{k}"])
            p = pts[0]
            ax.plot([p[0] - 4 * size * np.cos(th), p[0] + 4 * size * np.cos(th)],
                    [p[1] - 4 * size * np.sin(th), p[1] + 4 * size * np.sin(th)], ":", color=c, lw=1)
    for n in scene.frame:
        p = xy(n)
        ax.add_patch(plt.Polygon([p, p + [-size, -1.6 * size], p + [size, -1.6 * size]], closed=True,
                                 fill=False, hatch="///", ec="k"))
    moving = set(scene.moving_joints)
    for names in on.values():
        for n in names:
            p = xy(n)
            ax.plot(*p, "o", ms=6 if (n in moving or n in scene.frame) else 4, mfc="white", mec="k")
            ax.annotate(n, p, textcoords="offset points", xytext=(5, 5), fontsize=10)
    kinds = ", ".join(dict.fromkeys(g.type for g in scene.groups))
    ax.set_title(f"{scene.title}\n{kinds}; crank at {phi_deg:g} deg", fontsize=10)
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="best")
    ax.set_xlabel("x, m")
    ax.set_ylabel("y, m")
    fig.tight_layout()
    path = out / f"{stem}.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def main(argv: list[str]) -> int:
    stems = argv or sorted(p.stem for p in (ROOT / "workbooks").glob("*.toml"))
    out = ROOT / "docs" / "img"
    out.mkdir(parents=True, exist_ok=True)
    for stem in stems:
        print(draw(stem, out).relative_to(ROOT))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
