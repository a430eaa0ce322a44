"""The one family of errors sheetkin raises for its user.

Every error that is the user's to mend (a scene, a workbook, a class list, a roster, an
option on the command line) is an `InputError`; str() of it is one line naming the file,
line and key where there is one. The command line maps the family to exit codes and one
line on stderr (`sheetkin.cli`); anything outside it is a bug of ours ("internal error").

    SheetkinError
      InputError            an input cannot be used            -> exit 2
        UsageError          the command line's options do not fit -> exit 2
        (SceneError, UnusableWorkbook, ClassListError, RosterError, ... are InputErrors;
         sheetkin.xlsx keeps its own base, SpreadsheetError, under InputError)
      AssemblyError lives with the solver (sheetkin.kinematics.scene): exit 3

Each is a ValueError too, so that `except ValueError` in a caller's code, written before the
family existed, still catches them. This module imports nothing: every stage may use it.
"""
from __future__ import annotations

__all__ = ["InputError", "SheetkinError", "UsageError"]


class SheetkinError(ValueError):
    """The base of every error sheetkin raises on purpose: its message is one line for the user."""


class InputError(SheetkinError):
    """An input (a file, a value in it, an option) that cannot be used; the user can mend it."""


class UsageError(InputError):
    """Options on the command line that do not fit together or out of their range."""
