"""Issue 31: the behavioural check's notes, the given data typed as text, another class's
book and the score's new parts are said in Russian and Ukrainian (no English left)."""
from __future__ import annotations

import re

import pytest

from sheetkin.messages import say

NOTES = [
    "does not follow the given data (2; right for the issued data, wrong when they change; they earn nothing): "
    "x_A (row 40, i = 1-12: F40 =0.5236); y_A (row 41, i = 3: G41 =1)",
    "not judged: check by hand (1; sheetkin cannot evaluate their formulas, they are left out of the score): x_A",
    "check rows not judged: check by hand (2; sheetkin cannot evaluate their status): chk_Fi, chk_OA",
    "empty at i = 12",
    "check rows that do not check (2; they still pass when the given data change and the rows they check do not; "
    "counted as failing): chk_OA (row 59: D59 =0*$D$17); chk_Fi (row 48: D48 =IF($D$17>0,0,1))",
    "given L1 (Кинематика!D17) is the text '0,129', not a number: read as 0.129, as a spreadsheet reads it "
    "(type it as a number)",
    "this book is of another scheme, not of the class issued with a/roster.csv (its given data gamma_g1 are not "
    "the roster's); scene sheet edited: its seal (scene!C2) is missing",
    "this book is of a class issued with another roster, not a/roster.csv (variant fourbar-01 is not in it)",
]
ENGLISH = re.compile(r"\b(does|not|judged|check|hand|follow|given|empty|text|number|book|scheme|class|roster|"
                     r"row|their|they|the|of|is|as|pass|change|counted|failing|rows)\b")


@pytest.mark.parametrize("lang", ["ru", "uk"])
@pytest.mark.parametrize("note", NOTES)
def test_the_new_notes_are_said_in_the_teachers_language(note, lang):
    said = say(note, lang)
    # names of rows, cells, files and formulas stay as they are; no English word is left
    left = ENGLISH.findall(re.sub(r"[\w/.]+\.csv|[A-Za-z_]+\d*_\w+|chk_\w+|=\S+", "", said))
    assert not left, (said, left)
    for kept in re.findall(r"\b(?:x_A|y_A|chk_Fi|F40|0,129|fourbar-01|a/roster\.csv)\b", note):
        assert kept in said


@pytest.mark.parametrize(("lang", "want"), [("ru", "их верные положения: 9.5"),
                                           ("uk", "їхні правильні положення: 9.5")])
def test_the_score_explained_says_the_right_positions_and_not_judged(lang, want):
    text = ("63.5: 35 of 63 rows computed right: 59.5 of 90 (28 wrong, their right positions: 9.5); "
            "not judged, check by hand: 2 rows, 1 check rows")
    said = say(text, lang, "grading")
    assert want in said and "check by hand" not in said and "rows" not in said, said
