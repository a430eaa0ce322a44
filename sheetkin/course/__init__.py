"""Running a course: variants per student, validation of their books, grades and reports.

It owns the validator (`validator`: a student's book evaluated by the xlsx engine and
compared row by row with the reference), the local judgement of each row on the
student's own upstream values (`localjudge`), copy detection (`copies`), issued variants
with their roster, key and seals (`issued`), making variants (`variants`), Moodle grades
(`grades`), validating many files (`batch`) and the text, JSON and HTML reports
(`report`, `report_html`).
"""
from __future__ import annotations

from sheetkin.lazy import exports

# public name -> the module that defines it, imported on first use (sheetkin.lazy)
_EXPORTS = {
    "validate": "validator",
    "Report": "report_model",
    "RowReport": "report_model",
    "validate_many": "batch",
    "make_variants": "variants",
    "write_variants": "variants",
    "possible_copies": "copies",
    "read_roster": "issued",
    "read_key": "issued",
    "read_class_list": "grades",
    "write_grades": "grades",
    "text_report": "report",
    "json_report": "report",
    "html_report": "report",
}

__getattr__, __dir__ = exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
