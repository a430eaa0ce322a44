#!/usr/bin/env bash
# The installed package, as a user gets it: builds the wheel, installs it (not editable) into a
# fresh venv outside the repository, and runs the three quickstarts of the README there
# (engineer, teacher, student) with only what the wheel carries. Run by .ci/run.
# Usage: bash tests/wheel.sh
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
py="${PYTHON:-python}"
"$py" -m pip wheel -q --no-deps -w "$work/dist" "$repo" >/dev/null
# the wheel carries the package, its examples and its pages, and no maintainer's scripts
"$py" - "$work"/dist/sheetkin-*.whl <<'PY'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
docs_code = [n for n in names if n.startswith("sheetkin/docs/") and n.endswith(".py") and not n.endswith("__init__.py")]
assert not docs_code, docs_code
assert any(n.startswith("sheetkin/examples/") and n.endswith(".toml") for n in names)
assert not any(n.startswith(("tests/", "tools/", "benchmarks/")) for n in names), names
PY
"$py" -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q "$work"/dist/sheetkin-*.whl 2>&1 | { grep -v "^WARNING: Location" || true; }
export PATH="$work/venv/bin:$PATH"
cd "$work"                    # nothing of the repository on the path from here on
test "$(python -c 'import sheetkin, os; print(os.path.dirname(sheetkin.__file__))')" != "$repo/sheetkin"

# engineer: the bundled scenes, the command line, and pandas with a scene's text inline
sheetkin examples ex >/dev/null
sheetkin compute ex/fourbar.toml --at 150 --format csv | grep -q '^150.0,'
python - <<'PY'
import sheetkin
text = open("ex/crank_slider.toml").read()
df = sheetkin.compute(text)
assert len(df) == 13 and abs(df["x_A"][0] - 0.1) < 1e-15, df.head()
PY
sheetkin workbook ex/fourbar.toml -o fourbar.xlsx >/dev/null

# teacher: a class of variants, then the key books graded (each is a perfect student's book)
sheetkin variants ex/fourbar.toml -n 2 --out class --seed 1 >/dev/null 2>&1
# student: a filled book is the key's formulas in the exercise; the key itself grades as all correct
sheetkin validate class/*-key.xlsx --roster class/roster.csv --lang en >validate.txt
grep -q "all correct" validate.txt
# the documentation pages ship in the wheel (package data sheetkin.docs) and help points to them
# (into files first: grep -q leaves a pipe early, and sheetkin then exits 141, as a reader that left)
sheetkin docs >pages.txt && grep -q '^scene-format ' pages.txt
sheetkin docs scene-format >scene-format.md && grep -q '^# The scene format' scene-format.md
sheetkin --help >help.txt && grep -q 'sheetkin docs scene-format' help.txt
echo "tests/wheel.sh: the wheel installs and its quickstarts run ($(ls dist))"
