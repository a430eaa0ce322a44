"""Every group kind in sheetkin.groups.KINDS, against checks that are not the kind's own code.

Per case of tests/helpers/kinds.py (each kind, a guide on a moving link, a kulisa about a moving axis,
a three-group chain):
  * the loop-closure equations (the kind's `loop`, used by Newton and the mpmath reference)
    hold at the closed form's answer, and so do their differentiated forms with the
    closed form's rates: the Cramer systems' residuals;
  * the 50-digit mpmath solution of those equations (sheetkin.studies.bench.reference_mp) equals
    `compute`, and so does Newton (the bench's method);
  * 8th-order central differences of the positions in the crank angle equal the velocities,
    and of the velocities the accelerations (with the crank's epsilon);
  * kept distances and points on their lines, written out here;
  * the kinetostatics balances the energy (M_bal omega + P_ext - dU/dt - dT/dt = 0), which
    the group-by-group reactions do not use;
  * the workbook, recalculated by LibreOffice (one batched run), equals `compute` in every
    contract row and every dynamics row, and all its checks pass.
"""
from __future__ import annotations

import contextlib
import math
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from helpers.kinds import CASES, DYNAMICS, check_derivatives, check_geometry, check_loop, check_reference
from helpers.libreoffice import recalculate
from helpers.sheetrows import compare_accepted, compare_dynamics, relative_balance, rows_of
from hypothesis import given, settings
from hypothesis import strategies as st

import sheetkin
from sheetkin.course.grades import all_correct
from sheetkin.groups import KINDS
from sheetkin.groups.group import Guide
from sheetkin.kinematics.scene import SceneError, parse_scene
from sheetkin.kinematics.table import AssemblyError
from sheetkin.sheet.workbook import write_workbook
from sheetkin.studies.bench import errors, method_newton, reference_mp

SURFACE = ["KIND", "LECTURE", "SLIDES", "TITLE", "KEYS", "Params", "parse", "needs", "on_links", "new_joints",
           "carries", "sliders", "solve", "input_rows", "with_inputs", "rows", "pin_owner", "pairs", "reactions",
           "reaction_rows", "loop", "side_ok", "discriminant", "unknowns", "fourbar", "STABILITY"]
ANGLES = [0.0, 17.0, 95.5, 181.0, 263.25, 333.0]
WORKBOOKS_DIR = Path(__file__).resolve().parents[2] / "workbooks"


def scene_of(case: str):
    return parse_scene(CASES[case][1], f"{case}.toml")


@pytest.mark.parametrize("kind", list(KINDS))
def test_every_kind_module_has_the_whole_surface(kind):
    mod = KINDS[kind]
    missing = [name for name in SURFACE if not hasattr(mod, name)]
    assert not missing, f"{kind}: missing {missing}"
    assert kind == mod.KIND and {"type", "links"} <= set(mod.KEYS)


@pytest.mark.parametrize("kind", list(KINDS))
def test_every_kind_has_a_case(kind):
    assert any(k == kind for k, _ in CASES.values()) or any(
        g.type == kind for case in CASES for g in scene_of(case).groups), \
        f"no case in tests/helpers/kinds.py for {kind}"


def test_an_unknown_type_lists_every_kind():
    text = CASES["rrr_fourbar"][1].replace('type    = "RRR"', 'type    = "RRX"')
    with pytest.raises(SceneError) as e:
        parse_scene(text, "x.toml")
    assert all(k in str(e.value) for k in KINDS) and "\n" not in str(e.value)


# --------------------------------------------------------------------------- closed form
@pytest.mark.parametrize("case", list(CASES))
def test_loop_equations_and_cramer_residuals_vanish_at_the_closed_form(case):
    check_loop(scene_of(case), ANGLES)


@pytest.mark.parametrize("case", list(CASES))
def test_distances_are_kept_and_sliders_stay_on_their_lines(case):
    """Written out in tests/helpers/kinds.py from the contract, not from the kinds' code."""
    check_geometry(scene_of(case), ANGLES)


# --------------------------------------------------------------------------- independent solutions
@pytest.mark.parametrize("case", list(CASES))
def test_mpmath_reference_and_newton_equal_compute(case):
    scene = scene_of(case)
    check_reference(scene, ANGLES)
    # Newton warm-starts from the previous position: a revolution in 10 deg steps
    steps = np.arange(0.0, 360.0, 10.0)
    newton = method_newton(scene, steps)
    assert not newton.failures
    assert max(errors(newton.values, reference_mp(scene, steps, dps=20)).values()) < 1e-10


@pytest.mark.parametrize("case", list(CASES))
def test_velocities_and_accelerations_are_derivatives_of_the_positions(case):
    check_derivatives(scene_of(case), ANGLES)


# --------------------------------------------------------------------------- kinetostatics
@pytest.mark.parametrize("case", list(DYNAMICS))
def test_kinetostatics_balances_the_energy(case):
    scene = parse_scene(DYNAMICS[case][1], f"{case}.toml")
    sol = sheetkin.solve(scene, np.arange(0.0, 360.0, 7.5))
    from sheetkin.kinematics.dynamics import dynamics
    d = dynamics(scene, sol)
    assert relative_balance(d, scene, sol).max() <= 1e-9


# --------------------------------------------------------------------------- chains
def test_a_point_used_before_it_is_known_is_refused_naming_both():
    text = CASES["rrp_two_rockers"][1].replace('joints  = ["A", "B", "O1"]', 'joints  = ["A", "B", "D"]')
    with pytest.raises(SceneError) as e:
        parse_scene(text, "chain.toml")
    msg = str(e.value)
    assert "'D'" in msg and "group 1 (RRR A-B-D)" in msg and "group 2 (RRP O2-D)" in msg and "\n" not in msg
    # a [[point]] on a link placed only later
    text = CASES["chain_three_groups"][1].replace('joints = ["F", "G"]', 'joints = ["H", "G"]').replace(
        'joints = ["A", "E"]', 'joints = ["H", "E"]') + '[[point]]\nname = "H"\nlink = 7\nfrom = "G"\nalong = 0.1\n'
    with pytest.raises(SceneError) as e:
        parse_scene(text, "chain.toml")
    assert "'H'" in str(e.value) and "group 2 (RPR H-E)" in str(e.value) and "[[point]] 'H' on link 7" in str(e.value)


def test_a_moving_guide_passes_through_a_point_of_its_link():
    text = CASES["rrp_two_rockers"][1].replace('through = "O1", angle_deg = 0.0, link = 3',
                                               'through = "A", angle_deg = 0.0, link = 3')
    with pytest.raises(SceneError) as e:
        parse_scene(text, "two.toml")
    assert "guide.through" in str(e.value) and "'A' is not a point of link 3" in str(e.value)
    text = CASES["rrp_two_rockers"][1].replace('through = "O1", angle_deg = 0.0, link = 3',
                                               'through = [0.0, 0.0], link = 3')
    with pytest.raises(SceneError, match="guide.through"):
        parse_scene(text, "two.toml")
    text = CASES["rrp_two_rockers"][1].replace('link = 3 }', 'link = 5 }')
    with pytest.raises(SceneError, match="link 5 is not placed before group 2"):
        parse_scene(text, "two.toml")


def test_two_groups_may_not_define_the_same_slide():
    text = CASES["rpr_slotted_lever"][1] + '\n[[group]]\ntype = "RPR"\nlinks = [4, 5]\njoints = ["A", "C"]\n'
    with pytest.raises(SceneError, match="already defines the slide of 'A' .s_A."):
        parse_scene(text, "x.toml")


# --------------------------------------------------------------------------- the workbook
@pytest.fixture(scope="module")
def group_books(soffice, tmp_path_factory):
    """Every dynamics case's workbook, recalculated in one LibreOffice run."""
    src = tmp_path_factory.mktemp("groups")
    made = {}
    for case, (_, text) in DYNAMICS.items():
        scene = parse_scene(text, f"{case}.toml")
        path = src / f"{case}.xlsx"
        write_workbook(scene, path, scene_text=text, lang="en")
        made[case] = (path, scene)
    out = recalculate([p for p, _ in made.values()], tmp_path_factory.mktemp("groups_recalculated"))
    return {case: (openpyxl.load_workbook(out[p.resolve()], data_only=True).worksheets[0], scene)
            for case, (p, scene) in made.items()}


@pytest.mark.parametrize("case", list(DYNAMICS))
def test_libreoffice_recalculation_equals_compute(group_books, case):
    ws, scene = group_books[case]
    df = sheetkin.compute(scene, dynamics=True)
    compare_accepted(ws, scene, df)
    compare_dynamics(ws, scene, df)
    rows = rows_of(ws)
    failing = [n for n, r in rows.items() if isinstance(n, str) and n.startswith("chk_") and ws.cell(r, 4).value != 0]
    assert not failing and ws["D3"].value.startswith("all checks pass"), failing


# --------------------------------------------------------------------------- invariance
def _moved(scene, k: float, theta_deg: float, shift):
    """The scene turned by theta about the origin, scaled by k and shifted: the same
    mechanism elsewhere and of another size (only what is in the scene changes)."""
    import dataclasses
    th = math.radians(theta_deg)
    rot = lambda p: (k * (p[0] * math.cos(th) - p[1] * math.sin(th)) + shift[0],
                     k * (p[0] * math.sin(th) + p[1] * math.cos(th)) + shift[1])
    frame = {n: rot(p) for n, p in scene.frame.items()}
    groups = []
    for g in scene.groups:
        p = g.params
        changes = {}
        def guide(v):
            return v if v.moving else dataclasses.replace(v, point=rot(v.point), angle_deg=v.angle_deg + theta_deg)

        for f in dataclasses.fields(p):
            v = getattr(p, f.name)
            if isinstance(v, Guide):
                changes[f.name] = guide(v)
            elif isinstance(v, tuple) and v and all(isinstance(x, Guide) for x in v):
                changes[f.name] = tuple(guide(x) for x in v)
            elif f.name in ("lengths",):
                changes[f.name] = tuple(k * x for x in v)
            elif f.name in ("length", "offset"):
                changes[f.name] = k * v
            elif f.name.endswith("_deg"):          # an absolute angle (RPP's slot_angle_deg)
                changes[f.name] = v + theta_deg
        groups.append(dataclasses.replace(g, params=dataclasses.replace(p, **changes)))
    points = tuple(dataclasses.replace(q, along=k * q.along, across=k * q.across) for q in scene.points)
    crank = dataclasses.replace(scene.crank, length=k * scene.crank.length, phi0_deg=scene.crank.phi0_deg + theta_deg)
    by_index, by_name = {g.index: g for g in groups}, {q.name: q for q in points}
    plan = tuple((kk, crank if kk == "crank" else by_index[it.index] if kk == "group" else by_name[it.name])
                 for kk, it in scene.plan)
    return dataclasses.replace(scene, frame=frame, crank=crank, groups=tuple(groups), points=points, plan=plan)


@pytest.mark.parametrize("case", list(CASES))
@settings(max_examples=15, deadline=None, database=None)
@given(k=st.floats(0.01, 100.0), theta=st.floats(-180.0, 180.0),
       shift=st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)))
def test_the_same_mechanism_elsewhere_and_of_another_size(case, k, theta, shift):
    """Turned, scaled and moved: positions follow, slides scale by k, link angles turn by
    theta, angular rates stay, and the toggle measure does not change (scale-invariant)."""
    scene = scene_of(case)
    moved = _moved(scene, k, theta, shift)
    a, b = sheetkin.compute(scene), sheetkin.compute(moved)
    for col in a.columns:
        head = col.split("_")[0]
        if head in ("det",):
            assert np.allclose(a[col], b[col], rtol=1e-9, atol=1e-12), col
        elif head in ("omega", "eps"):
            assert np.allclose(a[col], b[col], rtol=1e-8, atol=1e-9), col
        elif head in ("s", "vs", "as", "v", "a"):
            assert np.allclose(k * a[col], b[col], rtol=1e-8, atol=1e-9 * k), col
        elif head == "phi":
            d = (b[col] - a[col] - theta) % 360.0
            assert np.all(np.minimum(d, 360.0 - d) < 1e-7), col


# --------------------------------------------------------------------------- fuzzing the group keys
def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v) if math.isfinite(v) else ("nan" if v != v else ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"


_atoms = st.one_of(st.integers(-3, 9), st.floats(allow_nan=True, allow_infinity=True), st.booleans(),
                   st.sampled_from(["O", "O1", "A", "B", "D", "E", "Z", "", "1x"]))
_values = st.recursive(_atoms, lambda inner: st.one_of(
    st.lists(inner, max_size=3),
    st.dictionaries(st.sampled_from(["through", "angle_deg", "link", "x"]), inner, max_size=4)), max_leaves=6)


@settings(max_examples=150, deadline=None, database=None)
@given(case=st.sampled_from(["rrp_two_rockers", "rpr_moving_axis", "rrr_fourbar", "prp_slider_on_coupler",
                             "rpp_scotch_yoke"]),
       key=st.sampled_from(["joints", "length", "lengths", "guide", "branch", "offset", "links", "type", "extra",
                            "guides", "slot_angle_deg"]),
       value=_values, drop=st.booleans())
def test_only_scene_errors_come_out_of_a_mangled_group(case, key, value, drop):
    """Any value (or none) for any key of the last group: a one-line SceneError, or a scene
    that computes (or cannot assemble: AssemblyError), never a traceback of ours."""
    text = CASES[case][1]
    head, _, last = text.rpartition("[[group]]")
    lines = [ln for ln in last.splitlines() if ln.split("=")[0].strip() != key]
    if not drop:
        lines.insert(1, f"{key} = {_toml_value(value)}")
    mangled = head + "[[group]]" + "\n".join(lines) + "\n"
    try:
        scene = parse_scene(mangled, "fuzz.toml")
    except SceneError as e:
        assert "\n" not in str(e) and str(e).startswith("fuzz.toml")
        return
    with contextlib.suppress(AssemblyError):
        sheetkin.compute(scene)


# --------------------------------------------------------------------------- the documentation
def _doc_section(kind: str) -> str:
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "docs" / "scene-format.md").read_text(encoding="utf-8")
    start = text.index(f"### {kind}")
    end = text.find("\n### ", start + 1)
    return text[start:end if end > 0 else None]


@pytest.mark.parametrize("kind", list(KINDS))
def test_every_kind_and_key_is_documented_for_students(kind):
    """docs/scene-format.md has a section per kind that names every one of its keys and
    its slides' output names."""
    section = _doc_section(kind)
    missing = [k for k in KINDS[kind].KEYS if f"`{k}" not in section and f"{k} " not in section]
    assert not missing, f"docs/scene-format.md, {kind}: keys not documented: {missing}"


# --------------------------------------------------------------------------- the validator
@pytest.mark.parametrize("stem, inputs, broken", [
    ("two_rockers_slotted", {"gamma_g2": 4.0, "L4": 0.31, "branch_g2": 1}, "vs_D"),
    ("kulisa_moving_axis", {"e_g2": 0.02, "along_E": 0.22}, "omega_5"),
    ("slider_on_coupler", {"gamma2_g2": 80.0, "gx2_g2": -0.12}, "vs2_L"),     # PRP: the fixed guide
    ("scotch_yoke", {"alpha_g1": 75.0, "gy_g1": 0.01}, "vs_A"),              # RPP: slot and guide
    ("three_group_chain", {"gamma1_g3": 10.0, "gamma2_g3": 40.0, "alpha_g2": 55.0}, "as2_N"),
])
def test_validator_takes_a_students_variant_and_names_a_broken_row(tmp_path, stem, inputs, broken):
    """A student's own inputs (the guide's angle on the moving rocker, a length, the
    branch; the kulisa's offset and its moving axis) are a variant, not mistakes, when the
    course grades the students' own data (--accept-changed-inputs); a formula broken in one
    column is named as the cause."""
    import functools
    import shutil

    from sheetkin.course.issued import Options
    from sheetkin.course.validator import validate
    validate = functools.partial(validate, options=Options(accept_changed=True))
    from helpers.sheetrows import set_input
    path = tmp_path / f"{stem}.xlsx"
    shutil.copy(WORKBOOKS_DIR / f"{stem}.xlsx", path)
    for name, value in inputs.items():
        set_input(path, name, value)
    report = validate(path)
    assert all_correct(report), [w.name for w in report.wrong]
    wb = openpyxl.load_workbook(path)
    ws = wb.worksheets[0]
    cell = ws.cell(rows_of(ws)[broken], 7)
    cell.value = "=-(" + cell.value[1:] + ")"
    wb.save(path)
    report = validate(path)
    assert not all_correct(report) and [w.name for w in report.causes] == [broken]
