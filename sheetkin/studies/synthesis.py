"""Synthesis of a crank-rocker four-bar from the time-ratio coefficient (seed 002).

Given the time-ratio coefficient K_w (overlap angle theta = pi (K_w - 1)/(K_w + 1)), the
rocker length l3, the rocker pivot's ordinate Y_D and the rocker's extreme angles gamma1 <
gamma2, find the crank l1, the coupler l2, the crank angle phi1H of the extended dead position
and the pivot's abscissa X_D from the four projection equations of the seed (crank pivot O at
the origin, B = D + l3 (cos gamma, sin gamma)):

    (l1 + l2) cos(phi1H)         = X_D + l3 cos(gamma1)
    (l1 + l2) sin(phi1H)         = Y_D + l3 sin(gamma1)
    (l2 - l1) cos(phi1H + theta) = X_D + l3 cos(gamma2)
    (l2 - l1) sin(phi1H + theta) = Y_D + l3 sin(gamma2)

Solved in closed form: with R1 = l1 + l2, R2 = l2 - l1, a = Y_D + l3 sin gamma1,
b = Y_D + l3 sin gamma2, c = l3 (cos gamma1 - cos gamma2), eliminating R1, R2 and X_D gives
a cot(phi) - b cot(phi + theta) = c, i.e. with psi = 2 phi + theta

    (a - b) sin(psi) + c cos(psi) = c cos(theta) - (a + b) sin(theta),

one harmonic equation; for each root phi the equations are linear in (R1, R2, X_D).
The crank turns counterclockwise: from the extended dead position (rocker at gamma1) it turns
180 + theta degrees to the folded one (rocker at gamma2), the working stroke, and 180 - theta
back, so K_w = (180 + theta) / (180 - theta).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sheetkin.errors import InputError

SYNTHESIS_KEYS = ("kw", "l3", "yd", "gamma1_deg", "gamma2_deg")   # a scene's [synthesis] table
# the title of a synthesized scene, in the language of the book it becomes (the book's title)
_SCENE_TITLE = {"ru": "Кривошипно-коромысловый механизм, синтезированный по K_w = {kw:g}",
                "uk": "Кривошипно-коромисловий механізм, синтезований за K_w = {kw:g}",
                "en": "Crank-rocker four-bar synthesized from K_w = {kw:g}"}


class SynthesisError(InputError):
    """Data with no crank-rocker solution; str() is one line naming the failed condition.
    `key` names the given datum at fault (a [synthesis] key: kw, l3, ...), if there is one."""

    def __init__(self, message: str, key: str | None = None):
        super().__init__(message)
        self.key = key


@dataclass(frozen=True)
class CrankRocker:
    """A synthesized crank-rocker four-bar (crank pivot O at the origin, rocker pivot D)."""
    kw: float
    l3: float
    yd: float
    gamma1_deg: float
    gamma2_deg: float
    theta_deg: float
    l1: float
    l2: float
    phi1H_deg: float
    X_D: float
    branch: int          # the scene's RRR branch: side of B relative to the directed line A->D

    def results(self) -> dict[str, float]:
        """The unknowns of the seed, under the names the CLI prints."""
        return {"l1": self.l1, "l2": self.l2, "phi1H_deg": self.phi1H_deg, "X_D": self.X_D}

    def synthesis_toml(self) -> str:
        """The scene's [synthesis] table: the data this mechanism was synthesized from
        (`sheetkin workbook` adds the synthesis sheet for them; parse_synthesis reads them)."""
        return ("[synthesis]            # the data this crank-rocker was synthesized from\n"
                + "".join(f"{k} = {float(getattr(self, k))!r}\n" for k in SYNTHESIS_KEYS))

    def scene_toml(self, omega: float = 10.0, positions: int = 13, step_deg: float = 30.0,
                   title: str | None = None, lang: str = "en") -> str:
        """A scene (docs/scene-format.md) ready for `compute` and `workbook`: frame O = (0, 0),
        D = (X_D, Y_D); crank O->A starting at phi1H (position 1 is the extended dead
        position); RRR group A-B-D on the branch that puts the rocker at gamma1 there; and the
        [synthesis] table with the given data."""
        title = title or _SCENE_TITLE.get(lang, _SCENE_TITLE["en"]).format(kw=self.kw)
        return (
            f'title = "{title}"\n'
            f"# sheetkin synth crank-rocker --kw {self.kw!r} --l3 {self.l3!r} --yd {self.yd!r} "
            f"--gamma1-deg {self.gamma1_deg!r} --gamma2-deg {self.gamma2_deg!r}\n"
            f"# theta = {self.theta_deg!r} deg; rocker extremes gamma1, gamma2 at crank angles "
            f"phi1H and phi1H + 180 + theta\n\n"
            f"{self.synthesis_toml()}\n"
            "[frame]\n"
            "O = [0.0, 0.0]\n"
            f"D = [{self.X_D!r}, {self.yd!r}]\n\n"
            "[crank]\n"
            'pivot = "O"\n'
            'joint = "A"\n'
            f"length = {self.l1!r}\n"
            f"phi0_deg = {self.phi1H_deg!r}\n"
            f"step_deg = {float(step_deg)!r}\n"
            f"positions = {int(positions)}\n"
            f"omega = {float(omega)!r}\n"
            "epsilon = 0.0\n\n"
            "[[group]]\n"
            'type = "RRR"\n'
            "links = [2, 3]\n"
            'joints = ["A", "B", "D"]\n'
            f"lengths = [{self.l2!r}, {self.l3!r}]\n"
            f"branch = {self.branch}\n"
            "# phi_2 = direction A->B, phi_3 = direction D->B (the rocker angle gamma)\n")


def overlap_angle_deg(kw: float) -> float:
    """theta = 180 (K_w - 1) / (K_w + 1), degrees."""
    return 180.0 * (kw - 1.0) / (kw + 1.0)


def _side(ax, ay, dx, dy, bx, by) -> float:
    return (dx - ax) * (by - ay) - (dy - ay) * (bx - ax)


def synthesize_crank_rocker(kw: float, l3: float, yd: float, gamma1_deg: float,
                            gamma2_deg: float) -> CrankRocker:
    """Solve the seed's four dead-position equations; refuse data with no crank-rocker."""
    for name, key, v in (("K_w", "kw", kw), ("l3", "l3", l3), ("Y_D", "yd", yd),
                         ("gamma1", "gamma1_deg", gamma1_deg), ("gamma2", "gamma2_deg", gamma2_deg)):
        if not math.isfinite(v):
            raise SynthesisError(f"{name} = {v}: expected a finite number", key)
    if kw < 1.0:
        raise SynthesisError(f"K_w = {kw:g} < 1: the time-ratio coefficient of a crank-rocker "
                             "(working stroke over return) is at least 1", "kw")
    if l3 <= 0:
        raise SynthesisError(f"l3 = {l3:g}: the rocker length must be positive", "l3")
    swing = gamma2_deg - gamma1_deg
    if swing <= 0:
        raise SynthesisError(f"gamma2 = {gamma2_deg:g} deg <= gamma1 = {gamma1_deg:g} deg: the "
                             "rocker's swing gamma2 - gamma1 must be positive", "gamma2_deg")
    if swing >= 180:
        raise SynthesisError(f"gamma2 - gamma1 = {swing:g} deg >= 180 deg: a rocker swings "
                             "less than half a turn", "gamma2_deg")
    theta_deg = overlap_angle_deg(kw)
    th, g1, g2 = math.radians(theta_deg), math.radians(gamma1_deg), math.radians(gamma2_deg)
    a = yd + l3 * math.sin(g1)
    b = yd + l3 * math.sin(g2)
    c = l3 * (math.cos(g1) - math.cos(g2))
    p, q = a - b, c
    r = c * math.cos(th) - (a + b) * math.sin(th)
    m = math.hypot(p, q)            # p sin(psi) + q cos(psi) = m cos(psi - beta)
    if m == 0 or abs(r) > m * (1 + 1e-12):
        raise SynthesisError("the dead-position equations have no solution for these data: no "
                             "four-bar has crank and coupler collinear at both rocker extremes "
                             f"with the overlap angle theta = {theta_deg:.6g} deg")
    beta = math.atan2(p, q)
    delta = math.acos(max(-1.0, min(1.0, r / m)))
    scale = max(l3, abs(yd), 1e-300)
    candidates = []
    for psi in (beta + delta, beta - delta):
        for k in (0, 1):
            phi = (psi - th) / 2 + k * math.pi
            # linear in (R1, R2, X_D): least squares, exact at a root
            mat = np.array([[math.cos(phi), 0.0, -1.0],
                            [math.sin(phi), 0.0, 0.0],
                            [0.0, math.cos(phi + th), -1.0],
                            [0.0, math.sin(phi + th), 0.0]])
            rhs = np.array([l3 * math.cos(g1), a, l3 * math.cos(g2), b])
            (r1, r2, xd), *_ = np.linalg.lstsq(mat, rhs, rcond=None)
            if np.max(np.abs(mat @ (r1, r2, xd) - rhs)) > 1e-9 * scale:
                continue
            candidates.append((float(r1), float(r2), float(xd), phi))
    # phi and phi + pi flip the signs of R1 and R2 together: keep the one with R1 = l1 + l2 > 0
    chosen: list[tuple[float, float, float, float]] = []
    for r1, r2, xd, phi in candidates:
        if r1 > 0 and not any(abs(r1 - u[0]) < 1e-12 * scale and abs(r2 - u[1]) < 1e-12 * scale
                              and abs(xd - u[2]) < 1e-12 * scale for u in chosen):
            chosen.append((r1, r2, xd, phi))
    if not chosen:
        raise SynthesisError("the dead-position equations give l1 + l2 <= 0 for these data: "
                             "no four-bar")
    uniq = [t for t in chosen if t[1] > 0 and t[0] > t[1]]
    if not uniq:
        r1, r2, _, _ = chosen[0]
        l1, l2 = (r1 - r2) / 2, (r1 + r2) / 2
        if l1 <= 0:
            raise SynthesisError(f"the dead-position equations give l1 = {l1:.6g} <= 0: no "
                                 "crank for these data")
        raise SynthesisError(f"the dead-position equations give l2 = {l2:.6g} <= l1 = {l1:.6g}"
                             ": the crank is longer than the coupler and cannot rotate fully")
    errors = []
    found = []
    for r1, r2, xd, phi in uniq:
        try:
            found.append(_check(kw, l3, yd, gamma1_deg, gamma2_deg, theta_deg, r1, r2, xd, phi))
        except SynthesisError as e:
            errors.append(str(e))
    if not found:
        raise SynthesisError(errors[0])
    # several: the one nearest the seed's initial guess (phi1H = 30 deg)
    return min(found, key=lambda s: abs(math.remainder(s.phi1H_deg - 30.0, 360.0)))


def _check(kw, l3, yd, gamma1_deg, gamma2_deg, theta_deg, r1, r2, xd, phi) -> CrankRocker:
    l1, l2 = (r1 - r2) / 2, (r1 + r2) / 2
    d = math.hypot(xd, yd)
    links = {"crank l1": l1, "coupler l2": l2, "rocker l3": l3, "frame OD": d}
    s_name = min(links, key=lambda name: links[name])
    s, big = links[s_name], max(links.values())
    if s_name != "crank l1" and links[s_name] < l1:
        raise SynthesisError(
            f"the crank is not the shortest link (l1 = {l1:.6g} > {s_name} = {s:.6g}): "
            "the crank cannot rotate fully, no crank-rocker")
    others = sum(links.values()) - s - big
    if s + big > others * (1 + 1e-12):
        raise SynthesisError(
            f"Grashof's condition violated: s + l = {s + big:.6g} > p + q = {others:.6g} "
            "(shortest + longest > sum of the other two): the crank cannot rotate fully")
    if s + big >= others * (1 - 1e-9):
        raise SynthesisError(
            f"Grashof's condition holds only with equality: s + l = p + q = {others:.6g}: "
            "a change-point mechanism, not a crank-rocker")
    # the RRR branch (B relative to A->D) must be the same in both dead positions
    g1, g2, th = math.radians(gamma1_deg), math.radians(gamma2_deg), math.radians(theta_deg)
    ax1, ay1 = l1 * math.cos(phi), l1 * math.sin(phi)
    bx1, by1 = xd + l3 * math.cos(g1), yd + l3 * math.sin(g1)
    ax2, ay2 = l1 * math.cos(phi + th + math.pi), l1 * math.sin(phi + th + math.pi)
    bx2, by2 = xd + l3 * math.cos(g2), yd + l3 * math.sin(g2)
    s1 = _side(ax1, ay1, xd, yd, bx1, by1)
    s2 = _side(ax2, ay2, xd, yd, bx2, by2)
    if s1 * s2 <= 0:
        raise SynthesisError("the extended and folded dead positions lie on different assembly "
                             "branches of the dyad A-B-D: the crank-rocker through gamma1 swings "
                             "to the mirror of gamma2, not to gamma2")
    phi_deg = math.degrees(phi) % 360.0
    return CrankRocker(kw=kw, l3=l3, yd=yd, gamma1_deg=gamma1_deg, gamma2_deg=gamma2_deg,
                       theta_deg=theta_deg, l1=l1, l2=l2, phi1H_deg=phi_deg, X_D=xd,
                       branch=1 if s1 > 0 else -1)


# --------------------------------------------------------------------------- the scene's table
def parse_synthesis(text: str, source: str = "<scene>") -> dict[str, float] | None:
    """The scene's [synthesis] table (the data its crank-rocker was synthesized from) as
    {kw, l3, yd, gamma1_deg, gamma2_deg}, or None if the scene has none. Raises SceneError,
    one line naming file, line and key, for a mistake in the scene, an unknown or missing
    key, a value that is not a number, data with no crank-rocker (K_w < 1, ...), or a scene
    whose first group is not the four-bar's dyad (an RRR from the crank's joint to a frame
    point), to which the synthesis sheet refers."""
    import tomllib

    from sheetkin.kinematics.scene import KeyLocator, SceneContext, SceneTable, parse_scene

    scene = parse_scene(text, source)          # the scene's own mistakes first
    data = tomllib.loads(text)
    if "synthesis" not in data:
        return None
    loc = KeyLocator(text)
    ctx = SceneContext(source, loc)
    tbl = SceneTable(ctx, data["synthesis"], "[synthesis]", "synthesis")
    if ("synthesis", 0) not in loc.tables:
        # an inline table `synthesis = {kw = ...}`: point at that line
        tbl.reporting_through(lambda key, msg: ctx.fail("[synthesis]", None, 0,
                                                        "synthesis" + (f".{key}" if key else ""), msg))
    tbl.check_keys(SYNTHESIS_KEYS)
    values = {k: tbl.get(k, "a number") for k in SYNTHESIS_KEYS}
    try:
        synthesize_crank_rocker(**values)
    except SynthesisError as e:
        tbl.fail(e.key, str(e) if e.key else f"no crank-rocker for these data: {e}")
    if fourbar_dyad(scene) is None:
        tbl.fail(None, "the data are a crank-rocker four-bar's, but the scene's first group is not "
                       f"an RRR dyad from the crank's joint {scene.crank.joint} to a frame point")
    return values


def fourbar_dyad(scene):
    """(coupler, rocker, the rocker's frame pivot, branch) of the four-bar the scene's first
    group closes with the crank (its kind's `fourbar`), or None: the synthesis sheet refers
    to that group."""
    from sheetkin.groups import kind_of
    g = scene.groups[0] if scene.groups else None
    return kind_of(g).fourbar(g, scene.crank.joint, scene.frame) if g else None


def scene_mismatches(scene, data: dict[str, float], tol: float = 1e-9) -> list[str]:
    """Where the scene's four-bar (crank, first group, frame points) differs by more than
    `tol` from the one its [synthesis] data give: the synthesis sheet's check rows comparing
    it with the kinematics sheet fail there. Empty for a scene written by `synth -o`."""
    m = synthesize_crank_rocker(**data)
    g, o = scene.groups[0], scene.crank.pivot
    l2, l3, d, branch = fourbar_dyad(scene)
    (ox, oy), (dx, dy) = scene.frame[o], scene.frame[d]
    pairs = [(f"L1 = {scene.crank.length:.9g}", scene.crank.length, "l1", m.l1),
             (f"L{g.links[0]} = {l2:.9g}", l2, "l2", m.l2),
             (f"L{g.links[1]} = {l3:.9g}", l3, "l3", m.l3),
             (f"x_{d} - x_{o} = {dx - ox:.9g}", dx - ox, "X_D", m.X_D),
             (f"y_{d} - y_{o} = {dy - oy:.9g}", dy - oy, "Y_D", m.yd),
             (f"branch = {branch:+d}", branch, "branch", m.branch)]
    return [f"{have_text} but the synthesis gives {name} = {want:.9g}"
            for have_text, have, name, want in pairs if not abs(have - want) <= tol]
