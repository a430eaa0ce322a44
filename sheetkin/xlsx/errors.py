"""The spreadsheet engine's own base of errors, under sheetkin's family (sheetkin.errors).

    SpreadsheetError(InputError)   a workbook or formula the engine cannot use
      UnusableWorkbook             the file is refused (sheetkin.xlsx.package)
      ParseError                   a formula cannot be read (sheetkin.xlsx.parse)
      EvaluationError              the workbook cannot be evaluated as a whole (sheetkin.xlsx.runs)

A caller of the engine alone catches SpreadsheetError; the command line maps every
InputError to one line and exit 2.
"""
from __future__ import annotations

from sheetkin.errors import InputError

__all__ = ["SpreadsheetError"]


class SpreadsheetError(InputError):
    """A workbook (or a formula in it) the spreadsheet engine cannot use; one line."""
