"""The pipeline runs one way: each package of sheetkin imports only the stages below it.

    xlsx (standalone)        groups -> kinematics -> sheet (writes workbooks; uses xlsx)
    course (grading) uses everything below; views and studies stand beside; cli on top.

Every import of a sheetkin module in sheetkin/ is read from the source (ast), those inside
functions too (a lazy import is still a dependency), and checked against ALLOWED below.
The few modules at the top of sheetkin/ (errors, untrusted, files, lazy, messages) import
nothing of sheetkin but errors and untrusted, and every stage may use them.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "sheetkin"

# The foundation: modules every stage may import (they import nothing above them).
FOUNDATION = {"errors", "untrusted", "files", "lazy", "messages"}

# stage -> the stages it may import (besides itself and FOUNDATION)
ALLOWED: dict[str, set[str]] = {
    "errors": set(),
    "untrusted": set(),                  # texts from students made harmless: stdlib only
    "files": {"errors", "untrusted"},
    "lazy": {"errors"},
    "messages": set(),                   # the messages' catalogue in en, ru, uk and its one `say`
    "xlsx": set(),                       # the spreadsheet engine stands alone
    "groups": set(),                     # the Assur group kinds: the bottom of the pipeline
    "kinematics": {"groups"},            # scene, solver, table; the geometry drawings share
    "sheet": {"groups", "kinematics", "xlsx"},   # xlsx: the engine fills the cached values
    "views": {"groups", "kinematics"},   # output files, drawings, animation, notebook pictures
    "studies": {"groups", "kinematics", "sheet", "xlsx"},   # bench (workbooks it times), synthesis
    "course": {"groups", "kinematics", "sheet", "xlsx", "views"},   # views: the report's drawing
    "cli": {"groups", "kinematics", "sheet", "xlsx", "views", "studies", "course"},
    "__main__": {"cli"},
    # the package itself (sheetkin/__init__.py) is the public API above every stage: it
    # re-exports the public names, each loaded on first use, and offers the notebook view
    # to the scene (_draw_scene: kinematics.scene.draw_in_notebook's default)
    "sheetkin": {"kinematics", "views", "xlsx"},
}

# Imports against ALLOWED that are declared, each with its reason: (importer, imported name).
EXCEPTIONS: dict[tuple[str, str], str] = {
    # the version string, for messages and reports; sheetkin/__init__.py imports no stage
    # eagerly, so this pulls in nothing above the importing stage
    ("sheet", "sheetkin.__version__"): "the version that issued a book, marked in its scene sheet (issue 31)",
    ("course", "sheetkin.__version__"): "the version in reports",
    ("cli", "sheetkin.__version__"): "the version in --version and internal-error lines",
}


def stage_of(module: str) -> str:
    """'sheetkin.kinematics.scene' -> 'kinematics'; 'sheetkin' -> 'sheetkin'."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "sheetkin"


def imports_of(path: Path, module: str) -> list[tuple[str, int]]:
    """(imported sheetkin name, line) of every import in the file, at any depth. A name
    imported from a package (`from sheetkin import x`) is given as 'sheetkin.x'."""
    is_package = path.name == "__init__.py"
    package = module if is_package else module.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target == "sheetkin":           # names of the package itself: which ones matters
                found += [(f"sheetkin.{a.name}", node.lineno) for a in node.names]
            else:
                found.append((target, node.lineno))
    return [(name, line) for name, line in found if name == "sheetkin" or name.startswith("sheetkin.")]


def violations(modules: dict[str, tuple[Path, list[tuple[str, int]]]]) -> list[str]:
    """Every import of `modules` ({module: (path, imports)}) against ALLOWED, not declared."""
    out = []
    for module, (path, imports) in sorted(modules.items()):
        stage = stage_of(module)
        for name, line in imports:
            target = stage_of(name)
            if (target == stage or (stage, name) in EXCEPTIONS or target in ALLOWED.get(stage, set())
                    or (target in FOUNDATION and stage not in FOUNDATION)):
                continue
            out.append(f"{path.relative_to(PACKAGE.parent)}:{line}: {stage} imports {name}")
    return out


def package_modules() -> dict[str, tuple[Path, list[tuple[str, int]]]]:
    modules = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        module = ".".join(rel.parts[:-1] if rel.name == "__init__" else rel.parts)
        modules[module] = (path, imports_of(path, module))
    return modules


def test_every_stage_imports_only_the_stages_below_it():
    modules = package_modules()
    assert len(modules) > 60 and "sheetkin.sheet.charts" in modules     # the walk sees the package
    assert not violations(modules), "\n".join(violations(modules))


def test_every_stage_is_in_the_allow_list():
    stages = {stage_of(m) for m in package_modules()}
    assert stages <= set(ALLOWED), stages - set(ALLOWED)


def test_the_declared_exceptions_are_still_used():
    used = {(stage_of(m), name) for m, (_, imports) in package_modules().items() for name, _ in imports}
    assert set(EXCEPTIONS) <= used, set(EXCEPTIONS) - used


@pytest.mark.parametrize(("module", "source", "bad"), [
    # a lower stage importing a higher one, at the top of the file
    ("sheetkin.sheet.charts", "from sheetkin.views.drawing import structure\n", "sheet imports sheetkin.views.drawing"),
    # ... or lazily, inside a function
    ("sheetkin.kinematics.scene", "def f():\n    from sheetkin.views.notebook import scene_repr_svg\n",
     "kinematics imports sheetkin.views.notebook"),
    # a relative import that climbs out of its package
    ("sheetkin.groups.rrr", "from ..kinematics import scene\n", "groups imports sheetkin.kinematics"),
    # the standalone engine importing the pipeline
    ("sheetkin.xlsx.cells", "import sheetkin.kinematics.table\n", "xlsx imports sheetkin.kinematics.table"),
    # the package's public API from a stage, other than its version
    ("sheetkin.sheet.workbook", "from sheetkin import compute\n", "sheet imports sheetkin.compute"),
])
def test_a_lower_stage_importing_a_higher_one_fails(tmp_path, module, source, bad):
    """The check finds a violation fed to it (here a synthetic module's source)."""
    path = PACKAGE / (module.split(".", 1)[1].replace(".", "/") + ".py")
    fake = tmp_path / path.name
    fake.write_text(source)
    found = violations({module: (path, imports_of(fake, module))})
    assert len(found) == 1 and found[0].endswith(bad), found


def test_allowed_imports_pass():
    path = PACKAGE / "course" / "grades.py"
    ok = violations({"sheetkin.course.grades": (path, [("sheetkin.errors", 1), ("sheetkin.sheet.checks", 2),
                                                       ("sheetkin.__version__", 3), ("sheetkin.course.report", 4)])})
    assert ok == []
