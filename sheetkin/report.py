"""Reports of the validator: text for the terminal, JSON, and an HTML page."""
from __future__ import annotations

import html
import json
import math

from .validator import Report


def _num(v) -> str:
    if isinstance(v, float):
        return "inf" if math.isinf(v) else f"{v:.6g}"
    return "empty" if v is None else str(v)


def text_report(rep: Report) -> str:
    head = f"{rep.path}"
    if rep.error:
        return f"{head}: UNUSABLE: {rep.error}\n"
    who = ", ".join(x for x in (rep.author, rep.title) if x)
    lines = [f"{head}" + (f" ({who})" if who else "") + f", {rep.positions} positions"]
    correct = sum(r.status == "correct" for r in rep.rows)
    lines.append(f"  {correct} rows correct, {len(rep.wrong)} wrong, {len(rep.missing)} missing or empty"
                 + ("  -> all correct" if rep.ok else ""))
    for r in rep.causes:
        lines.append(f"  likely cause: {r.name} (row {r.row}, {r.source}): wrong from position {r.first_wrong}"
                     f" (expected {_num(r.expected)}, got {_num(r.got)}); wrong at positions "
                     f"{_positions(r.wrong_cells)}; largest error {_num(r.max_error)}")
    dependents = [r for r in rep.wrong if not r.cause]
    for cause in rep.causes:
        deps = [r.name for r in dependents if cause.name in r.because_of]
        if deps:
            lines.append(f"  wrong only because they depend on {cause.name}: {', '.join(deps)}")
    for r in rep.missing:
        lines.append(f"  {r.status}: {r.name}" + (f" (row {r.row})" if r.row else " (no row of that name in column A)"))
    if rep.failing_checks:
        lines.append(f"  the sheet's own check rows that fail: {', '.join(rep.failing_checks)}")
    if rep.cache_mismatch:
        lines.append(f"  formula and saved value disagree at {len(rep.cache_mismatch)} cell(s): "
                     + "; ".join(rep.cache_mismatch[:5]) + (" ..." if len(rep.cache_mismatch) > 5 else ""))
    for p in rep.problems[:5]:
        lines.append(f"  cannot evaluate: {p} (the saved values were used)")
    return "\n".join(lines) + "\n"


def _positions(cells: list[int]) -> str:
    """1, 2, 3, 7 -> '1-3, 7'."""
    out, start = [], None
    for i, c in enumerate(cells):
        if start is None:
            start = c
        if i + 1 == len(cells) or cells[i + 1] != c + 1:
            out.append(f"{start}" if start == c else f"{start}-{c}")
            start = None
    return ", ".join(out)


def summary_table(reports: list[Report]) -> str:
    rows = [("file", "student", "result", "wrong", "missing", "first cause")]
    for r in reports:
        if r.error:
            rows.append((r.path, "", "unusable", "", "", r.error[len(r.path) + 2:][:60]))
        else:
            rows.append((r.path, r.author, "correct" if r.ok else "mistakes", str(len(r.wrong)),
                         str(len(r.missing)), r.causes[0].name if r.causes else ""))
    widths = [max(len(x[i]) for x in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(x[i].ljust(widths[i]) for i in range(len(x))).rstrip() for x in rows) + "\n"


def json_report(reports: list[Report]) -> str:
    def clean(o):
        if isinstance(o, float) and not math.isfinite(o):
            return None if math.isnan(o) else ("inf" if o > 0 else "-inf")
        if isinstance(o, dict):
            return {k: clean(v) for k, v in o.items()}
        if isinstance(o, list):
            return [clean(v) for v in o]
        return o
    return json.dumps(clean({"reports": [r.to_dict() for r in reports],
                             "all_correct": all(r.ok for r in reports)}), indent=1, ensure_ascii=False) + "\n"


_CSS = """body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse;margin:.5em 0}
td,th{border:1px solid #bbb;padding:2px 6px;font-size:90%;text-align:right}th{background:#eee}
td.name{text-align:left}.wrong{background:#ffc7ce}.ok{background:#c6efce}.cause{font-weight:bold}
.unusable{color:#9c0006}h2{margin-top:1.5em}"""


def html_report(reports: list[Report]) -> str:
    e = html.escape
    out = [f"<!doctype html><html><head><meta charset='utf-8'><title>sheetkin validation</title>"
           f"<style>{_CSS}</style></head><body><h1>sheetkin: validation of {len(reports)} workbook(s)</h1>",
           "<table><tr><th>file</th><th>student</th><th>result</th><th>wrong rows</th><th>first cause</th></tr>"]
    for r in reports:
        res = "unusable" if r.error else ("correct" if r.ok else "mistakes")
        cls = "wrong" if res != "correct" else "ok"
        out.append(f"<tr><td class='name'><a href='#{e(r.path)}'>{e(r.path)}</a></td><td class='name'>{e(r.author)}</td>"
                   f"<td class='{cls}'>{res}</td><td>{len(r.wrong)}</td>"
                   f"<td class='name'>{e(r.causes[0].name) if r.causes else ''}</td></tr>")
    out.append("</table>")
    for r in reports:
        out.append(f"<h2 id='{e(r.path)}'>{e(r.path)}</h2>")
        if r.error:
            out.append(f"<p class='unusable'>Unusable: {e(r.error)}</p>")
            continue
        out.append(f"<p>{e(r.author)} {e(r.title)}: {sum(x.status == 'correct' for x in r.rows)} rows correct, "
                   f"{len(r.wrong)} wrong, {len(r.missing)} missing or empty.</p>")
        bad = [x for x in r.rows if x.status != "correct"]
        if bad:
            out.append("<table><tr><th>row</th><th>status</th>" +
                       "".join(f"<th>{k}</th>" for k in range(1, r.positions + 1)) + "<th>note</th></tr>")
            for x in bad:
                cells = "".join(f"<td class='{'wrong' if k in x.wrong_cells else 'ok'}'></td>"
                                for k in range(1, r.positions + 1))
                note = ("likely cause" if x.cause else
                        f"depends on {', '.join(x.because_of)}" if x.because_of else "")
                if x.status == "wrong":
                    note += f"; first: expected {_num(x.expected)}, got {_num(x.got)}"
                out.append(f"<tr><td class='name{' cause' if x.cause else ''}'>{e(x.name)}</td><td>{x.status}</td>"
                           f"{cells}<td class='name'>{e(note)}</td></tr>")
            out.append("</table>")
        for title, items in (("Check rows of the sheet that fail", r.failing_checks),
                             ("Formula and saved value disagree", r.cache_mismatch),
                             ("Cannot evaluate", r.problems)):
            if items:
                out.append(f"<p>{title}:</p><ul>" + "".join(f"<li>{e(i)}</li>" for i in items) + "</ul>")
    out.append("</body></html>\n")
    return "\n".join(out)
