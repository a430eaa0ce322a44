"""The workbook's energy and dynamic analysis blocks (seed 003, the lecture's last two
sections), for scenes with [[mass]] / [[force]] tables: input rows for masses, gravity and
loads; the energies, inertia forces and powers; the kinetostatics of each Assur group from
the last back to the crank, the balancing moment and the energy balance, each block with its
check rows. Same names and the same equations as sheetkin.kinematics.dynamics (the reference)."""
from __future__ import annotations

from sheetkin.groups import kind_of
from sheetkin.groups.rows import Builder, LoadRows, Texts
from sheetkin.kinematics.dynamics import point_owners

# --------------------------------------------------------------------------- the rows' texts
# format templates, one table per language (fields: link k, centre of mass S, load n)
TEXTS = {
    "ru": {
        "g_x": "ускорение свободного падения: проекция на x",
        "g_y": "ускорение свободного падения: проекция на y",
        "m": "масса звена {k} (центр масс {S})",
        "J": "момент инерции звена {k} относительно {S}",
        "on_link": "звено {k}",
        "on_point": "звено {k}, точка {at}",
        "Fx": "внешняя сила {n} ({where}): проекция на x",
        "Fy": "внешняя сила {n} ({where}): проекция на y",
        "Mz": "внешний момент {n} на звено {k} (против часовой +)",
        "from": "{n} действует с угла кривошипа",
        "to": "{n} действует до угла кривошипа",
        "energy": "Энергетический анализ механизма",
        "T_k": "кинетическая энергия звена {k}: m v{S}^2/2 + J omega^2/2",
        "U_k": "потенциальная энергия звена {k}: -m g.r{S}",
        "chk_T_k": "проверка: T_{k} через модуль скорости v{S} (относительная невязка)",
        "Fix": "сила инерции звена {k} (Даламбер): -m a{S}, x",
        "Fiy": "сила инерции звена {k}: -m a{S}, y",
        "Mi": "момент сил инерции звена {k}: -J eps",
        "chk_Fi": "проверка: |Fi_{k}| = m a{S} (относительная невязка)",
        "on": "{n} действует (1) или нет (0)",
        "P_n": "мощность внешней нагрузки {n}",
        "P_ext": "мощность внешних сил и моментов",
        "T": "кинетическая энергия механизма",
        "U": "потенциальная энергия механизма",
        "chk_T": "проверка: T = сумма m v^2/2 + J omega^2/2 по модулям скоростей (относительная невязка)",
        "chk_U": "проверка: U_k = -m_k g.r_S и U = сумма U_k (относительная невязка)",
        "T_t": "скорость изменения кинетической энергии: сумма m v.a + J omega eps",
        "U_t": "скорость изменения потенциальной энергии: -сумма m g.v",
        "chk_P_in": "проверка: мощность сил инерции + dT/dt = 0 (относительно суммы модулей слагаемых)",
        "fd": "{q}: численная производная (относительная невязка)",
        "forces": "Динамический анализ: реакции в кинематических парах (кинетостатика групп Ассура)",
        "forces_g": "Группа {i} ({kind} {joints}): реакции",
        "forces_crank": "Кривошип: реакция стойки и уравновешивающий момент",
        "R_01": "стойки на кривошип в {at}",
        "M_bal": "уравновешивающий момент на кривошипе (против часовой +)",
        "P_bal": "мощность уравновешивающего момента M_bal Fi_t",
        "balance": "энергетический баланс: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (относительная невязка)",
    },
    "uk": {
        "g_x": "прискорення вільного падіння: проекція на x",
        "g_y": "прискорення вільного падіння: проекція на y",
        "m": "маса ланки {k} (центр мас {S})",
        "J": "момент інерції ланки {k} відносно {S}",
        "on_link": "ланка {k}",
        "on_point": "ланка {k}, точка {at}",
        "Fx": "зовнішня сила {n} ({where}): проекція на x",
        "Fy": "зовнішня сила {n} ({where}): проекція на y",
        "Mz": "внешний момент {n} на ланку {k} (проти годинникової +)",
        "from": "{n} діє з кута кривошипа",
        "to": "{n} діє до кута кривошипа",
        "energy": "Енергетичний аналіз механізму",
        "T_k": "кінетична енергія ланки {k}: m v{S}^2/2 + J omega^2/2",
        "U_k": "потенціальна енергія ланки {k}: -m g.r{S}",
        "chk_T_k": "перевірка: T_{k} через модуль швидкості v{S} (відносна нев'язка)",
        "Fix": "сила інерції ланки {k} (Д'Аламбер): -m a{S}, x",
        "Fiy": "сила інерції ланки {k}: -m a{S}, y",
        "Mi": "момент сил інерції ланки {k}: -J eps",
        "chk_Fi": "перевірка: |Fi_{k}| = m a{S} (відносна нев'язка)",
        "on": "{n} діє (1) або немає (0)",
        "P_n": "потужність зовнішньої навантаження {n}",
        "P_ext": "потужність зовнішніх сил і моментів",
        "T": "кінетична енергія механізму",
        "U": "потенціальна енергія механізму",
        "chk_T": "перевірка: T = сума m v^2/2 + J omega^2/2 за модулями швидкостей (відносна нев'язка)",
        "chk_U": "перевірка: U_k = -m_k g.r_S і U = сума U_k (відносна нев'язка)",
        "T_t": "швидкість зміни кінетичної енергії: сума m v.a + J omega eps",
        "U_t": "швидкість зміни потенціальної енергії: -сума m g.v",
        "chk_P_in": "перевірка: потужність сил інерції + dT/dt = 0 (відносно суми модулів доданків)",
        "fd": "{q}: чисельна похідна (відносна нев'язка)",
        "forces": "Динамічний аналіз: реакції в кінематичних парах (кінетостатика груп Ассура)",
        "forces_g": "Група {i} ({kind} {joints}): реакції",
        "forces_crank": "Кривошип: реакція стояка і зрівноважувальний момент",
        "R_01": "стояка на кривошип в {at}",
        "M_bal": "зрівноважувальний момент на кривошипі (проти годинникової +)",
        "P_bal": "потужність зрівноважувального моменту M_bal Fi_t",
        "balance": "енергетичний баланс: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (відносна нев'язка)",
    },
    "en": {
        "g_x": "gravity, x component",
        "g_y": "gravity, y component",
        "m": "mass of link {k} (centre of mass {S})",
        "J": "moment of inertia of link {k} about {S}",
        "on_link": "link {k}",
        "on_point": "link {k}, point {at}",
        "Fx": "external force {n} ({where}): x component",
        "Fy": "external force {n} ({where}): y component",
        "Mz": "external moment {n} on link {k} (counterclockwise +)",
        "from": "{n} acts from the crank angle",
        "to": "{n} acts up to the crank angle",
        "energy": "Energy analysis of the mechanism",
        "T_k": "kinetic energy of link {k}: m v{S}^2/2 + J omega^2/2",
        "U_k": "potential energy of link {k}: -m g.r{S}",
        "chk_T_k": "check: T_{k} from the speed v{S} (relative)",
        "Fix": "inertia force of link {k} (d'Alembert): -m a{S}, x",
        "Fiy": "inertia force of link {k}: -m a{S}, y",
        "Mi": "inertia moment of link {k}: -J eps",
        "chk_Fi": "check: |Fi_{k}| = m a{S} (relative)",
        "on": "{n} acts (1) or not (0)",
        "P_n": "power of the external load {n}",
        "P_ext": "power of the external forces and moments",
        "T": "kinetic energy of the mechanism",
        "U": "potential energy of the mechanism",
        "chk_T": "check: T = sum of m v^2/2 + J omega^2/2 from the speeds (relative)",
        "chk_U": "check: U_k = -m_k g.r_S and U = the sum of U_k (relative)",
        "T_t": "rate of change of the kinetic energy: sum of m v.a + J omega eps",
        "U_t": "rate of change of the potential energy: -sum of m g.v",
        "chk_P_in": "check: power of the inertia forces + dT/dt = 0 (relative to the sum of the terms' sizes)",
        "fd": "{q} against the numeric derivative (relative)",
        "forces": "Dynamic analysis: joint reactions (kinetostatics of the Assur groups)",
        "forces_g": "Group {i} ({kind} {joints}): reactions",
        "forces_crank": "The crank: the frame's reaction and the balancing moment",
        "R_01": "of the frame on the crank at {at}",
        "M_bal": "balancing moment on the crank (counterclockwise +)",
        "P_bal": "power of the balancing moment M_bal Fi_t",
        "balance": "energy balance: M_bal Fi_t + P_ext - dU/dt - dT/dt = 0 (relative)",
    },
}
T = Texts(TEXTS)


def dynamics_inputs(b: Builder):
    """Masses, moments of inertia, gravity and external loads (docs: `sheetkin docs dynamics`)."""
    sc = b.scene
    if any(sc.gravity):
        b.given("g_x", "m/s^2", T("g_x"), sc.gravity[0])
        b.given("g_y", "m/s^2", T("g_y"), sc.gravity[1])
    for m in sc.masses:
        b.given(f"m_{m.link}", "kg", T("m", k=m.link, S=m.centre), m.mass)
        b.given(f"J_{m.link}", "kg m^2", T("J", k=m.link, S=m.centre), m.inertia)
    for f in sc.forces:
        n = f.name
        where = T("on_point", k=f.link, at=f.at) if f.at else T("on_link", k=f.link)
        if f.at:
            b.given(f"Fx_{n}", "N", T("Fx", n=n, where=where), f.force[0])
            b.given(f"Fy_{n}", "N", T("Fy", n=n, where=where), f.force[1])
        if f.moment or not f.at:
            b.given(f"Mz_{n}", "N m", T("Mz", n=n, k=f.link), f.moment)
        if f.interval_deg:
            b.given(f"from_{n}", "deg", T("from", n=n), f.interval_deg[0])
            b.given(f"to_{n}", "deg", T("to", n=n), f.interval_deg[1])


def _rates(b: Builder, k: int) -> tuple[str, str]:
    """Angular velocity and acceleration of link k as references."""
    _, _, w, e = b.rot[k]
    return f"{{{w}}}", f"{{{e}}}"


def energy_rows(b: Builder):
    """The lecture's energy analysis (seed 003): the centres of mass' energies, the
    d'Alembert inertia forces, the energies' rates of change, the power of external loads."""
    sc = b.scene
    b.section("energy", T("energy"))
    t_rate, u_rate = [], []
    for mass in sc.masses:
        t, u = _link_energy_rows(b, mass.link, mass.centre)
        t_rate.append(t)
        u_rate += u
    if sc.masses:
        _energy_totals(b, t_rate, u_rate)
    _load_power_rows(b)


def _link_energy_rows(b: Builder, k: int, S: str) -> tuple[str, list[str]]:
    """Link k with its mass at S: its kinetic and potential energy, the d'Alembert inertia
    force and moment, each with its check; returns the terms of dT/dt and dU/dt."""
    m, J = f"{{m_{k}}}", f"{{J_{k}}}"
    w, e = _rates(b, k)
    vx, vy, ax, ay = (b.p(q, S) for q in ("vx", "vy", "ax", "ay"))
    b.accepted(f"T_{k}", "J", T("T_k", k=k, S=S), f"{m}*({vx}^2+{vy}^2)/2+{J}*{w}^2/2")
    u_rate = []
    if any(b.scene.gravity):
        b.accepted(f"U_{k}", "J", T("U_k", k=k, S=S), f"-{m}*({{g_x}}*{b.p('x', S)}+{{g_y}}*{b.p('y', S)})")
        u_rate.append(f"-{m}*({{g_x}}*{vx}+{{g_y}}*{vy})")
    v = f"{{v_{S}}}" if S not in b.frame else "0"
    # relative to the sizes at the same position (not to the row's largest value): the
    # check then reads only its own column, free of the step and of the other positions
    b.check(f"chk_T_{k}", "", T("chk_T_k", k=k, S=S),
            f"({{T_{k}}}-{m}*{v}^2/2-{J}*{w}^2/2)/(ABS({{T_{k}}})+{m}*{v}^2/2+{J}*{w}^2/2+1E-300)")
    b.accepted(f"Fix_{k}", "N", T("Fix", k=k, S=S), f"-{m}*{ax}")
    b.accepted(f"Fiy_{k}", "N", T("Fiy", k=k, S=S), f"-{m}*{ay}")
    b.accepted(f"Mi_{k}", "N m", T("Mi", k=k), f"-{J}*{e}")
    a = f"{{a_{S}}}" if S not in b.frame else "0"
    b.check(f"chk_Fi_{k}", "", T("chk_Fi", k=k, S=S),
            f"(SQRT({{Fix_{k}}}^2+{{Fiy_{k}}}^2)-{m}*{a})/(SQRT({{Fix_{k}}}^2+{{Fiy_{k}}}^2)+{m}*ABS({a})+1E-300)")
    return f"{m}*({vx}*{ax}+{vy}*{ay})+{J}*{w}*{e}", u_rate


def _load_power_rows(b: Builder):
    """The power of each external load (switched on over its interval of crank angles) and
    their sum P_ext."""
    powers = []
    for f in b.scene.forces:
        n = f.name
        on = ""
        if f.interval_deg:
            b.calc(f"on_{n}", "", T("on", n=n), f"IF(MOD({{phi_1}}-{{from_{n}}},360)<={{to_{n}}}-{{from_{n}}},1,0)")
            on = f"{{on_{n}}}*"
        terms = []
        if f.at:
            terms.append(f"{{Fx_{n}}}*{b.p('vx', f.at)}+{{Fy_{n}}}*{b.p('vy', f.at)}")
        if f.moment or not f.at:
            terms.append(f"{{Mz_{n}}}*{_rates(b, f.link)[0]}")
        b.calc(f"P_{n}", "W", T("P_n", n=n), f"{on}({'+'.join(terms)})")
        powers.append(f"{{P_{n}}}")
    if b.scene.forces:
        b.accepted("P_ext", "W", T("P_ext"), "+".join(powers))


def _energy_totals(b: Builder, t_rate: list[str], u_rate: list[str]):
    """The mechanism's energies and their rates, with the checks of the rates."""
    sc, gravity = b.scene, any(b.scene.gravity)
    b.accepted("T", "J", T("T"), "+".join(f"{{T_{m.link}}}" for m in sc.masses))
    if gravity:
        b.accepted("U", "J", T("U"), "+".join(f"{{U_{m.link}}}" for m in sc.masses))
    # the totals once more from the links' speeds and heights, not from the T_k, U_k rows
    # (free of the step; relative to the terms' sizes, as the energies may be near 0)
    t_terms = [f"{{m_{m.link}}}*{v}^2/2+{{J_{m.link}}}*{_rates(b, m.link)[0]}^2/2"
               for m in sc.masses for v in [f"{{v_{m.centre}}}" if m.centre not in b.frame else "0"]]
    b.check("chk_T", "", T("chk_T"), f"({{T}}-({'+'.join(t_terms)}))/(ABS({{T}})+{'+'.join(t_terms)}+1E-300)")
    if gravity:
        u_terms = [f"{{m_{m.link}}}*({{g_x}}*{b.p('x', m.centre)}+{{g_y}}*{b.p('y', m.centre)})" for m in sc.masses]
        each = "+".join(f"ABS({{U_{m.link}}}+{t})" for m, t in zip(sc.masses, u_terms, strict=False))
        size = "+".join(f"ABS({t})" for t in u_terms)
        b.check("chk_U", "", T("chk_U"), f"(ABS({{U}}+({'+'.join(u_terms)}))+{each})/({size}+1E-300)")
    b.accepted("T_t", "W", T("T_t"), "+".join(t_rate))
    if gravity:
        b.accepted("U_t", "W", T("U_t"), "+".join(u_rate))
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
    b.check("chk_P_in", "", T("chk_P_in"),
            f"({'+'.join(p_terms)}+{{T_t}})/({'+'.join(f'ABS({t})' for t in p_terms)}+ABS({{T_t}})+1E-300)")
    b.fdcheck("fd_T_t", T("fd", q="T_t"),
              "({T_t}-{Fi_t}*({T@next}-{T@prev})/(2*{Delta_Fi_rad})-2*{Fi_tt}*{T}/{Fi_t})/{scale:T_t}")
    if gravity:
        b.fdcheck("fd_U_t", T("fd", q="U_t"), "({U_t}-{Fi_t}*({U@next}-{U@prev})/(2*{Delta_Fi_rad}))/{scale:U_t}")


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
    b.section("forces", T("forces"))
    k = LoadRows(b, loads, couples)
    for g in reversed(sc.groups):
        b.section(f"forces_g{g.index}", T("forces_g", i=g.index, kind=g.type, joints="-".join(g.joints)))
        kind_of(g).reaction_rows(b, g, owner, k)
    c = sc.crank
    b.section("forces_crank", T("forces_crank"))
    k.link_loads(1, c.pivot)
    k.reaction("0_1", "-{Qx_1}", "-{Qy_1}", T("R_01", at=c.pivot))
    b.accepted("M_bal", "N m", T("M_bal"), "-{MQ_1}")
    k.equilibrium(1, c.pivot, [(c.pivot, "{Rx_0_1}", "{Ry_0_1}")], "{M_bal}")
    b.accepted("P_bal", "W", T("P_bal"), "{M_bal}*{Fi_t}")
    terms = (["{P_bal}"] + (["{P_ext}"] if sc.forces else []) + (["-{U_t}"] if gravity and sc.masses else [])
             + (["-{T_t}"] if sc.masses else []))
    size = "+".join(f"ABS({t.lstrip('-')})" for t in terms)
    b.check("chk_balance", "", T("balance"),
            f"({''.join(t if t.startswith('-') else '+' + t for t in terms)[1:]})/({size}+1E-300)")
