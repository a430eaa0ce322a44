"""Printing the kinematics sheet: pages a student can read and a teacher can mark.

Landscape A4 at 80 %, the name/unit/description/value columns (A-D) and the title rows
(1-4) repeated on every page, POSITIONS_PER_PAGE position columns per page (manual column
breaks), descriptions wrapped in a column wide enough for most of them on one line,
check-row cells aligned (the status centred in D, the position cells to the right, so a
"n/a" text no longer runs into D's 0), page numbers in the footer and a print area that
ends at the last row and the last position.
"""
from __future__ import annotations

from openpyxl.styles import Alignment
from openpyxl.worksheet.pagebreak import Break, ColBreak

POSITIONS_PER_PAGE = 6
# LibreOffice prints a width unit as about 2.46 mm at 100 % (measured on its PDF): A-D and
# six positions, 141 units, are 347 mm; at 80 % they fill landscape A4's 277 mm between
# the margins, and 11 pt text prints at 8.8 pt
SCALE = 80
WIDTHS = {"A": 14, "B": 7, "C": 40, "D": 14}
POSITION_WIDTH = 11
CHARS_PER_LINE = 40         # of column C at its width (proportional font: a safe count)
LINE_HEIGHT = 15.0          # pt, the default row height of one line


def setup_page(ws, rows, where: dict[str, int], cols: list[str], first_col: int = 5) -> None:
    """Column widths, alignment and the page setup of the kinematics sheet."""
    for col, w in WIDTHS.items():
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
            lines = -(-len(str(text)) // CHARS_PER_LINE)
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
    ws.page_margins.top, ws.page_margins.bottom = 0.5, 0.6
    ws.print_options.gridLines = True
    ws.oddFooter.center.text = "&P / &N"
    ws.oddFooter.right.text = "&A"
    breaks = ColBreak()
    for k in range(POSITIONS_PER_PAGE, len(cols), POSITIONS_PER_PAGE):
        breaks.append(Break(id=first_col - 1 + k))        # a break after this column
    ws.col_breaks = breaks
