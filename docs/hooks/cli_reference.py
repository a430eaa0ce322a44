"""MkDocs hook: the CLI reference page is generated from the argument parser itself
(sheetkin.cli.args.build_parser), so it can never drift from the options; docs/cli.md holds
only the marker `<!-- cli-reference -->` where the generated text goes."""
from __future__ import annotations

import argparse

MARKER = "<!-- cli-reference -->"


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:          # argparse keeps its subcommands only here
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _section(name: str, parser: argparse.ArgumentParser, level: int = 2) -> list[str]:
    parser.formatter_class = lambda prog: argparse.HelpFormatter(prog, width=80)
    out = [f"{'#' * level} `{name}`", "", "```text", parser.format_help().rstrip(), "```", ""]
    for sub, p in _subparsers(parser).items():
        out += _section(f"{name} {sub}", p, level + 1)
    return out


def reference() -> str:
    from sheetkin.cli.args import build_parser
    parser = build_parser()
    lines = _section("sheetkin", parser, 2)
    return "\n".join(lines)


def on_page_markdown(markdown: str, page, config, files) -> str:  # noqa: ARG001 (MkDocs' hook signature)
    if MARKER in markdown:
        return markdown.replace(MARKER, reference())
    return markdown
