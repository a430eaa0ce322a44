"""The project as others get it: the documentation site builds with no warning (mkdocs
--strict), and the wheel, installed into a fresh venv, carries what its quickstarts need
(tests/wheel.sh). Both run in CI; without mkdocs (the `docs` extra) the first is skipped,
except under CI, where a missing tool fails."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CI = os.environ.get("CI", "").lower() not in ("", "0", "false", "no")


def test_docs_site_builds_strict(tmp_path):
    if shutil.which("mkdocs") is None:
        if CI:
            pytest.fail("mkdocs not found: pip install -e '.[docs]'", pytrace=False)
        pytest.skip("mkdocs not found: pip install -e '.[docs]'")
    env = dict(os.environ, PYTHONPATH=str(ROOT), NO_MKDOCS_2_WARNING="1")
    p = subprocess.run(["mkdocs", "build", "--strict", "-d", str(tmp_path / "site")], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stderr[-3000:]
    cli = (tmp_path / "site" / "cli" / "index.html").read_text(encoding="utf-8")
    # the CLI reference is the parser's own help: every command is there
    from sheetkin.cli.args import build_parser
    commands = next(a for a in build_parser()._actions if a.dest == "command").choices
    assert all(f"sheetkin {c}" in cli for c in commands)


def test_the_wheel_runs_its_quickstarts():
    p = subprocess.run(["bash", str(ROOT / "tests" / "wheel.sh")], cwd=ROOT, capture_output=True, text=True,
                       timeout=1800, env=dict(os.environ, PYTHON=sys.executable))
    assert p.returncode == 0, (p.stdout + p.stderr)[-3000:]
    assert "the wheel installs and its quickstarts run" in p.stdout


def test_readme_tree_matches_the_packages():
    """The README's picture of the code names every package and top-level module of sheetkin,
    and nothing that is not there."""
    text = (ROOT / "README.md").read_text(encoding="utf8")
    block = text[text.index("```text\nsheetkin/"):]
    block = block[:block.index("```", 4)]
    named = set(re.findall(r"(\w+)/ ", block)) | set(re.findall(r"(\w+)\.py", block))
    pkg = ROOT / "sheetkin"
    real = {p.name for p in pkg.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    real |= {p.stem for p in pkg.glob("*.py") if p.stem not in ("__init__", "__main__")}
    assert named - {"sheetkin"} == real


def test_readme_test_command_is_what_ci_runs():
    """The README's set-up gives the test command that .ci/run runs, verbatim."""
    ci = [ln for ln in (ROOT / ".ci" / "run").read_text(encoding="utf8").splitlines() if ln.startswith("bash ")]
    readme = (ROOT / "README.md").read_text(encoding="utf8")
    setup = readme[readme.index("## Set-up from a checkout: two commands"):]
    assert len(ci) == 1 and f"\n{ci[0]}\n" in setup[:setup.index("\n## ", 5)]


def test_readme_reliability_counts_are_the_docs():
    """The README's reliability counts are the ones docs/reliability.md measured."""
    def counts(text: str) -> list[str]:
        m = re.search(r"(\d+) hand-written cases \((\d+) [^)]*?(\d+) (?:that must be )?handled.*?(\d+) fuzzed",
                      " ".join(text.split()))
        assert m, text[:200]
        return list(m.groups())
    readme = (ROOT / "README.md").read_text(encoding="utf8")
    docs = (ROOT / "docs" / "reliability.md").read_text(encoding="utf8")
    assert counts(readme) == counts(docs[docs.index("## Tests and counts"):])


def test_the_version_is_the_changelogs_latest_release():
    """The version lives in one place (sheetkin.__version__, which pyproject reads), and the
    changelog's latest release is that version."""
    import sheetkin
    changelog = (ROOT / "CHANGELOG.md").read_text(encoding="utf8")
    releases = re.findall(r"^## \[(\d+\.\d+\.\d+)\] - \d{4}-\d\d-\d\d$", changelog, flags=re.M)
    assert releases and releases[0] == sheetkin.__version__
    assert 'version = {attr = "sheetkin.__version__"}' in (ROOT / "pyproject.toml").read_text(encoding="utf8")
