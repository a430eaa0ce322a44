"""Draw the PRP and RPP diagrams of docs/scene-format.md from the bundled scenes.

    PYTHONPATH=. python tools/draw_prp_rpp.py        # writes docs/img/prp.png, docs/img/rpp.png

Each picture is the bundled mechanism (workbooks/slider_on_coupler.toml,
workbooks/scotch_yoke.toml) at one crank angle, solved by sheetkin itself, with the
contract's names (joints, guides, s_N, s2_N, s_K, s_J1) written on it.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sheetkin  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "img"


def _block(ax, x, y, angle_deg, w=0.06, h=0.035, color="#f4b183"):
    """A slider block (rectangle) centred at (x, y), its long side along angle_deg."""
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    pts = np.array([[-w, -h], [w, -h], [w, h], [-w, h], [-w, -h]]) / 2
    rot = pts @ np.array([[c, s], [-s, c]])
    ax.fill(x + rot[:, 0], y + rot[:, 1], color=color, ec="k", lw=1, zorder=3)


def _line(ax, p, angle_deg, t0, t1, **kw):
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    ax.plot([p[0] + t0 * c, p[0] + t1 * c], [p[1] + t0 * s, p[1] + t1 * s], **kw)


def _hinge(ax, x, y, name, dx=0.02, dy=0.02, fixed=False):
    ax.plot(x, y, "o", ms=7, mfc="white", mec="k", zorder=5)
    if fixed:
        ax.plot([x - 0.025, x + 0.025], [y - 0.03, y - 0.03], "k-", lw=2)
    ax.annotate(name, (x, y), (x + dx, y + dy), fontsize=11, weight="bold")


def draw_prp(path: Path, phi=60.0):
    scene = sheetkin.load_scene(ROOT / "workbooks" / "slider_on_coupler.toml")
    sol = sheetkin.compute(scene).iloc[int(round(phi / scene.crank.step_deg))]
    fig, ax = plt.subplots(figsize=(7.5, 6))
    A, B, L = (sol["x_A"], sol["y_A"]), (sol["x_B"], sol["y_B"]), (sol["x_L"], sol["y_L"])
    O, O1 = scene.frame["O"], scene.frame["O1"]
    ax.plot([O[0], A[0]], [O[1], A[1]], "k-", lw=3)
    ax.plot([A[0], B[0]], [A[1], B[1]], "-", color="#2f5597", lw=4, label="coupler AB (link 2)")
    ax.plot([B[0], O1[0]], [B[1], O1[1]], "k-", lw=3)
    eta, theta = sol["phi_4"], sol["phi_5"]
    _line(ax, A, eta, -0.1, sol["s_L"] + 0.15, color="#2f5597", ls="--", lw=1,
          label="guides[0]: the coupler's line (2), y = n + x tg eta")
    _line(ax, (-0.15, 0.0), theta, -0.6, 0.25, color="#c00000", lw=1.5,
          label="guides[1]: fixed line (1), here x = -0.15 (tg theta infinite)")
    for t in np.linspace(-0.55, 0.2, 10):
        ax.plot([-0.15, -0.17], [t, t - 0.02], color="#c00000", lw=0.8)
    _block(ax, *L, eta, color="#9dc3e6")
    _block(ax, *L, theta, w=0.08, h=0.03)
    _hinge(ax, *O, "O", fixed=True)
    _hinge(ax, *O1, "O1", fixed=True)
    _hinge(ax, *A, "A")
    _hinge(ax, *B, "B")
    _hinge(ax, *L, "N = L", dx=0.03, dy=-0.05)
    ax.annotate("", L, A, arrowprops=dict(arrowstyle="<->", color="#2f5597"))
    ax.text((A[0] + L[0]) / 2 + 0.02, (A[1] + L[1]) / 2 - 0.05, "s_L (A to L)", color="#2f5597", fontsize=11)
    ax.annotate("", L, (-0.15, 0.0), arrowprops=dict(arrowstyle="<->", color="#c00000"))
    ax.text(-0.23, L[1] / 2, "s2_L", color="#c00000", fontsize=11)
    ax.plot(-0.15, 0.0, "x", color="#c00000")
    ax.set_title(f"PRP: block 4 on the coupler's line, slider 5 on a fixed guide (phi_1 = {phi:g} deg)", fontsize=10)
    ax.set_aspect("equal")
    ax.set_xlim(-0.5, 0.3)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw_rpp(path: Path, phi=60.0):
    scene = sheetkin.load_scene(ROOT / "workbooks" / "scotch_yoke.toml")
    sol = sheetkin.compute(scene).iloc[int(round(phi / scene.crank.step_deg))]
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    O, A, K, C = scene.frame["O"], (sol["x_A"], sol["y_A"]), (sol["x_K"], sol["y_K"]), (sol["x_C"], sol["y_C"])
    ax.plot([-0.2, 0.5], [0, 0], color="#c00000", lw=1.5, label="guide of the yoke (frame), through O at 0 deg")
    for t in np.linspace(-0.2, 0.5, 20):
        ax.plot([t, t - 0.015], [-0.012, -0.03], color="#c00000", lw=0.8)
    ax.plot([K[0], K[0]], [-0.13, 0.13], color="#2f5597", lw=6, alpha=0.35, label="slot of the yoke (link 3), 90 deg")
    ax.plot([K[0], C[0]], [0.0, 0.0], color="#2f5597", lw=4)
    ax.plot([O[0], A[0]], [O[1], A[1]], "k-", lw=3)
    _block(ax, *A, 90.0, w=0.05, h=0.03)
    _hinge(ax, *O, "O", fixed=True, dx=-0.03)
    _hinge(ax, *A, "J1 = A", dx=0.02)
    _hinge(ax, *K, "K", dx=0.01, dy=-0.04)
    _hinge(ax, *C, "C", dy=0.02)
    ax.annotate("", K, O, arrowprops=dict(arrowstyle="<->", color="#c00000"))
    ax.text(K[0] / 2, -0.06, "s_K", color="#c00000", fontsize=11)
    ax.annotate("", A, K, arrowprops=dict(arrowstyle="<->", color="#2f5597"))
    ax.text(K[0] + 0.015, A[1] / 2, "s_A", color="#2f5597", fontsize=11)
    ax.set_title(f"RPP: Scotch yoke, a kulisa that moves straight (phi_1 = {phi:g} deg)", fontsize=10)
    ax.set_aspect("equal")
    ax.set_ylim(-0.18, 0.18)
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    OUT.mkdir(parents=True, exist_ok=True)
    draw_prp(OUT / "prp.png")
    draw_rpp(OUT / "rpp.png")
    print(f"{OUT / 'prp.png'}, {OUT / 'rpp.png'}: written")
