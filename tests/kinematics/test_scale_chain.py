"""The synthetic chain of benchmarks/scale.py: it parses, assembles over the revolution far
from toggles, and every group keeps its constraints (hinge distances, slider on its guide,
block on its slot)."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import sheetkin

_PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "scale.py"
_spec = importlib.util.spec_from_file_location("sheetkin_benchmarks_scale", _PATH)
scale = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(scale)

PHI = np.linspace(0.0, 360.0, 720, endpoint=False)


def _xy(df, scene, name):
    if name in scene.frame:
        x, y = scene.frame[name]
        return np.full(len(df), float(x)), np.full(len(df), float(y))
    return df[f"x_{name}"].to_numpy(), df[f"y_{name}"].to_numpy()


@pytest.mark.parametrize("n", [1, 5, 20, 50])
def test_chain_assembles_and_keeps_constraints(n):
    scene = sheetkin.parse_scene(scale.chain_scene_text(n))
    assert len(scene.groups) == n
    df = sheetkin.compute(scene, at=PHI)             # raises AssemblyError on any gap
    assert "assembled" not in df.columns
    dets = df[[f"det_g{g.index}" for g in scene.groups]].to_numpy()
    assert np.all(np.abs(dets) > 0.1)
    assert (df["near_toggle"].astype(str) == "").all()
    assert np.isfinite(df.drop(columns="near_toggle").to_numpy()).all()
    rrr = [g for g in scene.groups if g.type == "RRR"]
    assert rrr[0].index == 1 and (n < 5 or scene.groups[-1].type == "RRR")
    for g in scene.groups:
        if g.type == "RRR":
            (j1, nn, j2), (la, lb) = g.joints, g.lengths
            nx, ny = _xy(df, scene, nn)
            for j, length in ((j1, la), (j2, lb)):
                x, y = _xy(df, scene, j)
                assert np.max(np.abs(np.hypot(nx - x, ny - y) - length)) < 1e-12, (g.label, j)
        elif g.type == "RRP":
            j1, nn = g.joints
            nx, ny = _xy(df, scene, nn)
            x, y = _xy(df, scene, j1)
            assert np.max(np.abs(np.hypot(nx - x, ny - y) - g.lengths[0])) < 1e-12
            gx, gy = g.guide.point
            ux, uy = np.cos(np.radians(g.guide.angle_deg)), np.sin(np.radians(g.guide.angle_deg))
            assert np.max(np.abs((nx - gx) * uy - (ny - gy) * ux)) < 1e-12     # on the guide
        else:   # RPR with no offset: J1 on the slot line through J2 at phi_b, |J2 J1| = s_J1
            j1, j2 = g.joints
            x1, y1 = _xy(df, scene, j1)
            x2, y2 = _xy(df, scene, j2)
            th = np.radians(df[f"phi_{g.links[1]}"].to_numpy())
            dx, dy = x1 - x2, y1 - y2
            assert np.max(np.abs(dx * np.sin(th) - dy * np.cos(th))) < 1e-12
            assert np.max(np.abs(np.hypot(dx, dy) - df[f"s_{j1}"].to_numpy())) < 1e-12


def test_chain_mixes_group_types_and_is_deterministic():
    text = scale.chain_scene_text(20)
    assert text == scale.chain_scene_text(20, seed=0)
    assert text != scale.chain_scene_text(20, seed=1)
    kinds = [g.type for g in sheetkin.parse_scene(text).groups]
    assert kinds.count("RPR") == 3 and kinds.count("RRP") == 3
    assert {g.type for g in sheetkin.parse_scene(scale.chain_scene_text(20, mix=False)).groups} == {"RRR"}
    with pytest.raises(ValueError):
        scale.chain_scene_text(0)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_chain_other_seeds_assemble(seed):
    for mix in (True, False):
        scene = sheetkin.parse_scene(scale.chain_scene_text(50, seed, mix=mix))
        df = sheetkin.compute(scene, at=PHI)
        assert np.abs(df[[f"det_g{g.index}" for g in scene.groups]].to_numpy()).min() > 0.1
