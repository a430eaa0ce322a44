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

import numpy as np

from sheetkin.groups import kind_of
from sheetkin.groups.motion import Loads, Motion, Pair

from .scene import Force, Scene
from .solver import Solution


def point_owners(scene: Scene) -> dict[str, int]:
    """The link a later group is hinged to when it uses a point as its joint.

    Frame points belong to link 0, the crank's joint to the crank, a [[point]] to its link.
    A dyad's new joint carries three links once a later group uses it; each kind says which
    of its links the pin belongs to (`pin_owner`: RRR the coupler, RRP the slider).
    """
    owner = {name: 0 for name in scene.frame}
    owner[scene.crank.joint] = 1
    for g in scene.groups:
        owner.update(kind_of(g).pin_owner(g))
    for p in scene.points:
        owner[p.name] = p.link
    return owner


def reaction_pairs(scene: Scene) -> list[Pair]:
    """Every pair's reaction, crank first, then each group's (J1 side, inner, J2 side)."""
    owner = point_owners(scene)
    pairs = [Pair(0, 1, scene.crank.pivot)]
    for g in scene.groups:
        pairs += kind_of(g).pairs(g, owner)
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
    loads = {k: Loads() for k in range(0, 2 + 2 * len(scene.groups))}   # 0: the frame
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
            reactions.update(kind_of(g).reactions(g, known, sol.links, loads, owner))
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
