"""Energy and force analysis of a solved mechanism (numpy, no I/O).

The lecture's last two sections (seed 003, "Energy analysis", "Dynamic analysis"): after
the kinematics, the kinematic characteristics of the links' centres of mass, their kinetic
and potential energy, the Newtonian (d'Alembert) inertia forces, the rates of change of the
energies; then the forces in the joints, "with the mandatory check of the energy balance".

Kinetostatics runs group by group from the last Assur group back to the crank: each dyad is
statically determinate (6 equilibrium equations, 6 unknown reaction components), so with the
loads of its two links known - inertia, gravity, external forces, and the reactions of the
groups attached to it later - its reactions follow in closed form; the reactions it exerts
on the links it hangs from are loads for the earlier groups. The crank's moment equation
about its pivot gives the balancing moment M_bal. The energy balance
    M_bal omega_1 + P_ext + P_g + P_in = 0,   P_g = -dU/dt,  P_in = -dT/dt,
is an identity (the principle of virtual power) that the kinetostatics does not use, so it
checks every reaction the crank's moment depends on.

Names (columns of `compute --dynamics`, rows of the workbook):
  T_k U_k          kinetic and potential energy of link k (J), for links with a [[mass]]
  Fix_k Fiy_k Mi_k inertia force -m a_S (N) at the centre of mass, inertia moment -J eps_k (N m)
  T U T_t U_t      total energies (J) and their time derivatives (W); U only with gravity,
                   all four only with masses
  P_ext            power of the external forces and moments (W)
  Rx_i_j Ry_i_j R_i_j   force of link i on link j (i < j, 0 = frame) in their joint (N)
  M_i_j            for a sliding pair: the couple of link i on link j (N m); its force acts
                   through the slider's joint (RRP: the new joint; RPR: the block's J1)
  M_bal P_bal      balancing moment on the crank (N m, + counterclockwise), its power (W)
  balance          M_bal omega_1 + P_ext - U_t - T_t (W): zero up to rounding
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .scene import Force, Group, Scene
from .solver import Motion, Solution, cramer, inverse_det


@dataclass(frozen=True)
class Pair:
    """A kinematic pair whose reaction is computed: the force of link i on link j."""
    i: int
    j: int
    joint: str          # where the force acts (for a sliding pair: the slider's joint)
    sliding: bool = False

    @property
    def tag(self) -> str:
        return f"{self.i}_{self.j}"


def point_owners(scene: Scene) -> dict[str, int]:
    """The link a later group is hinged to when it uses a point as its joint.

    Frame points belong to link 0, the crank's joint to the crank, a [[point]] to its link.
    A dyad's new joint carries three links once a later group uses it; the pin is taken to
    belong to the dyad's first link for RRR (the coupler) and to the slider for RRP.
    """
    owner = {name: 0 for name in scene.frame}
    owner[scene.crank.joint] = 1
    for g in scene.groups:
        if g.type == "RRR":
            owner[g.joints[1]] = g.links[0]
        elif g.type == "RRP":
            owner[g.joints[1]] = g.links[1]
    for p in scene.points:
        owner[p.name] = p.link
    return owner


def reaction_pairs(scene: Scene) -> list[Pair]:
    """Every pair's reaction, crank first, then each group's (J1 side, inner, J2 side)."""
    owner = point_owners(scene)
    pairs = [Pair(0, 1, scene.crank.pivot)]
    for g in scene.groups:
        a, b = g.links
        j1 = g.joints[0]
        if g.type == "RRR":
            pairs += [Pair(owner[j1], a, j1), Pair(a, b, g.joints[1]), Pair(owner[g.joints[2]], b, g.joints[2])]
        elif g.type == "RRP":
            pairs += [Pair(owner[j1], a, j1), Pair(a, b, g.joints[1]), Pair(0, b, g.joints[1], True)]
        else:
            pairs += [Pair(owner[j1], a, j1), Pair(a, b, j1, True), Pair(owner[g.joints[1]], b, g.joints[1])]
    return pairs


def dynamics_names(scene: Scene) -> list[str]:
    """The columns `dynamics` returns, in order (empty for a scene with no masses or forces)."""
    if not scene.has_dynamics:
        return []
    gravity = any(scene.gravity)
    names = []
    for m in scene.masses:
        k = m.link
        names += [f"T_{k}"] + ([f"U_{k}"] if gravity else []) + [f"Fix_{k}", f"Fiy_{k}", f"Mi_{k}"]
    if scene.masses:
        names += ["T"] + (["U"] if gravity else []) + ["T_t"] + (["U_t"] if gravity else [])
    names += ["P_ext"] if scene.forces else []
    for p in reaction_pairs(scene):
        names += [f"Rx_{p.tag}", f"Ry_{p.tag}", f"R_{p.tag}"] + ([f"M_{p.tag}"] if p.sliding else [])
    return names + ["M_bal", "P_bal", "balance"]


def force_active(force: Force, phi_deg) -> np.ndarray:
    """1.0 where the crank angle is inside the force's interval (ends included), else 0.0."""
    phi = np.asarray(phi_deg, dtype=float)
    if force.interval_deg is None:
        return np.ones_like(phi)
    lo, hi = force.interval_deg
    return ((phi - lo) % 360.0 <= hi - lo).astype(float)


@dataclass
class _Loads:
    """Forces (x, y, fx, fy) and couples acting on one link, all arrays over positions."""
    forces: list = field(default_factory=list)
    couple: object = 0.0

    def add(self, at: Motion, fx, fy):
        self.forces.append((at.x, at.y, fx, fy))

    def resultant(self):
        return sum(f[2] for f in self.forces) + 0.0, sum(f[3] for f in self.forces) + 0.0

    def moment(self, px, py):
        """Moment about (px, py), counterclockwise positive."""
        return self.couple + sum((x - px) * fy - (y - py) * fx for x, y, fx, fy in self.forces)


def _cross(dx, dy, fx, fy):
    return dx * fy - dy * fx


def dynamics(scene: Scene, sol: Solution) -> dict[str, np.ndarray]:
    """Energies, inertia forces, joint reactions and the balancing moment at every position
    of a Solution (see the module's docstring for the names)."""
    if not scene.has_dynamics:
        return {}
    n = sol.phi1_deg.shape
    zero = np.zeros(n)
    gx, gy = scene.gravity
    gravity = bool(gx or gy)
    out: dict[str, np.ndarray] = {}
    loads = {k: _Loads() for k in range(0, 2 + 2 * len(scene.groups))}   # 0: the frame
    t_sum, u_sum, t_rate, u_rate = zero, zero, zero, zero
    for m in scene.masses:
        k, s, rot = m.link, sol.points.get(m.centre) or _frame_point(scene, m.centre, n), sol.links[m.link]
        w, e = rot.omega + zero, rot.eps + zero
        t = 0.5 * m.mass * (s.vx * s.vx + s.vy * s.vy) + 0.5 * m.inertia * w * w
        out[f"T_{k}"] = t
        # U = -m g.r (zero at the origin); dT/dt = m v.a + J omega eps; dU/dt = -m g.v
        if gravity:
            out[f"U_{k}"] = -m.mass * (gx * s.x + gy * s.y) + zero
            u_sum = u_sum + out[f"U_{k}"]
            u_rate = u_rate - m.mass * (gx * s.vx + gy * s.vy)
        fix, fiy, mi = -m.mass * s.ax + zero, -m.mass * s.ay + zero, -m.inertia * e
        out[f"Fix_{k}"], out[f"Fiy_{k}"], out[f"Mi_{k}"] = fix, fiy, mi
        t_sum = t_sum + t
        t_rate = t_rate + m.mass * (s.vx * s.ax + s.vy * s.ay) + m.inertia * w * e
        loads[k].add(s, fix + m.mass * gx, fiy + m.mass * gy)
        loads[k].couple = loads[k].couple + mi
    out["T"] = t_sum
    if gravity:
        out["U"] = u_sum
    out["T_t"] = t_rate
    if gravity:
        out["U_t"] = u_rate
    if scene.forces:
        p_ext = zero
        for f in scene.forces:
            on = force_active(f, sol.phi1_deg)
            fx, fy, mz = f.force[0] * on, f.force[1] * on, f.moment * on
            p_ext = p_ext + mz * sol.links[f.link].omega
            if f.at is not None:
                at = sol.points.get(f.at) or _frame_point(scene, f.at, n)
                loads[f.link].add(at, fx, fy)
                p_ext = p_ext + fx * at.vx + fy * at.vy
            loads[f.link].couple = loads[f.link].couple + mz
        out["P_ext"] = p_ext

    known = dict(sol.points)
    known.update({name: _frame_point(scene, name, n) for name in scene.frame})
    owner = point_owners(scene)
    reactions: dict[str, tuple] = {}
    # at a toggle the determinant is 0: the reactions come out inf/NaN there, as the
    # kinematics' rates do (compute flags those positions)
    with np.errstate(divide="ignore", invalid="ignore"):
        for g in reversed(scene.groups):
            reactions.update(_group_reactions(g, known, sol, loads, owner))
    # the crank: R_0_1 balances everything on it; the moment about the pivot gives M_bal
    o = known[scene.crank.pivot]
    fx, fy = loads[1].resultant()
    reactions["0_1"] = (-fx + zero, -fy + zero, None)
    m_bal = -loads[1].moment(o.x, o.y) + zero
    for p in reaction_pairs(scene):
        rx, ry, mc = reactions[p.tag]
        out[f"Rx_{p.tag}"], out[f"Ry_{p.tag}"], out[f"R_{p.tag}"] = rx, ry, np.hypot(rx, ry)
        if p.sliding:
            out[f"M_{p.tag}"] = mc
    out["M_bal"] = m_bal
    out["P_bal"] = m_bal * sol.links[1].omega
    out["balance"] = out["P_bal"] + out.get("P_ext", 0.0) - u_rate - t_rate
    return {name: out[name] for name in dynamics_names(scene)}


def _frame_point(scene: Scene, name: str, shape) -> Motion:
    x, y = scene.frame[name]
    z = np.zeros(shape)
    return Motion(x + z, y + z, z, z, z, z)


def _group_reactions(g: Group, known, sol: Solution, loads, owner) -> dict[str, tuple]:
    """One dyad's reactions from its links' loads; adds what it exerts on earlier links to
    their loads. Returns {pair tag: (Rx, Ry, couple or None)}, forces of i on j."""
    a, b = g.links
    la, lb = loads[a], loads[b]
    fax, fay = la.resultant()
    fbx, fby = lb.resultant()
    fx, fy = fax + fbx, fay + fby
    j1 = known[g.joints[0]]
    if g.type == "RRR":
        # a: R1 + X + Fa = 0, (J1 - N) x R1 + Ma(N) = 0; b: R2 - X + Fb = 0,
        # (J2 - N) x R2 + Mb(N) = 0. With R2 = -F - R1 both moment equations are in R1.
        nj, j2 = known[g.joints[1]], known[g.joints[2]]
        d1x, d1y, d2x, d2y = j1.x - nj.x, j1.y - nj.y, j2.x - nj.x, j2.y - nj.y
        m11, m12, m21, m22 = -d1y, d1x, -d2y, d2x
        _, inv = inverse_det(m11, m12, m21, m22)     # zero at the toggle, as the kinematics'
        r1x, r1y = cramer(m11, m12, m21, m22, -la.moment(nj.x, nj.y),
                          lb.moment(nj.x, nj.y) - _cross(d2x, d2y, fx, fy), inv)
        r2x, r2y = -fx - r1x, -fy - r1y
        xx, xy = -r1x - fax, -r1y - fay           # force of b on a at N
        loads[owner[g.joints[0]]].add(j1, -r1x, -r1y)
        loads[owner[g.joints[2]]].add(j2, -r2x, -r2y)
        return {f"{owner[g.joints[0]]}_{a}": (r1x, r1y, None), f"{a}_{b}": (-xx, -xy, None),
                f"{owner[g.joints[2]]}_{b}": (r2x, r2y, None)}
    if g.type == "RRP":
        # a: R1 + X + Fa = 0, (J1 - N) x R1 + Ma(N) = 0; slider b: -X + Q n + Fb = 0 and its
        # guide couple Mq = -Mb(N). Along the guide u: R1.u = -F.u (Q n has no u part).
        nj = known[g.joints[1]]
        gam = np.radians(g.guide_angle_deg)
        ux, uy = np.cos(gam), np.sin(gam)
        d1x, d1y = j1.x - nj.x, j1.y - nj.y
        m11, m12, m21, m22 = ux, uy, -d1y, d1x
        _, inv = inverse_det(m11, m12, m21, m22)     # zero when the coupler is across the guide
        r1x, r1y = cramer(m11, m12, m21, m22, -(fx * ux + fy * uy), -la.moment(nj.x, nj.y), inv)
        q = (r1x + fx) * uy - (r1y + fy) * ux     # -(R1 + F).n with n = (-uy, ux)
        xx, xy = -r1x - fax, -r1y - fay
        loads[owner[g.joints[0]]].add(j1, -r1x, -r1y)
        return {f"{owner[g.joints[0]]}_{a}": (r1x, r1y, None), f"{a}_{b}": (-xx, -xy, None),
                f"0_{b}": (-q * uy, q * ux, -lb.moment(nj.x, nj.y))}
    # RPR: block a on J1, slotted lever b about J2, slot direction e, normal n. The lever
    # acts on the block with P n through J1 and a couple C: block: R1 + P n + Fa = 0,
    # C + Ma(J1) = 0; lever about J2: (J1 - J2) x (-P n) - C + Mb(J2) = 0, R2 - P n + Fb = 0.
    j2 = known[g.joints[1]]
    rot = sol.links[b]
    nx, ny = -rot.s, rot.c
    c = -la.moment(j1.x, j1.y)
    p = (lb.moment(j2.x, j2.y) - c) / _cross(j1.x - j2.x, j1.y - j2.y, nx, ny)   # /s: 0 at the pivot
    r1x, r1y = -p * nx - fax, -p * ny - fay
    r2x, r2y = p * nx - fbx, p * ny - fby
    loads[owner[g.joints[0]]].add(j1, -r1x, -r1y)
    loads[owner[g.joints[1]]].add(j2, -r2x, -r2y)
    return {f"{owner[g.joints[0]]}_{a}": (r1x, r1y, None), f"{a}_{b}": (-p * nx, -p * ny, -c),
            f"{owner[g.joints[1]]}_{b}": (r2x, r2y, None)}
