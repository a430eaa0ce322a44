"""The files a command reads besides those its options name (issue 30): none of them may
be an output (`refuse_overwriting_inputs` in sheetkin.cli.commands refuses it in one line).

`validate` also reads the zips it finds in its folders (Moodle's download saved beside the
books), the assignment.csv beside --roster (written by `variants --class-list`), the roster's
scene files (for "typed numbers of another variant"), and the dated keys of earlier issues
beside the key (`.sheetkin-key-*`): `--grades` onto the class's assignment.csv, `--html` onto
a roster's scene file and `--grades` onto a zip in the input folder overwrote each.
"""
from __future__ import annotations

import contextlib
from pathlib import Path

MAX_FOUND = 100_000     # files looked at in the input folders (a class is a few hundred)


def more_inputs(args) -> list[str]:
    """The files `args.command` reads that its options do not name."""
    if getattr(args, "command", "") != "validate":
        return []
    out: list[str] = []
    for p in map(Path, getattr(args, "paths", None) or []):
        if p.is_dir():
            for k, f in enumerate(p.rglob("*")):
                if k >= MAX_FOUND:
                    break
                if f.suffix.lower() == ".zip" and f.is_file():
                    out.append(str(f))
    roster = getattr(args, "roster", None)
    if roster:
        from sheetkin.course.identity import ASSIGNMENT_FILE
        folder = Path(roster).parent
        out.append(str(folder / ASSIGNMENT_FILE))
        out += _roster_scenes(roster)
    key = getattr(args, "key", None) or (str(Path(roster).parent / ".sheetkin-key") if roster else None)
    if key:
        from sheetkin.course.issued import OLDER_KEYS
        out += [str(p) for p in sorted(Path(key).parent.glob(OLDER_KEYS))]
    return out


def _roster_scenes(roster: str) -> list[str]:
    """The scene (and key) files the roster names, beside it; none if it cannot be read
    (its own one line comes later, from the command)."""
    from sheetkin.course.issued import read_roster
    with contextlib.suppress(Exception):
        folder = Path(roster).parent
        return [str(folder / name) for files in read_roster(roster).files.values()
                for what, name in files.items() if name and what in ("scene", "key", "exercise")]
    return []


def check_outputs(outputs: list[tuple[str, str]]) -> None:
    """Every output's folder can take it, before the work (sheetkin.files.check_output):
    a read-only folder is one line naming the output now (issue 30)."""
    from sheetkin.files import check_output
    for opt, path in outputs:
        if path and path != "-" and opt != "--out":        # bench makes its --out folder
            check_output(path, f"{opt} file")
