"""Rows of a workbook's kinematics sheet by name, and the solver's values compared with
them: what the tests of the workbook, its dynamics and the group kinds share."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import openpyxl

import sheetkin
from sheetkin.kinematics.dynamics import dynamics_names

TOL = 1e-9      # relative to max(1, |value|): the sheet's formulas against the solver's numbers


def rows_of(ws) -> dict[str, int]:
    return {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value}


def row_values(ws, row: int, n: int) -> list:
    return [ws.cell(row, 5 + k).value for k in range(n)]


def set_input(path: Path, name: str, value: float):
    """Edit an input cell (column D of the row named `name`) as a user would."""
    wb = openpyxl.load_workbook(path)
    ws = wb.worksheets[0]
    ws.cell(rows_of(ws)[name], 4).value = value
    wb.save(path)


def compare_accepted(ws, scene, df, columns=None):
    """Every contract column's row equals the solver's values; returns the largest error."""
    rows = rows_of(ws)
    worst = 0.0
    for name in columns or sheetkin.column_names(scene):
        assert name in rows, f"no row named {name}"
        got = row_values(ws, rows[name], len(df))
        bad = [v for v in got if not isinstance(v, (int, float))]
        assert not bad, f"{name}: non-numeric cells {bad[:3]}"
        got, ref = np.array(got, dtype=float), df[name].to_numpy()
        d = np.abs(got - ref)
        if name.startswith("phi_"):
            d = np.minimum(d, 360.0 - d)
        err = d / np.maximum(1.0, np.abs(ref))
        assert np.all(err <= TOL), f"{name}: worst {err.max():.3g} at column {int(err.argmax())}"
        worst = max(worst, float(err.max()))
    return worst


def relative_balance(d: dict, scene=None, sol=None) -> np.ndarray:
    """|balance| relative to the sum of the balance's terms; with the scene and solution,
    also to the size of the powers the terms are sums of (every load's magnitude times the
    largest speed): at a dead centre all four terms can vanish while the loads do not, and
    the balance is then only as exact as the loads' rounding."""
    terms = [d["P_bal"], d.get("P_ext", 0.0), d.get("U_t", 0.0), d["T_t"]]
    scale = sum(np.abs(t) for t in terms) + 1e-300
    if scene is not None:
        v = np.max([np.hypot(p.vx, p.vy) for p in sol.points.values()], axis=0)
        w = np.max([np.abs(r.omega + 0.0 * sol.phi1_deg) for r in sol.links.values()], axis=0)
        gx, gy = scene.gravity
        for m in scene.masses:
            k = m.link
            scale = (scale + v * np.hypot(d[f"Fix_{k}"] + m.mass * gx, d[f"Fiy_{k}"] + m.mass * gy)
                     + w * np.abs(d[f"Mi_{k}"]))
        for f in scene.forces:
            scale = scale + v * math.hypot(*f.force) + w * abs(f.moment)
    return np.abs(d["balance"]) / scale


def compare_dynamics(ws, scene, df):
    rows = rows_of(ws)
    for name in dynamics_names(scene):
        if name == "balance":
            continue                                   # the sheet checks it, relative: chk_balance
        assert name in rows, f"no row {name}"
        got = np.array(row_values(ws, rows[name], len(df)), dtype=float)
        ref = df[name].to_numpy()
        scale = max(1.0, float(np.max(np.abs(ref))))
        assert np.all(np.abs(got - ref) <= 1e-9 * scale), (name, got, ref)
