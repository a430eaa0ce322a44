"""The charts sheet's pictures of the mechanism, live in the spreadsheet.

* A drawing of the mechanism at the position typed in the charts sheet's lilac cell B1
  (the kinematics sheet's position i, 0..N-1): the frame pivots, fixed guides, every link
  as a segment (a closed polygon for a link with three or more points), slider blocks turned along their
  guides, slots, and the points' paths behind them. Its data are helper cells (columns
  AD onwards, headed "drawing data") that pick the chosen position's column of the
  kinematics sheet's own rows with INDEX, so a changed position or length redraws it.
  A position where the mechanism cannot assemble gives #N/A, which charts leave out.
* Trajectories to equal scale: the axes' bounds are set at generation (from compute() over
  a revolution, padded) for a fixed plot-area layout, so that a circle is round.
* A fine path (FINE positions over a revolution) behind the sheet's coarse positions: the
  hidden sheet `paths` repeats the kinematics sheet's rows that the coordinates depend on,
  at the same row numbers with the same formulas, for FINE + 1 columns; its input cells
  refer to the kinematics sheet's, only its step is 360/FINE deg (the sign of Delta_Fi).
  An exercise workbook gets no `paths` sheet (it would hold the answers), nor does a book
  whose paths sheet would pass PATHS_MAX_CELLS (a long chain): both draw the sheet's own
  positions.
* The charts read the hidden sheet `plotted` (add_plotted_sheet), never the kinematics
  sheet's cells themselves: numbers or #N/A there, as Excel plots text as 0.

Nothing here knows a group kind: the links' points, guides and blocks come from
sheetkin.kinematics.geometry.structure, that is from each kind's `parts(g)`; a guide names the
input rows of its angle and point (GuidePart.angle_input, point_inputs), and its helper
cells refer to them, so the drawn guide turns and moves with what is typed there.
Spin button: openpyxl cannot write form controls, so the position is a plain input cell
with a data validation (whole number 1..N) instead.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any, cast

from openpyxl.chart import Reference, ScatterChart, Series
from openpyxl.chart.axis import ChartLines
from openpyxl.chart.data_source import NumFmt
from openpyxl.chart.layout import Layout, ManualLayout
from openpyxl.chart.marker import Marker
from openpyxl.chart.shapes import GraphicalProperties
from openpyxl.styles import Font, PatternFill
from openpyxl.utils import get_column_letter, quote_sheetname
from openpyxl.worksheet.datavalidation import DataValidation

from sheetkin.kinematics.geometry import FINE_POSITIONS, bounds, guide_span, revolution, structure
from sheetkin.kinematics.scene import Scene
from sheetkin.kinematics.table import compute

PATHS_SHEET = "paths"
# bounded work: the paths sheet repeats the rows the coordinates need at FINE + 1 positions;
# a long chain (hundreds of such rows) draws the sheet's own positions instead
PATHS_MAX_CELLS = 150_000
PLOTTED_SHEET = "plotted"
POSITION_CELL = "$B$1"
HELPER_COL = 30                    # AD: the drawing's helper cells
# lilac: a cell the student types in (the kinematics sheet's colour for "fill in")
TYPE_FILL = PatternFill("solid", fgColor="E4DFEC")
# chart size (cm) and the plot area's place in it (fractions): fixed, so that equal
# scale can be set through the axes' bounds
WIDTH, HEIGHT = 16.0, 12.0
PLOT = (0.12, 0.13, 0.84, 0.74)            # x, y, w, h of the inner plot area
PLOT_LEGEND = (0.11, 0.13, 0.66, 0.74)     # room for a legend on the right
ROWS_PER_CHART = 25                         # 12 cm of default-height rows, and a gap
COLORS = ["1F77B4", "FF7F0E", "2CA02C", "D62728", "9467BD", "8C564B", "E377C2", "7F7F7F", "BCBD22", "17BECF"]
# the charts sheet's words: texts, and (x, y) axis titles under "axes"
_TEXT: dict[str, dict[str, Any]] = {
    "ru": {
        "pos": "положение i =",
        "phi": "phi_1, град",
        "mech": "Механизм в положении i",
        "traj": "Траектории точек",
        "helper": "данные чертежа (вспомогательные ячейки)",
        "hint": "введите номер положения i: 0..{n}",
        "link": "звено {k}: {pts}",
        "guide": "направляющая г{i}",
        "slot": "паз г{i}",
        "block": "ползун {k} в {at}",
        "frame": "стойка",
        "axes": ("x, м", "y, м"),
    },
    "uk": {
        "pos": "положення i =",
        "phi": "phi_1, град",
        "mech": "Механізм у положенні i",
        "traj": "Траєкторії точок",
        "helper": "дані креслення (допоміжні клітинки)",
        "hint": "введіть номер положення i: 0..{n}",
        "link": "ланка {k}: {pts}",
        "guide": "напрямна г{i}",
        "slot": "паз г{i}",
        "block": "повзун {k} у {at}",
        "frame": "стояк",
        "axes": ("x, м", "y, м"),
    },
    "en": {
        "pos": "position i =",
        "phi": "phi_1, deg",
        "mech": "The mechanism at position i",
        "traj": "Trajectories of points",
        "helper": "drawing data (helper cells)",
        "hint": "type a position number i: 0..{n}",
        "link": "link {k}: {pts}",
        "guide": "guide g{i}",
        "slot": "slot g{i}",
        "block": "block {k} at {at}",
        "frame": "frame",
        "axes": ("x, m", "y, m"),
    },
}


# the helper scalars' labels (written in English where the cells are made)
HELPER_WORDS = {
    "ru": {"angle, deg": "угол, град", "slider's distance from the lever's joint": "смещение ползуна от шарнира",
           "base x": "x основания", "base y": "y основания"},
    "uk": {"angle, deg": "кут, град", "slider's distance from the lever's joint": "зміщення повзуна від шарніра",
           "base x": "x основи", "base y": "y основи"},
}


@dataclass
class SheetRows:
    """What the charts need from the kinematics sheet as written by sheetkin.sheet.workbook."""
    ws: Any                         # the kinematics worksheet (openpyxl)
    rows: list                      # its Row records (name, kind, guard)
    where: dict[str, int]           # row of each name
    templates: dict[str, str]       # compiled formulas: {c} this column, $D$r inputs
    cols: list[str]                 # position columns' letters
    marker: str                     # the "cannot assemble" text of guarded cells
    lang: str = "ru"
    exercise: bool = False
    plotted: Any = None             # the hidden sheet of the plotted rows (add_plotted_sheet)


# --------------------------------------------------------------------------- the paths sheet
_DEP = re.compile(r"\{[cpn]\}(\d+)|\$D\$(\d+)")


def needed_rows(info: SheetRows, names) -> list[str]:
    """The rows that the given rows depend on (their formulas and guards), in sheet order."""
    by_row = {r: n for n, r in info.where.items()}
    guard = {r.name: r.guard for r in info.rows}
    seen, stack = set(), list(names)
    while stack:
        n = stack.pop()
        if n in seen or n not in info.where:
            continue
        seen.add(n)
        stack += [by_row[int(a or b)] for a, b in _DEP.findall(info.templates.get(n, ""))]
        if guard.get(n):
            stack.append(guard[n])
    return [r.name for r in info.rows if r.name in seen]


def add_paths_sheet(wb, info: SheetRows, scene: Scene, fine: int = FINE_POSITIONS):
    """The hidden sheet of the coordinates over a revolution (see the module's docstring)."""
    ps = wb.create_sheet(PATHS_SHEET)
    ps.sheet_state = "hidden"
    kin = quote_sheetname(info.ws.title)
    points = scene.moving_joints + [p.name for p in scene.points]
    plotted = {f"{q}_{p}" for p in points for q in "xy"}
    need = set(needed_rows(info, plotted))
    first = info.ws.cell(1, 5).column          # E
    cols = [get_column_letter(first + k) for k in range(fine + 1)]
    ps["A1"] = f"{scene.title}: coordinates at {fine} positions over a revolution (sheetkin)"
    ps["A1"].data_type = "s"        # text, whatever the title starts with (never a formula)
    for row in info.rows:
        if row.name not in need:
            continue
        r = info.where[row.name]
        ps.cell(r, 1, row.name)
        if row.kind == "input":
            if row.name == "Delta_Fi":      # one revolution, the way the sheet's crank steps
                ps.cell(r, 4, f"=IF({kin}!$D${r}<0,-1,1)*{360.0 / fine!r}")
            else:
                ps.cell(r, 4, f"={kin}!$D${r}")
        elif row.kind == "derived":
            ps.cell(r, 4, info.templates[row.name])
        elif row.kind == "index":
            for k in range(len(cols)):
                ps.cell(r, first + k, k)
        elif row.name in info.templates:
            tpl = info.templates[row.name]
            if row.guard:       # #N/A, not the marker's text: a chart leaves #N/A out
                tpl = f'=IF({{c}}{info.where[row.guard]},{tpl[1:]},NA())'
            if row.name in plotted:     # a chart plots any other error as 0
                tpl = f"=IFERROR({tpl[1:]},NA())"
            for k, c in enumerate(cols):
                ps.cell(r, first + k, tpl.format(c=c, p=c, n=c))
    return ps, cols


def add_plotted_sheet(wb, info: SheetRows, names) -> object:
    """The hidden sheet `plotted`: the kinematics sheet's rows that the charts plot, at the
    same row and column, as numbers or #N/A. Excel plots a text cell (the "cannot assemble"
    marker, "n/a") or an error other than #N/A as 0, and one text cell among a series' X
    values turns all of them into 1, 2, 3 ...; #N/A is left out by every spreadsheet."""
    ps = wb.create_sheet(PLOTTED_SHEET)
    ps.sheet_state = "hidden"
    kin = quote_sheetname(info.ws.title)
    ps["A1"] = "the charts' data: the kinematics sheet's rows, #N/A where a cell is not a number (sheetkin)"
    first = info.ws.cell(1, 5).column          # E
    for name in dict.fromkeys(names):
        r = info.where[name]
        ps.cell(r, 1, name)
        for k, c in enumerate(info.cols):
            ps.cell(r, first + k, f"=IF(ISNUMBER({kin}!{c}{r}),{kin}!{c}{r},NA())")
    info.plotted = ps
    return ps


# --------------------------------------------------------------------------- helper cells
class _Helper:
    """Helper cells on the charts sheet: series blocks (label, x, y per row) in AD:AF and
    scalars (label, value) in AH:AI."""

    def __init__(self, cs, title: str, words: dict[str, str] | None = None):
        self.cs, self.row, self.srow = cs, 3, 3
        self.words = words or {}          # the scalars' labels in the book's language
        self.x = get_column_letter(HELPER_COL + 1)
        self.y = get_column_letter(HELPER_COL + 2)
        cs.cell(1, HELPER_COL, title).font = Font(bold=True)

    def series(self, label: str, pts: list[tuple[str, str]]) -> tuple[int, int]:
        start = self.row
        for k, (x, y) in enumerate(pts):
            self.cs.cell(self.row, HELPER_COL, label if k == 0 else None)
            self.cs.cell(self.row, HELPER_COL + 1, "=" + x).number_format = "0.000000"
            self.cs.cell(self.row, HELPER_COL + 2, "=" + y).number_format = "0.000000"
            self.row += 1
        self.row += 1
        return start, self.row - 2

    def scalar(self, label: str, formula: str) -> str:
        r = self.srow
        tag, _, what = label.rpartition(": ")
        self.cs.cell(r, HELPER_COL + 4, f"{tag}: {self.words.get(what, what)}" if tag else label)
        self.cs.cell(r, HELPER_COL + 5, "=" + formula).number_format = "0.000000"
        self.srow += 1
        return f"${get_column_letter(HELPER_COL + 5)}${r}"


def _num(x) -> str:
    """A number as formula text (repr of a numpy float would be np.float64(...))."""
    return repr(float(x))


def _na(v: str) -> str:
    return f"IF(ISNUMBER({v}),{v},NA())"


class _Cells:
    """Formulas for the chosen position's values, from the kinematics sheet."""

    def __init__(self, info: SheetRows, scene: Scene):
        self.info, self.scene = info, scene
        self.kin = quote_sheetname(info.ws.title)
        self.span = f"${info.cols[0]}${{r}}:${info.cols[-1]}${{r}}"

    def input(self, name: str) -> str | None:
        r = self.info.where.get(name)
        return f"{self.kin}!$D${r}" if r else None

    def at(self, name: str) -> str:
        r = self.info.where[name]
        return _na(f"INDEX({self.kin}!{self.span.format(r=r)},{POSITION_CELL}+1)")

    def xy(self, p) -> tuple[str, str]:
        if isinstance(p, tuple):
            return _num(p[0]), _num(p[1])
        if p in self.scene.frame:
            # a frame point's coordinates are inputs of the sheet: they always have rows
            return cast(str, self.input(f"x_{p}")), cast(str, self.input(f"y_{p}"))
        return self.at(f"x_{p}"), self.at(f"y_{p}")

    def angle(self, link: int) -> str:
        """phi_link in degrees at the chosen position (0 for the frame)."""
        return "0" if link == 0 else self.at(f"phi_{link}")


def _guide_cells(h: _Helper, c: _Cells, g, tag: str):
    """(x, y of the base point, ux, uy) cells of a guide at the chosen position."""
    # the kind names the input rows of its guide's angle and point (groups.parts.GuidePart)
    gamma = c.input(g.angle_input) if g.angle_input else None
    if gamma is None:
        theta = f"{c.angle(g.link)}+{_num(g.angle_deg)}"
    else:
        theta = gamma if g.link == 0 else f"{c.angle(g.link)}+{gamma}"
    th = h.scalar(f"{tag}: angle, deg", theta)
    ux = h.scalar(f"{tag}: cos", f"COS(RADIANS({th}))")
    uy = h.scalar(f"{tag}: sin", f"SIN(RADIANS({th}))")
    if g.foot_of is not None:         # a slot: the foot of the lever's joint on the line
        (px, py), (sx, sy) = c.xy(g.foot_of), c.xy(g.slider)
        d = h.scalar(f"{tag}: slider's distance from the lever's joint", f"-({sx}-{px})*{uy}+({sy}-{py})*{ux}")
        bx = h.scalar(f"{tag}: base x", f"{px}-{d}*{uy}")
        by = h.scalar(f"{tag}: base y", f"{py}+{d}*{ux}")
        return bx, by, ux, uy
    point = [c.input(r) for r in g.point_inputs] if g.point_inputs else []
    if isinstance(g.through, tuple) and point and None not in point:
        tx, ty = point
    else:
        tx, ty = c.xy(g.through)
    bx = h.scalar(f"{tag}: base x", f"{tx}-{_num(g.offset)}*{uy}")
    by = h.scalar(f"{tag}: base y", f"{ty}+{_num(g.offset)}*{ux}")
    return bx, by, ux, uy


# --------------------------------------------------------------------------- charts
def _nice(x: float) -> float:
    e = 10 ** math.floor(math.log10(x))
    return next(m * e for m in (1, 2, 2.5, 5, 10) if m * e >= x)


def equal_axes(box, plot=PLOT, width=WIDTH, height=HEIGHT):
    """Axis bounds (xmin, xmax, ymin, ymax) and a common major unit such that one metre is
    as long on both axes of a plot area `plot` (fractions of a width x height chart), and
    the box fits."""
    x0, y0, x1, y1 = box
    wp, hp = plot[2] * width, plot[3] * height
    unit = _nice(max(x1 - x0, y1 - y0) / 4)
    k = max((x1 - x0 + unit) / wp, (y1 - y0 + unit) / hp)        # metres per cm
    sx, sy = k * wp - (x1 - x0) - unit, k * hp - (y1 - y0) - unit
    xmin = math.floor((x0 - sx / 2) / unit) * unit
    ymin = math.floor((y0 - sy / 2) / unit) * unit
    return xmin, xmin + k * wp, ymin, ymin + k * hp, unit


def _chart(title: str, box, plot, legend: bool, axes: tuple[str, str] = ("x, m", "y, m")) -> ScatterChart:
    ch = ScatterChart()
    ch.scatterStyle = "lineMarker"   # required by the schema; each series sets its own lines and markers
    ch.title, ch.style, ch.width, ch.height = title, 2, WIDTH, HEIGHT
    ch.visible_cells_only = False            # helper cells may sit in hidden rows
    x0, x1, y0, y1, unit = equal_axes(box, plot)
    for axis, lo, hi, other in ((ch.x_axis, x0, x1, y0), (ch.y_axis, y0, y1, x0)):
        axis.delete = False
        axis.crosses, axis.crossesAt = None, round(other, 12)    # at the bottom and the left
        # not General: the ticks min + k unit carry round-off (1.1E-16 for 0)
        axis.numFmt = NumFmt(formatCode="0.0##", sourceLinked=False)
        axis.scaling.min, axis.scaling.max, axis.majorUnit = round(lo, 12), round(hi, 12), unit
    ch.x_axis.title, ch.y_axis.title = axes
    ch.x_axis.majorGridlines = ChartLines()
    # (openpyxl writes the plot area's layout from chart.layout, not plot_area.layout)
    ch.layout = Layout(manualLayout=ManualLayout(layoutTarget="inner", xMode="edge", yMode="edge",
                                                 x=plot[0], y=plot[1], w=plot[2], h=plot[3]))
    if legend:
        ch.legend.position = "r"
    else:
        ch.legend = None
    return ch


def _style(s: Series, color: str, width_pt: float = 0.0, marker: str = "none", dash: str | None = None,
           fill: str | None = None):
    s.smooth = False
    s.marker = Marker(symbol=marker, size=5 if marker != "none" else None)
    if marker != "none":
        s.marker.graphicalProperties = GraphicalProperties(solidFill=fill or color)
        s.marker.graphicalProperties.line.solidFill = color
    if width_pt:
        s.graphicalProperties.line.solidFill = color
        s.graphicalProperties.line.width = int(width_pt * 12700)
        if dash:
            s.graphicalProperties.line.prstDash = dash
    else:
        s.graphicalProperties.line.noFill = True
    return s


def _ref(sheet, row: int, c0: int, c1: int) -> Reference:
    return Reference(sheet, min_col=c0, max_col=c1, min_row=row, max_row=row)


def add_drawing_charts(wb, cs, scene: Scene, info: SheetRows, top: int = 3) -> int:
    """Write the position cell, the helper cells, the drawing and the trajectory chart on
    the charts sheet `cs`; returns the first row free for the other charts."""
    text = _TEXT[info.lang]
    n = len(info.cols)
    st = structure(scene)
    fine_df = compute(scene, revolution(scene, FINE_POSITIONS), allow_gaps=True)
    spans = [guide_span(scene, fine_df, g) for g in st.guides]
    box = bounds(scene, fine_df, st, spans)
    r = 0.022 * max(box[2] - box[0], box[3] - box[1])
    _position_cell(cs, text, n)
    c = _Cells(info, scene)
    cs["C1"] = text["phi"]
    cs["D1"] = "=" + c.at("phi_1")
    cs["D1"].number_format = "0.00"

    h = _Helper(cs, text["helper"], HELPER_WORDS.get(info.lang))
    mech = _chart(text["mech"], box, PLOT, legend=False, axes=text["axes"])
    traj = _chart(text["traj"], box, PLOT_LEGEND, legend=True, axes=text["axes"])
    _path_series(wb, scene, info, mech, traj)
    _mechanism_series(cs, h, c, st, spans, r, mech, text)
    cs.add_chart(mech, f"A{top}")
    cs.add_chart(traj, f"K{top}")
    cs.cell(2, HELPER_COL, "x, y: INDEX(...; B1+1); #N/A").font = Font(italic=True)
    return top + ROWS_PER_CHART


def _position_cell(cs, text: dict, n: int) -> None:
    """The position cell B1 (the kinematics sheet's row i, from 0) with its validation."""
    cs.column_dimensions["A"].width = 16
    cs.column_dimensions["C"].width = 12
    cs["A1"] = text["pos"]
    cs["A1"].font = Font(bold=True)
    cs["B1"] = 0                      # the kinematics sheet's row i: positions from 0
    cs["B1"].fill = TYPE_FILL
    cs["B1"].font = Font(bold=True)
    dv = DataValidation(type="whole", operator="between", formula1="0", formula2=str(n - 1), allow_blank=False,
                        showErrorMessage=True, promptTitle=text["pos"], prompt=text["hint"].format(n=n - 1),
                        errorTitle=text["pos"], error=text["hint"].format(n=n - 1))
    dv.showInputMessage = True
    cs.add_data_validation(dv)
    dv.add("B1")


def _path_series(wb, scene: Scene, info: SheetRows, mech, traj) -> None:
    """Each moving point's path: on the drawing, from the paths sheet over a whole turn (or
    the sheet's own positions), and its positions as markers on the trajectory chart."""
    n = len(info.cols)
    moving = scene.moving_joints + [p.name for p in scene.points]
    fine_cells = len(needed_rows(info, [f"{q}_{p}" for p in moving for q in "xy"])) * (FINE_POSITIONS + 1)
    paths = None if info.exercise or fine_cells > PATHS_MAX_CELLS else add_paths_sheet(wb, info, scene)
    first, last = 5, 4 + n
    for k, p in enumerate(moving):
        color = COLORS[k % len(COLORS)]
        xr, yr = info.where[f"x_{p}"], info.where[f"y_{p}"]
        if paths:
            ps, pcols = paths
            pc1 = 4 + len(pcols)
            for ch in (mech, traj):
                s = Series(_ref(ps, yr, 5, pc1), _ref(ps, xr, 5, pc1), title=f"{p} ({len(pcols) - 1})")
                ch.series.append(_style(s, "9BB7D4" if ch is mech else color, 1.0))
        data = info.plotted or info.ws
        s = Series(_ref(data, yr, first, last), _ref(data, xr, first, last), title=p)
        traj.series.append(_style(s, color, 0, "circle"))
        if not paths:               # the exercise's paths (or a long chain's): the sheet's own positions
            s = Series(_ref(data, yr, first, last), _ref(data, xr, first, last), title=p)
            mech.series.append(_style(s, "9BB7D4", 0.75))


def _mechanism_series(cs, h, c, st, spans, r: float, mech, text: dict) -> None:
    """The mechanism at the position of B1: guides and slots, links, blocks, the frame's
    pivots, each a series of helper cells (h) that follow the kinematics sheet."""
    def add(label, pts, color, width, marker="none", dash=None, fill=None):
        r0, r1 = h.series(label, pts)
        s = Series(Reference(cs, min_col=HELPER_COL + 2, min_row=r0, max_row=r1),
                   Reference(cs, min_col=HELPER_COL + 1, min_row=r0, max_row=r1), title=label)
        mech.series.append(_style(s, color, width, marker, dash, fill))

    for g, (t0, t1) in zip(st.guides, spans, strict=False):
        tag = text["guide" if g.link == 0 else "slot"].format(i=g.group)
        bx, by, ux, uy = _guide_cells(h, c, g, tag)
        a, b = (_num(t0 - 1.5 * r), _num(t1 + 1.5 * r)) if g.link == 0 else (_num(t0 - r), _num(t1 + r))
        add(tag, [(f"{bx}+({a})*{ux}", f"{by}+({a})*{uy}"), (f"{bx}+({b})*{ux}", f"{by}+({b})*{uy}")],
            "595959" if g.link == 0 else "1F4E79", 1.5 if g.link == 0 else 0.75,
            dash=None if g.link == 0 else "dash")
    for k, pts in st.members.items():
        if len(pts) < 2:
            continue
        ring = list(pts) + ([pts[0]] if len(pts) >= 3 else [])
        add(text["link"].format(k=k, pts="-".join(pts)), [c.xy(p) for p in ring], "1F4E79", 2.25, "circle",
            fill="FFFFFF")
    for blk in st.blocks:
        tag = text["block"].format(k=blk.link, at=blk.at)
        _, _, ux, uy = _guide_cells(h, c, blk.guide, tag)
        cx, cy = c.xy(blk.at)
        hl, hw = 1.3 * r, 0.75 * r
        corners = [(-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1)]
        add(tag, [(f"{cx}+({_num(i * hl)})*{ux}-({_num(j * hw)})*{uy}",
                   f"{cy}+({_num(i * hl)})*{uy}+({_num(j * hw)})*{ux}")
                  for i, j in corners], "B8860B", 1.5)
    if st.pivots:
        add(text["frame"], [c.xy(p) for p in st.pivots], "595959", 0, "triangle", fill="BFBFBF")
