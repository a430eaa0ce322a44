"""`sheetkin docs` lists the documentation pages (docs/*.md, package data `sheetkin.docs` in the
wheel) and prints one; help texts and errors point to those pages, never to the repository."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers.clirun import run

from sheetkin.cli.args import build_parser

ROOT = Path(__file__).resolve().parents[2]
PAGES = sorted(p.stem for p in (ROOT / "docs").glob("*.md"))


def test_lists_every_page_with_its_title(capsys):
    code, out, err = run(capsys, "docs")
    assert code == 0, err
    listed = [line.split()[0] for line in out.splitlines() if line and not line.startswith("sheetkin docs")]
    assert listed == PAGES
    title = (ROOT / "docs" / "scene-format.md").read_text(encoding="utf-8").splitlines()[0][2:]
    assert re.search(rf"^scene-format +{re.escape(title)}$", out, re.M)


@pytest.mark.parametrize("name", ["scene-format", "scene-format.md", "tutorial"])
def test_prints_a_page_as_written(capsys, name):
    code, out, err = run(capsys, "docs", name)
    assert code == 0, err
    assert out == (ROOT / "docs" / f"{name.removesuffix('.md')}.md").read_text(encoding="utf-8")


def test_the_generated_cli_page_says_where_its_text_is(capsys):
    code, out, _ = run(capsys, "docs", "cli")
    assert code == 0 and "<!-- cli-reference -->" not in out and "sheetkin COMMAND --help" in out


def test_an_unknown_page_is_one_line_naming_the_pages(capsys):
    code, out, err = run(capsys, "docs", "nope")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "'nope'" in err and "scene-format" in err and "tutorial" in err


def _help_texts(parser) -> list[str]:
    texts = [parser.description or ""]
    for action in parser._actions:                      # argparse keeps its options only here
        texts.append(str(action.help or ""))
        if isinstance(action.choices, dict):            # the subcommands' parsers
            for sub in action.choices.values():
                texts += _help_texts(sub)
    return texts


def test_help_texts_name_pages_not_repository_paths():
    texts = _help_texts(build_parser())
    assert not [t for t in texts if re.search(r"README|docs/|in the repository", t)]
    named = {m for t in texts for m in re.findall(r"sheetkin docs ([\w-]+)", t)}
    assert "scene-format" in named and named <= set(PAGES), named


def test_api_page_names_every_public_name_and_prints_in_a_terminal(capsys):
    """The API page documents every name of `sheetkin.__all__` under the module that defines it
    (mkdocstrings cannot see the lazily loaded ones through `sheetkin`), and `sheetkin docs api`
    prints each as its signature and docstring, not as mkdocstrings' directives."""
    import sheetkin
    from sheetkin.cli import main

    page = (Path(__file__).resolve().parents[2] / "docs" / "api.md").read_text(encoding="utf-8")
    for name in set(sheetkin.__all__) - {"__version__"}:
        obj = getattr(sheetkin, name)
        assert f"::: {obj.__module__}.{name}\n" in page, name
        assert (obj.__doc__ or "").strip() and not obj.__doc__.startswith(name + "("), name
    assert main(["docs", "api"]) == 0
    out = capsys.readouterr().out
    assert "\n::: " not in out and "\n    options:" not in out and "### `compute(" in out


def test_changelog_page_is_the_changelog(capsys):
    from sheetkin.cli import main

    assert main(["docs", "changelog"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("# Changelog") and "--8<--" not in out and "## [" in out
