"""The validation report as one offline HTML page a teacher works in.

A summary table (student, group, variant, score, result, likely causes, missing rows, the
file) that sorts on a click on its headers; per student a <details> block (closed; a click
on the name in the table opens it) with what went wrong, the wrong cells position by
position, and a picture of the student's mechanism (inline SVG, sheetkin.views.drawing) at the
first position where the likely cause goes wrong. Positions are named as the sheet names
them: its row `i` and the crank angle phi_1. Everything (style, script, pictures) is in
the file; nothing is fetched.

Fields that the validator may not have (variant, student, group, given data changed, seal:
issue 13) are shown when present (getattr with a default). The score is the one grades.csv
gives (sheetkin/course/grades.py); possible copies (sheetkin/course/copies.py) link to each other.
"""
from __future__ import annotations

import html
import math
from pathlib import Path
from typing import TYPE_CHECKING

from sheetkin.messages import message, say

from .report_model import Report
from .report_texts import READS_TYPED, words
from .scratch_report import mapping_table

if TYPE_CHECKING:
    from .copies import Copies

_CSS = """body{font-family:sans-serif;margin:1.2em;color:#222}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:2px 6px;font-size:90%}
th{background:#eee}th button{font:inherit;font-weight:bold;background:none;border:0;cursor:pointer;padding:0}
th[aria-sort=ascending] button::after{content:" \\25B2"}th[aria-sort=descending] button::after{content:" \\25BC"}
td.num{text-align:right}.wrong{background:#ffc7ce}.ok{background:#c6efce}.cause{font-weight:bold}
.empty{background:#f2f2f2;background-image:repeating-linear-gradient(45deg,#ddd 0 2px,transparent 2px 6px)}
.typed{background:#ffeb9c}.notjudged{background:#bdd7ee}td.held{font-style:italic;color:#9c0006}
td{overflow-wrap:break-word}body{max-width:1320px}
#summary td{overflow-wrap:anywhere;min-width:6em}#summary td.num{overflow-wrap:normal;min-width:0}
#summary td:nth-last-child(-n+2){min-width:8em;max-width:22em}
.unusable{color:#9c0006}details{margin:.6em 0;border:1px solid #ddd;padding:.3em .6em}
summary{cursor:pointer;font-weight:bold}.pic{float:right;margin:0 0 .5em 1em}.cells td{min-width:1.2em}
.note{color:#555;font-size:90%}.clear{clear:both}
.bar{display:inline-block;height:.8em;background:#c0504d;vertical-align:middle}
#class-scores .bar{background:#4f81bd}#class td{border:0;padding:1px 6px}"""

_SCRIPT = """
"use strict";
// sort the summary table on a click on a header: numbers as numbers, the rest as text
document.querySelectorAll("#summary th button").forEach((btn, col) => {
  btn.addEventListener("click", () => {
    const th = btn.parentElement, table = th.closest("table"), body = table.tBodies[0];
    const asc = th.getAttribute("aria-sort") !== "ascending";
    table.querySelectorAll("th").forEach(h => h.removeAttribute("aria-sort"));
    th.setAttribute("aria-sort", asc ? "ascending" : "descending");
    const key = tr => tr.cells[col].dataset.sort ?? tr.cells[col].textContent.trim();
    const rows = Array.from(body.rows);
    rows.sort((a, b) => {
      const x = key(a), y = key(b), nx = parseFloat(x), ny = parseFloat(y);
      const c = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : x.localeCompare(y);
      return asc ? c : -c;
    });
    rows.forEach(r => body.appendChild(r));
  });
});
// a student's name (in the table, or as a possible copy) opens their details
document.querySelectorAll("a[data-open]").forEach(a => {
  a.addEventListener("click", () => { document.getElementById(a.dataset.open).open = true; });
});
"""


def _num(v) -> str:
    if isinstance(v, float):
        return "inf" if math.isinf(v) else f"{v:.6g}"
    return "empty" if v is None else str(v)


# a cell of a row's positions: each state its colour (_CSS) and word; green only when right
CELL_STATES = ("ok", "wrong", "empty", "typed", "notjudged")
_CELL_WORDS = {
    "en": {"ok": "right", "wrong": "wrong", "empty": "not filled in", "typed": "typed, not computed",
           "notjudged": "not judged: check by hand"},
    "ru": {"ok": "верно", "wrong": "неверно", "empty": "не заполнено", "typed": "введено числом, не вычислено",
           "notjudged": "не проверено: проверьте вручную"},
    "uk": {"ok": "правильно", "wrong": "неправильно", "empty": "не заповнено",
           "typed": "введено числом, не обчислено", "notjudged": "не перевірено: перевірте вручну"},
}


def cell_state(row, j: int) -> str:
    """The state of position j of a row (CELL_STATES): a row sheetkin cannot judge, an
    empty or missing row, a typed one, then right or wrong at j."""
    if getattr(row, "not_judged", False):
        return "notjudged"
    if row.status in ("missing", "empty"):
        return "empty"
    if j in row.wrong_cells:
        return "wrong"
    if row.is_typed:
        return "typed"
    return "ok"


def cell_word(state: str, lang: str) -> str:
    return _CELL_WORDS.get(lang, _CELL_WORDS["en"])[state]


def position_name(rep: Report, k: int, lang: str = "en") -> str:
    """Position column k (1-based) as the sheet names it: 'i = 3 (phi_1 = 90 deg)'."""
    t = words(lang)
    names = rep.position_names or []
    if k is not None and 0 < k <= len(names):
        i, phi = names[k - 1]
        return f"i = {i:g} (phi_1 = {phi:g} {t['deg']})"
    return f"{t['position']} {k}"


def position_list(rep: Report, cells: list[int], lang: str = "en") -> str:
    """Wrong position columns as the sheet's i values, runs shortened: 'i = 0-2, 6'."""
    names = rep.position_names or []
    ids = [int(names[k - 1][0]) if 0 < k <= len(names) else k for k in cells]
    out, start = [], None
    for n, c in enumerate(ids):
        if start is None:
            start = c
        if n + 1 == len(ids) or ids[n + 1] != c + 1:
            out.append(f"{start}" if start == c else f"{start}-{c}")
            start = None
    return ("i = " if names else words(lang)["positions"] + " ") + ", ".join(out)


def score(rep: Report) -> float | None:
    """The score of grades.csv (sheetkin/course/grades.py); None for an unusable file (the
    table shows no number, and the reason)."""
    if rep.error:
        return None
    from .grades import score as grade_score
    return grade_score(rep)


def _given_changed(ch) -> str:
    """'L1 (D6): 0.14 -> 0.05' from the validator's {"name", "cell", "issued", "got"}."""
    if not isinstance(ch, dict):
        return str(ch)
    cell = f" ({ch['cell']})" if ch.get("cell") else ""
    return f"{ch.get('name', '?')}{cell}: {_num(ch.get('issued'))} -> {_num(ch.get('got'))}"


_IN_THE_BOOK = {"en": "name in the book", "ru": "имя в книге", "uk": "ім'я в книзі"}


def copy_label(rep: Report, me, lang: str = "en") -> str:
    """A book of a group of possible copies as the teacher needs it: who handed it in (the
    Moodle folder's student), and the name typed in it when that is another (a copy of
    Petrova's book handed in by Orlov reads "Орлов Денис (имя в книге: Петрова Анна)")."""
    from .identity import same_name_loosely
    handed = str(me.submitter) if me is not None and me.submitter else ""
    typed = str(rep.student or "")
    if not handed:
        return typed or _file(rep)
    handed = say(handed, lang)
    if typed and not same_name_loosely(typed, handed.split(" (")[0]):
        return f"{handed} ({_IN_THE_BOOK.get(lang, _IN_THE_BOOK['en'])}: {typed})"
    return handed


def _copy_links(reports, k: int, copies, with_reason: bool, lang: str = "en", ids: list | None = None) -> str:
    """Links to the submissions report k may be copied from (or to): at most MAX_LISTED of
    its cluster (sheetkin/course/copies.py), so that the page stays linear in the class."""
    from .copies import MAX_LISTED
    e = html.escape
    out = []
    others = copies.others(k)
    if not others and copies.sources.get(k):      # a variant's key: the reason names it
        return e(say(copies.why(k), lang))
    for j in others[:MAX_LISTED]:
        other = reports[j]
        name = copy_label(other, ids[j] if ids else None, lang)
        out.append(f"<a href='#{_anchor(other, j)}' data-open='{_anchor(other, j)}'>{e(name)}</a>"
                   + (f" ({e(other.path)})" if with_reason else ""))
    if len(others) > MAX_LISTED:
        out.append(e(say(message("and_more", n=len(others) - MAX_LISTED), lang).strip()))
    text = ", ".join(out)
    return text + (f": {e(say(copies.why(k), lang))}" if with_reason and text else "")


def _cut(names: str, width: int) -> str:
    """A ", "-joined list cut to about `width` characters at a name, "..." for the rest."""
    if len(names) <= width:
        return names
    return names[:width].rsplit(", ", 1)[0] + ", ..."


def _anchor(rep: Report, k: int) -> str:
    return f"s{k}"


def _picture(rep: Report, lang: str = "en") -> str:
    """The student's mechanism (their variant) at the first position where the first likely
    cause is wrong, else at the first position; '' when it cannot be drawn."""
    scene = rep.variant_scene
    if scene is None:
        return ""
    try:
        from sheetkin.views.drawing import picture, svg
        at = scene.crank_angles_deg()
        names = rep.position_names or []
        k = next((c.first_wrong for c in rep.causes if c.first_wrong), 1)
        phi = names[k - 1][1] if 0 < k <= len(names) else at[min(k, len(at)) - 1]
        pic = picture(scene, [phi])
        cap = pic.captions[0]                    # "phi_1 = 90 deg[: cannot assemble ...]"
        from sheetkin.views.animate import say as said  # the drawing's words ("cannot assemble") in lang
        pic.captions[0] = position_name(rep, k, lang) + said(cap.split(" deg", 1)[1] if " deg" in cap else "", lang)
        pic.title = said(pic.title, lang)           # an issued variant's title: "... (вариант fourbar-01)"
        return svg(pic, 0, 360)
    except Exception as exc:           # a picture is a help, never a reason to lose the report
        return f"<p class='note'>({words(lang)['no_picture']}: {html.escape(str(exc))})</p>"


def _file(rep: Report) -> str:
    """Who a book is when the student left their name blank: its file, never A2 (the
    scheme's author, which every exercise carries: issue 13)."""
    return Path(rep.path).name or rep.path


def _identity_lines(me, lang: str) -> list[str]:
    """A book's identity flags and why the class list names no one (or several), in `lang`."""
    if me is None:
        return []
    return [say(x, lang) for x in [*me.flags, *([me.unmatched] if me.unmatched else [])]]


def _summary_row(rep: Report, k: int, copy: str = "", lang: str = "en", me=None, held: bool = False) -> str:
    e, t = html.escape, words(lang)
    who = rep.student or _file(rep)
    group = rep.group
    variant = rep.variant or ""
    from .grades import VERDICTS, counts, verdict
    res = verdict(rep)
    cls = "ok" if res == "all correct" else "wrong"
    c = counts(rep)
    sc = score(rep)
    causes = ", ".join(c.name for c in rep.causes) if not rep.error else say(rep.reason, lang)[:80]
    missing = ", ".join(r.name for r in rep.missing)
    if rep.given_changed:
        causes = t["given_changed"] + (f"; {causes}" if causes else "")
    flags = _identity_lines(me, lang)
    return (f"<tr><td><a href='#{_anchor(rep, k)}' data-open='{_anchor(rep, k)}'>{e(who or rep.path)}</a></td>"
            f"<td>{e(group)}</td><td>{e(str(variant))}</td>"
            f"<td class='num{' held' if held else ''}' data-sort='{'' if sc is None else f'{sc:.3f}'}'>"
            f"{'' if sc is None else f'{sc:.1f}'}{' (' + e(t['held']) + ')' if held else ''}</td>"
            f"<td class='{cls}' data-sort='{VERDICTS.index(res)}'>{say(res, lang, 'grading')}</td>"
            f"<td class='num'>{'' if rep.error else c['correct']}</td>"
            f"<td class='num'>{'' if rep.error else c['typed']}</td>"
            f"<td class='num'>{'' if rep.error else c['wrong']}</td>"
            f"<td>{e(causes)}</td><td class='num' data-sort='{c['missing']}'>{c['missing'] or ''}"
            f"{' (' + e(_cut(missing, 80)) + ')' if missing else ''}</td>"
            f"<td class='{'wrong' if copy else ''}'>{copy}</td>"
            + (f"<td class='{'wrong' if flags else ''}'>{e('; '.join(flags))}</td>" if me is not None else "")
            + f"<td>{e(rep.path)}</td></tr>")


def _details(rep: Report, k: int, copy: str = "", lang: str = "en", me=None) -> list[str]:
    """A book's details: who and what (_facts), its score and counts (_score_lines), the
    likely causes (_cause_lines), its rows position by position (_cells_table) and the
    lists of failing checks and notes (_lists)."""
    e, t = html.escape, words(lang)
    from .grades import verdict
    out = [f"<details id='{_anchor(rep, k)}'><summary>{e(rep.student or _file(rep))}: "
           f"{e(say(verdict(rep), lang, 'grading'))}</summary>",
           f"<p class='note'>{e(rep.path)}{' - ' + e(rep.title) if rep.title else ''}</p>"]
    if rep.error:
        out.append(f"<p class='unusable'>{t['unusable_p']}: {e(say(rep.error, lang))}</p></details>")
        return out
    out.append(f"<div class='pic'>{_picture(rep, lang)}</div>")
    out += _facts(rep, copy, lang, me)
    out += _score_lines(rep, lang)
    out += _cause_lines(rep, lang)
    out += _cells_table(rep, lang)
    out += _lists(rep, lang, me)
    out += mapping_table(rep, lang)     # hook (issue 33): a from-scratch book's mapping; [] otherwise
    out.append("<div class='clear'></div></details>")
    return out


def _facts(rep: Report, copy: str, lang: str, me) -> list[str]:
    """Student, group, variant, seal; the given data changed, a possible copy, who handed it in."""
    e, t = html.escape, words(lang)
    out = []
    for label, v in (("student", rep.student), ("group", rep.group), ("variant", rep.variant), ("seal", rep.seal)):
        if label == "seal" and v == "ok":            # "seal: ok" in words: "печать цела"
            out.append(f"<p class='note'>{t['seal_ok']}</p>")
        elif v:
            out.append(f"<p class='note'>{t[label]}: {e(say(str(v), lang))}</p>")
    changed = rep.given_changed or []
    if changed:
        out.append(f"<p class='wrong'>{t['given_changed']}: " + e(", ".join(_given_changed(c) for c in changed))
                   + "</p>")
    if copy:
        out.append(f"<p class='wrong'>{t['copy_of']}: {copy}</p>")
    flags = _identity_lines(me, lang)
    if flags:
        out.append(f"<p class='wrong identity'>{t['identity_h']}: " + e("; ".join(flags)) + "</p>")
    return out


def _score_lines(rep: Report, lang: str) -> list[str]:
    """The score explained, the rows counted, the typed rows (and those reading typed numbers)."""
    e = html.escape
    from .grades import counts, explain
    n = counts(rep)
    said = say(f"score {explain(rep)} (the rules:", lang, "grading")
    out = [f"<p>{e(said)} <code>sheetkin docs grading</code>)</p>",
           "<p>" + e(say(f"{n['correct']} of {n['total']} rows correct (computed), {n['typed']} typed "
                         f"(not computed), {n['wrong']} wrong, {n['missing']} missing or empty.", lang, "grading"))
           + "</p>"]
    typed = rep.typed
    if typed:
        out.append("<p class='wrong'>" + e(say("typed, not computed: ", lang, "grading"))
                   + e(", ".join(x.name for x in typed)) + "</p>")
        pasted = [x.name for x in typed if x.reads_typed]
        if pasted:
            out.append("<p class='wrong'>" + e(say(f"{READS_TYPED}: ", lang, "grading")) + e(", ".join(pasted))
                       + "</p>")
    return out


def _cause_lines(rep: Report, lang: str) -> list[str]:
    """Each likely cause: its row, where it first goes wrong, expected and got."""
    e, t = html.escape, words(lang)
    out = []
    for c in rep.causes:
        src = e(t.get(c.source, c.source) or "")
        out.append(f"<p class='cause'>{t['cause']}: {e(c.name)} ({t['row']} {c.row}, {src}):"
                   f" {t['wrong_from']} {e(position_name(rep, c.first_wrong or 1, lang))}, {t['expected']} "
                   f"{e(_num(c.expected))}, {t['got']} {e(_num(c.got))}; {t['wrong_at']} "
                   f"{e(position_list(rep, c.wrong_cells, lang))}"
                   + (f"<br>{e(say(c.note, lang))}" if c.note else "") + "</p>")
    return out


def _row_word(x, lang: str) -> str:
    """A row's status word, agreeing with its cells: a typed row is never "right"."""
    if getattr(x, "not_judged", False):
        return cell_word("notjudged", lang)
    if x.is_typed and x.status not in ("missing", "empty"):
        return cell_word("typed", lang)
    t = words(lang)
    return str(t.get(x.status, x.status))


def _row_note(rep: Report, x, lang: str) -> str:
    t = words(lang)
    note = (t["cause"] if x.cause else
            f"{t['depends_on']} {', '.join(x.because_of)}" if x.because_of else "")
    if x.status == "wrong":
        note += (f"; {t['first_at']} {position_name(rep, x.first_wrong or 1, lang)}: {t['expected']} "
                 f"{_num(x.expected)}, {t['got']} {_num(x.got)}")
    return note


def _cells_table(rep: Report, lang: str) -> list[str]:
    """The rows not right (wrong, empty, typed, not judged), a cell per position in its
    state's colour and word (cell_state)."""
    e, t = html.escape, words(lang)
    # a typed row equal to the reference, and a row not judged, are not right either
    bad = [x for x in rep.rows if x.status != "correct" or x.is_typed or getattr(x, "not_judged", False)]
    if not bad:
        return []
    names = rep.position_names or []
    head = "".join(f"<th title='phi_1 = {names[j][1]:g} {t['deg']}'>{names[j][0]:g}<br>{names[j][1]:g}&deg;</th>"
                   if j < len(names) else f"<th>{j}</th>" for j in range(rep.positions))
    out = [f"<table class='cells'><caption class='note'>{t['cells_caption']}</caption>"
           f"<tr><th>{t['row']}</th><th>{t['status']}</th>{head}<th>{t['note']}</th></tr>"]
    for x in bad:
        cells = "".join(
            f"<td class='{state}' title='{e(position_name(rep, j, lang))}: {e(cell_word(state, lang))}'></td>"
            for j in range(1, rep.positions + 1) for state in (cell_state(x, j),))
        out.append(f"<tr><td class='{'cause' if x.cause else ''}'>{e(x.name)}</td>"
                   f"<td>{e(_row_word(x, lang))}</td>{cells}<td>{e(_row_note(rep, x, lang))}</td></tr>")
    out.append("</table>")
    return out


def _lists(rep: Report, lang: str, me) -> list[str]:
    """Failing checks, check rows deleted or typed over, notes, cache disagreements, problems."""
    e, t = html.escape, words(lang)
    out = []
    for title, items in ((t["failing_checks"], rep.failing_checks),
                         (message("check_rows_deleted"), rep.checks_deleted),
                         (message("check_statuses_typed_over"), rep.checks_typed),
                         ("Notes", [n for n in rep.notes
                                    if me is None or not n.startswith("identity: ")]),   # shown above
                         (t["disagree_h"], rep.cache_mismatch),
                         (t["cannot_h"], rep.problems)):
        if items:
            out.append(f"<p>{e(say(title, lang))}:</p><ul>" + "".join(f"<li>{e(say(i, lang))}</li>" for i in items)
                       + "</ul>")
    return out


def html_page(reports: list[Report], copies: Copies | None = None, lang: str = "en",
              identities: list | None = None, copies_policy: str = "hold") -> str:
    """The page (module docstring). identities: sheetkin.course.identity.identify's, one per
    report: who handed each book in, shown in the summary and the details; copies_policy
    (`validate --copies`): with hold, the possible copies are counted and marked held for
    review, as grades.csv holds them."""
    t = words(lang)
    ids = identities if identities is not None and len(identities) == len(reports) else [None] * len(reports)
    graded = graded_books(reports, identities)     # an older file of a student is not counted
    from .copies import Copies
    from .grades import all_correct
    correct = sum(all_correct(r) for r in graded)
    copies = copies if copies is not None else Copies()
    out = [f"<!doctype html><html lang='{lang}'><head><meta charset='utf-8'>"
           f"<link rel='icon' href='data:,'><title>{t['title']}</title>"
           f"<style>{_CSS}</style></head><body>",
           f"<h1>{html.escape(t['h1'].format(n=len(reports)))}</h1>",
           f"<p>{html.escape(t['intro'].format(c=correct, o=len(graded) - correct))}</p>"]
    out += class_at_a_glance(reports, lang, identities, copies, copies_policy)
    held = held_books(reports, copies, identities, copies_policy)
    out += [f"<h2>{t['students']}</h2>",
            "<table id='summary'><thead><tr>" + "".join(
                f"<th><button type='button'>{t.get(h, h)}</button></th>" for h in
                ("student", "group", "variant", "score", "result", "rows correct", "rows typed", "wrong_rows",
                 "likely_causes", "missing_rows", "copy_of", *(("identity",) if identities is not None else ()),
                 "file")) + "</tr></thead><tbody>"]
    out += [_summary_row(r, k, _copy_links(reports, k, copies, False, lang, ids), lang, ids[k], k in held)
            for k, r in enumerate(reports)]
    out.append("</tbody></table>")
    out += _copy_groups(reports, copies, lang, ids)
    for k, r in enumerate(reports):
        out += _details(r, k, _copy_links(reports, k, copies, True, lang, ids), lang, ids[k])
    out.append(f"<script>{_SCRIPT}</script></body></html>\n")
    return "\n".join(out)


SHOWN_IN_GROUP = 50          # the books a group of possible copies names on its line


def _copy_groups(reports: list[Report], copies, lang: str, ids: list | None = None) -> list[str]:
    """Each group of possible copies (sheetkin/course/copies.py) a line: its books (links)
    and its reasons; one line per group, never every pair."""
    clusters = copies.clusters
    if not clusters:
        return []
    e, t = html.escape, words(lang)
    out = [f"<h3 id='copies'>{t['copies_h']}</h3><ul id='copy-groups'>"]
    for c in clusters:
        names = [f"<a href='#{_anchor(reports[i], i)}' data-open='{_anchor(reports[i], i)}'>"
                 f"{e(copy_label(reports[i], ids[i] if ids else None, lang))}</a>"
                 for i in c.members[:SHOWN_IN_GROUP]]
        more = len(c.members) - SHOWN_IN_GROUP
        why = "; ".join(say(x, lang) if len(m) == len(c.members) else
                        f"{say(x, lang)} ({len(m)})" for x, m in c.reasons)
        out.append(f"<li>{len(c.members)}: {', '.join(names)}{f' (+{more})' if more > 0 else ''}: {e(why)}</li>")
    return out + ["</ul>"]


def _share_table(ident: str, what: str, counts: list[tuple[str, int]], books: int, t: dict,
                 apart: dict[str, dict[str, int]] | None = None, lang: str = "en") -> str:
    """A table of names with how many books got each wrong and that share as a bar; with
    `apart` ({cell state: {name: books}}), a column for each state (typed, not filled in):
    the books where the row is so, not counted as wrong."""
    e = html.escape
    apart = apart or {}
    extra = "".join(f"<th class='{s}'>{e(cell_word(s, lang))}</th>" for s in apart)
    out = [f"<table id='{ident}'><tr><th>{what}</th><th>{t['books']}</th><th>{t['share']}</th>{extra}</tr>"]
    for n, c in counts:
        share = c / books
        more = "".join(f"<td class='num' data-state='{s}'>{apart[s].get(n, 0) or ''}</td>" for s in apart)
        out.append(f"<tr data-row='{e(n)}' data-share='{share:.4f}'><td>{e(n)}</td><td class='num'>{c}</td>"
                   f"<td><span class='bar' style='width:{share * 20:.2f}em'></span> {100 * share:.0f}%</td>{more}</tr>")
    return "".join(out) + "</table>"


def graded_books(reports: list[Report], identities: list | None = None) -> list[Report]:
    """The books that are graded: not an older file of a student whose newer one is
    (identity.py's superseded_by)."""
    ids = identities if identities is not None and len(identities) == len(reports) else [None] * len(reports)
    return [r for r, me in zip(reports, ids, strict=True) if me is None or me.superseded_by is None]


def held_books(reports: list[Report], copies=None, identities: list | None = None,
               copies_policy: str = "hold") -> set[int]:
    """The graded books held for review as possible copies (grades.csv leaves their score
    empty, status STATUS_HELD): none unless the policy is hold (`validate --copies`)."""
    if copies is None or copies_policy != "hold":
        return set()
    from .grades import copy_text
    graded = {id(r) for r in graded_books(reports, identities)}
    return {i for i, r in enumerate(reports) if id(r) in graded and copy_text(reports, i, copies)}


def class_at_a_glance(reports: list[Report], lang: str = "en", identities: list | None = None,
                      copies=None, copies_policy: str = "hold") -> list[str]:
    """Issue 22: the picture of the class before the list of students. Each row's share of
    wrong books (computed wrong: grades.row_verdict), in the lecture's order (the order of
    the rows in the sheet), as bars, and beside it the books where the row is typed (numbers
    where formulas belong) and where it is not filled in: issue 34, neither is wrong; then
    the distribution of scores in tens. Only graded books count (an older file of a student
    is not one); a line says how many, and how many of them are held for review as possible
    copies (copies, copies_policy: held_books). Rows right in every book are left out; the
    bars are plain HTML (no script needed)."""
    from .grades import row_verdict, typed_accepted
    e, t = html.escape, words(lang)
    held = len(held_books(reports, copies, identities, copies_policy))
    reports = graded_books(reports, identities)
    usable = [r for r in reports if not r.error]
    out = [f"<section id='class'><h2>{t['class']}</h2>",
           f"<p id='class-counts' data-graded='{len(reports)}' data-held='{held}'>"
           f"{e(t['class_counts'].format(n=len(reports), h=held))}</p>"]
    order: list[str] = []
    wrong: dict[str, int] = {}
    typed: dict[str, int] = {}
    empty: dict[str, int] = {}
    for r in usable:
        acc = typed_accepted(r, None)
        for x in r.rows:
            if x.name not in wrong:
                order.append(x.name)
                wrong[x.name] = typed[x.name] = empty[x.name] = 0
            if getattr(x, "not_judged", False):
                continue
            v = row_verdict(x, acc)
            if v == "missing":
                empty[x.name] += 1
            elif v == "typed":
                typed[x.name] += 1
            elif v == "wrong":
                wrong[x.name] += 1
    shown = [n for n in order if wrong[n] or typed[n] or empty[n]]
    out.append(f"<h3>{e(t['class_rows'].format(n=len(usable)))}</h3>")
    if not shown:
        out.append(f"<p class='note'>{t['none_wrong']}</p>")
    else:
        out.append(_share_table("class-rows", t["row"], [(n, wrong[n]) for n in shown], len(usable), t,
                                {"typed": typed, "empty": empty}, lang))
    failing: dict[str, int] = {}
    for r in usable:                    # in the sheet's order, as each book lists them
        for n in r.failing_checks:
            failing[n] = failing.get(n, 0) + 1
    if failing:
        out.append(f"<h3>{e(t['class_checks'])}</h3>")
        out.append(_share_table("class-checks", t["check"], list(failing.items()), len(usable), t))
    scores = [score(r) or 0.0 for r in reports]
    bins = [0] * 10
    for sc in scores:
        bins[min(int(sc // 10), 9)] += 1
    top = max(bins) or 1
    out.append(f"<h3>{e(t['class_scores'].format(n=len(scores)))}</h3><table id='class-scores'>")
    for k, c in enumerate(bins):
        label = f"{10 * k}-{10 * k + 9 if k < 9 else 100}"
        out.append(f"<tr data-bin='{label}' data-count='{c}'><td>{label}</td><td class='num'>{c}</td>"
                   f"<td><span class='bar' style='width:{12 * c / top:.2f}em'></span></td></tr>")
    out.append("</table></section>")
    return out
