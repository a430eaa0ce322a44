"""Every example shown in the README and the docs runs, and prints what the page shows.

A page's ```toml blocks with a title (```toml title="slider.toml") are written to files of
that name; its ```console blocks are run in order, each `$ command` in bash in one folder per
page (the bundled examples written there first by `sheetkin examples .`), and what the
command prints (stdout, then stderr) must equal the lines shown under it, trailing spaces
aside. A line `...` in the shown output stands for any number of lines. ```pycon blocks are
run as doctests in the same folder."""
from __future__ import annotations

import doctest
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```(\w+)([^\n]*)\n(.*?)^```", re.M | re.S)


def _blocks(page: Path) -> list[tuple[str, str, str]]:
    return [(m.group(1), m.group(2), m.group(3)) for m in FENCE.finditer(page.read_text(encoding="utf-8"))]


def _commands(body: str) -> list[tuple[str, list[str]]]:
    out: list[tuple[str, list[str]]] = []
    for line in body.splitlines():
        if line.startswith("$ "):
            out.append((line[2:], []))
        elif out:
            out[-1][1].append(line.rstrip())
    return out


def _matches(shown: list[str], got: list[str]) -> bool:
    """`...` in `shown` matches any run of lines (also none)."""
    pattern = "\n".join(".*?" if s == "..." else re.escape(s) for s in shown)
    pattern = pattern.replace("\n.*?\n", "(?:\n.*?)?\n")
    return re.fullmatch(pattern, "\n".join(got), re.S) is not None


def _pages_with_examples() -> list[Path]:
    return [p for p in PAGES if any(kind in ("console", "pycon") for kind, _, _ in _blocks(p))]


@pytest.mark.parametrize("page", _pages_with_examples(), ids=lambda p: p.name)
def test_examples_print_what_the_page_shows(page, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="100")
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env['PATH']}"
    subprocess.run([sys.executable, "-m", "sheetkin", "examples", "."], cwd=tmp_path, env=env,
                   check=True, capture_output=True)
    for kind, info, body in _blocks(page):
        title = re.search(r'title="([^"]+)"', info)
        if title and kind != "console":
            (tmp_path / title.group(1)).write_text(body, encoding="utf-8")
        elif kind == "console":
            for command, shown in _commands(body):
                command = re.sub(r"^sheetkin\b", f"{sys.executable} -m sheetkin", command)
                command = command.replace("| sheetkin ", f"| {sys.executable} -m sheetkin ")
                p = subprocess.run(["bash", "-c", command], cwd=tmp_path, env=env, capture_output=True,
                                   text=True, timeout=600)
                got = [ln.rstrip() for ln in (p.stdout + p.stderr).splitlines()]
                while shown and shown[-1] == "":
                    shown.pop()
                assert _matches(shown, got), f"{page.name}: `{command}` printed:\n" + "\n".join(got)
        elif kind == "pycon":
            test = doctest.DocTestParser().get_doctest(body, {}, page.name, str(page), 0)
            runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
            old = Path.cwd()
            os.chdir(tmp_path)
            try:
                runner.run(test)
            finally:
                os.chdir(old)
            assert runner.failures == 0, f"{page.name}: a Python example differs (see the output above)"
