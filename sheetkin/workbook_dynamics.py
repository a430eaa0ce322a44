"""The workbook's energy and dynamic analysis blocks (seed 003, the lecture's last two
sections), for scenes with [[mass]] / [[force]] tables: input rows for masses, gravity and
loads; the energies, inertia forces and powers; the kinetostatics of each Assur group from
the last back to the crank, the balancing moment and the energy balance, each block with its
check rows. Same names and the same equations as sheetkin.dynamics (the reference)."""
from __future__ import annotations

from .dynamics import point_owners
from .workbook import _Builder, _cramer_rows, _det_row

def dynamics_inputs(b: _Builder):
    """Masses, moments of inertia, gravity and external loads (README: "Masses and forces")."""
    sc = b.scene
    if any(sc.gravity):
        b.input("g_x", "m/s^2", "ускорение свободного падения: проекция на x", "gravity, x component", sc.gravity[0])
        b.input("g_y", "m/s^2", "ускорение свободного падения: проекция на y", "gravity, y component", sc.gravity[1])
    for m in sc.masses:
        b.input(f"m_{m.link}", "kg", f"масса звена {m.link} (центр масс {m.centre})", f"mass of link {m.link} (centre of mass {m.centre})", m.mass)
        b.input(f"J_{m.link}", "kg m^2", f"момент инерции звена {m.link} относительно {m.centre}", f"moment of inertia of link {m.link} about {m.centre}", m.inertia)
    for f in sc.forces:
        n, where = f.name, f"звено {f.link}" + (f", точка {f.at}" if f.at else "")
        where_en = f"link {f.link}" + (f", point {f.at}" if f.at else "")
        if f.at:
            b.input(f"Fx_{n}", "N", f"внешняя сила {n} ({where}): проекция на x", f"external force {n} ({where_en}): x component", f.force[0])
            b.input(f"Fy_{n}", "N", f"внешняя сила {n} ({where}): проекция на y", f"external force {n} ({where_en}): y component", f.force[1])
        if f.moment or not f.at:
            b.input(f"Mz_{n}", "N m", f"внешний момент {n} на звено {f.link} (против часовой +)", f"external moment {n} on link {f.link} (counterclockwise +)", f.moment)
        if f.interval_deg:
            b.input(f"from_{n}", "deg", f"{n} действует с угла кривошипа", f"{n} acts from the crank angle", f.interval_deg[0])
            b.input(f"to_{n}", "deg", f"{n} действует до угла кривошипа", f"{n} acts up to the crank angle", f.interval_deg[1])


def _rates(b: _Builder, k: int) -> tuple[str, str]:
    """Angular velocity and acceleration of link k as references."""
    _, _, w, e = b.rot[k]
    return f"{{{w}}}", f"{{{e}}}"


def energy_rows(b: _Builder):
    """The lecture's energy analysis (seed 003): the centres of mass' energies, the
    d'Alembert inertia forces, the energies' rates of change, the power of external loads."""
    sc, gravity = b.scene, any(b.scene.gravity)
    b.section("energy", "Энергетический анализ механизма", "Energy analysis of the mechanism")
    t_rate, u_rate = [], []
    for mass in sc.masses:
        k, S = mass.link, mass.centre
        m, J = f"{{m_{k}}}", f"{{J_{k}}}"
        w, e = _rates(b, k)
        vx, vy, ax, ay = (b.p(q, S) for q in ("vx", "vy", "ax", "ay"))
        b.add(f"T_{k}", "J", f"кинетическая энергия звена {k}: m v{S}^2/2 + J omega^2/2", f"kinetic energy of link {k}: m v{S}^2/2 + J omega^2/2",
              "accepted", f"{m}*({vx}^2+{vy}^2)/2+{J}*{w}^2/2")
        if gravity:
            b.add(f"U_{k}", "J", f"потенциальная энергия звена {k}: -m g.r{S}", f"potential energy of link {k}: -m g.r{S}",
                  "accepted", f"-{m}*({{g_x}}*{b.p('x', S)}+{{g_y}}*{b.p('y', S)})")
            u_rate.append(f"-{m}*({{g_x}}*{vx}+{{g_y}}*{vy})")
        v = f"{{v_{S}}}" if S not in b.frame else "0"
        b.add(f"chk_T_{k}", "", f"проверка: T_{k} через модуль скорости v{S} (относительная невязка)", f"check: T_{k} from the speed v{S} (relative)",
              "check", f"({{T_{k}}}-{m}*{v}^2/2-{J}*{w}^2/2)/({{scale:T_{k}}})")
        b.add(f"Fix_{k}", "N", f"сила инерции звена {k} (Даламбер): -m a{S}, x", f"inertia force of link {k} (d'Alembert): -m a{S}, x", "accepted", f"-{m}*{ax}")
        b.add(f"Fiy_{k}", "N", f"сила инерции звена {k}: -m a{S}, y", f"inertia force of link {k}: -m a{S}, y", "accepted", f"-{m}*{ay}")
        b.add(f"Mi_{k}", "N m", f"момент сил инерции звена {k}: -J eps", f"inertia moment of link {k}: -J eps", "accepted", f"-{J}*{e}")
        a = f"{{a_{S}}}" if S not in b.frame else "0"
        b.add(f"chk_Fi_{k}", "", f"проверка: |Fi_{k}| = m a{S} (относительная невязка)", f"check: |Fi_{k}| = m a{S} (relative)",
              "check", f"(SQRT({{Fix_{k}}}^2+{{Fiy_{k}}}^2)-{m}*{a})/({{scale:Fix_{k}}}+{{scale:Fiy_{k}}})")
        t_rate.append(f"{m}*({vx}*{ax}+{vy}*{ay})+{J}*{w}*{e}")
    if sc.masses:
        _energy_totals(b, t_rate, u_rate)
    powers = []
    for f in sc.forces:
        n = f.name
        on = ""
        if f.interval_deg:
            b.add(f"on_{n}", "", f"{n} действует (1) или нет (0)", f"{n} acts (1) or not (0)", "calc",
                  f"IF(MOD({{phi_1}}-{{from_{n}}},360)<={{to_{n}}}-{{from_{n}}},1,0)")
            on = f"{{on_{n}}}*"
        terms = []
        if f.at:
            terms.append(f"{{Fx_{n}}}*{b.p('vx', f.at)}+{{Fy_{n}}}*{b.p('vy', f.at)}")
        if f.moment or not f.at:
            terms.append(f"{{Mz_{n}}}*{_rates(b, f.link)[0]}")
        b.add(f"P_{n}", "W", f"мощность внешней нагрузки {n}", f"power of the external load {n}", "calc", f"{on}({'+'.join(terms)})")
        powers.append(f"{{P_{n}}}")
    if sc.forces:
        b.add("P_ext", "W", "мощность внешних сил и моментов", "power of the external forces and moments", "accepted", "+".join(powers))


def _energy_totals(b: _Builder, t_rate: list[str], u_rate: list[str]):
    """The mechanism's energies and their rates, with the checks of the rates."""
    sc, gravity = b.scene, any(b.scene.gravity)
    b.add("T", "J", "кинетическая энергия механизма", "kinetic energy of the mechanism", "accepted",
          "+".join(f"{{T_{m.link}}}" for m in sc.masses))
    if gravity:
        b.add("U", "J", "потенциальная энергия механизма", "potential energy of the mechanism", "accepted",
              "+".join(f"{{U_{m.link}}}" for m in sc.masses))
    b.add("T_t", "W", "скорость изменения кинетической энергии: сумма m v.a + J omega eps", "rate of change of the kinetic energy: sum of m v.a + J omega eps",
          "accepted", "+".join(t_rate))
    if gravity:
        b.add("U_t", "W", "скорость изменения потенциальной энергии: -сумма m g.v", "rate of change of the potential energy: -sum of m g.v",
              "accepted", "+".join(u_rate))
    # checks: the inertia forces' power is -dT/dt; the rates against numeric derivatives
    # (T is quadratic in the crank's rate, so dT/dt = Fi_t dT/dFi + 2 Fi_tt T / Fi_t)
    p_in = "+".join(f"{{Fix_{m.link}}}*{b.p('vx', m.centre)}+{{Fiy_{m.link}}}*{b.p('vy', m.centre)}+{{Mi_{m.link}}}*{_rates(b, m.link)[0]}"
                    for m in sc.masses)
    b.add("chk_P_in", "", "проверка: мощность сил инерции + dT/dt = 0 (относительная невязка)", "check: power of the inertia forces + dT/dt = 0 (relative)",
          "check", f"({p_in}+{{T_t}})/{{scale:T_t}}")
    b.add("fd_T_t", "", "T_t: численная производная (относительная невязка)", "T_t against the numeric derivative (relative)", "fdcheck",
          "({T_t}-{Fi_t}*({T@next}-{T@prev})/(2*{Delta_Fi_rad})-2*{Fi_tt}*{T}/{Fi_t})/{scale:T_t}")
    if gravity:
        b.add("fd_U_t", "", "U_t: численная производная (относительная невязка)", "U_t against the numeric derivative (relative)", "fdcheck",
              "({U_t}-{Fi_t}*({U@next}-{U@prev})/(2*{Delta_Fi_rad}))/{scale:U_t}")


def kinetostatics_rows(b: _Builder):
    """Joint reactions group by group from the last Assur group back to the crank (as
    sheetkin.dynamics; names Rx_i_j: the force of link i on link j), the balancing moment,
    and the energy balance the lecture demands."""
    sc, gravity = b.scene, any(b.scene.gravity)
    owner = point_owners(sc)
    loads: dict[int, list] = {k: [] for k in range(0, 2 + 2 * len(sc.groups))}   # (point, fx, fy)
    couples: dict[int, list] = {k: [] for k in loads}
    for m in sc.masses:
        k = m.link
        gx, gy = ("{m_%d}*{g_x}+" % k, "{m_%d}*{g_y}+" % k) if gravity else ("", "")
        loads[k].append((m.centre, f"({gx}{{Fix_{k}}})", f"({gy}{{Fiy_{k}}})"))
        couples[k].append(f"{{Mi_{k}}}")
    for f in sc.forces:
        on = f"{{on_{f.name}}}*" if f.interval_deg else ""
        if f.at:
            loads[f.link].append((f.at, f"{on}{{Fx_{f.name}}}", f"{on}{{Fy_{f.name}}}"))
        if f.moment or not f.at:
            couples[f.link].append(f"{on}{{Mz_{f.name}}}")
    b.section("forces", "Динамический анализ: реакции в кинематических парах (кинетостатика групп Ассура)",
              "Dynamic analysis: joint reactions (kinetostatics of the Assur groups)")

    def link_loads(k: int, ref: str):
        """Rows Qx_k, Qy_k, MQ_k: the known loads on link k and their moment about ref; then
        the check that takes the moment once more, about the origin."""
        fx = "+".join(f for _, f, _ in loads[k]) or "0"
        fy = "+".join(f for _, _, f in loads[k]) or "0"
        mom = [f"({b.p('x', p)}-{b.p('x', ref)})*{y}-({b.p('y', p)}-{b.p('y', ref)})*{x}" for p, x, y in loads[k]]
        b.add(f"Qx_{k}", "N", f"главный вектор известных нагрузок звена {k}, x", f"resultant of the known loads on link {k}, x", "calc", fx)
        b.add(f"Qy_{k}", "N", f"главный вектор известных нагрузок звена {k}, y", f"resultant of the known loads on link {k}, y", "calc", fy)
        b.add(f"MQ_{k}", "N m", f"их момент относительно {ref}", f"their moment about {ref}", "calc", "+".join(mom + couples[k]) or "0")
        about_o = "+".join([f"{b.p('x', p)}*{y}-{b.p('y', p)}*{x}" for p, x, y in loads[k]] + couples[k]) or "0"
        b.add(f"chk_MQ_{k}", "", f"проверка: момент нагрузок звена {k} относительно начала координат (относительная невязка)",
              f"check: the moment of link {k}'s loads about the origin (relative)", "check",
              f"({about_o}-({{MQ_{k}}}+{b.p('x', ref)}*{{Qy_{k}}}-{b.p('y', ref)}*{{Qx_{k}}}))/(1+ABS({{Qx_{k}}})+ABS({{Qy_{k}}})+ABS({{MQ_{k}}}))")

    def magnitude(tag: str, ru: str, en: str):
        b.add(f"R_{tag}", "N", f"модуль реакции {ru}", f"magnitude of the reaction {en}", "accepted", f"SQRT({{Rx_{tag}}}^2+{{Ry_{tag}}}^2)")

    def reaction(tag: str, rx: str, ry: str, ru: str, en: str):
        b.add(f"Rx_{tag}", "N", f"реакция {ru}, x", f"reaction {en}, x", "accepted", rx)
        b.add(f"Ry_{tag}", "N", f"реакция {ru}, y", f"reaction {en}, y", "accepted", ry)
        magnitude(tag, ru, en)

    def cramer_reaction(i: int, tag: str, mat, rhs, det_unit: str, det_text: tuple[str, str], ru: str, en: str):
        """The group's determinant, the reaction at J1 by Cramer's rule (lecture slide 20),
        the check putting it back into its two equations, and its magnitude."""
        det = f"Delta_R_g{i}"
        _det_row(b, det, mat, det_unit, *det_text)
        _cramer_rows(b, mat, det, ((f"Rx_{tag}", "N", f"реакция {ru} (Крамер), x", f"reaction {en} (Cramer), x"),
                                   (f"Ry_{tag}", "N", f"реакция {ru} (Крамер), y", f"reaction {en} (Cramer), y")),
                     rhs, (f"chk_Rsys_g{i}", "реакция в её двух уравнениях", "the reaction put back into its two equations"))
        magnitude(tag, ru, en)

    def equilibrium(k: int, ref: str, acting, couple: str):
        """Check row: link k's three equilibrium equations with every reaction on it, the
        moments taken about the origin (not about ref, where the loads were summed)."""
        fx = "+".join([f"{{Qx_{k}}}"] + [x for _, x, _ in acting])
        fy = "+".join([f"{{Qy_{k}}}"] + [y for _, _, y in acting])
        mom = "+".join([f"{{MQ_{k}}}", f"{b.p('x', ref)}*{{Qy_{k}}}-{b.p('y', ref)}*{{Qx_{k}}}"]
                       + [f"{b.p('x', p)}*{y}-{b.p('y', p)}*{x}" for p, x, y in acting] + ([couple] if couple else []))
        size = "+".join(["1", f"ABS({{Qx_{k}}})", f"ABS({{Qy_{k}}})"] + [f"ABS({x})+ABS({y})" for _, x, y in acting])
        b.add(f"chk_eq_{k}", "", f"проверка: равновесие звена {k} (силы и моменты, относительная невязка)",
              f"check: equilibrium of link {k} (forces and moments, relative)", "check",
              f"(ABS({fx})+ABS({fy})+ABS({mom}))/({size})")

    for g in reversed(sc.groups):
        i, (a, bl) = g.index, g.links
        J1 = g.joints[0]
        o1 = owner[J1]
        b.section(f"forces_g{i}", f"Группа {i} ({g.type} {'-'.join(g.joints)}): реакции", f"Group {i} ({g.type} {'-'.join(g.joints)}): reactions")
        t1, tab = f"{o1}_{a}", f"{a}_{bl}"
        r1 = (f"{{Rx_{t1}}}", f"{{Ry_{t1}}}")
        rab = (f"{{Rx_{tab}}}", f"{{Ry_{tab}}}")
        if g.type == "RRR":
            N, J2 = g.joints[1], g.joints[2]
            o2 = owner[J2]
            t2 = f"{o2}_{bl}"
            link_loads(a, N)
            link_loads(bl, N)
            d1x, d1y = f"({b.p('x', J1)}-{b.p('x', N)})", f"({b.p('y', J1)}-{b.p('y', N)})"
            d2x, d2y = f"({b.p('x', J2)}-{b.p('x', N)})", f"({b.p('y', J2)}-{b.p('y', N)})"
            # moments about N: d1 x R1 = -MQ_a and d2 x R2 = -MQ_b with R2 = -(Q_a + Q_b) - R1
            qx, qy = f"({{Qx_{a}}}+{{Qx_{bl}}})", f"({{Qy_{a}}}+{{Qy_{bl}}})"
            cramer_reaction(i, t1, (f"(-{d1y})", d1x, f"(-{d2y})", d2x), (f"(-{{MQ_{a}}})", f"({{MQ_{bl}}}-({d2x}*{qy}-{d2y}*{qx}))"),
                            "m^2", (f"определитель: ({J1}-{N}) x ({J2}-{N}) (0 в мёртвом положении)",
                                    f"determinant: ({J1}-{N}) x ({J2}-{N}) (0 at the toggle)"),
                            f"звена {o1} на звено {a} в {J1}", f"of link {o1} on link {a} at {J1}")
            reaction(tab, f"{r1[0]}+{{Qx_{a}}}", f"{r1[1]}+{{Qy_{a}}}", f"звена {a} на звено {bl} в {N}", f"of link {a} on link {bl} at {N}")
            reaction(t2, f"-{qx}-{r1[0]}", f"-{qy}-{r1[1]}", f"звена {o2} на звено {bl} в {J2}", f"of link {o2} on link {bl} at {J2}")
            equilibrium(a, N, [(J1, *r1), (N, f"(-{rab[0]})", f"(-{rab[1]})")], "")
            equilibrium(bl, N, [(N, *rab), (J2, f"{{Rx_{t2}}}", f"{{Ry_{t2}}}")], "")
            loads[o2].append((J2, f"(-{{Rx_{t2}}})", f"(-{{Ry_{t2}}})"))
        elif g.type == "RRP":
            N = g.joints[1]
            link_loads(a, N)
            link_loads(bl, N)
            ux, uy = f"COS(RADIANS({{gamma_g{i}}}))", f"SIN(RADIANS({{gamma_g{i}}}))"
            d1x, d1y = f"({b.p('x', J1)}-{b.p('x', N)})", f"({b.p('y', J1)}-{b.p('y', N)})"
            # along the guide: R1.u = -(Q_a + Q_b).u; moments of link a about N: d1 x R1 = -MQ_a
            qx, qy = f"({{Qx_{a}}}+{{Qx_{bl}}})", f"({{Qy_{a}}}+{{Qy_{bl}}})"
            cramer_reaction(i, t1, (ux, uy, f"(-{d1y})", d1x), (f"(-({qx}*{ux}+{qy}*{uy}))", f"(-{{MQ_{a}}})"),
                            "m", (f"определитель: ({J1}-{N}).u (0, когда шатун поперёк направляющей)",
                                  f"determinant: ({J1}-{N}).u (0 with the coupler across the guide)"),
                            f"звена {o1} на звено {a} в {J1}", f"of link {o1} on link {a} at {J1}")
            reaction(tab, f"{r1[0]}+{{Qx_{a}}}", f"{r1[1]}+{{Qy_{a}}}", f"звена {a} на ползун {bl} в {N}", f"of link {a} on slider {bl} at {N}")
            tg = f"0_{bl}"
            # the guide pushes across itself: -(R1 + Q).n n with n = (-uy, ux)
            qn = f"(({r1[0]}+{qx})*{uy}-({r1[1]}+{qy})*{ux})"
            reaction(tg, f"-{qn}*{uy}", f"{qn}*{ux}", f"направляющей на ползун {bl} (через {N})", f"of the guide on slider {bl} (through {N})")
            b.add(f"M_{tg}", "N m", f"момент реакции направляющей на ползун {bl}", f"couple of the guide on slider {bl}", "accepted", f"-{{MQ_{bl}}}")
            equilibrium(a, N, [(J1, *r1), (N, f"(-{rab[0]})", f"(-{rab[1]})")], "")
            equilibrium(bl, N, [(N, *rab), (N, f"{{Rx_{tg}}}", f"{{Ry_{tg}}}")], f"{{M_{tg}}}")
        else:
            J2 = g.joints[1]
            o2 = owner[J2]
            t2 = f"{o2}_{bl}"
            link_loads(a, J1)
            link_loads(bl, J2)
            c, s = f"{{cos_{bl}}}", f"{{sin_{bl}}}"
            # the lever acts on the block with P n through J1 (n = (-sin, cos)) and a couple
            # C = -MQ_a; the lever's moments about J2: (J1 - J2) x (-P n) - C + MQ_b = 0
            cross = f"(({b.p('x', J1)}-{b.p('x', J2)})*{c}+({b.p('y', J1)}-{b.p('y', J2)})*{s})"
            b.add(f"Pn_g{i}", "N", f"давление кулисы {bl} на камень {a} по нормали к кулисе", f"push of lever {bl} on block {a} across the slot",
                  "calc", f"({{MQ_{bl}}}+{{MQ_{a}}})/{cross}")
            P = f"{{Pn_g{i}}}"
            reaction(tab, f"-{P}*(-{s})", f"-{P}*{c}", f"камня {a} на кулису {bl} (через {J1})", f"of block {a} on lever {bl} (through {J1})")
            b.add(f"M_{tab}", "N m", f"момент реакции камня {a} на кулису {bl}", f"couple of block {a} on lever {bl}", "accepted", f"{{MQ_{a}}}")
            reaction(t1, f"-{P}*(-{s})-{{Qx_{a}}}", f"-{P}*{c}-{{Qy_{a}}}", f"звена {o1} на камень {a} в {J1}", f"of link {o1} on block {a} at {J1}")
            equilibrium(a, J1, [(J1, *r1), (J1, f"(-{rab[0]})", f"(-{rab[1]})")], f"(-{{M_{tab}}})")
            reaction(t2, f"{P}*(-{s})-{{Qx_{bl}}}", f"{P}*{c}-{{Qy_{bl}}}", f"звена {o2} на кулису {bl} в {J2}", f"of link {o2} on lever {bl} at {J2}")
            equilibrium(bl, J2, [(J1, *rab), (J2, f"{{Rx_{t2}}}", f"{{Ry_{t2}}}")], f"{{M_{tab}}}")
            loads[o2].append((J2, f"(-{{Rx_{t2}}})", f"(-{{Ry_{t2}}})"))
        loads[o1].append((J1, f"(-{r1[0]})", f"(-{r1[1]})"))
    c = sc.crank
    b.section("forces_crank", "Кривошип: реакция стойки и уравновешивающий момент", "The crank: the frame's reaction and the balancing moment")
    link_loads(1, c.pivot)
    reaction("0_1", "-{Qx_1}", "-{Qy_1}", f"стойки на кривошип в {c.pivot}", f"of the frame on the crank at {c.pivot}")
    b.add("M_bal", "N m", "уравновешивающий момент на кривошипе (против часовой +)", "balancing moment on the crank (counterclockwise +)", "accepted", "-{MQ_1}")
    equilibrium(1, c.pivot, [(c.pivot, "{Rx_0_1}", "{Ry_0_1}")], "{M_bal}")
    b.add("P_bal", "W", "мощность уравновешивающего момента M_bal Fi_t", "power of the balancing moment M_bal Fi_t", "accepted", "{M_bal}*{Fi_t}")
    terms = (["{P_bal}"] + (["{P_ext}"] if sc.forces else []) + (["-{U_t}"] if gravity and sc.masses else [])
             + (["-{T_t}"] if sc.masses else []))
    size = "+".join(f"ABS({t.lstrip('-')})" for t in terms)
    b.add("chk_balance", "", "энергетический баланс: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (относительная невязка)",
          "energy balance: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (relative)", "check",
          f"({''.join(t if t.startswith('-') else '+' + t for t in terms)[1:]})/({size}+1E-300)")
