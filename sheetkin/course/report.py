"""Reports of the validator: text for the terminal, JSON, and an HTML page."""
from __future__ import annotations

import json
import math
import re
from typing import TYPE_CHECKING

from sheetkin.messages import message, say

from .copies import MAX_LISTED
from .grades import all_correct, counts, explain, report_dict, score, verdict
from .issued import changed_line
from .layout import VALUE_COL
from .report_html import position_list, position_name
from .report_model import Report
from .report_texts import READS_TYPED, words
from .scratch import ScratchReport
from .scratch_report import mapping_lines

if TYPE_CHECKING:
    from .copies import Copies


def _num(v) -> str:
    if isinstance(v, float):
        return "inf" if math.isinf(v) else f"{v:.6g}"
    return "empty" if v is None else str(v)


def text_report(rep: Report, lang: str = "en") -> str:
    """The report of one book for the terminal, in `lang` (ru, uk, en)."""
    t = words(lang)
    head = f"{rep.path}"
    if rep.error:
        return f"{head}: {t['unusable']}: {say(rep.error, lang)}\n"
    # who: the student (their own cells D1, D2), never the scheme's author
    who = ", ".join(x for x in (rep.student, rep.title) if x)
    lines = [f"{head}" + (f" ({who})" if who else "") + f", {rep.positions} {t['positions']}"]
    lines += issued_lines(rep, lang)
    # the counts, the verdict and the score: one vocabulary with the HTML, JSON and grades.csv
    lines += [say(counts_line(rep), lang, "grading"), say(f"  {verdict(rep)}; score {explain(rep)}", lang, "grading")]
    lines += _typed_lines(rep, lang)
    lines += _cause_lines(rep, lang)
    lines += _dependent_lines(rep, lang)
    lines += _missing_lines(rep, lang)
    lines += _sheet_problem_lines(rep, lang)
    lines += mapping_lines(rep, lang)   # hook (issue 33): a from-scratch book's mapping; [] otherwise
    return "\n".join(lines) + "\n"


def _typed_lines(rep: Report, lang: str) -> list[str]:
    """The rows typed, not computed, and those whose formulas read only typed numbers."""
    t = words(lang)
    lines = []
    typed = rep.typed
    if typed:
        lines.append(say(f"  typed, not computed ({len(typed)}): ", lang, "grading") + ", ".join(
            f"{r.name} ({t['row']} {r.row}, {_typed_where(rep, r, lang)})" for r in typed[:12])
            + (" ..." if len(typed) > 12 else "")
            + say("; accepted (--accept-typed)" if rep.accepted_typed
                  else "; they earn nothing", lang, "grading"))
    pasted = [r.name for r in typed if r.reads_typed]
    if pasted:
        lines.append(say(f"  {READS_TYPED} ({len(pasted)}): ", lang, "grading") + ", ".join(pasted[:12])
                     + (" ..." if len(pasted) > 12 else ""))
    return lines


def _cause_lines(rep: Report, lang: str) -> list[str]:
    """The causes, those with a note (typed numbers: cell, digits, the error they carry) first."""
    t = words(lang)
    lines = []
    for r in sorted(rep.causes, key=lambda r: not r.note):
        where = f"{r.name} ({t['row']} {r.row}, {t.get(r.source, r.source)})"
        note = r.note
        if note:
            lines.append(f"  {t['cause']}: {where}: {say(note, lang)}"
                         + (f"; {t['wrong_at']} {position_list(rep, r.wrong_cells, lang)}" if r.wrong_cells else ""))
        elif r.first_wrong is None:           # a value of column D (a derived row)
            lines.append(f"  {t['cause']}: {where}: {t['expected']} {_num(r.expected)}, {t['got']} {_num(r.got)}")
        else:
            lines.append(f"  {t['cause']}: {where}: {t['wrong_from']} {position_name(rep, r.first_wrong, lang)}"
                         f" ({t['expected']} {_num(r.expected)}, {t['got']} {_num(r.got)}); {t['wrong_at']} "
                         f"{position_list(rep, r.wrong_cells, lang)}; "
                         + (t["error_value"] if math.isinf(r.max_error) else f"{t['largest']} {_num(r.max_error)}"))
    return lines


def _dependent_lines(rep: Report, lang: str) -> list[str]:
    """The wrong rows below each cause, then below each given value that differs from the
    reference's (the issued variant's)."""
    t = words(lang)
    lines = []
    dependents = [r for r in rep.wrong if not r.cause]
    for cause in rep.causes:
        deps = [r.name for r in dependents if cause.name in r.because_of]
        if deps:
            lines.append(f"  {t['depend']} {cause.name}: {', '.join(deps)}")
    causes = {r.name for r in rep.causes}
    given = sorted({n for r in dependents for n in r.because_of if n not in causes})
    for n in given:
        deps = [r.name for r in dependents if n in r.because_of]
        lines.append(f"  {t['depend']} {n}: {', '.join(deps)}")
    return lines


def _missing_lines(rep: Report, lang: str) -> list[str]:
    """One line per kind (an empty exercise once printed 60 lines "empty: Fi (row 32)" ...)."""
    t = words(lang)
    lines = []
    from_scratch = isinstance(rep, ScratchReport) and bool(rep.mapping)     # its rows have no row numbers
    for status in ("missing", "empty"):
        rows = [r for r in rep.missing if r.status == status]
        if rows:
            lines.append(f"  {t[status]} ({len(rows)}): " + ", ".join(
                r.name + (f" ({t['row']} {r.row})" if r.row else "") for r in rows)
                + (t["no_row"] if status == "missing" and not from_scratch else ""))
    return lines


def _sheet_problem_lines(rep: Report, lang: str) -> list[str]:
    """The student's own failing checks, formulas that disagree with their saved values,
    what the evaluator could not compute."""
    t = words(lang)
    lines = []
    if rep.failing_checks:
        lines.append(f"  {t['own_checks']}: {', '.join(rep.failing_checks)}")
    if rep.cache_mismatch:
        lines.append("  " + t["disagree"].format(n=len(rep.cache_mismatch)) + ": "
                     + "; ".join(say(m, lang) for m in rep.cache_mismatch[:5])
                     + (" ..." if len(rep.cache_mismatch) > 5 else ""))
    saved = _saved_rows(rep)
    for p in rep.problems[:5]:
        lines.append(f"  {t['cannot']}: {say(p, lang)}" + (f" {t['saved_used']}" if _rows_of(p, rep) & saved else ""))
    return lines


# where an evaluator's problem is ("Sheet!E42:Q42: what"): its sheet and rows
_WHERE = re.compile(r"(?P<sheet>[^!]+)!\$?[A-Z]{1,3}\$?(?P<r1>\d+)(?::\$?[A-Z]{1,3}\$?(?P<r2>\d+))?: ")


def _saved_rows(rep: Report) -> set[int]:
    """The graded rows where the value the spreadsheet saved stood in for a formula sheetkin
    cannot compute (the validator's source "cached")."""
    return {r.row for r in rep.rows if r.source == "cached" and r.row is not None}


def _rows_of(problem: str, rep: Report) -> set[int]:
    """The graded sheet's rows an evaluator's problem concerns (none on another sheet)."""
    m = _WHERE.match(problem)
    layout = rep.layout
    if m is None or (layout is not None and m.group("sheet") != layout.sheet):
        return set()
    r1 = int(m.group("r1"))
    return set(range(r1, int(m.group("r2") or r1) + 1))


def _typed_where(rep: Report, r, lang: str) -> str:
    """Where a row holds typed values: its positions, or (a derived row) its cell in column D."""
    if r.kind == "derived":
        layout = rep.layout
        return layout.cell(r.row, VALUE_COL) if layout is not None else f"D{r.row}"
    return position_list(rep, r.typed_cells, lang)


def counts_line(rep: Report) -> str:
    """The graded rows by verdict, the same counts as the HTML, the JSON and grades.csv."""
    c = counts(rep)
    return (f"  {c['correct']} of {c['total']} rows correct (computed), {c['typed']} typed (not computed), "
            f"{c['wrong']} wrong, {c['missing']} missing or empty; check rows: {c['checks_passing']} of "
            f"{c['checks_apply']} that apply passing"
            + (f", {c['checks_failing']} failing" if c['checks_failing'] else "")
            + (f", {c['checks_deleted']} deleted" if c['checks_deleted'] else "")
            + (f", {c['checks_typed']} typed over" if c['checks_typed'] else ""))


def issued_lines(rep: Report, lang: str = "en") -> list[str]:
    """Issue 13: the given data changed and the seal, first and prominently; then who
    filled it in and the variant."""
    t = words(lang)
    out = []
    if rep.given_changed:
        how = t["own_inputs"] if rep.accepted_changes else t["fail_issued"]
        out.append(f"  !! {say(changed_line(rep.given_changed), lang)} ({how})")
    if rep.seal and rep.seal != "ok":
        out.append(f"  !! {say(rep.seal, lang)}")
    who = ", ".join(f"{t[k]} {v}" for k, v in (("student", rep.student), ("group", rep.group),
                                              ("variant", rep.variant)) if v)
    if who:
        out.append(f"  {who}" + (f", {t['seal_ok']}" if rep.seal == "ok" else ""))
    out += [f"  {t['note']}: {say(n, lang)}" for n in rep.notes]
    return out


def summary_table(reports: list[Report], lang: str = "en") -> str:
    t = words(lang)
    rows = [(t["file"], t["student"], t["result"], t["score"], t["correct"], t["typed"], t["wrong"], t["missing"],
             t["first_cause"])]
    for r in reports:
        if r.error:
            rows.append((r.path, "", t["unusable"].lower(), "", "", "", "", "", say(r.reason, lang)[:60]))
        else:
            # the student's own cells (D1, D2), never the scheme's author
            who = ", ".join(x for x in (r.student, r.group) if x)
            c = counts(r)
            rows.append((r.path, who, say(verdict(r), lang, "grading"), f"{score(r):.1f}", str(c["correct"]),
                         str(c["typed"]), str(c["wrong"]), str(c["missing"]), r.causes[0].name if r.causes else ""))
    widths = [max(len(x[i]) for x in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(x[i].ljust(widths[i]) for i in range(len(x))).rstrip() for x in rows) + "\n"


def _named_positions(rep: Report) -> dict:
    """grades.report_dict, each row's wrong positions also named as the sheet names them: wrong_i,
    first_wrong_i and first_wrong_phi_1 (wrong_cells, first_wrong: 1-based column counts)."""
    d = report_dict(rep)
    names = rep.position_names or []
    for row in d.get("rows", []):
        cells = row.get("wrong_cells") or []
        row["wrong_i"] = [names[k - 1][0] for k in cells if 0 < k <= len(names)]
        k = row.get("first_wrong")
        row["first_wrong_i"], row["first_wrong_phi_1"] = (names[k - 1] if k and 0 < k <= len(names) else (None, None))
    return d


def json_report(reports: list[Report], copies: Copies | None = None, lang: str = "en") -> str:
    """Every report (grades.report_dict: verdict, score, score_explained, summary counts), each
    with its possible copies (sheetkin/course/copies.py): file, student and why. The notes
    and the reasons of copies are in `lang`; the keys, verdicts and counts, for programs,
    stay as they are."""
    def clean(o):
        if isinstance(o, float) and not math.isfinite(o):
            return None if math.isnan(o) else ("inf" if o > 0 else "-inf")
        if isinstance(o, dict):
            return {k: clean(v) for k, v in o.items()}
        if isinstance(o, list):
            return [clean(v) for v in o]
        return o
    from .copies import Copies
    copies = copies if copies is not None else Copies()
    out = []
    for i, r in enumerate(reports):
        d = _named_positions(r)
        # at most MAX_LISTED others of its cluster: the report stays linear in the class
        others = copies.others(i)[:MAX_LISTED]
        d["possible_copy_of"] = [{"file": reports[j].path, "student": reports[j].student,
                                  "why": say(copies.why(i), lang)} for j in others]
        # sources that are no submission (a variant's key): its file, whom it was issued to
        d["possible_copy_of"] += [{"file": f, "student": s, "why": say(why, lang)}
                                  for f, s, why in copies.sources.get(i, [])]
        if "notes" in d:
            d["notes"] = [say(n, lang) for n in d["notes"]]
        out.append(d)
    return json.dumps(clean({"reports": out,
                             "all_correct": all(all_correct(r) for r in reports)}), indent=1, ensure_ascii=False) + "\n"


def html_report(reports: list[Report], copies: Copies | None = None, lang: str = "en",
                identities: list | None = None, copies_policy: str = "hold") -> str:
    """One offline page: the class at a glance, a sortable summary, per-student details,
    pictures (report_html.py), in `lang`; with identities (sheetkin.course.identity), who
    handed each book in and what does not fit; copies_policy (`validate --copies`): the
    possible copies held for review, as in grades.csv."""
    from .report_html import html_page
    return html_page(reports, copies, lang, identities, copies_policy)


def copies_lines(reports: list[Report], copies, lang: str = "en") -> str:
    """After the summary table: each cluster of possible copies (sheetkin/course/copies.py)
    a line, its files and its reasons (each reason's files when not the whole cluster)."""
    out = []
    for c in copies.clusters:
        files = ", ".join(reports[i].path for i in c.members)
        why = "; ".join(t if len(m) == len(c.members) else f"{t} ({', '.join(reports[i].path for i in m)})"
                        for t, m in c.reasons)
        out.append(say(message("possible_copy_files", n=len(c.members)) + f"{files}: {why}", lang) + "\n")
    return "".join(out)
