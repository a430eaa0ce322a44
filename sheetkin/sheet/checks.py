"""The check rows' status cells (column D), their colours, and the summary at the top (D3).

A check row's status, in the order it is decided:
  "не заполнено"  a row the check reads is not filled in yet (an exercise workbook): grey;
  1               a cell of the row is an error, or a residual is past the tolerance: red;
  "н/д"           no position to check (a numeric-derivative check above 3 deg, or a group
                  that assembles nowhere): grey, not a green 0;
  0               every residual within the tolerance: green.
Row 2 holds the counts (filled, passing, failing, n/a, not filled: one cell each, E2:I2,
labelled by their number formats) and D3 the verdict, with the number of failing checks
and the plural of "проверка" that goes with it: short, as D3 prints on every page.
The formulas use only what Excel, LibreOffice, Gnumeric and sheetkin's evaluator all read alike
(IF, COUNT, SUM, SUMPRODUCT over a comparison, ISERROR of one value, MOD), so every
spreadsheet shows the same (tests/xlsx/test_three_engines.py).
Imports nothing from sheetkin.
"""
from __future__ import annotations

from openpyxl.formatting.rule import FormulaRule
from openpyxl.styles import Alignment, Font, PatternFill

# A conditional format's solid fill (a dxf) is painted with bgColor by Excel and with
# fgColor by LibreOffice and Gnumeric: both carry the colour, so all three paint it.
GREEN = PatternFill("solid", fgColor="C6EFCE", bgColor="C6EFCE")
RED = PatternFill("solid", fgColor="FFC7CE", bgColor="FFC7CE")
GREY = PatternFill("solid", fgColor="D9D9D9", bgColor="D9D9D9")
WHITE = PatternFill("solid", fgColor="FFFFFF", bgColor="FFFFFF")
HIDDEN = Font(color="FFFFFF")

STATUS = {
    "ru": {"na": "н/д", "unfilled": "не заполнено", "pass": "все проверки выполнены",
           "fail": "есть невыполненные проверки", "partial": "заполнены не все строки",
           "filled": "заполнено", "passing": "выполнено", "failing": "не выполнено",
           "forms": ("проверка", "проверки", "проверок")},
    "uk": {"na": "н/д", "unfilled": "не заповнено", "pass": "усі перевірки виконано",
           "fail": "є невиконані перевірки", "partial": "заповнено не всі рядки",
           "filled": "заповнено", "passing": "виконано", "failing": "не виконано",
           "forms": ("перевірка", "перевірки", "перевірок")},
    "en": {"na": "n/a", "unfilled": "not filled in", "pass": "all checks pass",
           "fail": "checks fail", "partial": "not all rows filled in",
           "filled": "filled in", "passing": "pass", "failing": "fail",
           "forms": ("check", "checks", "checks")},
}
# the counts' cells in row 3 and what they hold (number formats label them on the sheet)
# (row 2, so that D3's sentence runs on over the empty E3, F3 ... on the screen and the page)
COUNT_CELLS = {"filled": "E2", "passing": "F2", "failing": "G2", "na": "H2", "unfilled": "I2"}


def plural(n: int, lang: str = "ru") -> str:
    """The form of "проверка" after the number n: 1, 21, 101 проверка; 2-4, 22-24
    проверки; 0, 5-20, 11-14, 25-30 проверок (Ukrainian: the same rule, "перевірка").
    English: 1 check, otherwise checks."""
    one, few, many = STATUS[lang]["forms"]
    if lang == "en":
        return one if n == 1 else many
    if n % 10 == 1 and n % 100 != 11:
        return one
    if 2 <= n % 10 <= 4 and not 12 <= n % 100 <= 14:
        return few
    return many


def plural_formula(cell: str, lang: str) -> str:
    """plural() as a spreadsheet formula of the number in `cell`."""
    one, few, many = (f'"{w}"' for w in STATUS[lang]["forms"])
    if lang == "en":
        return f"IF({cell}=1,{one},{many})"
    return (f"IF(AND(MOD({cell},10)=1,MOD({cell},100)<>11),{one},"
            f"IF(AND(MOD({cell},10)>=2,MOD({cell},10)<=4,OR(MOD({cell},100)<12,MOD({cell},100)>14)),{few},{many}))")


def status_formula(lang: str, rng: str, tol: str, reads: list[str], expected: str | None) -> str:
    """Column D of a check row. rng: the row's cells; reads: the ranges of the computed rows
    it reads (blank there: not filled in); expected: how many positions must give a number
    (the assembled ones), None for a numeric-derivative check (its ends are always n/a)."""
    t = STATUS[lang]
    within = f"MAX({rng})<={tol},MIN({rng})>=-{tol}"
    if expected is None:
        judge = f'IF(COUNT({rng})=0,"{t["na"]}",IF(AND({within}),0,1))'
    else:
        judge = f'IF(AND(COUNT({rng})=0,{expected}=0),"{t["na"]}",IF(AND(COUNT({rng})={expected},{within}),0,1))'
    # any error in the row: SUM passes the first error on. Not SUMPRODUCT(--ISERROR(rng)): Gnumeric
    # reads ISERROR of a range there by implicit intersection and fails every check
    judge = f"IF(ISERROR(SUM({rng})),1,{judge})"
    if not reads:
        return "=" + judge
    blanks = "+".join(f'SUMPRODUCT(--({r}=""))' for r in reads)
    return f'=IF(IFERROR({blanks},0)>0,"{t["unfilled"]}",{judge})'


def colour_check_row(ws, rng: str, top: str, status: str, tol: str, lang: str = "ru") -> None:
    """The row's cells: blank (white on white) while the rows the check reads are not
    filled in (a residual of empty cells is a number, and a grey "0.0E+00" read as a pass),
    green within the tolerance, red past it or an error, grey while the status is n/a.
    The status cell: green 0, red 1, grey text."""
    d = f"${status[0]}{status[1:]}"
    cf = ws.conditional_formatting
    cf.add(rng, FormulaRule(formula=[f'{d}="{STATUS[lang]["unfilled"]}"'], font=HIDDEN, fill=WHITE,
                            stopIfTrue=True))
    cf.add(rng, FormulaRule(formula=[f"NOT(ISNUMBER({d}))"], fill=GREY, stopIfTrue=True))
    cf.add(rng, FormulaRule(formula=[f"ISERROR({top})"], fill=RED))
    cf.add(rng, FormulaRule(formula=[f"AND(ISNUMBER({top}),ABS({top})<={tol})"], fill=GREEN))
    cf.add(rng, FormulaRule(formula=[f"AND(ISNUMBER({top}),ABS({top})>{tol})"], fill=RED))
    cf.add(status, FormulaRule(formula=[f"ISERROR({status})"], fill=RED, stopIfTrue=True))
    cf.add(status, FormulaRule(formula=[f"ISTEXT({status})"], fill=GREY))
    cf.add(status, FormulaRule(formula=[f"AND(ISNUMBER({status}),{status}=0)"], fill=GREEN))
    cf.add(status, FormulaRule(formula=[f"AND(ISNUMBER({status}),{status}<>0)"], fill=RED))


def write_summary(ws, lang: str, status_cells: list[str], status_range: str) -> None:
    """The counts in E2:I2 and the sentence in D3 (see the module's docstring).
    status_range: column D from the first check row to the last row; it holds the check
    rows' statuses and nothing else (the input block's numbers are above it), so the counts
    are a few functions of one range whatever the number of groups: Excel's 8,192
    characters and 255 arguments per formula are never near (a list of the status cells
    grew by about 290 characters a group and passed 8,192 at 31 groups)."""
    t = STATUS[lang]
    numbers, failing = f"COUNT({status_range})", f"SUM({status_range})"
    na = f'SUMPRODUCT(--({status_range}="{t["na"]}"))'
    unfilled = f'SUMPRODUCT(--({status_range}="{t["unfilled"]}"))'
    c = COUNT_CELLS
    formulas = {"filled": f"={len(status_cells)}-{c['unfilled']}", "passing": f"={numbers}-{failing}",
                "failing": f"={failing}", "na": f"={na}", "unfilled": f"={unfilled}"}
    # 8 pt: at 9 pt "не выполнено: 0" filled its cell and ran into "выполнено: 0" on paper
    # (LibreOffice does not shrink a number to fit, nor wrap a number's label)
    grey, fit = Font(color="808080", size=8), Alignment(horizontal="right", shrink_to_fit=True)
    for key, cell in c.items():
        ws[cell] = formulas[key]
        ws[cell].number_format = f'"{t[key]}: "0'
        ws[cell].font, ws[cell].alignment = grey, fit

    head = (f'IF(AND({c["failing"]}=0,{c["unfilled"]}=0),"{t["pass"]}",'
            f'IF({c["failing"]}>0,"{t["fail"]}","{t["partial"]}"))')
    # D3 prints on every page (rows 1-4 and columns A-D repeat): the verdict and the
    # failing count, short enough for the narrowest page; the counts are in E2:I2
    f = c["failing"]
    ws["D3"] = f'={head}&IF({f}>0,": "&{f}&" "&{plural_formula(f, lang)},"")'
    ws["D3"].font = Font(bold=True)
    # right-aligned, the sentence runs to the left over the empty B3:C3, which print on
    # every page with D (to the right, over E3 ..., it was cut at each page's edge)
    ws["D3"].alignment = Alignment(horizontal="right")
    cf = ws.conditional_formatting
    cf.add("D3", FormulaRule(formula=[f"{c['failing']}>0"], fill=RED, stopIfTrue=True))
    cf.add("D3", FormulaRule(formula=[f"{c['unfilled']}>0"], fill=GREY, stopIfTrue=True))
    cf.add("D3", FormulaRule(formula=[f"AND({c['failing']}=0,{c['unfilled']}=0)"], fill=GREEN))


def passing(status) -> bool:
    """Whether a status cell's value says the check passes: 0 only (green); "н/д", "не
    заполнено", 1 and errors do not (an empty exercise passes nothing)."""
    return isinstance(status, (int, float)) and not isinstance(status, bool) and status == 0


def not_applicable(status) -> bool:
    """Whether a status cell's value is "н/д" (no position to check, in either language)."""
    return isinstance(status, str) and status in {t["na"] for t in STATUS.values()}


def failing(status) -> bool:
    """Whether a status cell's value (as read back) says the check fails: 1 (any number
    but 0) or an error; 0, "н/д" and "не заполнено" do not fail."""
    if isinstance(status, bool):
        return False
    if isinstance(status, (int, float)):
        return status != 0
    return isinstance(status, str) and status.startswith("#")
