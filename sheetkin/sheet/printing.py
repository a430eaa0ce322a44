"""Printing the kinematics sheet: pages a student can read and a teacher can mark.

Landscape A4, the name/unit/description/value columns (A-D) and the title rows (1-4)
repeated on every page, the positions spread evenly over the pages across (at most
POSITIONS_PER_PAGE a page) and the scale chosen so that the widest page's positions fill
the page's width (the print setting `fit_scale`; before, a fixed 80 % left a position's
width blank on 4 of 6 pages and printed 13 positions on 3 pages across), the rows spread
evenly down (manual column and row breaks: no page holds only a few rows or one
position), descriptions wrapped in a column wide enough for most of them on one line,
check-row cells aligned (the status centred in D, the position cells to the right, so a
"n/a" text no longer runs into D's 0), the scheme's title wrapped over the first page's
positions (E1, never cut at the page's edge) and in the page header, page numbers in the
footer and a print area that ends at the last row and the last position.
"""
from __future__ import annotations

from openpyxl.styles import Alignment
from openpyxl.worksheet.pagebreak import Break, ColBreak, RowBreak

# LibreOffice prints a width unit as about 2.46 mm at 100 % (measured on its PDF: A-D and
# four positions, 130 units, were 257 mm at 80 %); landscape A4 leaves 279 mm between the
# side margins of 0.35 in
UNIT_MM = 2.47
PAGE_WIDTH_MM = 297.0 - 2 * 0.35 * 25.4
WIDTHS = {"A": 14, "B": 7, "C": 40, "D": 14}
POSITION_WIDTH = 11
# the smallest scale that keeps the sheet's 11 pt text readable on paper (7.9 pt) and the
# largest that is still a page of the lecture's size; at MIN_SCALE, A-D and 7 positions
# fill the width: 13 positions print 7 + 6 on two pages across
MIN_SCALE, MAX_SCALE = 72, 85
POSITIONS_PER_PAGE = int((PAGE_WIDTH_MM * 100 / MIN_SCALE / UNIT_MM - sum(WIDTHS.values())) // POSITION_WIDTH)
CHARS_PER_LINE = 40         # of column C at its width (proportional font: a safe count)
LINE_HEIGHT = 15.0          # pt, the default row height of one line
# landscape A4 is 595 pt high; the top margin holds the page header (the title, 9 pt:
# at a top margin of 0.4 in and a header margin of 0.3 in it had 7 pt and printed over
# row 1), the bottom one the page number
TOP_IN, HEADER_IN, BOTTOM_IN = 0.55, 0.15, 0.5
PAGE_HEIGHT_PT = 595.3 - (TOP_IN + BOTTOM_IN) * 72
# the rows LibreOffice puts on a page fall 1-3 % short of the geometry's (measured on the
# four-bar's PDF at 80 %: 570 to 584 pt below the title rows where the geometry gives 590)
ROOM = 0.96
TITLE_CHARS_PER_UNIT = 0.9  # bold 11 pt characters of E1 per width unit (measured: ~1)


def fit_scale(widest: int) -> int:
    """The print scale (%) at which columns A-D and `widest` positions fill the page's
    width: at most MAX_SCALE (a book of few positions gives column C the rest)."""
    units = sum(WIDTHS.values()) + widest * POSITION_WIDTH
    return max(MIN_SCALE, min(MAX_SCALE, int(PAGE_WIDTH_MM * 100 / (UNIT_MM * units))))


def setup_page(ws, rows, where: dict[str, int], cols: list[str], first_col: int = 5,
               title_cell: str = "E1") -> None:
    """Column widths, alignment and the page setup of the kinematics sheet."""
    # the width a page across leaves over its positions goes to the descriptions (fewer
    # wrapped rows, fewer pages): 13 positions print 5 a page, C gains one position's width
    strips = column_strips(len(cols))
    widest = max(b - a for a, b in zip([0] + strips, strips, strict=False))
    scale = fit_scale(widest)
    # the width a page across leaves over its positions at that scale goes to the
    # descriptions (fewer wrapped rows, fewer pages)
    room = int(PAGE_WIDTH_MM * 100 / (UNIT_MM * scale)) - sum(WIDTHS.values()) - widest * POSITION_WIDTH
    widths = {**WIDTHS, "C": WIDTHS["C"] + max(0, room)}
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
    title_rows = _title_rows(ws, title_cell, strips[0])
    last_row = max(where.values())
    ws.print_area = f"A1:{cols[-1]}{last_row}"
    ws.print_title_rows = "1:4"
    ws.print_title_cols = "A:D"
    ps = ws.page_setup
    ps.orientation, ps.paperSize, ps.scale = "landscape", ws.PAPERSIZE_A4, scale
    ws.sheet_properties.pageSetUpPr.fitToPage = False
    ws.page_margins.left = ws.page_margins.right = 0.35
    ws.page_margins.top, ws.page_margins.bottom, ws.page_margins.header = TOP_IN, BOTTOM_IN, HEADER_IN
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
    cap = ROOM * (PAGE_HEIGHT_PT * 100 / scale - title_rows)
    for r in page_starts(sorted(heights), cap)[1:]:
        ws.row_breaks.append(Break(id=r - 1))           # a break after row r - 1


def _title_rows(ws, title_cell: str, first_page: int) -> float:
    """E1's title merged over the first page's positions and wrapped there at word breaks
    (it ran on over the columns and was cut mid-word at the page's edge); row 1 gets the
    height of its lines. Returns the height of the title rows 1-4, which print on every page."""
    cell = ws[title_cell]
    first = cell.column
    ws.merge_cells(start_row=cell.row, start_column=first, end_row=cell.row, end_column=first + first_page - 1)
    cell.alignment = Alignment(wrap_text=True, vertical="top")
    per_line = max(1, int(first_page * POSITION_WIDTH * TITLE_CHARS_PER_UNIT))
    words, lines, used = str(cell.value or "").split(), 1, 0
    for w in words:                 # as the spreadsheet wraps: at spaces, never inside a word
        if used and used + 1 + len(w) > per_line:
            lines, used = lines + 1, 0
        used += (1 if used else 0) + len(w)
    ws.row_dimensions[cell.row].height = lines * LINE_HEIGHT
    return (lines + 1 + 1 + 2) * LINE_HEIGHT


def column_strips(n: int, most: int = POSITIONS_PER_PAGE) -> list[int]:
    """The last position (1-based count) on each page across: as even as the pages allow
    (13 positions at most 6 a page: 5, 9, 13, not 6, 12, 13 with one position alone on its
    page); the first page is never narrower than the others (E1's title is wrapped over it)."""
    pages = -(-n // most)
    return [-(-n * (k + 1) // pages) for k in range(pages)]      # the first page the widest


def page_starts(rows: list[tuple[int, float, bool]], cap: float) -> list[int]:
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
