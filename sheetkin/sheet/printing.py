"""Printing the kinematics sheet: pages a student can read and a teacher can mark.

Landscape A4 at 80 %, the name/unit/description/value columns (A-D) and the title rows
(1-4) repeated on every page, at most POSITIONS_PER_PAGE position columns per page, the
positions and the rows spread evenly over the pages (manual column and row breaks: no
page holds only a few rows or one position), descriptions wrapped in a column wide enough for most of them on one line,
check-row cells aligned (the status centred in D, the position cells to the right, so a
"n/a" text no longer runs into D's 0), page numbers in the footer and a print area that
ends at the last row and the last position.
"""
from __future__ import annotations

from openpyxl.styles import Alignment
from openpyxl.worksheet.pagebreak import Break, ColBreak, RowBreak

POSITIONS_PER_PAGE = 6
# LibreOffice prints a width unit as about 2.46 mm at 100 % (measured on its PDF): A-D and
# six positions, 141 units, are 347 mm; at 80 % they fill landscape A4's 277 mm between
# the margins, and 11 pt text prints at 8.8 pt
SCALE = 80
WIDTHS = {"A": 14, "B": 7, "C": 40, "D": 14}
POSITION_WIDTH = 11
CHARS_PER_LINE = 40         # of column C at its width (proportional font: a safe count)
LINE_HEIGHT = 15.0          # pt, the default row height of one line
# the rows below the title rows 1-4 that LibreOffice puts on a page at SCALE: 570 to 584
# pt (measured on the four-bar's PDF, 2026-11-26: pages of 35, 27, 25, 30 rows); with room
PAGE_HEIGHT = 570.0


def setup_page(ws, rows, where: dict[str, int], cols: list[str], first_col: int = 5,
               title_cell: str = "E1") -> None:
    """Column widths, alignment and the page setup of the kinematics sheet."""
    # the width a page across leaves over its positions goes to the descriptions (fewer
    # wrapped rows, fewer pages): 13 positions print 5 a page, C gains one position's width
    strips = column_strips(len(cols))
    widest = max(b - a for a, b in zip([0] + strips, strips, strict=False))
    spare = (POSITIONS_PER_PAGE - widest) * POSITION_WIDTH
    widths = {**WIDTHS, "C": WIDTHS["C"] + spare}
    per_line = CHARS_PER_LINE * widths["C"] // WIDTHS["C"]
    for col, w in widths.items():
        ws.column_dimensions[col].width = w
    for c in cols:
        ws.column_dimensions[c].width = POSITION_WIDTH
    wrap = Alignment(wrap_text=True, vertical="top")
    centre, right = Alignment(horizontal="center"), Alignment(horizontal="right")
    for col in "ABCD":                 # the header row: "value / check" on two lines
        ws[f"{col}4"].alignment = Alignment(wrap_text=True, vertical="bottom")
    ws.row_dimensions[4].height = 2 * LINE_HEIGHT
    for row in rows:
        r = where[row.name]
        text = ws.cell(r, 3).value
        if text:
            ws.cell(r, 3).alignment = wrap
            # LibreOffice does not fit row heights to wrapped text when it opens a file
            lines = -(-len(str(text)) // per_line)
            if lines > 1:
                ws.row_dimensions[r].height = lines * LINE_HEIGHT
        if row.kind in ("check", "fdcheck"):
            ws.cell(r, 4).alignment = centre
            for k in range(len(cols)):
                ws.cell(r, first_col + k).alignment = right
    last_row = max(where.values())
    ws.print_area = f"A1:{cols[-1]}{last_row}"
    ws.print_title_rows = "1:4"
    ws.print_title_cols = "A:D"
    ps = ws.page_setup
    ps.orientation, ps.paperSize, ps.scale = "landscape", ws.PAPERSIZE_A4, SCALE
    ws.sheet_properties.pageSetUpPr.fitToPage = False
    ws.page_margins.left = ws.page_margins.right = 0.35
    ws.page_margins.top, ws.page_margins.bottom = 0.4, 0.5
    ws.print_options.gridLines = True
    # the scheme's title on every page (E1 prints only on the pages of the first positions)
    ws.oddHeader.center.text = str(ws[title_cell].value or "").replace("&", "&&")
    ws.oddHeader.center.size = 9
    ws.oddFooter.center.text = "&P / &N"
    ws.oddFooter.right.text = "&A"
    breaks = ColBreak()
    for k in column_strips(len(cols))[:-1]:
        breaks.append(Break(id=first_col - 1 + k))        # a break after this column
    ws.col_breaks = breaks
    heights = [(r, ws.row_dimensions[r].height or LINE_HEIGHT, row.kind == "section")
               for row in rows for r in [where[row.name]]]
    ws.row_breaks = RowBreak()
    for r in page_starts(sorted(heights))[1:]:
        ws.row_breaks.append(Break(id=r - 1))           # a break after row r - 1


def column_strips(n: int, most: int = POSITIONS_PER_PAGE) -> list[int]:
    """The last position (1-based count) on each page across: as even as the pages allow
    (13 positions: 5, 9, 13, not 6, 12, 13 with one position alone on its page)."""
    pages = -(-n // most)
    return [round(n * (k + 1) / pages) for k in range(pages)]


def page_starts(rows: list[tuple[int, float, bool]], cap: float = PAGE_HEIGHT) -> list[int]:
    """The first row of each page down, for rows (row, height in pt, is a section title):
    as many pages as the rows need, each filled to about the same height (no page with a
    few rows left over), a page begun at a section title when one is near."""
    total = sum(h for _, h, _ in rows)
    pages = max(1, -(-int(total) // int(cap)))
    while True:
        target = total / pages
        for early in (0.85, 2.0):           # at a section title if that keeps the page count
            starts, acc = [rows[0][0]], 0.0
            for r, h, section in rows:
                if acc > 0 and (acc + h > min(cap, 1.08 * target) or (section and acc >= early * target)):
                    starts.append(r)
                    acc = 0.0
                acc += h
            if len(starts) <= pages:
                return starts
        pages += 1
