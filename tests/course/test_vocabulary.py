"""One vocabulary (issue 21, item 7) on reports built by hand: the verdict, the counts and the
score come from sheetkin/course/grades.py and agree; "all correct" is full marks; typed rows
earn nothing; the copies of a class are one line per group, never every pair. (The same
rules on books made in LibreOffice: test_grading_rules.py.)"""
from __future__ import annotations

from sheetkin.course import grades
from sheetkin.course.copies import Cluster, Copies
from sheetkin.course.grades import all_correct
from sheetkin.course.report import copies_lines, text_report
from sheetkin.course.report_model import Report, RowReport


def report(correct=4, typed=0, wrong=0, typed_only=False, checks=10, deleted=0) -> Report:
    rows = [RowReport(f"ok{k}", 10 + k, "correct", formula_cells=13) for k in range(correct)]
    rows += [RowReport(f"t{k}", 20 + k, "correct", typed_cells=list(range(1, 14)), source="typed",
                       formula_cells=0 if typed_only else 1) for k in range(typed)]
    rows += [RowReport(f"w{k}", 40 + k, "wrong", wrong_cells=[1], formula_cells=13) for k in range(wrong)]
    rep = Report("b.xlsx", rows=rows, positions=13, checks_issued=checks,
                 checks_deleted=[f"chk{k}" for k in range(deleted)], failing_checks=[f"chk{k}" for k in range(deleted)])
    rep.checks_total, rep.checks_passing, rep.checks_apply = checks - deleted, checks - deleted, checks
    return rep


def test_all_correct_is_full_marks():
    for rep in (report(), report(typed=1), report(wrong=1), report(deleted=1), report(correct=0, typed=3)):
        s, v = grades.score(rep), grades.verdict(rep)
        assert (v == "all correct") == (s == 100.0) == all_correct(rep)
        c = grades.counts(rep)
        assert c["correct"] + c["typed"] + c["wrong"] + c["missing"] == c["total"]
        assert grades.explain(rep).startswith(f"{s:.1f}: ")
        assert f"{c['correct']} of {c['total']} rows correct" in text_report(rep) and v in text_report(rep)


def test_typed_rows_earn_nothing_and_a_book_without_formulas_fails():
    one = report(correct=3, typed=1)
    assert grades.counts(one)["typed"] == 1 and grades.score(one) == grades.ROWS_SHARE * 3 / 4 + grades.CHECKS_SHARE
    relaxed = report(correct=3, typed=1)
    relaxed.accepted_typed = True
    assert grades.score(relaxed) == 100.0
    typed = report(correct=0, typed=4, typed_only=True)
    typed.accepted_typed = True                     # even accepted, no formula: at most 10
    assert grades.score(typed) <= grades.NO_FORMULA_CAP and grades.verdict(typed) == "typed, not computed"


def test_deleted_checks_lose_their_share_and_count_as_failing():
    rep = report(deleted=2)
    expected = grades.ROWS_SHARE + grades.CHECKS_SHARE * 8 / 10 - 2 * grades.CHECK_PENALTY
    assert grades.score(rep) == round(expected, 1)
    assert "check rows intact and filled in: 8.0 of 10 (2 deleted)" in grades.explain(rep)


def test_copies_one_line_per_group():
    n = 40
    reps = [Report(f"s{k}.xlsx") for k in range(n)]
    copies = Copies([Cluster(list(range(n)), [("byte-identical files", list(range(n)))])])
    lines = copies_lines(reps, copies).splitlines()
    assert len(lines) == 1 and f"{n} files" in lines[0] and lines[0].endswith("byte-identical files")
    pair = copies_lines(reps[:2], Copies([Cluster([0, 1], [("x", [0, 1])])]))
    assert pair == "possible copy: 2 files s0.xlsx, s1.xlsx: x\n"
