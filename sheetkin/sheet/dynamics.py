"""The workbook's energy and dynamic analysis blocks (seed 003, the lecture's last two
sections), for scenes with [[mass]] / [[force]] tables: input rows for masses, gravity and
loads; the energies, inertia forces and powers; the kinetostatics of each Assur group from
the last back to the crank, the balancing moment and the energy balance, each block with its
check rows. Same names and the same equations as sheetkin.kinematics.dynamics (the reference)."""
from __future__ import annotations

from sheetkin.groups import kind_of
from sheetkin.groups.rows import Builder, LoadRows
from sheetkin.kinematics.dynamics import point_owners


def dynamics_inputs(b: Builder):
    """Masses, moments of inertia, gravity and external loads (docs: `sheetkin docs dynamics`)."""
    sc = b.scene
    if any(sc.gravity):
        b.input("g_x", "m/s^2", "ускорение свободного падения: проекция на x", "gravity, x component", sc.gravity[0])
        b.input("g_y", "m/s^2", "ускорение свободного падения: проекция на y", "gravity, y component", sc.gravity[1])
    for m in sc.masses:
        b.input(
            f"m_{m.link}",
            "kg",
            f"масса звена {m.link} (центр масс {m.centre})",
            f"mass of link {m.link} (centre of mass {m.centre})",
            m.mass,
        )
        b.input(
            f"J_{m.link}",
            "kg m^2",
            f"момент инерции звена {m.link} относительно {m.centre}",
            f"moment of inertia of link {m.link} about {m.centre}",
            m.inertia,
        )
    for f in sc.forces:
        n, where = f.name, f"звено {f.link}" + (f", точка {f.at}" if f.at else "")
        where_en = f"link {f.link}" + (f", point {f.at}" if f.at else "")
        if f.at:
            b.input(
                f"Fx_{n}",
                "N",
                f"внешняя сила {n} ({where}): проекция на x",
                f"external force {n} ({where_en}): x component",
                f.force[0],
            )
            b.input(
                f"Fy_{n}",
                "N",
                f"внешняя сила {n} ({where}): проекция на y",
                f"external force {n} ({where_en}): y component",
                f.force[1],
            )
        if f.moment or not f.at:
            b.input(
                f"Mz_{n}",
                "N m",
                f"внешний момент {n} на звено {f.link} (против часовой +)",
                f"external moment {n} on link {f.link} (counterclockwise +)",
                f.moment,
            )
        if f.interval_deg:
            b.input(
                f"from_{n}",
                "deg",
                f"{n} действует с угла кривошипа",
                f"{n} acts from the crank angle",
                f.interval_deg[0],
            )
            b.input(
                f"to_{n}",
                "deg",
                f"{n} действует до угла кривошипа",
                f"{n} acts up to the crank angle",
                f.interval_deg[1],
            )


def _rates(b: Builder, k: int) -> tuple[str, str]:
    """Angular velocity and acceleration of link k as references."""
    _, _, w, e = b.rot[k]
    return f"{{{w}}}", f"{{{e}}}"


def energy_rows(b: Builder):
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
        b.add(
            f"T_{k}",
            "J",
            f"кинетическая энергия звена {k}: m v{S}^2/2 + J omega^2/2",
            f"kinetic energy of link {k}: m v{S}^2/2 + J omega^2/2",
            "accepted",
            f"{m}*({vx}^2+{vy}^2)/2+{J}*{w}^2/2",
        )
        if gravity:
            b.add(
                f"U_{k}",
                "J",
                f"потенциальная энергия звена {k}: -m g.r{S}",
                f"potential energy of link {k}: -m g.r{S}",
                "accepted",
                f"-{m}*({{g_x}}*{b.p('x', S)}+{{g_y}}*{b.p('y', S)})",
            )
            u_rate.append(f"-{m}*({{g_x}}*{vx}+{{g_y}}*{vy})")
        v = f"{{v_{S}}}" if S not in b.frame else "0"
        # relative to the sizes at the same position (not to the row's largest value): the
        # check then reads only its own column, free of the step and of the other positions
        b.add(
            f"chk_T_{k}",
            "",
            f"проверка: T_{k} через модуль скорости v{S} (относительная невязка)",
            f"check: T_{k} from the speed v{S} (relative)",
            "check",
            f"({{T_{k}}}-{m}*{v}^2/2-{J}*{w}^2/2)/(ABS({{T_{k}}})+{m}*{v}^2/2+{J}*{w}^2/2+1E-300)",
        )
        b.add(
            f"Fix_{k}",
            "N",
            f"сила инерции звена {k} (Даламбер): -m a{S}, x",
            f"inertia force of link {k} (d'Alembert): -m a{S}, x",
            "accepted",
            f"-{m}*{ax}",
        )
        b.add(
            f"Fiy_{k}",
            "N",
            f"сила инерции звена {k}: -m a{S}, y",
            f"inertia force of link {k}: -m a{S}, y",
            "accepted",
            f"-{m}*{ay}",
        )
        b.add(
            f"Mi_{k}",
            "N m",
            f"момент сил инерции звена {k}: -J eps",
            f"inertia moment of link {k}: -J eps",
            "accepted",
            f"-{J}*{e}",
        )
        a = f"{{a_{S}}}" if S not in b.frame else "0"
        b.add(
            f"chk_Fi_{k}",
            "",
            f"проверка: |Fi_{k}| = m a{S} (относительная невязка)",
            f"check: |Fi_{k}| = m a{S} (relative)",
            "check",
            f"(SQRT({{Fix_{k}}}^2+{{Fiy_{k}}}^2)-{m}*{a})/(SQRT({{Fix_{k}}}^2+{{Fiy_{k}}}^2)+{m}*ABS({a})+1E-300)",
        )
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
        b.add(
            f"P_{n}",
            "W",
            f"мощность внешней нагрузки {n}",
            f"power of the external load {n}",
            "calc",
            f"{on}({'+'.join(terms)})",
        )
        powers.append(f"{{P_{n}}}")
    if sc.forces:
        b.add(
            "P_ext",
            "W",
            "мощность внешних сил и моментов",
            "power of the external forces and moments",
            "accepted",
            "+".join(powers),
        )


def _energy_totals(b: Builder, t_rate: list[str], u_rate: list[str]):
    """The mechanism's energies and their rates, with the checks of the rates."""
    sc, gravity = b.scene, any(b.scene.gravity)
    b.add("T", "J", "кинетическая энергия механизма", "kinetic energy of the mechanism", "accepted",
          "+".join(f"{{T_{m.link}}}" for m in sc.masses))
    if gravity:
        b.add("U", "J", "потенциальная энергия механизма", "potential energy of the mechanism", "accepted",
              "+".join(f"{{U_{m.link}}}" for m in sc.masses))
    # the totals once more from the links' speeds and heights, not from the T_k, U_k rows
    # (free of the step; relative to the terms' sizes, as the energies may be near 0)
    t_terms = [f"{{m_{m.link}}}*{v}^2/2+{{J_{m.link}}}*{_rates(b, m.link)[0]}^2/2"
               for m in sc.masses for v in [f"{{v_{m.centre}}}" if m.centre not in b.frame else "0"]]
    b.add("chk_T", "", "проверка: T = сумма m v^2/2 + J omega^2/2 по модулям скоростей (относительная невязка)",
          "check: T = sum of m v^2/2 + J omega^2/2 from the speeds (relative)", "check",
          f"({{T}}-({'+'.join(t_terms)}))/(ABS({{T}})+{'+'.join(t_terms)}+1E-300)")
    if gravity:
        u_terms = [f"{{m_{m.link}}}*({{g_x}}*{b.p('x', m.centre)}+{{g_y}}*{b.p('y', m.centre)})" for m in sc.masses]
        each = "+".join(f"ABS({{U_{m.link}}}+{t})" for m, t in zip(sc.masses, u_terms, strict=False))
        size = "+".join(f"ABS({t})" for t in u_terms)
        b.add(
            "chk_U",
            "",
            "проверка: U_k = -m_k g.r_S и U = сумма U_k (относительная невязка)",
            "check: U_k = -m_k g.r_S and U = the sum of U_k (relative)",
            "check",
            f"(ABS({{U}}+({'+'.join(u_terms)}))+{each})/({size}+1E-300)",
        )
    b.add(
        "T_t",
        "W",
        "скорость изменения кинетической энергии: сумма m v.a + J omega eps",
        "rate of change of the kinetic energy: sum of m v.a + J omega eps",
        "accepted",
        "+".join(t_rate),
    )
    if gravity:
        b.add(
            "U_t",
            "W",
            "скорость изменения потенциальной энергии: -сумма m g.v",
            "rate of change of the potential energy: -sum of m g.v",
            "accepted",
            "+".join(u_rate),
        )
    # checks: the inertia forces' power is -dT/dt; the rates against numeric derivatives
    # (T is quadratic in the crank's rate, so dT/dt = Fi_t dT/dFi + 2 Fi_tt T / Fi_t)
    p_terms = [
        t
        for m in sc.masses
        for t in (
            f"{{Fix_{m.link}}}*{b.p('vx', m.centre)}",
            f"{{Fiy_{m.link}}}*{b.p('vy', m.centre)}",
            f"{{Mi_{m.link}}}*{_rates(b, m.link)[0]}",
        )
    ]
    b.add(
        "chk_P_in",
        "",
        "проверка: мощность сил инерции + dT/dt = 0 (относительно суммы модулей слагаемых)",
        "check: power of the inertia forces + dT/dt = 0 (relative to the sum of the terms' sizes)",
        "check",
        f"({'+'.join(p_terms)}+{{T_t}})/({'+'.join(f'ABS({t})' for t in p_terms)}+ABS({{T_t}})+1E-300)",
    )
    b.add(
        "fd_T_t",
        "",
        "T_t: численная производная (относительная невязка)",
        "T_t against the numeric derivative (relative)",
        "fdcheck",
        "({T_t}-{Fi_t}*({T@next}-{T@prev})/(2*{Delta_Fi_rad})-2*{Fi_tt}*{T}/{Fi_t})/{scale:T_t}",
    )
    if gravity:
        b.add(
            "fd_U_t",
            "",
            "U_t: численная производная (относительная невязка)",
            "U_t against the numeric derivative (relative)",
            "fdcheck",
            "({U_t}-{Fi_t}*({U@next}-{U@prev})/(2*{Delta_Fi_rad}))/{scale:U_t}",
        )


def kinetostatics_rows(b: Builder):
    """Joint reactions group by group from the last Assur group back to the crank (as
    sheetkin.kinematics.dynamics; names Rx_i_j: the force of link i on link j), the balancing moment,
    and the energy balance the lecture demands."""
    sc, gravity = b.scene, any(b.scene.gravity)
    owner = point_owners(sc)
    loads: dict[int, list] = {k: [] for k in range(0, 2 + 2 * len(sc.groups))}   # (point, fx, fy)
    couples: dict[int, list] = {k: [] for k in loads}
    for m in sc.masses:
        k = m.link
        gx, gy = (f"{{m_{k}}}*{{g_x}}+", f"{{m_{k}}}*{{g_y}}+") if gravity else ("", "")
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
    k = LoadRows(b, loads, couples)
    for g in reversed(sc.groups):
        b.section(
            f"forces_g{g.index}",
            f"Группа {g.index} ({g.type} {'-'.join(g.joints)}): реакции",
            f"Group {g.index} ({g.type} {'-'.join(g.joints)}): reactions",
        )
        kind_of(g).reaction_rows(b, g, owner, k)
    c = sc.crank
    b.section(
        "forces_crank",
        "Кривошип: реакция стойки и уравновешивающий момент",
        "The crank: the frame's reaction and the balancing moment",
    )
    k.link_loads(1, c.pivot)
    k.reaction(
        "0_1", "-{Qx_1}", "-{Qy_1}", f"стойки на кривошип в {c.pivot}", f"of the frame on the crank at {c.pivot}"
    )
    b.add(
        "M_bal",
        "N m",
        "уравновешивающий момент на кривошипе (против часовой +)",
        "balancing moment on the crank (counterclockwise +)",
        "accepted",
        "-{MQ_1}",
    )
    k.equilibrium(1, c.pivot, [(c.pivot, "{Rx_0_1}", "{Ry_0_1}")], "{M_bal}")
    b.add(
        "P_bal",
        "W",
        "мощность уравновешивающего момента M_bal Fi_t",
        "power of the balancing moment M_bal Fi_t",
        "accepted",
        "{M_bal}*{Fi_t}",
    )
    terms = (["{P_bal}"] + (["{P_ext}"] if sc.forces else []) + (["-{U_t}"] if gravity and sc.masses else [])
             + (["-{T_t}"] if sc.masses else []))
    size = "+".join(f"ABS({t.lstrip('-')})" for t in terms)
    b.add("chk_balance", "", "энергетический баланс: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (относительная невязка)",
          "energy balance: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (relative)", "check",
          f"({''.join(t if t.startswith('-') else '+' + t for t in terms)[1:]})/({size}+1E-300)")
