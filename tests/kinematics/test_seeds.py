"""The seeds' printed numbers are the first oracles (shared/seeds/README.md).

Numbers below are copied verbatim from the seed files. Mathcad shows 3 decimals and
drops trailing zeros (seed 000 prints 2.8 for 2.800, 56 for 56.000), so its numbers are
checked to +-0.0005; seed 001's article retypes numbers with fewer digits, checked to half
a unit of the last printed digit.
"""
from pathlib import Path

import numpy as np
import pytest

import sheetkin

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
MATHCAD = 0.0005


def printed_tolerance(text: str) -> float:
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0 ** -decimals


def check(got, printed: dict[str, str], tol=None):
    """Every printed value, to its precision; one message listing all misses."""
    misses = []
    for name, text in printed.items():
        t = printed_tolerance(text) if tol is None else tol
        value = got[name]
        if not abs(value - float(text)) <= t + 1e-12:
            misses.append(f"{name}: got {value:.6f}, printed {text} (+-{t:g})")
    assert not misses, "; ".join(misses)


# --------------------------------------------------------------------------- seed 000
@pytest.fixture(scope="module")
def fourbar():
    return sheetkin.load_scene(WORKBOOKS / "fourbar.toml")


def test_seed000_true_values_at_150_deg(fourbar):
    """Seed 000, 'for the position phi1 = 150 deg, omega1 = 20, eps1 = 0'."""
    row = sheetkin.compute(fourbar, at=[150.0], analogs=True).iloc[0]
    check(row, {
        "x_A": "-0.121", "y_A": "0.07", "x_B": "-0.311", "y_B": "-0.393",
        "x_S2": "-0.269", "y_S2": "-0.291", "x_S3": "-0.195", "y_S3": "-0.444",
        "phi_2": "247.697", "phi_3": "156.163",
        "vx_A": "-1.4", "vy_A": "-2.425", "v_A": "2.8",
        "vx_B": "-1.122", "vy_B": "-2.539", "v_B": "2.776",
        "vx_S2": "-1.183", "vy_S2": "-2.514", "v_S2": "2.778",
        "vx_S3": "-0.702", "vy_S3": "-1.59", "v_S3": "1.738",
        "ax_A": "48.497", "ay_A": "-28", "a_A": "56",
        "ax_B": "18.015", "ay_B": "-15.301", "a_B": "23.635",
        "ax_S2": "24.699", "ay_S2": "-18.086", "a_S2": "30.613",
        "omega_2": "0.601", "eps_2": "-66.044", "omega_3": "8.164", "eps_3": "19.75",
        # the analogs d/dphi, d2/dphi2 (seed 000, sections 3 and 4)
        "vqx_A": "-0.07", "vqy_A": "-0.121", "vqx_B": "-0.056", "vqy_B": "-0.127",
        "vqx_S2": "-0.059", "vqy_S2": "-0.126", "vqx_S3": "-0.035", "vqy_S3": "-0.079",
        "omegaq_2": "0.03", "omegaq_3": "0.408",
        "aqx_A": "0.121", "aqy_A": "-0.07", "aqx_B": "0.045", "aqy_B": "-0.038",
        "aqx_S2": "0.062", "aqy_S2": "-0.045", "epsq_2": "-0.165", "epsq_3": "0.049",
    }, tol=MATHCAD)
    # the auxiliary vector O1A of the seed's solution: |O1A| = 0.612
    assert abs(np.hypot(row.x_A - 0.0, row.y_A + 0.53) - 0.612) <= MATHCAD


SEED000_TABLE = {   # phi1 = 0, 30, ..., 360 deg
    "v_B": "1.745 0.718 0.337 1.421 2.321 2.776 2.632 1.72 0.158 2.441 3.374 2.771 1.745",
    "v_S2": "1.868 0.922 0.737 1.596 2.384 2.778 2.659 1.893 0.559 2.041 3.114 2.778 1.868",
    "v_S3": "1.092 0.449 0.211 0.89 1.453 1.738 1.648 1.077 0.099 1.529 2.113 1.735 1.092",
    "a_B": "40.674 39.274 41.505 40.219 31.459 23.635 27.669 53.372 88.278 73.942 33.49 42.945 40.674",
    "a_S2": "39.138 42.621 44.289 42.038 35.326 30.613 32.75 50.597 79.598 69.535 18.728 29.28 39.138",
    "omega_2": "3.763 5.451 5.435 4.179 2.384 0.601 -1.154 -3.229 -5.774 -7.179 -4.613 0.136 3.763",
    "omega_3": "-5.131 -2.111 0.992 4.179 6.827 8.164 7.74 5.058 -0.464 -7.179 -9.923 -8.151 -5.131",
    "eps_2": "101.264 29.631 -28.081 -63.081 -70.217 -66.044 -70.505 -90.03 -95.236 13.053 "
             "166.967 172.268 101.264",
    "eps_3": "116.695 115.425 122.07 116.996 79.934 19.75 -55.073 -154.877 -259.64 -211.278 "
             "2.563 107.42 116.695",
}
# Seed 000's slip (shared/seeds/README.md): a_qS3x, a_qS3y differentiate v_qS2, so its
# printed a_S3 column repeats a_S2. This is that printed column.
SEED000_PRINTED_A_S3 = SEED000_TABLE["a_S2"]


@pytest.mark.parametrize("name", sorted(SEED000_TABLE))
def test_seed000_table(fourbar, name):
    df = sheetkin.compute(fourbar)
    assert list(df.phi_1) == [30.0 * i for i in range(13)]
    printed = SEED000_TABLE[name].split()
    misses = [f"phi1={p:g}: got {g:.4f}, printed {t}" for p, g, t in zip(df.phi_1, df[name], printed, strict=False)
              if not abs(g - float(t)) <= MATHCAD]
    assert not misses, f"{name}: " + "; ".join(misses)


def test_seed000_a_S3_slip_corrected(fourbar):
    """S3 lies on the rocker O1B, so a_S3 = a_B * |O1 S3| / |O1 B| exactly; the seed's
    printed a_S3 (= its a_S2) is wrong except where the two happen to agree."""
    df = sheetkin.compute(fourbar)
    np.testing.assert_allclose(df.a_S3, df.a_B * 0.2129 / 0.34, rtol=1e-13)
    printed = np.array(SEED000_PRINTED_A_S3.split(), dtype=float)
    assert np.all(np.abs(df.a_S3 - printed) > 1.0)          # the slip is not reproduced
    assert np.all(np.abs(df.a_S2 - printed) <= MATHCAD)     # it is a_S2, as the README says


# --------------------------------------------------------------------------- seed 004
SEED004_TABLE = """
360  71.565  2.53   -1      24     3.5    84.073
300  76.813  1.753  3.327   52     11.643 186.076
240  103.187 1.753  3.327   -52    11.643 186.076
180  108.435 2.53   -1      -24    3.5    84.073
120  97.369  3.119  -2.368  -5.197 8.287  26.755
60   82.631  3.119  -2.368  5.197  8.287  26.755
0    71.565  2.53   -1      24     3.5    84.073
"""


def test_seed004_table():
    """Seed 004's table: phi1, phi3, S_AB, omega3, eps3, V_C, W_C (crank clockwise)."""
    df = sheetkin.compute(WORKBOOKS / "slotted_lever.toml")
    rows = [line.split() for line in SEED004_TABLE.strip().splitlines()]
    assert list(df.phi_1) == [float(r[0]) for r in rows]
    for (_, row), printed in zip(df.iterrows(), rows, strict=False):
        check(row, dict(zip(["phi_3", "s_A", "omega_3", "eps_3", "v_C", "a_C"], printed[1:], strict=False)),
              tol=MATHCAD)


# --------------------------------------------------------------------------- seed 001
def test_seed001_shaper_printed_values():
    """Seed 001's Given-Find results at its (unprinted) crank angle; see shaper.toml."""
    scene = sheetkin.load_scene(WORKBOOKS / "shaper.toml")
    r = sheetkin.compute(scene, at=[scene.crank.phi0_deg]).iloc[0]
    check(r, {"phi_3": "101.811", "phi_4": "182.758", "s_A": "0.181", "s_D": "-0.3",
              "omega_3": "3.617", "omega_4": "-1.816", "vx_D": "-1.753",
              "eps_3": "-36.2", "eps_4": "-13.09", "ax_D": "19.21"})
    assert r.vy_D == 0 and r.ay_D == 0 and abs(r.y_D - 0.470002) < 1e-15   # the ram stays on its guide
    # the article's vectors: relative velocity/acceleration of A3 (on the lever) w.r.t. A1
    # (on the crank) lie along the slot: v_A3A1 = -vs_A u, a_A3A1r = -as_A u
    u = np.array([np.cos(np.radians(r.phi_3)), np.sin(np.radians(r.phi_3))])
    l31 = r.s_A * u
    rot = np.array([-l31[1], l31[0]])                        # omega x l31 / omega
    got = {"vA3A1x": -r.vs_A * u[0], "vA3A1y": -r.vs_A * u[1],
           "aA3A1x": -r.as_A * u[0], "aA3A1y": -r.as_A * u[1],
           "vA3x": r.omega_3 * rot[0], "vA3y": r.omega_3 * rot[1],
           "aA3x": r.eps_3 * rot[0] - r.omega_3 ** 2 * l31[0],
           "aA3y": r.eps_3 * rot[1] - r.omega_3 ** 2 * l31[1]}
    check(got, {"vA3A1x": "0.089", "vA3A1y": "-0.425", "aA3A1x": "1.54", "aA3A1y": "-7.35",
                "vA3x": "-0.641", "vA3y": "-0.134", "aA3x": "6.895", "aA3y": "-0.977"})


def test_seed001_crank_angle_window():
    """The scene's comment: printed phi3 pins phi1 to 248.2612..248.2633 deg (l31 = 0.181)."""
    scene = sheetkin.load_scene(WORKBOOKS / "shaper.toml")
    df = sheetkin.compute(scene, at=[248.2605, 248.2612, 248.2632, 248.2640])
    ok = (np.abs(df.phi_3 - 101.811) <= 0.0005) & (np.abs(df.s_A - 0.181) <= 0.0005)
    assert list(ok) == [False, True, True, False]
