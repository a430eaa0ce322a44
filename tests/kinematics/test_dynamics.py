"""Energy and force analysis (issue 6, part 2): `compute --dynamics` and the workbook blocks.

Oracles, none of them the code under test:
  * closed forms: a lone crank (M_bal = (J + m r^2) eps + m g r cos phi); a slider-crank with
    mass only in the slider (M_bal = m omega^2 x'' x', x(phi) written out and differentiated
    by mpmath);
  * each link's three equilibrium equations with every reaction on it, summed about the
    origin (the kinetostatics sums moments about the joints, and never uses the crank's
    or the whole mechanism's force balance);
  * the energy balance M_bal omega + P_ext - dU/dt - dT/dt = 0, with dT/dt and dU/dt taken as
    numeric derivatives, at 50 digits, of T and U built from the independent mpmath
    reference kinematics (sheetkin.studies.bench.reference_mp), for the seeds' scenes with masses;
  * random mechanisms (the property tests' strategies) with random masses and loads;
  * LibreOffice's recalculation of the generated workbooks.
"""
from __future__ import annotations

import math
from pathlib import Path

import mpmath
import numpy as np
import openpyxl
import pytest
from helpers.libreoffice import recalculate
from helpers.scenes import CHANGE_POINT, OFFSET_CHAIN, SIX_BAR
from helpers.sheetrows import compare_dynamics, relative_balance, rows_of, set_input
from helpers.strategies import KINDS, MECHANISMS
from hypothesis import given, settings
from hypothesis import strategies as st

import sheetkin
from sheetkin.cli.commands import main
from sheetkin.kinematics.dynamics import dynamics, dynamics_names, force_active, reaction_pairs
from sheetkin.kinematics.scene import SceneError, parse_scene
from sheetkin.kinematics.solver import solve
from sheetkin.sheet.workbook import write_workbook
from sheetkin.studies.bench import reference_mp

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"
BALANCE_TOL = 1e-9


def with_dynamics(text: str, extra: str, gravity=(0.0, -9.81)) -> str:
    """A scene text with `gravity` first (a top-level key) and [[mass]]/[[force]] tables last."""
    head = f"gravity = [{gravity[0]!r}, {gravity[1]!r}]\n" if gravity else ""
    return head + text + "\n" + extra


def mass(link, m, J, centre) -> str:
    return f'[[mass]]\nlink = {link}\nmass = {float(m)!r}\ninertia = {float(J)!r}\ncentre = "{centre}"\n'


def equilibrium_residuals(scene, sol, d) -> dict[int, float]:
    """Each link's force and moment sums (about the origin) with every load and reaction on
    it, relative to the largest link's sum of force magnitudes (moments divided by the
    mechanism's size)."""
    n = sol.phi1_deg.shape
    gx, gy = scene.gravity
    sums = {k: [np.zeros(n), np.zeros(n), np.zeros(n)] for k in range(1, 2 + 2 * len(scene.groups))}
    size = {k: np.zeros(n) for k in sums}
    span = max([1.0] + [abs(c) for p in scene.frame.values() for c in p]
               + [abs(sol.points[p].x).max() + abs(sol.points[p].y).max() for p in sol.points])

    def point(name):
        if name in scene.frame:
            x, y = scene.frame[name]
            return x + np.zeros(n), y + np.zeros(n)
        return sol.points[name].x, sol.points[name].y

    def push(k, at, fx, fy, couple=0.0):
        if k == 0:
            return
        x, y = point(at) if at else (0.0, 0.0)
        s = sums[k]
        s[0] = s[0] + fx
        s[1] = s[1] + fy
        s[2] = s[2] + x * fy - y * fx + couple
        size[k] = size[k] + np.abs(fx) + np.abs(fy) + np.abs(couple) / span

    for m in scene.masses:
        push(m.link, m.centre, d[f"Fix_{m.link}"] + m.mass * gx, d[f"Fiy_{m.link}"] + m.mass * gy, d[f"Mi_{m.link}"])
    for f in scene.forces:
        on = force_active(f, sol.phi1_deg)
        push(f.link, f.at, f.force[0] * on, f.force[1] * on, f.moment * on)
    for p in reaction_pairs(scene):
        rx, ry = d[f"Rx_{p.tag}"], d[f"Ry_{p.tag}"]
        c = d[f"M_{p.tag}"] if p.sliding else 0.0
        push(p.j, p.joint, rx, ry, c)
        push(p.i, p.joint, -rx, -ry, -c)
    push(1, None, 0.0, 0.0, d["M_bal"])
    # relative to the largest load sum of any link: a link that carries nothing of its own
    # passes on reactions that are the rounding noise of the others
    whole = np.max(list(size.values()), axis=0) + 1e-300
    return {k: float(np.max((np.abs(s[0]) + np.abs(s[1]) + np.abs(s[2]) / span) / whole))
            for k, s in sums.items()}


# --------------------------------------------------------------------------- closed forms
LONE_CRANK = """
title = "lone crank"
[frame]
O = [0.1, -0.2]
[crank]
pivot = "O"
joint = "A"
length = 0.3
positions = 13
omega = 7.0
epsilon = -2.5
[[point]]
name = "S1"
link = 1
from = "O"
along = 0.12
across = 0.05
"""


def test_lone_crank_closed_form():
    m, J, g = 3.0, 0.04, 9.81
    scene = parse_scene(with_dynamics(LONE_CRANK, mass(1, m, J, "S1"), (0.0, -g)))
    phi = np.arange(0.0, 360.0, 15.0)
    df = sheetkin.compute(scene, phi, dynamics=True)
    r = math.hypot(0.12, 0.05)
    delta = math.atan2(0.05, 0.12)
    w, eps = 7.0, -2.5
    th = np.radians(phi) + delta                     # direction O -> S1
    m_bal = (J + m * r * r) * eps + m * g * r * np.cos(th)
    np.testing.assert_allclose(df["M_bal"], m_bal, rtol=1e-12, atol=1e-12)
    # the pivot carries the weight and the centripetal/tangential force: R = m a_S - m g
    ax = -eps * r * np.sin(th) - w * w * r * np.cos(th)
    ay = eps * r * np.cos(th) - w * w * r * np.sin(th)
    np.testing.assert_allclose(df["Rx_0_1"], m * ax, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(df["Ry_0_1"], m * ay + m * g, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(df["T"], 0.5 * (J + m * r * r) * w * w, rtol=1e-13)
    np.testing.assert_allclose(df["U"], m * g * (-0.2 + r * np.sin(th)), rtol=1e-12, atol=1e-12)
    assert relative_balance(df).max() <= 1e-12


CRANK_SLIDER = """
title = "slider-crank"
[frame]
O = [0.0, 0.0]
[crank]
pivot = "O"
joint = "A"
length = 0.1
positions = 13
omega = 15.0
[[group]]
type = "RRP"
links = [2, 3]
joints = ["A", "B"]
length = 0.35
guide = { through = [0.0, 0.03], angle_deg = 0.0 }
branch = 1
"""


def test_slider_crank_with_mass_only_in_the_slider():
    """No other masses, gravity across the guide: the slider's inertia alone loads the crank,
    M_bal omega = m a_B v_B, i.e. M_bal = m omega^2 x'(phi) x''(phi) with
    x(phi) = r cos phi + sqrt(L^2 - (r sin phi - e)^2)."""
    m, r, L, e, w = 12.0, 0.1, 0.35, 0.03, 15.0
    scene = parse_scene(with_dynamics(CRANK_SLIDER, mass(3, m, 0.0, "B")))
    phi = np.arange(0.0, 360.0, 10.0) + 3.0
    df = sheetkin.compute(scene, phi, dynamics=True)
    mpmath.mp.dps = 30
    x = lambda p: r * mpmath.cos(p) + mpmath.sqrt(L * L - (r * mpmath.sin(p) - e) ** 2)
    want = [float(m * w * w * mpmath.diff(x, mpmath.radians(p), 1) * mpmath.diff(x, mpmath.radians(p), 2))
            for p in phi]
    np.testing.assert_allclose(df["M_bal"], want, rtol=1e-10, atol=1e-10 * max(map(abs, want)))
    # the massless coupler is a two-force member: its forces lie along A -> B
    ux, uy = df["x_B"] - df["x_A"], df["y_B"] - df["y_A"]
    cross = df["Rx_1_2"] * uy - df["Ry_1_2"] * ux
    assert np.max(np.abs(cross) / (df["R_1_2"] * L + 1e-300)) <= 1e-12
    # the guide holds the slider's weight and the coupler's push across it, and no couple
    np.testing.assert_allclose(df["Rx_0_3"], 0.0, atol=1e-9)
    np.testing.assert_allclose(df["Ry_0_3"], m * 9.81 - df["Ry_2_3"], rtol=1e-12)
    np.testing.assert_allclose(df["M_0_3"], 0.0, atol=1e-12)


# --------------------------------------------------------------------------- the seeds
SEED_MASSES = {
    "fourbar": mass(1, 1.4, 0.01, "A") + mass(2, 5.0, 0.104, "S2") + mass(3, 3.4, 0.033, "S3")
    + '[[force]]\nname = "load"\nlink = 3\nat = "B"\nforce = [20.0, -150.0]\nmoment = 4.0\n',
    "slotted_lever": mass(2, 0.8, 0.0, "A") + mass(3, 20.0, 20.4, "C")
    + '[[force]]\nlink = 3\nmoment = -50.0\nfrom_deg = 30.0\nto_deg = 250.0\n',
    "crank_slider": "",            # filled below from the scene's own links
    "shaper_dynamics": "",
}


def seed_scene(stem: str):
    text = (WORKBOOKS / f"{stem}.toml").read_text(encoding="utf-8")
    if stem == "crank_slider":
        sc = parse_scene(text)
        g = sc.groups[0]
        extra = mass(g.links[0], 2.0, 0.02, g.joints[0]) + mass(g.links[1], 6.0, 0.0, g.joints[1])
        extra += f'[[force]]\nlink = {g.links[1]}\nat = "{g.joints[1]}"\nforce = [-300.0, 40.0]\n'
        return parse_scene(with_dynamics(text, extra))
    if stem == "shaper_dynamics":
        return parse_scene(text)
    return parse_scene(with_dynamics(text, SEED_MASSES[stem]))


@pytest.mark.parametrize("stem", list(SEED_MASSES))
def test_seed_scenes_energy_balance_against_the_mpmath_reference(stem):
    """M_bal from the kinetostatics against the energy method on independent kinematics:
    M_bal omega = dT/dt + dU/dt - P_ext, with T and U from reference_mp's 50-digit velocities
    and positions, and their time derivatives as central differences in the crank angle
    (the crank turns uniformly in these scenes, so d/dt = omega d/dphi)."""
    scene = seed_scene(stem)
    assert scene.crank.epsilon == 0.0
    phi = np.array(scene.crank_angles_deg()) + 0.37      # off the interval ends of the loads
    df = sheetkin.compute(scene, phi, dynamics=True)
    assert relative_balance(df).max() <= BALANCE_TOL
    w = scene.crank.omega
    h = 1e-9                  # degrees: truncation ~h^2 = 1e-22, 50 digits absorb the cancellation
    ends = {s: phi + s * h for s in (-1, 1)}
    with mpmath.workdps(50):
        ref = {s: reference_mp(scene, ends[s]) for s in (-1, 1)}
        for k, p in enumerate(phi):
            step = mpmath.radians(mpmath.mpf(ends[1][k]) - mpmath.mpf(ends[-1][k]))   # exactly as rounded
            rates = []
            for fn in (energy_T, energy_U):
                diff = (fn(scene, ref[1], k) - fn(scene, ref[-1], k)) / step
                rates.append(w * diff)
            p_ext = external_power(scene, df, k)
            want = (rates[0] + rates[1] - p_ext) / w
            got = df["M_bal"].iloc[k]
            scale = (abs(df["P_bal"].iloc[k]) + abs(df["T_t"].iloc[k]) + abs(p_ext)) / abs(w)
            assert abs(got - float(want)) <= 1e-9 * scale, (stem, p, got, float(want))


def _kinematics(scene, ref, k, name):
    if name in scene.frame:
        x, y = scene.frame[name]
        return mpmath.mpf(x), mpmath.mpf(y), 0, 0
    return tuple(ref[f"{q}_{name}"][k] for q in ("x", "y", "vx", "vy"))


def energy_T(scene, ref, k):
    total = mpmath.mpf(0)
    for m in scene.masses:
        _, _, vx, vy = _kinematics(scene, ref, k, m.centre)
        w = scene.crank.omega if m.link == 1 else ref[f"omega_{m.link}"][k]
        total += m.mass * (vx * vx + vy * vy) / 2 + m.inertia * w * w / 2
    return total


def energy_U(scene, ref, k):
    gx, gy = scene.gravity
    return sum((-m.mass * (gx * _kinematics(scene, ref, k, m.centre)[0] + gy * _kinematics(scene, ref, k, m.centre)[1])
                for m in scene.masses), mpmath.mpf(0))


def external_power(scene, df, k):
    """P_ext from the solver's velocities (the forces' own definition, not the code's sum)."""
    total = 0.0
    for f in scene.forces:
        if not force_active(f, df["phi_1"].to_numpy()[k:k + 1])[0]:
            continue
        if f.at:
            total += f.force[0] * df[f"vx_{f.at}"].iloc[k] + f.force[1] * df[f"vy_{f.at}"].iloc[k]
        w = scene.crank.omega if f.link == 1 else df[f"omega_{f.link}"].iloc[k]
        total += f.moment * w
    return total


@pytest.mark.parametrize("stem", list(SEED_MASSES))
def test_seed_scenes_every_link_in_equilibrium(stem):
    scene = seed_scene(stem)
    phi = np.arange(0.0, 360.0, 2.5) + 0.1
    sol = solve(scene, phi)
    res = equilibrium_residuals(scene, sol, dynamics(scene, sol))
    assert max(res.values()) <= 1e-12, res


def test_chains_pass_reactions_back_through_points_and_joints():
    """Two groups each, the second hung on a point of the first's link: the reactions the
    later group exerts reach the earlier links (equilibrium of every link checks it)."""
    for text, extra in (
        (SIX_BAR, mass(2, 1.0, 0.01, "A") + mass(3, 2.0, 0.02, "C") + mass(4, 1.5, 0.015, "S4")
         + mass(5, 2.5, 0.03, "D") + '[[force]]\nlink = 5\nat = "D"\nforce = [10.0, -80.0]\n'),
        (OFFSET_CHAIN, mass(1, 0.7, 0.002, "A") + mass(2, 0.3, 0.0001, "A") + mass(3, 4.0, 0.12, "C")
         + mass(4, 1.1, 0.01, "S4") + mass(5, 9.0, 0.0, "D")
         + '[[force]]\nname = "tool"\nlink = 5\nat = "D"\nforce = [-400.0, 25.0]\nfrom_deg = 20.0\nto_deg = 200.0\n'
         + '[[force]]\nname = "spring"\nlink = 3\nmoment = 12.0\n'),
    ):
        scene = parse_scene(with_dynamics(text, extra, (0.4, -9.81)))
        phi = np.arange(0.0, 360.0, 5.0) + 0.2
        sol = solve(scene, phi)
        d = dynamics(scene, sol)
        assert max(equilibrium_residuals(scene, sol, d).values()) <= 1e-12
        assert relative_balance(d).max() <= BALANCE_TOL


# --------------------------------------------------------------------------- random mechanisms
@settings(max_examples=60, deadline=None, database=None)
@given(data=st.data(), kind=st.sampled_from(KINDS))
def test_random_mechanisms_energy_balance(data, kind):
    m = data.draw(MECHANISMS[kind], label="mechanism")
    S = float(m.size)
    draw = data.draw
    centres = {1: draw(st.sampled_from(["O", "A"])), 2: "P2", 3: "P3"}
    extra = "".join(mass(k, draw(st.floats(0.1, 50.0)), draw(st.floats(0.0, 2.0)) * S * S, c)
                    for k, c in centres.items() if draw(st.booleans()) or k == 3)
    lo = draw(st.floats(-360.0, 360.0))
    span = draw(st.floats(10.0, 350.0))
    fx, fy = draw(st.floats(-1e3, 1e3)), draw(st.floats(-1e3, 1e3))
    extra += (f'[[force]]\nlink = 2\nat = "P2"\nforce = [{fx!r}, {fy!r}]\n'
              f'moment = {draw(st.floats(-100.0, 100.0))!r}\nfrom_deg = {lo!r}\nto_deg = {lo + span!r}\n')
    g = (draw(st.floats(-10.0, 10.0)), draw(st.floats(-10.0, 10.0)))
    scene = parse_scene(with_dynamics(m.toml, extra, g))
    sol = solve(scene, np.array(m.angles))
    d = dynamics(scene, sol)
    assert list(d) == dynamics_names(scene)
    assert relative_balance(d, scene, sol).max() <= BALANCE_TOL
    assert max(equilibrium_residuals(scene, sol, d).values()) <= 1e-11


# --------------------------------------------------------------------------- scene, CLI
@pytest.mark.parametrize("extra, expected", [
    ('[[mass]]\nlink = 2\nmass = 5.0\ncentre = "S3"\n',
     "key 'centre': expected a joint or point of link 2 (A, B, S2), got 'S3'"),
    ('[[mass]]\nlink = 7\nmass = 5.0\ncentre = "A"\n', "key 'link': expected a moving link 1..3, got 7"),
    ('[[mass]]\nlink = 2\nmass = 0.0\ncentre = "A"\n', "key 'mass': expected a positive mass in kg, got 0"),
    ('[[mass]]\nlink = 2\nmass = 1.0\ninertia = -1.0\ncentre = "A"\n',
     "key 'inertia': expected a moment of inertia >= 0"),
    ('[[mass]]\nlink = 2\nmass = 1.0\ncentre = "A"\n[[mass]]\nlink = 2\nmass = 2.0\ncentre = "B"\n',
     "link 2 already has a [[mass]]"),
    ('[[force]]\nlink = 2\nat = "B"\n', "expected `force = [Fx, Fy]` (N, with `at`) and/or `moment`"),
    ('[[force]]\nlink = 2\nforce = [1.0, 2.0]\n', "key 'at': missing; expected a joint or point of link 2"),
    ('[[force]]\nlink = 3\nat = "B"\nforce = [1.0]\n', "key 'force': expected an array of 2 numbers"),
    ('[[force]]\nlink = 3\nmoment = 1.0\nfrom_deg = 90.0\n', "key 'to_deg': missing; expected a number"),
    ('[[force]]\nlink = 3\nmoment = 1.0\nfrom_deg = 90.0\nto_deg = 30.0\n',
     "expected from_deg < to_deg < from_deg + 360"),
    ('[[force]]\nname = "F"\nlink = 3\nmoment = 1.0\n[[force]]\nname = "F"\nlink = 2\nmoment = 1.0\n',
     "name 'F' is used by another [[force]]"),
    ('[[force]]\nname = "ext"\nlink = 3\nmoment = 1.0\n', "key 'name': 'ext' is reserved (P_ext names a total)"),
])
def test_scene_errors_name_the_line_and_key(extra, expected):
    from helpers.scenes import FOURBAR
    text = FOURBAR + "\n" + extra
    with pytest.raises(SceneError) as e:
        parse_scene(text, "bad.toml")
    msg = str(e.value)
    assert expected in msg and "\n" not in msg
    line = int(msg.split(":")[1])
    assert text.splitlines()[line - 1].strip(), msg         # points at a real line


def test_compute_dynamics_cli(tmp_path, capsys):
    path = WORKBOOKS / "shaper_dynamics.toml"
    assert main(["compute", str(path), "--dynamics", "--format", "csv", "-o", str(tmp_path / "d.csv")]) == 0
    import pandas as pd
    df = pd.read_csv(tmp_path / "d.csv")
    scene = sheetkin.load_scene(path)
    names = list(df.columns)
    contract = sheetkin.column_names(scene)
    assert names[:len(contract)] == contract
    assert names[len(contract):len(contract) + len(dynamics_names(scene))] == dynamics_names(scene)
    assert relative_balance(df).max() <= BALANCE_TOL
    # the cutting force acts over its interval only, and against the ram's working motion
    on = force_active(scene.forces[0], df["phi_1"].to_numpy()).astype(bool)
    assert on.any() and not on.all()
    assert np.all(df["P_ext"][on] < 0) and np.all(df["P_ext"][~on] == 0)
    assert np.all(df["vx_D"][on] > 0)
    # without masses or forces --dynamics is a one-line error, exit 2
    capsys.readouterr()
    assert main(["compute", str(WORKBOOKS / "fourbar.toml"), "--dynamics"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--dynamics needs [[mass]]" in err and "\n" not in err


# --------------------------------------------------------------------------- the workbook
@pytest.fixture(scope="module")
def dyn_books(soffice, tmp_path_factory):
    src = tmp_path_factory.mktemp("dyn")
    made = {}

    def make(key, text, **kw):
        scene = parse_scene(text, f"{key}.toml")
        path = src / f"{key}.xlsx"
        write_workbook(scene, path, scene_text=text, **kw)
        made[key] = (path, scene)
        return path

    make("shaper_dynamics", (WORKBOOKS / "shaper_dynamics.toml").read_text(encoding="utf-8"), lang="en")
    make("lone_crank", with_dynamics(LONE_CRANK, mass(1, 3.0, 0.04, "S1")))
    make("six_bar", with_dynamics(SIX_BAR, mass(2, 1.0, 0.01, "A") + mass(3, 2.0, 0.02, "C") + mass(5, 2.5, 0.03, "D")
                                  + '[[force]]\nlink = 4\nat = "S4"\nforce = [10.0, -80.0]\nmoment = -3.0\n'
                                  + '[[force]]\nlink = 3\nmoment = 2.0\nfrom_deg = 100.0\nto_deg = 300.0\n',
                                  (0.3, -9.81)))
    make("offset_chain", with_dynamics(OFFSET_CHAIN, mass(2, 0.3, 0.0001, "A") + mass(3, 4.0, 0.12, "C")
                                       + mass(5, 9.0, 0.0, "D")
                                       + '[[force]]\nlink = 5\nat = "D"\nforce = [-400.0, 25.0]\n'
                                       + 'from_deg = 20.0\nto_deg = 200.0\n'))
    # loads without masses (no energy rows), masses without gravity (no potential energy)
    make("forces_only", (WORKBOOKS / "fourbar.toml").read_text(encoding="utf-8")
         + '\n[[force]]\nlink = 3\nat = "B"\nforce = [10.0, -50.0]\n'
         + '[[force]]\nname = "M"\nlink = 2\nmoment = 3.0\nfrom_deg = 0.0\nto_deg = 90.0\n')
    make("no_gravity", with_dynamics(CRANK_SLIDER, mass(2, 1.5, 0.01, "A") + mass(3, 12.0, 0.0, "B"), None))
    text = (WORKBOOKS / "shaper_dynamics.toml").read_text(encoding="utf-8")
    live = make("live", text)
    set_input(live, "m_5", 55.0)
    set_input(live, "Fx_cut", -2100.0)
    set_input(live, "to_cut", 170.0)
    out = recalculate([p for p, _ in made.values()], tmp_path_factory.mktemp("dyn_recalculated"))
    return {key: (openpyxl.load_workbook(out[p.resolve()], data_only=True).worksheets[0], scene, p)
            for key, (p, scene) in made.items()}


@pytest.mark.parametrize("key", ["shaper_dynamics", "lone_crank", "six_bar", "offset_chain", "forces_only",
                                 "no_gravity"])
def test_workbook_dynamics_rows_equal_compute(dyn_books, key):
    ws, scene, _ = dyn_books[key]
    compare_dynamics(ws, scene, sheetkin.compute(scene, dynamics=True))
    rows = rows_of(ws)
    must = ["chk_balance"] + [f"chk_eq_{k}" for k in range(1, 2 + 2 * len(scene.groups))]
    must += ["chk_P_in"] + [f"chk_{q}_{m.link}" for m in scene.masses for q in ("T", "Fi")] if scene.masses else []
    for chk in must:
        assert chk in rows and ws.cell(rows[chk], 4).value == 0, chk
    present = {n for n in rows if isinstance(n, str)}
    assert ("T" in present) == bool(scene.masses) and ("U" in present) == bool(scene.masses and any(scene.gravity))
    assert ws["D3"].value.startswith(("all checks pass", "все проверки выполнены"))


def test_workbook_dynamics_is_live(dyn_books):
    """The ram's mass and the cutting force edited in the input block: every row follows."""
    import dataclasses
    ws, scene, _ = dyn_books["live"]
    masses = tuple(dataclasses.replace(m, mass=55.0) if m.link == 5 else m for m in scene.masses)
    forces = (dataclasses.replace(scene.forces[0], force=(-2100.0, 0.0), interval_deg=(-10.0, 170.0)),)
    changed = dataclasses.replace(scene, masses=masses, forces=forces)
    df = sheetkin.compute(changed, dynamics=True)
    assert not np.allclose(df["M_bal"], sheetkin.compute(scene, dynamics=True)["M_bal"])
    compare_dynamics(ws, changed, df)
    assert ws["D3"].value.startswith("все проверки выполнены")


def test_validator_names_a_wrong_reaction(tmp_path):
    """A reaction's sign flipped: the validator names it as the cause and blames nothing else
    (its magnitude R_4_5 is still right); the sheet's equilibrium checks of both links fail."""
    from sheetkin.course.validator import validate
    text = (WORKBOOKS / "shaper_dynamics.toml").read_text(encoding="utf-8")
    path = tmp_path / "student.xlsx"
    write_workbook(parse_scene(text, "s.toml"), path, scene_text=text)
    wb = openpyxl.load_workbook(path)
    ws = wb.worksheets[0]
    r = rows_of(ws)["Ry_4_5"]
    for k in range(13):
        c = ws.cell(r, 5 + k)
        c.value = "=-(" + c.value[1:] + ")"
    wb.save(path)
    rep = validate(path)
    causes = [x.name for x in rep.rows if x.status == "wrong" and x.cause]
    assert causes == ["Ry_4_5"]
    wrong = {x.name for x in rep.rows if x.status == "wrong"}
    assert wrong == {"Ry_4_5"}
    assert {"chk_eq_4", "chk_eq_5"} <= set(rep.failing_checks)


def test_toggle_reactions_are_flagged_not_silent(tmp_path, capsys):
    """At the change point the dyad's determinant is 0: the reactions are undefined there
    and grow without bound near it; compute --dynamics says so, naming the angles. 1e-7 deg
    is within the dead-point band (docs/dead-points.md: the discriminant is 3e-18 of its
    terms, 0 in LibreOffice): the group does not assemble there, as in every spreadsheet."""
    path = tmp_path / "cp.toml"
    path.write_text(CHANGE_POINT, encoding="utf-8")
    assert main(["compute", str(path), "--dynamics", "--at", "1e-7", "--at", "0.001", "--at", "30",
                 "--format", "csv", "--allow-gaps"]) == 0
    out, err = capsys.readouterr()
    assert [x for x in err.splitlines() if "cannot assemble" in x]
    toggles = [x for x in err.splitlines() if "near a toggle" in x]
    assert len(toggles) == 1 and "0.001 deg" in toggles[0]
    scene = parse_scene(CHANGE_POINT)
    df = sheetkin.compute(scene, [0.001, 30.0], dynamics=True)
    assert df["R_1_2"][0] > 1e4 * df["R_1_2"][1]         # grows like 1/det near the toggle
    assert relative_balance(df).max() <= BALANCE_TOL       # and still balances at 1e-3 deg


def test_dynamics_charts_reference_the_rows():
    """Two more charts: M_bal with the powers, and every joint reaction's magnitude."""
    from sheetkin.sheet.workbook import build_workbook, built_fingerprint
    scene = sheetkin.load_scene(WORKBOOKS / "shaper_dynamics.toml")
    wb = build_workbook(scene)
    charts = built_fingerprint(wb)["charts"]
    assert len(charts) == 7          # with the mechanism drawn at a chosen position
    rows = rows_of(wb.worksheets[0])
    flat = " ".join(" ".join(c) for c in charts)
    for name in ["M_bal", "P_bal", "P_ext", "T_t"] + [f"R_{p.tag}" for p in reaction_pairs(scene)]:
        assert f"$E${rows[name]}:$Q${rows[name]}" in flat, name
