"""Running a course: variants per student, validation of their books, grades and reports.

Each module is one thing a teacher would name. One book: `validator.validate` reads the
issued book back (`book`: its embedded scene, identity cells, language), builds the
variant's reference (`reference`), judges the computed rows (`rows`, with the local
judgement of each row on the student's own upstream values in `localjudge`) and the check
rows (`checks`) into a report (`report_model`: Report, RowReport). A class:
`class_grading.grade_class` validates many files (`batch`), matches each with its student
(`identity`, `classlist`), finds copies (`copies`) and warns about the roster and key
(`issued`: roster, key, seals). Around them: making variants (`variants`), Moodle grades and
the verdict (`grades`), the text, JSON and HTML reports (`report`, `report_html`,
`report_texts`; their messages in three languages: sheetkin.messages), the one precision
(`tolerance`) and the caches
(`caches.clear_caches`).
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
