"""Hypothesis strategies: random assemblable instances of every group kind and of chains of
kinds, as scene text, for the property tests (tests/kinematics/test_properties.py).

Each kind's strategy is in its own section, in the contract's order (RRR, RRP, RPR, PRP,
RPP), then the chains; each builds its mechanism so that it assembles at the drawn crank
angles, away from its toggle (the constructions say how). STRATEGIES maps a name to a
strategy of (scene text, crank angles in degrees, length scale). The checks the property
tests apply to them are tests/helpers/kinds.py's (written out from the contract, not from the
kinds' code).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

import sheetkin


# --------------------------------------------------------------------------- plane vectors
def e(phi):
    """Unit vector at angle phi (radians)."""
    return np.array([np.cos(phi), np.sin(phi)])


def e_perp(phi):
    """e(phi) turned +90 deg, i.e. d e(phi) / d phi."""
    return np.array([-np.sin(phi), np.cos(phi)])


def cross(a, b):
    """z-component of a x b: positive when b points to the left of a."""
    return a[0] * b[1] - a[1] * b[0]


def angle_diff(a, b):
    """a - b wrapped to (-pi, pi], so that 359.9 deg and 0.1 deg are close."""
    d = np.asarray(a) - np.asarray(b)
    return np.arctan2(np.sin(d), np.cos(d))


# --------------------------------------------------------------------------- mechanisms
@dataclass
class PointSpec:
    """A [[point]]: `along` the link's direction from `origin`, `across` to its left."""
    name: str
    link: int
    origin: str
    along: float
    across: float


@dataclass
class Mechanism:
    """One random mechanism: crank O-A (link 1) and one dyad (links 2, 3).

    Joint names are fixed: crank pivot O, crank joint A; RRR: A-B-O1; RRP: coupler A-B,
    slider B on the guide through G; RPR: block on A, slotted lever about O1.
    """
    kind: str                       # "RRR", "RRP" or "RPR"
    frame: dict                     # name -> np.array([x, y])
    L1: float
    omega: float
    epsilon: float
    group: dict                     # the dyad's parameters (see the strategies)
    points: list
    angles: list                    # crank angles to test, degrees
    size: float                     # length scale for relative tolerances

    @property
    def toml(self) -> str:
        return scene_toml(self)

    def scene(self):
        return sheetkin.parse_scene(self.toml, source=f"<random {self.kind}>")

    @property
    def new_joints(self):
        return ["B"] if self.kind in ("RRR", "RRP") else []

    @property
    def sliders(self):
        return {"RRR": [], "RRP": ["B"], "RPR": ["A"]}[self.kind]

    @property
    def omega_scale(self):
        return abs(self.omega)

    @property
    def eps_scale(self):
        return self.omega ** 2 + abs(self.epsilon)


def fl(x) -> str:
    """A float as TOML: Python's repr is the shortest round-trip form and valid TOML."""
    return repr(float(x))


def scene_toml(m: Mechanism) -> str:
    out = [f'title = "random {m.kind}"', "", "[frame]"]
    out += [f"{name} = [{fl(p[0])}, {fl(p[1])}]" for name, p in m.frame.items()]
    out += ["", "[crank]", 'pivot = "O"', 'joint = "A"', f"length = {fl(m.L1)}",
            "phi0_deg = 0.0", "step_deg = 30.0", "positions = 13",
            f"omega = {fl(m.omega)}", f"epsilon = {fl(m.epsilon)}",
            "", "[[group]]", f'type = "{m.kind}"', "links = [2, 3]"]
    g = m.group
    if m.kind == "RRR":
        out += ['joints = ["A", "B", "O1"]', f"lengths = [{fl(g['L2'])}, {fl(g['L3'])}]",
                f"branch = {g['branch']}"]
    elif m.kind == "RRP":
        through = '"G"' if g["named_guide"] else f"[{fl(g['G'][0])}, {fl(g['G'][1])}]"
        out += ['joints = ["A", "B"]', f"length = {fl(g['L'])}",
                f"guide = {{ through = {through}, angle_deg = {fl(g['gamma_deg'])} }}",
                f"branch = {g['branch']}"]
    else:
        out += ['joints = ["A", "O1"]']
        if g["write_offset"]:          # else the spec's default offset 0 is exercised
            out += [f"offset = {fl(g['offset'])}"]
    for p in m.points:
        out += ["", "[[point]]", f'name = "{p.name}"', f"link = {p.link}", f'from = "{p.origin}"',
                f"along = {fl(p.along)}", f"across = {fl(p.across)}"]
    return "\n".join(out) + "\n"


def contract_columns(m: Mechanism) -> list[str]:
    """The spec's output columns, in the spec's order, written out independently."""
    cols = ["phi_1"] + [f"{q}_{k}" for k in (2, 3) for q in ("phi", "omega", "eps")]
    for p in ["A"] + m.new_joints + [p.name for p in m.points]:
        cols += [f"{q}_{p}" for q in ("x", "y", "vx", "vy", "v", "ax", "ay", "a")]
    for p in m.sliders:
        cols += [f"{q}_{p}" for q in ("s", "vs", "as")]
    return cols


# --------------------------------------------------------------------------- strategies
sizes = st.floats(-2.0, 1.0).map(lambda t: 10.0 ** t)      # 1 cm .. 10 m
signs = st.sampled_from([-1, 1])


def signed(lo, hi):
    return st.tuples(signs, st.floats(lo, hi)).map(lambda t: t[0] * t[1])


crank_angles = st.lists(st.floats(-360.0, 720.0), min_size=1, max_size=4)
omegas = signed(0.5, 50.0)
epsilons = signed(0.5, 500.0)          # never zero: the epsilon terms must be exercised


def draw_point(draw, name, link, origins, S):
    return PointSpec(name, link, draw(st.sampled_from(origins)),
                     S * draw(st.floats(-1.5, 1.5)), S * draw(st.floats(-1.5, 1.5)))


def mechanism_size(frame, lengths, points):
    return max([abs(c) for p in frame.values() for c in p] + list(lengths)
               + [abs(p.along) + abs(p.across) for p in points])


@st.composite
def fourbars(draw):
    """Crank + RRR dyad assembling over the whole revolution.

    Construction: with coupler L2 and rocker L3 fixed, the diagonal d = |A O1| and the
    transmission angle mu (at B) are tied by d^2 = L2^2 + L3^2 - 2 L2 L3 cos(mu). Choosing
    the range [mu_min, mu_max] inside [25, 155] deg fixes d_min, d_max; the crank sweeps
    d = |A O1| over [D - L1, D + L1], so D = (d_min + d_max)/2, L1 = (d_max - d_min)/2. The
    dyad then assembles at every crank angle with sin(mu) >= sin 25 deg (well-conditioned,
    both branches far apart).
    """
    S = draw(sizes)
    L2 = S
    L3 = S * draw(st.floats(0.4, 2.5))
    mu_min = draw(st.floats(25.0, 80.0))
    mu_max = draw(st.floats(mu_min + 15.0, 155.0))

    def diagonal(mu_deg):
        return math.sqrt(L2 * L2 + L3 * L3 - 2.0 * L2 * L3 * math.cos(math.radians(mu_deg)))

    d_min, d_max = diagonal(mu_min), diagonal(mu_max)
    D, L1 = 0.5 * (d_min + d_max), 0.5 * (d_max - d_min)
    O = S * np.array([draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0))])
    O1 = O + D * e(draw(st.floats(0.0, 2.0 * math.pi)))
    frame = {"O": O, "O1": O1}
    points = [draw_point(draw, "P2", 2, ["A", "B"], S), draw_point(draw, "P3", 3, ["O1", "B"], S)]
    return Mechanism("RRR", frame, L1, draw(omegas), draw(epsilons),
                     {"L2": L2, "L3": L3, "branch": draw(signs), "mu": (mu_min, mu_max)},
                     points, draw(crank_angles), mechanism_size(frame, [L1, L2, L3, D], points))


@st.composite
def crank_sliders(draw):
    """Crank + RRP dyad on a guide through G at a random angle, offset from the crank pivot.

    h(A), the signed distance of A from the guide, stays within |h(O)| + L1; a coupler
    L = (|h(O)| + L1) / rho with rho <= 0.85 keeps |h| / L <= 0.85, so it always assembles
    and the coupler never stands perpendicular to the guide.
    """
    S = draw(sizes)
    L1 = S
    O = S * np.array([draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0))])
    gamma_deg = draw(st.floats(-180.0, 360.0))
    u, n = e(math.radians(gamma_deg)), e_perp(math.radians(gamma_deg))
    h_O = S * draw(st.floats(-1.5, 1.5))            # O lies h_O to the left of the guide
    G = O - h_O * n + S * draw(st.floats(-2.0, 2.0)) * u
    L = (abs(h_O) + L1) / draw(st.floats(0.15, 0.85))
    named = draw(st.booleans())                     # through = "G" (frame point) or [x, y]
    frame = {"O": O, "G": G} if named else {"O": O}
    points = [draw_point(draw, "P2", 2, ["A", "B"], S), draw_point(draw, "P3", 3, ["B"], S)]
    size = mechanism_size({"O": O, "G": G}, [L1, L], points)
    return Mechanism("RRP", frame, L1, draw(omegas), draw(epsilons),
                     {"L": L, "G": G, "gamma_deg": gamma_deg, "branch": draw(signs),
                      "named_guide": named},
                     points, draw(crank_angles), size)


@st.composite
def slotted_levers(draw):
    """Crank + RPR dyad: block on A slides in a lever turning about O1.

    L1 < D gives an oscillating lever, L1 > D a rotating one; |A O1| never drops below
    r_min = |D - L1| >= 0.2 max(D, L1), and the slot offset stays below 0.8 r_min, so the
    slide s = sqrt(|A O1|^2 - offset^2) stays well away from zero.
    """
    S = draw(sizes)
    D = S
    L1 = D * draw(st.one_of(st.floats(0.1, 0.8), st.floats(1.25, 3.0)))
    r_min = abs(D - L1)
    offset = draw(st.one_of(st.just(0.0), signed(0.05, 0.8).map(lambda r: r * r_min)))
    O = S * np.array([draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0))])
    O1 = O + D * e(draw(st.floats(0.0, 2.0 * math.pi)))
    frame = {"O": O, "O1": O1}
    points = [draw_point(draw, "P2", 2, ["A"], S), draw_point(draw, "P3", 3, ["O1"], S)]
    write_offset = offset != 0.0 or draw(st.booleans())
    return Mechanism("RPR", frame, L1, draw(omegas), draw(epsilons),
                     {"offset": offset, "write_offset": write_offset},
                     points, draw(crank_angles), mechanism_size(frame, [L1, D], points))


MECHANISMS = {"RRR": fourbars(), "RRP": crank_sliders(), "RPR": slotted_levers()}
KINDS = list(MECHANISMS)




# --------------------------------------------------------------------------- moving guides and axes
def random_chains():
    """Hypothesis strategy: a random assemblable four-bar (tests/kinematics/test_properties.py) extended
    by a random chain of the generalised groups: an RRP on a guide of its rocker (two
    rockers with a slotted pair), an RPR about a point E of the rocker (a kulisa with a
    moving axis), or both with the RRP's guide on that kulisa. Every added group assembles
    over the whole revolution, away from its toggle (|det| >= 0.5). Returns
    (scene text, crank angles, length scale)."""
    @st.composite
    def build(draw):
        m = draw(fourbars())
        S = m.size
        text = m.toml
        revolution = np.arange(0.0, 360.0, 1.0)
        what = draw(st.sampled_from(["slotted", "moving_axis", "both"]))

        def line_distances(text, through, k, angle_deg, point):
            """|h| of `point` from the line through `through` at phi_k + A, over a revolution."""
            sol = sheetkin.solve(sheetkin.parse_scene(text), revolution)
            g = sol.points.get(through)
            gx, gy = (g.x, g.y) if g is not None else sheetkin.parse_scene(text).frame[through]
            r = sol.links[k]
            th = np.arctan2(r.s, r.c) + math.radians(angle_deg)
            return np.abs(-(point[0] - gx) * np.sin(th) + (point[1] - gy) * np.cos(th))

        def add_rrp(text, links, through, k):
            O = m.frame["O"]
            p = O + S * np.array([draw(st.floats(-2.0, 2.0)), draw(st.floats(-2.0, 2.0))])
            A = draw(st.floats(-90.0, 90.0))
            text = text.replace("[crank]", f"Q{k} = [{fl(p[0])}, {fl(p[1])}]\n\n[crank]", 1)
            h = line_distances(text, through, k, A, p)
            L = float(h.max()) / draw(st.floats(0.1, 0.85)) + 1e-3 * S
            return text + (f'\n[[group]]\ntype = "RRP"\nlinks = [{links[0]}, {links[1]}]\njoints = ["Q{k}", "N{k}"]\n'
                           f"length = {fl(L)}\nguide = {{ through = \"{through}\", angle_deg = {fl(A)}, link = {k} }}\n"
                           f"branch = {draw(st.sampled_from([-1, 1]))}\n")

        def add_rpr(text):
            along, across = S * draw(st.floats(0.2, 1.5)), S * draw(st.floats(-0.5, 0.5))
            text += f'\n[[point]]\nname = "E"\nlink = 3\nfrom = "O1"\nalong = {fl(along)}\nacross = {fl(across)}\n'
            sol = sheetkin.solve(sheetkin.parse_scene(text), revolution)
            d = np.hypot(sol.points["A"].x - sol.points["E"].x, sol.points["A"].y - sol.points["E"].y)
            assume(d.min() > 0.05 * S)
            off = draw(st.sampled_from([0.0, 0.3, -0.5])) * float(d.min())
            return text + (f'\n[[group]]\ntype = "RPR"\nlinks = [4, 5]\njoints = ["A", "E"]\noffset = {fl(off)}\n')

        if what == "slotted":
            text = add_rrp(text, (4, 5), "O1", 3)
        elif what == "moving_axis":
            text = add_rpr(text)
        else:
            text = add_rrp(add_rpr(text), (6, 7), "E", 5)
        return text, m.angles, S
    return build()


# --------------------------------------------------------------------------- PRP and RPP, chains of kinds
def crank_text(title: str, frame: dict, L1: float, omega: float, epsilon: float) -> str:
    """A scene's head: the frame points (name -> (x, y)) and the crank O A (link 1)."""
    out = [f'title = "{title}"', "", "[frame]"]
    out += [f"{name} = [{fl(p[0])}, {fl(p[1])}]" for name, p in frame.items()]
    out += ["", "[crank]", 'pivot = "O"', 'joint = "A"', f"length = {fl(L1)}", "phi0_deg = 0.0",
            "step_deg = 30.0", "positions = 13", f"omega = {fl(omega)}", f"epsilon = {fl(epsilon)}", ""]
    return "\n".join(out) + "\n"


def point_text(name: str, link: int, origin: str, along: float, across: float) -> str:
    return (f'[[point]]\nname = "{name}"\nlink = {link}\nfrom = "{origin}"\nalong = {fl(along)}\n'
            f"across = {fl(across)}\n\n")


def _guide(through, angle_deg, link=0) -> str:
    at = f'"{through}"' if isinstance(through, str) else f"[{fl(through[0])}, {fl(through[1])}]"
    return f"{{ through = {at}, angle_deg = {fl(angle_deg)}" + (f", link = {link} }}" if link else " }")


def _lines_apart(text: str, angles, group: int, margin: float = 0.2) -> bool:
    """Group `group`'s two lines (a PRP) are at least `margin` (a sine) from parallel at the
    crank angles: the solver's toggle measure, used only to filter the drawn mechanisms."""
    sol = sheetkin.solve(sheetkin.parse_scene(text), np.asarray(angles, dtype=float))
    return bool(np.all(np.abs(sol.det[group]) >= margin))


@st.composite
def sliders_on_coupler(draw):
    """PRP: a random four-bar (fourbars) whose coupler (link 2) carries guide 1 through A or B
    at a random angle to it, guide 2 fixed through a random point at a random angle (the
    lecture's slider on the coupler with a fixed guide). Two lines cross unless parallel:
    the draw is kept where they are at least 0.2 (a sine) from parallel at its crank
    angles, so that N stays within 5 sizes."""
    m = draw(fourbars())
    S = m.size
    G = m.frame["O"] + S * np.array([draw(st.floats(-2.0, 2.0)), draw(st.floats(-2.0, 2.0))])
    text = m.toml + ("\n[[group]]\ntype = \"PRP\"\nlinks = [4, 5]\njoints = [\"L\"]\n"
                     f"guides = [{_guide(draw(st.sampled_from(['A', 'B'])), draw(st.floats(-180.0, 180.0)), 2)}, "
                     f"{_guide(G, draw(st.floats(-180.0, 360.0)))}]\n")
    assume(_lines_apart(text, m.angles, 2))
    return text, m.angles, 5 * S


@st.composite
def scotch_yokes(draw):
    """RPP: the crank's block A in the slot of a yoke that slides along a fixed guide through G
    at gamma; the slot at alpha = gamma +- (20 .. 160) deg, so |sin(alpha - gamma)| >= 0.34
    and it assembles at every crank angle (K within 3 sizes of G). A point on the yoke."""
    S = draw(sizes)
    O = S * np.array([draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0))])
    G = O + S * np.array([draw(st.floats(-2.0, 2.0)), draw(st.floats(-2.0, 2.0))])
    gamma = draw(st.floats(-180.0, 360.0))
    alpha = gamma + draw(signed(20.0, 160.0))
    named = draw(st.booleans())                     # through = "G" (frame point) or [x, y]
    frame = {"O": O, "G": G} if named else {"O": O}
    text = crank_text("random RPP", frame, S, draw(omegas), draw(epsilons))
    text += ("[[group]]\ntype = \"RPP\"\nlinks = [2, 3]\njoints = [\"A\", \"K\"]\n"
             f"slot_angle_deg = {fl(alpha)}\nguide = {_guide('G' if named else G, gamma)}\n\n")
    text += point_text("P3", 3, "K", S * draw(st.floats(-1.5, 1.5)), S * draw(st.floats(-1.5, 1.5)))
    size = float(np.max(np.abs(np.concatenate([O, G])))) + 5 * S
    return text, draw(crank_angles), size


@st.composite
def kind_chains(draw):
    """A crank and two or three groups of any kind, each on points known before it (the
    crank's A, an earlier group's new joint, a [[point]] on an earlier link), built so that
    every group assembles at every crank angle, away from its toggle. Every moving point P
    carries a bound R >= |P - O| over the revolution, and each group is sized from it:
      RRR  J2 a frame point 3R from O, lengths 0.8 .. 1.3 of that: |J1 J2| in [2R, 4R] stays
           0.5 R inside |L2 - L3| and 0.8 R inside L2 + L3;
      RRP  a fixed guide with |h(O)| <= 1.5 R, the coupler (|h(O)| + R) / rho, rho <= 0.85;
      RPP  the slot 20 .. 160 deg from its fixed guide;
      RPR  J2 a frame point 1.5 .. 3 R from O, |offset| <= 0.8 (|J1 J2|'s minimum);
      PRP  (last) guide 1 on an earlier moving link through one of its points, guide 2
           fixed; kept where the lines are 0.2 (a sine) from parallel at the crank angles.
    Groups that place no joint with a bound (RPR, PRP) come last."""
    S = draw(sizes)
    O = S * np.array([draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0))])
    frame = {"O": O}
    bound = {"A": S}                   # moving point -> bound on its distance from O
    on_link = {1: ["A"]}               # moving link -> its moving points
    body, link = "", 2
    slid = set()                       # points a slide is already named after (s_P: once)
    n = draw(st.integers(2, 3))
    kinds = []
    for i in range(n):
        last = i == n - 1
        kind = draw(st.sampled_from(["RRR", "RRP", "RPP", "RPR", "PRP"] if last else ["RRR", "RRP", "RPP"]))
        kinds.append(kind)
        a, b = link, link + 1
        link += 2
        # RPP and RPR name a slide after their block's joint J1 (s_J1): a point has one
        free = sorted(set(bound) - slid) if kind in ("RPP", "RPR") else sorted(bound)
        assume(free)
        j1 = draw(st.sampled_from(free))
        if kind in ("RPP", "RPR"):
            slid.add(j1)
        R = bound[j1]
        head = f'[[group]]\ntype = "{kind}"\nlinks = [{a}, {b}]\n'
        if kind == "RRR":
            D = 3 * R
            frame[f"F{i}"] = O + D * e(draw(st.floats(0.0, 2 * math.pi)))
            l2, l3 = D * draw(st.floats(0.8, 1.3)), D * draw(st.floats(0.8, 1.3))
            body += head + (f'joints = ["{j1}", "N{i}", "F{i}"]\nlengths = [{fl(l2)}, {fl(l3)}]\n'
                            f"branch = {draw(signs)}\n\n")
            bound[f"N{i}"] = D + l3
            on_link[a], on_link[b] = [j1, f"N{i}"], [f"N{i}"]
        elif kind == "RRP":
            gamma = draw(st.floats(-180.0, 360.0))
            u, nrm = e(math.radians(gamma)), e_perp(math.radians(gamma))
            h_O = R * draw(st.floats(-1.5, 1.5))
            G = O - h_O * nrm + R * draw(st.floats(-2.0, 2.0)) * u
            L = (abs(h_O) + R) / draw(st.floats(0.15, 0.85))
            body += head + (f'joints = ["{j1}", "N{i}"]\nlength = {fl(L)}\nguide = {_guide(G, gamma)}\n'
                            f"branch = {draw(signs)}\n\n")
            bound[f"N{i}"] = R + L
            on_link[a], on_link[b] = [j1, f"N{i}"], [f"N{i}"]
        elif kind == "RPP":
            gamma = draw(st.floats(-180.0, 360.0))
            G = O + R * np.array([draw(st.floats(-2.0, 2.0)), draw(st.floats(-2.0, 2.0))])
            body += head + (f'joints = ["{j1}", "K{i}"]\nslot_angle_deg = {fl(gamma + draw(signed(20.0, 160.0)))}\n'
                            f"guide = {_guide(G, gamma)}\n\n")
            g = float(np.hypot(*(G - O)))
            bound[f"K{i}"] = g + (R + g) / math.sin(math.radians(20.0))
            on_link[a], on_link[b] = [j1], [f"K{i}"]
        elif kind == "RPR":
            D = R * draw(st.floats(1.5, 3.0))
            frame[f"F{i}"] = O + D * e(draw(st.floats(0.0, 2 * math.pi)))
            off = draw(st.one_of(st.just(0.0), signed(0.05, 0.8))) * (D - R)
            body += head + f'joints = ["{j1}", "F{i}"]\noffset = {fl(off)}\n\n'
        else:
            k = draw(st.sampled_from(sorted(on_link)))
            G = O + R * np.array([draw(st.floats(-2.0, 2.0)), draw(st.floats(-2.0, 2.0))])
            through, angle = draw(st.sampled_from(on_link[k])), draw(st.floats(-180.0, 180.0))
            body += head + (f'joints = ["L{i}"]\nguides = [{_guide(through, angle, k)}, '
                            f"{_guide(G, draw(st.floats(-180.0, 360.0)))}]\n\n")
        slid.update({"RRP": [f"N{i}"], "RPP": [f"K{i}"], "PRP": [f"L{i}"]}.get(kind, []))
        if kind in ("RRR", "RRP", "RPP") and draw(st.booleans()):
            # a [[point]] on one of the group's links, usable by the next group
            k = draw(st.sampled_from([a, b]))
            origin = draw(st.sampled_from(on_link[k]))
            along, across = R * draw(st.floats(-1.0, 1.0)), R * draw(st.floats(-1.0, 1.0))
            body += point_text(f"P{i}", k, origin, along, across)
            bound[f"P{i}"] = bound[origin] + abs(along) + abs(across)
            on_link[k].append(f"P{i}")
    angles = draw(crank_angles)
    text = crank_text(f"random chain {'-'.join(kinds)}", frame, S, draw(omegas), draw(epsilons)) + body
    if kinds[-1] == "PRP":
        assume(_lines_apart(text, angles, n))
    return text, angles, max(bound.values()) + float(np.max(np.abs(O)))


def _as_text(strategy):
    return strategy.map(lambda m: (m.toml, m.angles, m.size))


# name -> strategy of (scene text, crank angles, length scale): every kind, then chains
STRATEGIES = {"RRR": _as_text(fourbars()), "RRP": _as_text(crank_sliders()), "RPR": _as_text(slotted_levers()),
              "PRP": sliders_on_coupler(), "RPP": scotch_yokes(),
              "moving guides and axes": random_chains(), "chains of kinds": kind_chains()}
