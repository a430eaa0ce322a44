"""The one precision of grading: two numbers are the same up to rounding when they differ
by at most max(ATOL, RTOL * |reference|). A computed cell against the reference
(sheetkin.course.rows), a row on the student's own inputs (sheetkin.course.localjudge) and
a given value read back from a saved book (sheetkin.course.issued: LibreOffice writes 15
digits) all use it."""
from __future__ import annotations

RTOL = 1e-9
ATOL = 1e-9
