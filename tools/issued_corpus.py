"""Make the corpus of books issued by every released version of sheetkin (issue 31, item 4):
tests/data/issued/<version>/<scheme>/ holds what that version's `sheetkin variants` issued
(the exercise, roster.csv, the variant's scene, the teacher's key file) and students' books
made from the exercise in LibreOffice, through UNO, as students make them:

    honest.xlsx     every row filled with the key's formulas
    wrong.xlsx      one row (WRONG_ROW) computed 10% off at every position
    typed.xlsx      one row (TYPED_ROW) typed as numbers instead of formulas
    last-empty.xlsx the last position (360 deg, the same as 0 deg) left empty in every row

The books are committed: a later version must grade them as the version that issued them
did (`tests/course/test_issued_corpus.py`). Rerun only to add a released version:

    python tools/issued_corpus.py 0.1.0=3032383 0.2.0=223431f

Each version is checked out into a temporary git worktree and run there (its own code makes
its own books); the students' edits are made with tests/helpers/studentbooks.py (LibreOffice + UNO).
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from helpers.studentbooks import Recipe, key_formulas, key_values, make_books  # noqa: E402

SCHEMES = ("fourbar", "crank_slider", "slotted_lever", "shaper")
WRONG_ROW = {"fourbar": "vx_A", "crank_slider": "vx_A", "slotted_lever": "vx_A", "shaper": "vx_A"}
TYPED_ROW = {"fourbar": "x_A", "crank_slider": "x_A", "slotted_lever": "x_A", "shaper": "x_A"}
SEED = "2026"


def issue(version: str, commit: str, out: Path) -> None:
    with tempfile.TemporaryDirectory(prefix="sheetkin-corpus-") as tmp:
        tree = Path(tmp) / "tree"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach", str(tree), commit], check=True)
        try:
            for scheme in SCHEMES:
                dst = Path(tmp) / scheme
                subprocess.run([sys.executable, "-m", "sheetkin", "variants", f"workbooks/{scheme}.toml", "-n", "1",
                                "--seed", SEED, "--out", str(dst)], cwd=tree, check=True, capture_output=True,
                               env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"})
                students(scheme, dst, out / version / scheme)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=True)


def students(scheme: str, issued: Path, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    exercise = next(issued.glob("*-exercise.xlsx"))
    key = next(issued.glob("*-key.xlsx"))
    for p in [exercise, *issued.glob("*.toml"), issued / "roster.csv", issued / ".sheetkin-key"]:
        shutil.copy2(p, out / p.name)
    last = max(c for _, c, _ in key_formulas(exercise, key))
    typed = TYPED_ROW[scheme]
    books = {
        out / "honest.xlsx": Recipe(exercise, key).honest().identity("Иванов Иван", "ГМ-21"),
        out / "wrong.xlsx": Recipe(exercise, key).honest().wrap(WRONG_ROW[scheme], "=1.1*({f})"),
        out / "typed.xlsx": Recipe(exercise, key).honest(skip=(typed,)).type_values(key_values(key, [typed])),
    }
    empty_last = Recipe(exercise, key)
    empty_last.ops.append(["formulas", "main", [f for f in key_formulas(exercise, key) if f[1] != last]])
    books[out / "last-empty.xlsx"] = empty_last
    make_books(books)
    for p in books:
        print(p.relative_to(ROOT))


def main(argv: list[str]) -> None:
    out = ROOT / "tests" / "data" / "issued"
    for arg in argv or ["0.1.0=3032383", "0.2.0=223431f"]:
        version, commit = arg.split("=")
        issue(version, commit, out)


if __name__ == "__main__":
    main(sys.argv[1:])
