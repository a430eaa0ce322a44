"""PRP and RPP in whole scenes: the bundled mechanisms and random assemblable instances and
chains against the 50-digit mpmath reference (bench.reference_mp: Newton on each group's
loop equations, independent of the closed form), the kinetostatics' energy balance, Newton
near a toggle, and the scene errors of the two kinds (one line naming file, line and key)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import sheetkin
from sheetkin.kinematics.scene import SceneError, parse_scene
from sheetkin.studies.bench import FAMILIES, method_newton, reference_mp

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
NEW = ["slider_on_coupler", "scotch_yoke", "three_group_chain"]
REF_TOL = 1e-11


def agrees_with_reference(scene, phis, tol=REF_TOL):
    """Every contract quantity of compute equals the mpmath reference, relative to the
    largest value of its family (x, y, s together; vx, vy, vs; ... as the bench measures
    them), absolutely below 1; angles modulo 360."""
    df = sheetkin.compute(scene, at=phis)
    ref = {name: np.array([float(v) for v in values]) for name, values in reference_mp(scene, list(phis),
                                                                                       dps=30).items()}
    family = {name: FAMILIES[name.split("_")[0]] for name in ref}
    scale = {f: max([1.0] + [float(np.abs(ref[n]).max()) for n in ref if family[n] == f]) for f in family.values()}
    for name, want in ref.items():
        d = np.abs(df[name].to_numpy() - want)
        if name.startswith("phi_"):
            d = np.minimum(d, 360 - d)
        assert d.max() <= tol * scale[family[name]], (name, df[name].to_numpy(), want)
    return df


@pytest.mark.parametrize("stem", NEW)
def test_bundled_mechanism_agrees_with_the_mpmath_reference(stem):
    scene = sheetkin.load_scene(WORKBOOKS / f"{stem}.toml")
    agrees_with_reference(scene, scene.crank_angles_deg())


@pytest.mark.parametrize("stem", NEW)
def test_bundled_mechanism_kinetostatics_balances_energy(stem):
    scene = sheetkin.load_scene(WORKBOOKS / f"{stem}.toml")
    df = sheetkin.compute(scene, dynamics=True)
    assert np.abs(df["P_bal"]).max() > 1.0                     # there is power to balance
    assert np.abs(df["balance"]).max() <= 1e-9 * np.abs(df["P_bal"]).max()


def test_slider_on_coupler_joint_is_on_the_coupler_line_and_the_vertical_guide():
    scene = sheetkin.load_scene(WORKBOOKS / "slider_on_coupler.toml")
    df = sheetkin.compute(scene)
    assert np.allclose(df["x_L"], -0.15, atol=1e-15)            # x = -0.15, tg theta infinite
    cross = (df["x_B"] - df["x_A"]) * (df["y_L"] - df["y_A"]) - (df["y_B"] - df["y_A"]) * (df["x_L"] - df["x_A"])
    assert np.abs(cross).max() < 1e-15
    assert np.allclose(df["s2_L"], df["y_L"], atol=1e-15)       # the guide passes through (-0.15, 0)
    assert np.allclose(np.hypot(df["x_L"] - df["x_A"], df["y_L"] - df["y_A"]), np.abs(df["s_L"]), atol=1e-15)


def test_scotch_yoke_is_harmonic():
    """K follows x = L1 cos(phi), the block s_A = L1 sin(phi): the textbook's Scotch yoke."""
    scene = sheetkin.load_scene(WORKBOOKS / "scotch_yoke.toml")
    df = sheetkin.compute(scene)
    phi, r, w = np.radians(df["phi_1"]), scene.crank.length, scene.crank.omega
    assert np.allclose(df["s_K"], r * np.cos(phi), atol=1e-15)
    assert np.allclose(df["vs_K"], -r * w * np.sin(phi), atol=1e-14)
    assert np.allclose(df["as_K"], -r * w * w * np.cos(phi), atol=1e-13)
    assert np.allclose(df["s_A"], r * np.sin(phi), atol=1e-15)
    assert (df["det_g1"] == 1.0).all()


# --------------------------------------------------------------------------- random instances
HEAD = """title = "random"
[frame]
O = [0.0, 0.0]
O2 = [{o2x}, {o2y}]
[crank]
pivot = "O"
joint = "A"
length = {r}
phi0_deg = 0.0
step_deg = 30.0
positions = 13
omega = {w}
epsilon = {e}
"""
MASS = """
[[mass]]
link = {k}
mass = {m}
inertia = {j}
centre = "{c}"
"""

num = st.floats(-1.0, 1.0, allow_nan=False).map(lambda v: round(v, 6))
angle = st.floats(-180.0, 180.0).map(lambda v: round(v, 4))
crank = st.fixed_dictionaries({"r": st.floats(0.05, 0.5).map(lambda v: round(v, 6)), "w": st.floats(-30, 30),
                               "e": st.floats(-100, 100), "o2x": num, "o2y": num})


def crossing_ok(a, b, limit=0.2):
    return abs(math.sin(math.radians(a - b))) > limit


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crank, angle, angle, num, num, st.lists(st.floats(0, 360), min_size=3, max_size=3))
# ax_N ~ 1e-26 beside ay_N ~ 1e2 (N far out, 12 deg from parallel): measured on its family's scale
@example({"r": 0.5, "w": 18.0, "e": 0.0, "o2x": 0.0, "o2y": 0.0}, 0.0, 180.0, 1.0, 0.0, [0.0, 0.0, 192.0])
def test_random_prp_on_the_crank_agrees_with_the_reference(c, a1, a2, gx, gy, phis):
    """guides[0] on the crank (through A, at a1 to it), guides[1] on the frame at a2: the
    lines cross except where phi_1 + a1 = a2 (mod 180), a toggle the positions avoid."""
    phis = [p for p in phis if crossing_ok(p + a1, a2)]
    if not phis:
        return
    text = HEAD.format(**c) + f"""
[[group]]
type = "PRP"
links = [2, 3]
joints = ["N"]
guides = [{{ through = "A", angle_deg = {a1}, link = 1 }}, {{ through = [{gx}, {gy}], angle_deg = {a2} }}]
""" + MASS.format(k=2, m=0.5, j=0.01, c="N") + MASS.format(k=3, m=1.5, j=0.02, c="N")
    scene = parse_scene(text, "random.toml")
    agrees_with_reference(scene, phis)
    df = sheetkin.compute(scene, at=phis, dynamics=True)
    assert np.abs(df["balance"]).max() <= 1e-8 * (1 + np.abs(df["P_bal"]).max() + np.abs(df["T_t"]).max())


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crank, angle, angle, num, num, st.lists(st.floats(0, 360), min_size=3, max_size=3))
def test_random_rpp_agrees_with_the_reference(c, alpha, gamma, gx, gy, phis):
    if not crossing_ok(alpha, gamma):
        return
    text = HEAD.format(**c) + f"""
[[group]]
type = "RPP"
links = [2, 3]
joints = ["A", "K"]
slot_angle_deg = {alpha}
guide = {{ through = [{gx}, {gy}], angle_deg = {gamma} }}
""" + MASS.format(k=2, m=0.3, j=0.001, c="A") + MASS.format(k=3, m=2.0, j=0.05, c="K")
    scene = parse_scene(text, "random.toml")
    agrees_with_reference(scene, phis)
    df = sheetkin.compute(scene, at=phis, dynamics=True)
    assert np.abs(df["balance"]).max() <= 1e-8 * (1 + np.abs(df["P_bal"]).max() + np.abs(df["T_t"]).max())


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crank, angle, angle, angle, angle, num, num, st.lists(st.floats(0, 360), min_size=3, max_size=3))
def test_random_chain_rpp_prp_rpr_agrees_with_the_reference(c, alpha, gamma, a1, a2, gx, gy, phis):
    """crank -> RPP (yoke driven by A) -> PRP (one guide on the yoke, one on the crank) ->
    RPR (a block on the frame point O2 in a kulisa turning about N: a kulisa with a moving
    axis; its s_O2 keeps the names apart): three kinds, guides on a turning
    and on a translating link, masses on every link."""
    # PRP's lines: yoke's (alpha + a1, constant) against the crank's (phi + a2)
    phis = [p for p in phis if crossing_ok(alpha + a1, p + a2, 0.3)]
    if not crossing_ok(alpha, gamma) or not phis:
        return
    text = HEAD.format(**c) + f"""
[[group]]
type = "RPP"
links = [2, 3]
joints = ["A", "K"]
slot_angle_deg = {alpha}
guide = {{ through = [{gx}, {gy}], angle_deg = {gamma} }}

[[group]]
type = "PRP"
links = [4, 5]
joints = ["N"]
guides = [{{ through = "K", angle_deg = {a1}, link = 3 }}, {{ through = "A", angle_deg = {a2}, link = 1 }}]

[[group]]
type = "RPR"
links = [6, 7]
joints = ["O2", "N"]
""" + "".join(MASS.format(k=k, m=0.2 * k, j=0.01 * k, c=cn)
              for k, cn in ((1, "A"), (2, "A"), (3, "K"), (4, "N"), (5, "N"), (6, "O2"), (7, "N")))
    scene = parse_scene(text, "random.toml")
    sol = sheetkin.solve(scene, phis)
    n, o2 = sol.points["N"], scene.frame["O2"]
    keep = [p for i, p in enumerate(phis) if math.hypot(n.x[i] - o2[0], n.y[i] - o2[1]) > 0.05]
    if not keep:
        return
    agrees_with_reference(scene, keep, tol=1e-9)
    df = sheetkin.compute(scene, at=keep, dynamics=True)
    assert np.abs(df["balance"]).max() <= 1e-7 * (1 + np.abs(df["P_bal"]).max() + np.abs(df["T_t"]).max())


# --------------------------------------------------------------------------- near a toggle
def test_newton_flags_prp_guides_turning_parallel():
    """guides[0] on the crank at 0 deg to it, guides[1] horizontal: parallel at phi_1 = 0 and
    180. Walking towards 180 deg the solver's toggle measure is sin of the angle between
    the lines, and Newton's Jacobian becomes singular with it (the stability study's flag)."""
    text = HEAD.format(r=0.1, w=10.0, e=0.0, o2x=0.0, o2y=0.0) + """
[[group]]
type = "PRP"
links = [2, 3]
joints = ["N"]
guides = [{ through = "A", angle_deg = 0.0, link = 1 }, { through = [0.0, 0.05], angle_deg = 0.0 }]
"""
    scene = parse_scene(text, "toggle.toml")
    phis = [180.0 - d for d in (30.0, 1.0, 1e-3)]
    df = sheetkin.compute(scene, at=phis)
    assert np.allclose(np.abs(df["det_g1"]), np.abs(np.sin(np.radians(phis))), atol=1e-15)
    res = method_newton(scene, np.array(phis))
    flagged = [p for flag in res.flags.values() for p in flag]
    assert 180.0 - 1e-3 in flagged and 150.0 not in flagged


# --------------------------------------------------------------------------- scene errors
FOUR = (WORKBOOKS / "slider_on_coupler.toml").read_text(encoding="utf-8")
YOKE = (WORKBOOKS / "scotch_yoke.toml").read_text(encoding="utf-8")
PRP_GUIDES = """guides = [{ through = "A", angle_deg = 0.0, link = 2 },     # line (2): the coupler AB; s_L = |AL|
          { through = [-0.15, 0.0], angle_deg = 90.0 }]     # line (1): x = -0.15; s2_L = y_L"""
YOKE_GUIDE = 'guide          = { through = "O", angle_deg = 0.0 }   # the yoke\'s guide on the frame'


@pytest.mark.parametrize("text, key, words", [
    (FOUR.replace(PRP_GUIDES, ""), "guides", "got nothing"),
    (FOUR.replace(PRP_GUIDES, 'guides = [{ through = "A", angle_deg = 0.0, link = 2 }]'), "guides", "2 guides"),
    (FOUR.replace(PRP_GUIDES,
                  'guides = [{ through = "O", angle_deg = 0.0 }, { through = [0.1, 0.0], angle_deg = 90.0 }]'),
     "guides", "both guides are on the frame"),
    (FOUR.replace(PRP_GUIDES,
                  'guides = [{ through = "A", angle_deg = 0.0, link = 2 }, { through = [0.1, 0.0], angel = 9 }]'),
     "guides[1]", "angel"),
    (FOUR.replace(PRP_GUIDES, 'guides = [{ through = "O1", angle_deg = 0.0, link = 2 }, { through = [0.1, 0.0] }]'),
     "guides[0].through", "not a point of link 2"),
    (FOUR.replace(PRP_GUIDES, 'guides = [{ through = "A", angle_deg = 0.0, link = 5 }, { through = [0.1, 0.0] }]'),
     "guides", "not placed before"),
    (YOKE.replace(YOKE_GUIDE, 'guide = { through = "A", angle_deg = 0.0, link = 1 }'), "guide", "on the frame"),
    (YOKE.replace("slot_angle_deg = 90.0", "slot_angle_deg = 180.0"), "slot_angle_deg", "runs along the guide"),
    (YOKE.replace('joints         = ["A", "K"]', 'joints = ["A", "A"]'), "joints", "must differ"),
    (YOKE.replace("slot_angle_deg = 90.0", "slot = 90.0"), "slot", ""),
], ids=["prp-no-guides", "prp-one-guide", "prp-both-on-frame", "prp-typo-in-guide", "prp-through-not-on-link",
        "prp-guide-on-later-link", "rpp-guide-on-moving-link", "rpp-slot-along-guide", "rpp-same-joints",
        "rpp-unknown-key"])
def test_prp_and_rpp_mistakes_give_one_line_errors(text, key, words):
    with pytest.raises(SceneError) as err:
        parse_scene(text, "mistake.toml")
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith("mistake.toml:"), msg
    assert f"'{key}" in msg and words in msg, msg


# --------------------------------------------------------------------------- the sheet's kinetostatics
@pytest.fixture(scope="module")
def dyn_sheets(soffice, tmp_path_factory):
    """The three bundled workbooks (with their masses and forces), recalculated by
    LibreOffice in one soffice run."""
    from helpers.libreoffice import recalculate

    from sheetkin.sheet.workbook import write_workbook
    src = tmp_path_factory.mktemp("prp_rpp")
    made = {}
    for stem in NEW:
        text = (WORKBOOKS / f"{stem}.toml").read_text(encoding="utf-8")
        scene = parse_scene(text, f"{stem}.toml")
        write_workbook(scene, src / f"{stem}.xlsx", scene_text=text)
        made[stem] = (src / f"{stem}.xlsx", scene)
    out = recalculate([p for p, _ in made.values()], tmp_path_factory.mktemp("prp_rpp_recalculated"))
    import openpyxl
    return {k: (openpyxl.load_workbook(out[p.resolve()], data_only=True).worksheets[0], s) for k, (p,
                                                                                                   s) in made.items()}


@pytest.mark.parametrize("stem", NEW)
def test_libreoffice_kinetostatics_rows_equal_compute(dyn_sheets, stem):
    """Every reaction, couple and M_bal row of the sheet (PRP's and RPP's blocks included),
    recalculated by LibreOffice, equals compute --dynamics; every check row passes."""
    from sheetkin.kinematics.dynamics import dynamics_names
    ws, scene = dyn_sheets[stem]
    df = sheetkin.compute(scene, dynamics=True)
    rows = {ws.cell(r, 1).value: r for r in range(1, ws.max_row + 1) if ws.cell(r, 1).value}
    names = [n for n in dynamics_names(scene) if n != "balance"]
    assert any(n.startswith("M_") and n != "M_bal" for n in names)      # a sliding pair's couple
    for name in names:
        got = np.array([ws.cell(rows[name], 5 + k).value for k in range(len(df))], dtype=float)
        ref = df[name].to_numpy()
        assert np.all(np.abs(got - ref) <= 1e-9 * max(1.0, float(np.abs(ref).max()))), (name, got, ref)
    failing = [n for n, r in rows.items() if str(n).startswith("chk") and ws.cell(r, 4).value != 0]
    assert not failing and ws["D3"].value.startswith("все проверки выполнены"), failing
