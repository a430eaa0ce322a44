"""issue 34: the HTML report true at a glance: a position green only when right (empty,
typed, wrong, not judged each their colour and word), the class at a glance counting
graded books only and empty rows apart from wrong ones, a copy named by who handed it in."""
from __future__ import annotations

import re

from sheetkin.course.identity import Identity
from sheetkin.course.report_html import CELL_STATES, cell_state, cell_word, class_at_a_glance, copy_label, html_page
from sheetkin.course.report_model import Report, RowReport


def _book(path, rows, student=""):
    rep = Report(path, rows=rows, positions=4, student=student)
    rep.checks_total = 0
    return rep


def test_each_state_its_colour_and_word_green_only_when_right():
    rows = [RowReport("ok", 10, "correct"), RowReport("w", 11, "wrong", wrong_cells=[2]),
            RowReport("e", 12, "empty"), RowReport("m", None, "missing"),
            RowReport("t", 13, "correct", source="typed", typed_cells=[1, 2, 3, 4])]
    nj = RowReport("nj", 14, "correct")
    nj.not_judged = True
    rep = _book("a.xlsx", [*rows, nj])
    assert rows[4].is_typed                                  # the model calls it typed
    got = {r.name: [cell_state(r, j) for j in range(1, 5)] for r in rep.rows}
    assert got["w"] == ["ok", "wrong", "ok", "ok"]
    assert got["e"] == got["m"] == ["empty"] * 4 and got["t"] == ["typed"] * 4 and got["nj"] == ["notjudged"] * 4
    for lang in ("ru", "uk", "en"):
        words = [cell_word(s, lang) for s in CELL_STATES]
        assert len(set(words)) == len(CELL_STATES)            # each its own word
    assert cell_word("empty", "ru") == "не заполнено" and cell_word("wrong", "ru") == "неверно"
    page = html_page([rep], lang="ru")
    cells = re.findall(r"<td class='(\w+)' title='[^']*: ([^']*)'></td>", page)
    assert ("empty", "не заполнено") in cells and ("typed", "введено числом, не вычислено") in cells
    assert all(word == "верно" for cls, word in cells if cls == "ok")
    assert "<tr><td class=''>t</td><td>введено числом, не вычислено</td>" in page     # the row's word too
    assert not any(cls == "ok" for cls, word in cells if word != "верно")
    # every state has its own colour in the page's style
    colours = {c: re.search(rf"\.{c}{{background:(#[0-9a-f]+)", page).group(1) for c in CELL_STATES}
    assert len(set(colours.values())) == len(CELL_STATES)


def test_the_class_at_a_glance_counts_graded_books_and_empty_apart():
    old = _book("old.xlsx", [RowReport("omega_2", 10, "wrong", wrong_cells=[1])])
    new = _book("new.xlsx", [RowReport("omega_2", 10, "correct")])
    empty = _book("b.xlsx", [RowReport("omega_2", 10, "empty")])
    ids = [Identity(ident="i", superseded_by=1), Identity(ident="i"), Identity(ident="p")]
    html = "".join(class_at_a_glance([old, new, empty], "ru", ids))
    # two graded books: omega_2 wrong in none, not filled in in one
    row = re.search(r"<tr data-row='omega_2' data-share='([\d.]+)'>(.*?)</tr>", html)
    assert row and float(row.group(1)) == 0.0 and row.group(2).endswith("<td class='num' data-state='empty'>1</td>")
    assert "не заполнено" in html and "(проверено книг: 2)" in html


def test_a_copy_names_who_handed_it_in_and_whose_book_it_is():
    me = Identity(ident="o@x", submitter="Денис Орлов (Moodle participant 4)")
    rep = _book("orlov-final.xlsx", [], student="Петрова Анна")
    assert copy_label(rep, me, "ru") == "Денис Орлов (участник Moodle 4) (имя в книге: Петрова Анна)"
    own = _book("petrova.xlsx", [], student="Петрова Анна")
    assert copy_label(own, Identity(submitter="Анна Петрова (Moodle participant 2)"), "en") == \
        "Анна Петрова (Moodle participant 2)"
    assert copy_label(own, None, "en") == "Петрова Анна"


def _class_with_each_kind():
    """A typed row, a wrong row, an empty row, and two books held as copies of each other;
    an older file (superseded) whose wrong row must not count."""
    from sheetkin.course.copies import Cluster, Copies
    typed = _book("typed.xlsx", [RowReport("omega_2", 10, "correct", source="typed", typed_cells=[1, 2, 3, 4]),
                                 RowReport("eps_2", 11, "correct")], student="Иванов")
    wrong = _book("wrong.xlsx", [RowReport("omega_2", 10, "correct"),
                                 RowReport("eps_2", 11, "wrong", wrong_cells=[2])], student="Петров")
    empty = _book("empty.xlsx", [RowReport("omega_2", 10, "empty"), RowReport("eps_2", 11, "correct")],
                  student="Сидоров")
    copy_a = _book("a.xlsx", [RowReport("omega_2", 10, "correct"), RowReport("eps_2", 11, "correct")],
                   student="Орлов")
    copy_b = _book("b.xlsx", [RowReport("omega_2", 10, "correct"), RowReport("eps_2", 11, "correct")],
                   student="Орлова")
    older = _book("old.xlsx", [RowReport("omega_2", 10, "wrong", wrong_cells=[1]),
                               RowReport("eps_2", 11, "wrong", wrong_cells=[1])], student="Петров")
    reports = [typed, wrong, empty, copy_a, copy_b, older]
    ids = [Identity(ident=f"s{k}") for k in range(5)] + [Identity(ident="s1", superseded_by=1)]
    copies = Copies([Cluster([3, 4], [("byte-identical files", [3, 4])])])
    return reports, ids, copies


def _counts(page: str) -> dict[str, list[str]]:
    """{row: [wrong books, typed, not filled in]} of the class-rows table."""
    table = re.search(r"<table id='class-rows'>(.*?)</table>", page).group(1)
    out = {}
    for name, cells in re.findall(r"<tr data-row='(\w+)'[^>]*>(.*?)</tr>", table):
        nums = re.findall(r"<td class='num'(?: data-state='(\w+)')?>(\d*)</td>", cells)
        out[name] = {state or "wrong": int(v or 0) for state, v in nums}
    return out


def test_the_class_at_a_glance_typed_and_empty_apart_from_wrong_and_held_counted():
    reports, ids, copies = _class_with_each_kind()
    for lang, typed_word, empty_word, held_word in (
            ("ru", "введено числом, не вычислено", "не заполнено", "отложено для проверки"),
            ("en", "typed, not computed", "not filled in", "held for review")):
        page = html_page(reports, copies, lang, ids)
        got = _counts(page)
        # the older file's wrong rows are not counted; typed and empty are not wrong
        assert got["omega_2"] == {"wrong": 0, "typed": 1, "empty": 1}
        assert got["eps_2"] == {"wrong": 1, "typed": 0, "empty": 0}
        head = re.search(r"<table id='class-rows'><tr>(.*?)</tr>", page).group(1)
        assert f"<th class='typed'>{typed_word}</th><th class='empty'>{empty_word}</th>" in head
        counts = re.search(r"<p id='class-counts' data-graded='(\d+)' data-held='(\d+)'>([^<]*)</p>", page)
        assert counts and counts.group(1, 2) == ("5", "2")
        assert "5" in counts.group(3) and "2" in counts.group(3)
        # the two copies' scores are marked held in the students' table, no other
        held = re.findall(r"<td class='num held'[^>]*>([^<]*)</td>", page)
        assert len(held) == 2 and all(held_word in h for h in held)
        # with --copies keep nothing is held
        kept = html_page(reports, copies, lang, ids, copies_policy="keep")
        assert "data-held='0'" in kept and "num held" not in kept
