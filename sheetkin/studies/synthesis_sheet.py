"""The synthesis sheet: the crank-rocker's synthesis (sheetkin.studies.synthesis) written as
live formulas, in Russian, Ukrainian or English, alone (`sheetkin synth --workbook`) or beside
a scene's kinematics sheet (`sheetkin workbook` of a scene with a [synthesis] table), with
check rows comparing the two. The mathematics and the scene's table stay in synthesis.py;
this module only writes the sheet.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .synthesis import fourbar_dyad, scene_mismatches

# --------------------------------------------------------------------------- the workbook
SYNTH_SHEET_TITLES = {"ru": "Синтез", "uk": "Синтез", "en": "Synthesis"}
_ARC_POINTS = 31
# (name, unit, ru, en, formula | None for an input, "cand" for a per-root row in D and E); a
# section's name is "#..." (its title in ru, en; the Ukrainian texts are in _UK_ROWS).
# In formulas {name} is the value cell $D$r of the row `name`, {c} the candidate's column.
_SYNTH_ROWS = [
    ("#given", "", "Исходные данные", "Given data"),
    ("K_w", "", "коэффициент изменения средней скорости хода коромысла", "time-ratio coefficient"),
    ("l3", "m", "длина коромысла |DB|", "rocker length |DB|"),
    ("Y_D", "m", "ордината центра вращения коромысла D", "ordinate of the rocker pivot D"),
    ("gamma1_deg", "deg", "угол коромысла в начальном (разогнутом) крайнем положении",
     "rocker angle at the extended dead position"),
    ("gamma2_deg", "deg", "угол коромысла в конечном (сложенном) крайнем положении",
     "rocker angle at the folded dead position"),
    ("phi_ref_deg", "deg", "приближение phi1H (из нескольких корней выбирается ближайший)",
     "initial guess of phi1H (of several roots the nearest is chosen)"),
    ("Tol", "", "допуск проверок", "tolerance of the checks"),
    ("#overlap", "", "Угол перекрытия", "Overlap angle"),
    ("theta", "rad", "theta = pi (K_w - 1)/(K_w + 1)", "theta = pi (K_w - 1)/(K_w + 1)",
     "=PI()*({K_w}-1)/({K_w}+1)"),
    ("theta_deg", "deg", "угол перекрытия, град", "overlap angle, deg", "=DEGREES({theta})"),
    ("g1", "rad", "gamma1, рад", "gamma1, rad", "=RADIANS({gamma1_deg})"),
    ("g2", "rad", "gamma2, рад", "gamma2, rad", "=RADIANS({gamma2_deg})"),
    ("#closed", "", "Решение в замкнутой форме: a ctg(phi) - b ctg(phi + theta) = c",
     "Closed-form solution: a cot(phi) - b cot(phi + theta) = c"),
    ("a", "m", "a = Y_D + l3 sin(gamma1)", "a = Y_D + l3 sin(gamma1)", "={Y_D}+{l3}*SIN({g1})"),
    ("b", "m", "b = Y_D + l3 sin(gamma2)", "b = Y_D + l3 sin(gamma2)", "={Y_D}+{l3}*SIN({g2})"),
    ("c", "m", "c = l3 (cos(gamma1) - cos(gamma2))", "c = l3 (cos(gamma1) - cos(gamma2))",
     "={l3}*(COS({g1})-COS({g2}))"),
    ("p", "m", "p = a - b; psi = 2 phi + theta: p sin(psi) + c cos(psi) = r",
     "p = a - b; psi = 2 phi + theta: p sin(psi) + c cos(psi) = r", "={a}-{b}"),
    ("r", "m", "r = c cos(theta) - (a + b) sin(theta)", "r = c cos(theta) - (a + b) sin(theta)",
     "={c}*COS({theta})-({a}+{b})*SIN({theta})"),
    ("m", "m", "m = sqrt(p^2 + c^2)", "m = sqrt(p^2 + c^2)", "=SQRT({p}^2+{c}^2)"),
    ("solvable", "", "уравнение имеет корни: m > 0, |r| <= m",
     "the equation has roots: m > 0, |r| <= m", "=AND({m}>0,ABS({r})<={m}*(1+1E-12))"),
    ("beta", "rad", "beta = atan2(p, c)", "beta = atan2(p, c)", "=ATAN2({c},{p})"),
    ("delta", "rad", "delta = acos(r/m)", "delta = acos(r/m)",
     "=ACOS(MAX(-1,MIN(1,IF({m}>0,{r}/{m},0))))"),
    ("#roots", "", "Два корня (D: psi = beta + delta, E: psi = beta - delta); при phi четыре уравнения "
     "линейны в R1 = l1 + l2, R2 = l2 - l1, X_D: нормальные уравнения (точны в корне, годны и при "
     "theta = 0)",
     "Two roots (D: psi = beta + delta, E: psi = beta - delta); at phi the four equations are "
     "linear in R1 = l1 + l2, R2 = l2 - l1, X_D: the normal equations (exact at a root, also for "
     "theta = 0)"),
    ("phi0", "rad", "phi = (psi - theta)/2", "phi = (psi - theta)/2",
     "cand", "=({beta}+{delta}-{theta})/2", "=({beta}-{delta}-{theta})/2"),
    ("den", "", "sin^2(phi) + sin^2(phi + theta): 0 только при theta = 0, phi = 0 или pi (не корень)",
     "sin^2(phi) + sin^2(phi + theta): 0 only for theta = 0, phi = 0 or pi (not a root)",
     "cand", "=SIN({c}@phi0)^2+SIN({c}@phi0+{theta})^2"),
    ("X_D_c", "m", "X_D = (x s1 + y s2 - l3 (cos(gamma1) + cos(gamma2)))/den, x = cos(phi), "
     "y = cos(phi + theta), s1 = l3 cos(gamma1) x + a sin(phi), s2 = l3 cos(gamma2) y + "
     "b sin(phi + theta)",
     "X_D = (x s1 + y s2 - l3 (cos(gamma1) + cos(gamma2)))/den, x = cos(phi), "
     "y = cos(phi + theta), s1 = l3 cos(gamma1) x + a sin(phi), s2 = l3 cos(gamma2) y + "
     "b sin(phi + theta)",
     "cand", "=IF({c}@den>0,(COS({c}@phi0)*({l3}*COS({g1})*COS({c}@phi0)+{a}*SIN({c}@phi0))"
             "+COS({c}@phi0+{theta})*({l3}*COS({g2})*COS({c}@phi0+{theta})+{b}*SIN({c}@phi0+{theta}))"
             "-{l3}*(COS({g1})+COS({g2})))/{c}@den,0)"),
    ("R1_0", "m", "l1 + l2 при phi: s1 + x X_D", "l1 + l2 at phi: s1 + x X_D",
     "cand", "={l3}*COS({g1})*COS({c}@phi0)+{a}*SIN({c}@phi0)+COS({c}@phi0)*{c}@X_D_c"),
    ("flip", "", "-1: phi + pi даёт l1 + l2 > 0", "-1: phi + pi gives l1 + l2 > 0",
     "cand", "=IF({c}@R1_0<0,-1,1)"),
    ("phi", "rad", "phi1H-кандидат", "candidate phi1H",
     "cand", "={c}@phi0+IF({c}@flip<0,PI(),0)"),
    ("R1", "m", "R1 = l1 + l2", "R1 = l1 + l2", "cand", "={c}@flip*{c}@R1_0"),
    ("R2", "m", "R2 = l2 - l1 = s2 + y X_D", "R2 = l2 - l1 = s2 + y X_D",
     "cand", "={c}@flip*({l3}*COS({g2})*COS({c}@phi0+{theta})+{b}*SIN({c}@phi0+{theta})"
             "+COS({c}@phi0+{theta})*{c}@X_D_c)"),
    ("fit", "m", "наибольшая невязка четырёх уравнений (у постороннего корня велика)",
     "the four equations' largest residual (large at a spurious root)",
     "cand", "=MAX(ABS({c}@R1*COS({c}@phi)-{c}@X_D_c-{l3}*COS({g1})),ABS({c}@R1*SIN({c}@phi)-{a}),"
             "ABS({c}@R2*COS({c}@phi+{theta})-{c}@X_D_c-{l3}*COS({g2})),"
             "ABS({c}@R2*SIN({c}@phi+{theta})-{b}))"),
    ("l1_c", "m", "l1 = (R1 - R2)/2", "l1 = (R1 - R2)/2", "cand", "=({c}@R1-{c}@R2)/2"),
    ("l2_c", "m", "l2 = (R1 + R2)/2", "l2 = (R1 + R2)/2", "cand", "=({c}@R1+{c}@R2)/2"),
    ("OD_c", "m", "длина стойки |OD|", "frame length |OD|",
     "cand", "=SQRT({c}@X_D_c^2+{Y_D}^2)"),
    ("phi_deg_c", "deg", "phi1H, град, 0..360", "phi1H, deg, 0..360",
     "cand", "=MOD(DEGREES({c}@phi),360)"),
    ("side_H", "m^2", "сторона B относительно A->D, начальное положение",
     "side of B relative to A->D, extended position",
     "cand", "=({c}@X_D_c-{c}@l1_c*COS({c}@phi))*({Y_D}+{l3}*SIN({g1})-{c}@l1_c*SIN({c}@phi))"
             "-({Y_D}-{c}@l1_c*SIN({c}@phi))*({c}@X_D_c+{l3}*COS({g1})-{c}@l1_c*COS({c}@phi))"),
    ("side_K", "m^2", "сторона B относительно A->D, конечное положение",
     "side of B relative to A->D, folded position",
     "cand", "=({c}@X_D_c+{c}@l1_c*COS({c}@phi+{theta}))*({Y_D}+{l3}*SIN({g2})+{c}@l1_c*SIN({c}@phi+{theta}))"
             "-({Y_D}+{c}@l1_c*SIN({c}@phi+{theta}))*({c}@X_D_c+{l3}*COS({g2})+{c}@l1_c*COS({c}@phi+{theta}))"),
    ("valid", "", "кривошипно-коромысловый: корень, l2 > l1 > 0, кривошип короче всех, Грасгоф "
     "строго, одна сборка в обоих положениях",
     "a crank-rocker: a root, l2 > l1 > 0, the crank the shortest link, Grashof strictly, one "
     "branch in both positions",
     "cand", "=AND({solvable},{c}@fit<=1E-9*MAX({l3},ABS({Y_D})),{c}@R1>0,{c}@R2>0,{c}@R1>{c}@R2,"
             "{c}@l1_c<=MIN({c}@l2_c,{l3},{c}@OD_c),"
             "MIN({c}@l1_c,{c}@l2_c,{l3},{c}@OD_c)+MAX({c}@l1_c,{c}@l2_c,{l3},{c}@OD_c)<"
             "({c}@l1_c+{c}@l2_c+{l3}+{c}@OD_c-MIN({c}@l1_c,{c}@l2_c,{l3},{c}@OD_c)"
             "-MAX({c}@l1_c,{c}@l2_c,{l3},{c}@OD_c))*(1-1E-9),{c}@side_H*{c}@side_K>0)"),
    ("dist", "deg", "|phi1H - приближение|", "|phi1H - initial guess|",
     "cand", "=ABS(MOD({c}@phi_deg_c-{phi_ref_deg}+180,360)-180)"),
    ("root", "", "выбранный корень: 1 (D), 2 (E), 0 - нет решения",
     "chosen root: 1 (D), 2 (E), 0 - no solution",
     "=IF(AND(D{valid},E{valid}),IF(D{dist}<=E{dist},1,2),IF(D{valid},1,IF(E{valid},2,0)))"),
    ("#solution", "", "Решение", "Solution"),
    ("l1", "m", "длина кривошипа", "crank length", "=IF({root}=0,\"{marker}\",IF({root}=1,D{l1_c},E{l1_c}))"),
    ("l2", "m", "длина шатуна", "coupler length", "=IF({root}=0,\"{marker}\",IF({root}=1,D{l2_c},E{l2_c}))"),
    ("phi1H_deg", "deg", "угол кривошипа в начальном положении",
     "crank angle at the extended dead position",
     "=IF({root}=0,\"{marker}\",IF({root}=1,D{phi_deg_c},E{phi_deg_c}))"),
    ("X_D", "m", "абсцисса центра вращения коромысла D", "abscissa of the rocker pivot D",
     "=IF({root}=0,\"{marker}\",IF({root}=1,D{X_D_c},E{X_D_c}))"),
    ("branch", "", "ветвь группы A-B-D сцены: сторона B относительно A->D (+1 слева)",
     "the scene's branch of the dyad A-B-D: the side of B relative to A->D (+1 left)",
     "=IF({root}=0,\"{marker}\",SIGN(IF({root}=1,D{side_H},E{side_H})))"),
    ("phi1H", "rad", "phi1H, рад", "phi1H, rad", "=RADIANS({phi1H_deg})"),
    ("#check", "", "Проверка: решение в четырёх уравнениях (левая часть - правая)",
     "Check: the solution in the four equations (left side - right side)"),
    ("res_1", "m", "(l1 + l2) cos(phi1H) - X_D - l3 cos(gamma1)",
     "(l1 + l2) cos(phi1H) - X_D - l3 cos(gamma1)",
     "=({l1}+{l2})*COS({phi1H})-({X_D}+{l3}*COS({g1}))"),
    ("res_2", "m", "(l1 + l2) sin(phi1H) - Y_D - l3 sin(gamma1)",
     "(l1 + l2) sin(phi1H) - Y_D - l3 sin(gamma1)",
     "=({l1}+{l2})*SIN({phi1H})-({Y_D}+{l3}*SIN({g1}))"),
    ("res_3", "m", "(l2 - l1) cos(phi1H + theta) - X_D - l3 cos(gamma2)",
     "(l2 - l1) cos(phi1H + theta) - X_D - l3 cos(gamma2)",
     "=({l2}-{l1})*COS({phi1H}+{theta})-({X_D}+{l3}*COS({g2}))"),
    ("res_4", "m", "(l2 - l1) sin(phi1H + theta) - Y_D - l3 sin(gamma2)",
     "(l2 - l1) sin(phi1H + theta) - Y_D - l3 sin(gamma2)",
     "=({l2}-{l1})*SIN({phi1H}+{theta})-({Y_D}+{l3}*SIN({g2}))"),
]
# In a scene's workbook: the kinematics sheet's input block against the solution ({kin:L1} is
# that sheet's cell of L1, ...; O the crank's pivot, D the rocker's). Check rows, like res_*.
_LINK_ROWS = [
    ("#kinematics", "", "Проверка: лист кинематики считает синтезированный механизм (его исходные данные "
     "- решение)", "Check: the kinematics sheet computes the synthesized mechanism (its input "
     "data - the solution)"),
    ("kin_l1", "m", "L1 (лист кинематики) - l1", "L1 (kinematics sheet) - l1", "={kin:L1}-{l1}"),
    ("kin_l2", "m", "длина шатуна (лист кинематики) - l2", "coupler length (kinematics sheet) - l2",
     "={kin:L2}-{l2}"),
    ("kin_l3", "m", "длина коромысла (лист кинематики) - l3",
     "rocker length (kinematics sheet) - l3", "={kin:L3}-{l3}"),
    ("kin_X_D", "m", "x_D - x_O (лист кинематики) - X_D", "x_D - x_O (kinematics sheet) - X_D",
     "={kin:x_D}-{kin:x_O}-{X_D}"),
    ("kin_Y_D", "m", "y_D - y_O (лист кинематики) - Y_D", "y_D - y_O (kinematics sheet) - Y_D",
     "={kin:y_D}-{kin:y_O}-{Y_D}"),
    ("kin_branch", "", "ветвь группы 1 (лист кинематики) - branch",
     "group 1's branch (kinematics sheet) - branch", "={kin:branch}-{branch}"),
]
# The Ukrainian texts of the rows (the Russian and English ones are in the rows above), by
# row name or section ("#given" ...), and of the dead positions' points
_UK_ROWS = {
    "#given": "Вихідні дані", "K_w": "коефіцієнт зміни середньої швидкості ходу коромисла",
    "l3": "довжина коромисла |DB|", "Y_D": "ордината центра обертання коромисла D",
    "gamma1_deg": "кут коромисла в початковому (розігнутому) крайньому положенні",
    "gamma2_deg": "кут коромисла в кінцевому (складеному) крайньому положенні",
    "phi_ref_deg": "наближення phi1H (з кількох коренів обирається найближчий)", "Tol": "допуск перевірок",
    "#overlap": "Кут перекриття", "theta": "theta = pi (K_w - 1)/(K_w + 1)", "theta_deg": "кут перекриття, град",
    "g1": "gamma1, рад", "g2": "gamma2, рад",
    "#closed": "Розв'язок у замкненій формі: a ctg(phi) - b ctg(phi + theta) = c",
    "a": "a = Y_D + l3 sin(gamma1)", "b": "b = Y_D + l3 sin(gamma2)", "c": "c = l3 (cos(gamma1) - cos(gamma2))",
    "p": "p = a - b; psi = 2 phi + theta: p sin(psi) + c cos(psi) = r",
    "r": "r = c cos(theta) - (a + b) sin(theta)", "m": "m = sqrt(p^2 + c^2)",
    "solvable": "рівняння має корені: m > 0, |r| <= m", "beta": "beta = atan2(p, c)", "delta": "delta = acos(r/m)",
    "#roots": "Два корені (D: psi = beta + delta, E: psi = beta - delta); при phi чотири рівняння лінійні "
              "відносно R1 = l1 + l2, R2 = l2 - l1, X_D: нормальні рівняння (точні в корені, придатні й при "
              "theta = 0)",
    "phi0": "phi = (psi - theta)/2",
    "den": "sin^2(phi) + sin^2(phi + theta): 0 лише при theta = 0, phi = 0 або pi (не корінь)",
    "X_D_c": "X_D = (x s1 + y s2 - l3 (cos(gamma1) + cos(gamma2)))/den, x = cos(phi), y = cos(phi + theta), "
             "s1 = l3 cos(gamma1) x + a sin(phi), s2 = l3 cos(gamma2) y + b sin(phi + theta)",
    "R1_0": "l1 + l2 при phi: s1 + x X_D", "flip": "-1: phi + pi дає l1 + l2 > 0", "phi": "phi1H-кандидат",
    "R1": "R1 = l1 + l2", "R2": "R2 = l2 - l1 = s2 + y X_D",
    "fit": "найбільша нев'язка чотирьох рівнянь (у стороннього кореня велика)",
    "l1_c": "l1 = (R1 - R2)/2", "l2_c": "l2 = (R1 + R2)/2", "OD_c": "довжина стояка |OD|",
    "phi_deg_c": "phi1H, град, 0..360", "side_H": "бік B відносно A->D, початкове положення",
    "side_K": "бік B відносно A->D, кінцеве положення",
    "valid": "кривошипно-коромисловий: корінь, l2 > l1 > 0, кривошип коротший за всі ланки, Грасгоф строго, "
             "одне складання в обох положеннях",
    "dist": "|phi1H - наближення|", "root": "обраний корінь: 1 (D), 2 (E), 0 - немає розв'язку",
    "#solution": "Розв'язок", "l1": "довжина кривошипа", "l2": "довжина шатуна",
    "phi1H_deg": "кут кривошипа в початковому положенні", "X_D": "абсциса центра обертання коромисла D",
    "branch": "гілка групи A-B-D сцени: бік B відносно A->D (+1 ліворуч)", "phi1H": "phi1H, рад",
    "#check": "Перевірка: розв'язок у чотирьох рівняннях (ліва частина - права)",
    "res_1": "(l1 + l2) cos(phi1H) - X_D - l3 cos(gamma1)", "res_2": "(l1 + l2) sin(phi1H) - Y_D - l3 sin(gamma1)",
    "res_3": "(l2 - l1) cos(phi1H + theta) - X_D - l3 cos(gamma2)",
    "res_4": "(l2 - l1) sin(phi1H + theta) - Y_D - l3 sin(gamma2)",
    "#kinematics": "Перевірка: аркуш кінематики обчислює синтезований механізм (його вихідні дані - розв'язок)",
    "kin_l1": "L1 (аркуш кінематики) - l1", "kin_l2": "довжина шатуна (аркуш кінематики) - l2",
    "kin_l3": "довжина коромисла (аркуш кінематики) - l3", "kin_X_D": "x_D - x_O (аркуш кінематики) - X_D",
    "kin_Y_D": "y_D - y_O (аркуш кінематики) - Y_D", "kin_branch": "гілка групи 1 (аркуш кінематики) - branch",
    "X_H": "абсциси, початкове положення", "Y_H": "ординати, початкове положення",
    "X_K": "абсциси, кінцеве положення", "Y_K": "ординати, кінцеве положення",
}
_SYNTH_TEXT = {
    "ru": {"name": "имя", "unit": "ед.", "desc": "описание", "value": "значение / корень 1",
           "value2": "корень 2", "checks": "проверки", "pass": "все проверки выполнены",
           "fail": "проверки не выполнены", "marker": "нет решения",
           "title": "Синтез кривошипно-коромыслового механизма по коэффициенту K_w",
           "points": "Крайние положения: точки O, A, B, D", "arc": "Дуга коромысла (точка B)",
           "chart": "Механизм в крайних положениях", "H": "начальное (разогнутое)",
           "K": "конечное (сложенное)", "arcs": "дуга коромысла", "k": "номер точки",
           "gamma": "угол коромысла", "axis_x": "x, м", "axis_y": "y, м"},
    "uk": {"name": "ім'я", "unit": "од.", "desc": "опис", "value": "значення / корінь 1",
           "value2": "корінь 2", "checks": "перевірки", "pass": "усі перевірки виконано",
           "fail": "перевірки не виконано", "marker": "немає розв'язку",
           "title": "Синтез кривошипно-коромислового механізму за коефіцієнтом K_w",
           "points": "Крайні положення: точки O, A, B, D", "arc": "Дуга коромисла (точка B)",
           "chart": "Механізм у крайніх положеннях", "H": "початкове (розігнуте)",
           "K": "кінцеве (складене)", "arcs": "дуга коромисла", "k": "номер точки",
           "gamma": "кут коромисла", "axis_x": "x, м", "axis_y": "y, м"},
    "en": {"name": "name", "unit": "unit", "desc": "description", "value": "value / root 1",
           "value2": "root 2", "checks": "checks", "pass": "all checks pass",
           "fail": "checks fail", "marker": "no solution",
           "title": "Synthesis of a crank-rocker from the time-ratio coefficient K_w",
           "points": "Dead positions: points O, A, B, D", "arc": "The rocker's arc (point B)",
           "chart": "The mechanism in its dead positions", "H": "extended",
           "K": "folded", "arcs": "rocker's arc", "k": "point number", "gamma": "rocker angle",
           "axis_x": "x, m", "axis_y": "y, m"},
}


def row_text(row: tuple, lang: str) -> str:
    """A row's (or a section's) description in `lang`: its Russian or English text, or the
    Ukrainian of _UK_ROWS."""
    return _UK_ROWS[row[0]] if lang == "uk" else row[2] if lang == "ru" else row[3]


@dataclass
class _SynthSheet:
    """The synthesis sheet being written: where each named row sits, and how its formula
    templates become cell formulas ({name} an absolute cell, D{name}/E{name} a root's)."""
    ws: Any
    text: dict[str, str]
    lang: str
    where: dict[str, int]
    pts: dict[str, int]
    arc: dict[str, int]
    after: int
    arc0: int
    kinematics: dict[str, str] | None

    def fill(self, tpl: str, col: str = "D") -> str:
        import re
        where = self.where
        tpl = tpl.replace("{marker}", self.text["marker"])
        tpl = re.sub(r"\{kin:(\w+)\}", lambda m: (self.kinematics or {})[m.group(1)], tpl)
        tpl = re.sub(r"\{c\}@(\w+)", lambda m: f"{col}{where[m.group(1)]}", tpl)
        tpl = re.sub(r"D\{(\w+)\}", lambda m: f"D{where[m.group(1)]}", tpl)
        tpl = re.sub(r"E\{(\w+)\}", lambda m: f"E{where[m.group(1)]}", tpl)
        return re.sub(r"\{(\w+)\}", lambda m: f"$D${where[m.group(1)]}", tpl)


def add_synthesis_sheet(wb, kw: float, l3: float, yd: float, gamma1_deg: float,
                        gamma2_deg: float, lang: str = "ru", *, tol: float = 1e-9,
                        phi_ref_deg: float = 30.0, kinematics: dict[str, str] | None = None,
                        index: int | None = None):
    """Add to the openpyxl Workbook `wb` (at `index`, default last) the sheet solving seed 002
    with live formulas, titled SYNTH_SHEET_TITLES[lang]: the given data (yellow, editable),
    theta, the closed form above with its two roots side by side (columns D, E) and the choice
    between them written with IF (the same rules as synthesize_crank_rocker; K_w = 1 too), the
    four equations' residuals against Tol, the dead positions' points, the rocker's arc and a
    chart of both. With `kinematics` ({"L1", "L2", "L3", "x_O", "y_O", "x_D", "y_D", "branch"}
    -> a cell of another sheet), check rows compare those cells with the solution as well.
    Returns the sheet."""
    if lang not in _SYNTH_TEXT:
        raise ValueError(f"lang must be one of {', '.join(_SYNTH_TEXT)}, got {lang!r}")
    values = {"K_w": kw, "l3": l3, "Y_D": yd, "gamma1_deg": gamma1_deg,
              "gamma2_deg": gamma2_deg, "phi_ref_deg": phi_ref_deg, "Tol": tol}
    rows = _SYNTH_ROWS + (_LINK_ROWS if kinematics else [])
    first = 5
    where = {row[0]: first + k for k, row in enumerate(rows) if not row[0].startswith("#")}
    after = first + len(rows) + 1
    pts = {"X_H": after + 1, "Y_H": after + 2, "X_K": after + 3, "Y_K": after + 4}
    arc0 = after + 6
    arc = {"k": arc0 + 1, "gamma_arc": arc0 + 2, "X_arc": arc0 + 3, "Y_arc": arc0 + 4}
    where.update(pts)
    ws = wb.create_sheet(SYNTH_SHEET_TITLES[lang], index)
    sheet = _SynthSheet(ws, _SYNTH_TEXT[lang], lang, where, pts, arc, after, arc0, kinematics)
    _synthesis_rows(sheet, rows, values, first)
    _synthesis_verdict(sheet)
    _dead_position_rows(sheet)
    _rocker_arc_rows(sheet)
    _synthesis_chart(sheet)
    ws.freeze_panes = "D5"
    ws.page_setup.orientation = "landscape"
    ws.page_setup.paperSize = ws.PAPERSIZE_A4
    ws.sheet_properties.pageSetUpPr.fitToPage = True
    ws.page_setup.fitToWidth, ws.page_setup.fitToHeight = 1, 0
    return ws


def _synthesis_rows(sheet: _SynthSheet, rows, values: dict[str, float], first: int) -> None:
    """The title, the headers, the given data (yellow) and the solution's rows: a root per
    column (D, E) where a row has two candidates."""
    from openpyxl.styles import Font

    from sheetkin.groups.lang import UNITS
    from sheetkin.sheet.workbook import INPUT_FILL, SECTION_FONT
    ws, text, lang = sheet.ws, sheet.text, sheet.lang
    ws["A1"] = text["title"]
    ws["A1"].font = Font(bold=True, size=14)
    ws["A3"] = text["checks"]
    ws["A3"].font = SECTION_FONT
    for col, key in zip("ABCDE", ("name", "unit", "desc", "value", "value2"), strict=False):
        ws[f"{col}4"] = text[key]
        ws[f"{col}4"].font = SECTION_FONT
    for k, row in enumerate(rows):
        r = first + k
        name, unit = row[:2]
        said = row_text(row, lang)
        if name.startswith("#"):
            ws.cell(r, 1, said).font = SECTION_FONT
            continue
        ws.cell(r, 1, name)
        ws.cell(r, 2, UNITS[lang].get(unit, unit))
        ws.cell(r, 3, said)
        if len(row) == 4:
            ws.cell(r, 4, float(values[name])).fill = INPUT_FILL
            continue
        checked = name.startswith(("res_", "kin_"))
        fmt = ("0.0E+00" if checked else "General" if name in
               ("solvable", "flip", "valid", "root", "branch") else "0.000000000")
        if row[4] == "cand":
            tpls = row[5:] if len(row) == 7 else (row[5], row[5])
            for col, tpl in zip("DE", tpls, strict=False):
                ws[f"{col}{r}"] = sheet.fill(tpl, col)
                ws[f"{col}{r}"].number_format = fmt
        else:
            ws.cell(r, 4, sheet.fill(row[4])).number_format = fmt


def _synthesis_verdict(sheet: _SynthSheet) -> None:
    """The residuals green within Tol, red past it, and D3's verdict over all of them."""
    from openpyxl.formatting.rule import FormulaRule

    from sheetkin.sheet.checks import GREEN, RED
    from sheetkin.sheet.workbook import SECTION_FONT
    ws, text, where = sheet.ws, sheet.text, sheet.where
    tolc = f"$D${where['Tol']}"
    res = [f"D{r}" for name, r in where.items() if name.startswith(("res_", "kin_"))]
    for c in res:
        ws.conditional_formatting.add(c, FormulaRule(formula=[f"AND(ISNUMBER({c}),ABS({c})<={tolc})"], fill=GREEN))
        ws.conditional_formatting.add(c, FormulaRule(formula=[f"OR(NOT(ISNUMBER({c})),ABS({c})>{tolc})"], fill=RED))
    absmax = ",".join(f"ABS({c})" for c in res)
    ws["D3"] = (f'=IF(COUNT({",".join(res)})<{len(res)},"{text["fail"]}",'
                f'IF(MAX({absmax})<={tolc},"{text["pass"]}","{text["fail"]}"))')
    ws["D3"].font = SECTION_FONT
    ws.conditional_formatting.add("D3", FormulaRule(formula=[f'D3="{text["pass"]}"'], fill=GREEN))
    ws.conditional_formatting.add("D3", FormulaRule(formula=[f'D3<>"{text["pass"]}"'], fill=RED))


def _dead_position_rows(sheet: _SynthSheet) -> None:
    """The dead positions' points O, A, B, D (columns D..G), as in the seed."""
    from sheetkin.groups.lang import UNITS
    from sheetkin.sheet.workbook import SECTION_FONT
    ws, after = sheet.ws, sheet.after
    ws.cell(after, 1, sheet.text["points"]).font = SECTION_FONT
    for j, p in enumerate("OABD"):
        ws.cell(after, 4 + j, p).font = SECTION_FONT
    pt = {"X_H": ("0", "={l1}*COS({phi1H})", "=({l1}+{l2})*COS({phi1H})", "={X_D}"),
          "Y_H": ("0", "={l1}*SIN({phi1H})", "=({l1}+{l2})*SIN({phi1H})", "={Y_D}"),
          "X_K": ("0", "={l1}*COS({phi1H}+{theta}+PI())", "=({l2}-{l1})*COS({phi1H}+{theta})", "={X_D}"),
          "Y_K": ("0", "={l1}*SIN({phi1H}+{theta}+PI())", "=({l2}-{l1})*SIN({phi1H}+{theta})", "={Y_D}")}
    desc = {"X_H": ("абсциссы, начальное положение", "abscissae, extended position"),
            "Y_H": ("ординаты, начальное положение", "ordinates, extended position"),
            "X_K": ("абсциссы, конечное положение", "abscissae, folded position"),
            "Y_K": ("ординаты, конечное положение", "ordinates, folded position")}
    for name, r in sheet.pts.items():
        ws.cell(r, 1, name)
        ws.cell(r, 2, UNITS[sheet.lang].get("m", "m"))
        ws.cell(r, 3, _UK_ROWS[name] if sheet.lang == "uk" else desc[name][0 if sheet.lang == "ru" else 1])
        for j, f in enumerate(pt[name]):
            cell = ws.cell(r, 4 + j, 0.0 if f == "0" else sheet.fill(f))
            cell.number_format = "0.000000"


def _rocker_arc_rows(sheet: _SynthSheet) -> None:
    """The rocker's arc: gamma1 .. gamma2 in _ARC_POINTS points (columns D..)."""
    from openpyxl.utils import get_column_letter

    from sheetkin.groups.lang import UNITS
    from sheetkin.sheet.workbook import SECTION_FONT
    ws, text, arc = sheet.ws, sheet.text, sheet.arc
    ws.cell(sheet.arc0, 1, text["arc"]).font = SECTION_FONT
    n = _ARC_POINTS
    cols = [get_column_letter(4 + k) for k in range(n)]
    labels = {"k": ("", text["k"]), "gamma_arc": ("deg", text["gamma"]),
              "X_arc": ("m", "X_D + l3 cos(gamma)"), "Y_arc": ("m", "Y_D + l3 sin(gamma)")}
    for name, r in arc.items():
        ws.cell(r, 1, name)
        ws.cell(r, 2, UNITS[sheet.lang].get(labels[name][0], labels[name][0]))
        ws.cell(r, 3, labels[name][1])
        for k, c in enumerate(cols):
            if name == "k":
                ws.cell(r, 4 + k, k)
                continue
            f = {"gamma_arc": f"={{gamma1_deg}}+({{gamma2_deg}}-{{gamma1_deg}})*{c}{arc['k']}/{n - 1}",
                 "X_arc": f"={{X_D}}+{{l3}}*COS(RADIANS({c}{arc['gamma_arc']}))",
                 "Y_arc": f"={{Y_D}}+{{l3}}*SIN(RADIANS({c}{arc['gamma_arc']}))"}[name]
            ws.cell(r, 4 + k, sheet.fill(f)).number_format = "0.00" if name == "gamma_arc" else "0.0000"
    for col, width in zip("ABCDE", (14, 6, 56, 16, 16), strict=True):
        ws.column_dimensions[col].width = width


def _synthesis_chart(sheet: _SynthSheet) -> None:
    """The mechanism in its dead positions and the rocker's arc, at G3."""
    from openpyxl.chart import Reference, ScatterChart, Series
    from openpyxl.chart.data_source import NumFmt
    ws, text, pts, arc = sheet.ws, sheet.text, sheet.pts, sheet.arc
    ch = ScatterChart()
    ch.scatterStyle = "lineMarker"   # required by the schema; each series sets its own lines and markers
    ch.title, ch.style, ch.height, ch.width = text["chart"], 2, 12, 14
    ch.x_axis.title, ch.y_axis.title = text["axis_x"], text["axis_y"]
    for axis in (ch.x_axis, ch.y_axis):
        axis.delete = False
        axis.crosses = "min"
        axis.numFmt = NumFmt(formatCode="General", sourceLinked=False)
    def row_ref(r: int, c0: int, c1: int) -> Reference:
        return Reference(ws, min_col=c0, max_col=c1, min_row=r, max_row=r)
    for xs, ys, label, c1 in ((pts["X_H"], pts["Y_H"], text["H"], 7),
                              (pts["X_K"], pts["Y_K"], text["K"], 7),
                              (arc["X_arc"], arc["Y_arc"], text["arcs"], 3 + _ARC_POINTS)):
        s = Series(row_ref(ys, 4, c1), row_ref(xs, 4, c1), title=label)
        s.marker.symbol = "circle" if c1 == 7 else "none"
        s.smooth = False
        ch.series.append(s)
    ws.add_chart(ch, "G3")


def build_synthesis_workbook(kw: float, l3: float, yd: float, gamma1_deg: float,
                             gamma2_deg: float, *, lang: str = "ru", tol: float = 1e-9,
                             phi_ref_deg: float = 30.0):
    """A workbook of one sheet: add_synthesis_sheet's."""
    from sheetkin.sheet.cached import CachedWorkbook

    wb = CachedWorkbook()           # saved with every formula's value
    wb.remove(wb.active)
    add_synthesis_sheet(wb, kw, l3, yd, gamma1_deg, gamma2_deg, lang, tol=tol,
                        phi_ref_deg=phi_ref_deg)
    return wb


def add_scene_synthesis_sheet(wb, scene, data: dict[str, float], lang: str = "ru") -> list[str]:
    """Add the synthesis sheet for the scene's [synthesis] `data` (parse_synthesis) to the
    scene's workbook `wb` (build_workbook: the kinematics sheet first, the hidden scene sheet
    last), before the hidden sheet, with check rows comparing the kinematics sheet's input
    block with the solution. Returns scene_mismatches: where those checks fail."""
    from sheetkin.sheet.workbook import SCENE_SHEET

    kin = wb.worksheets[0]
    g = scene.groups[0]
    o, d = scene.crank.pivot, fourbar_dyad(scene)[2]
    names = {"L1": "L1", "L2": f"L{g.links[0]}", "L3": f"L{g.links[1]}", "x_O": f"x_{o}",
             "y_O": f"y_{o}", "x_D": f"x_{d}", "y_D": f"y_{d}", "branch": f"branch_g{g.index}"}
    found: dict[object, int] = {}
    for r, (v,) in enumerate(kin.iter_rows(min_col=1, max_col=1, values_only=True), 1):
        found.setdefault(v, r)
    sheet = "'" + kin.title.replace("'", "''") + "'"
    cells = {k: f"{sheet}!$D${found[n]}" for k, n in names.items()}
    index = wb.sheetnames.index(SCENE_SHEET) if SCENE_SHEET in wb.sheetnames else None
    add_synthesis_sheet(wb, **data, lang=lang, kinematics=cells, index=index)
    return scene_mismatches(scene, data)
