"""The error family (sheetkin.errors): every error the package raises for its user is an
InputError, and the command line maps the family, from any stage, to one line and exit 2
(AssemblyError to 3), anything else to one "internal error" line and exit 70."""
from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest
from helpers.clirun import run

import sheetkin
import sheetkin.cli.commands as commands
from sheetkin.errors import InputError, SheetkinError, UsageError

# Exception classes of the package that are not the user's to mend, each with its reason.
OUTSIDE_THE_FAMILY = {
    # the family's own root: every error raised on purpose is one of its InputErrors
    "sheetkin.errors.SheetkinError": "the root",
    # an OSError, so that every reader's `except OSError` names the file in its one line;
    # the command line maps OSError to exit 2 with the file's name (its strerror says why)
    "sheetkin.files.RefusedFile": "an OSError",
    # SIGTERM raised as a KeyboardInterrupt so every clean-up runs: exit 143, not an error
    "sheetkin.cli.commands.Terminated": "a signal",
    # control flow inside one module (a formula that is not a simple one); never leaves it
    "sheetkin.xlsx.cells._NotSimple": "module-private control flow",
    # a kernel's Excel error (#NUM!, #VALUE!): becomes the cell's error value, never the user's
    "sheetkin.xlsx.cellwise.Fail": "an Excel error value inside the engine",
    # OFFSET/INDIRECT reading a cell computed later: the cell is "not computed here"
    "sheetkin.xlsx.context.ReadsLater": "the engine's control flow",
    # the per-file time limit's alarm: a BaseException so no `except Exception` swallows it;
    # the file is reported as taking too long, the class goes on
    "sheetkin.course.batch._TooLong": "the per-file time limit's alarm",
}


def _exception_classes() -> dict[str, type[BaseException]]:
    found = {}
    for info in pkgutil.walk_packages(sheetkin.__path__, "sheetkin."):
        if info.name.endswith("__main__"):
            continue
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if inspect.isclass(obj) and issubclass(obj, BaseException) and obj.__module__ == info.name:
                found[f"{info.name}.{name}"] = obj
    return found


CLASSES = _exception_classes()


def test_every_error_class_is_in_the_family():
    strays = sorted(name for name, cls in CLASSES.items()
                    if not issubclass(cls, InputError) and name not in OUTSIDE_THE_FAMILY)
    assert not strays, f"not InputErrors (declare them in OUTSIDE_THE_FAMILY with a reason): {strays}"
    assert set(OUTSIDE_THE_FAMILY) <= set(CLASSES), "a declared exception no longer exists"


def test_the_family_is_valueerrors_under_one_root():
    assert issubclass(UsageError, InputError) and issubclass(InputError, SheetkinError)
    assert issubclass(SheetkinError, ValueError)      # callers' `except ValueError` still catch them
    for name, cls in CLASSES.items():
        if issubclass(cls, InputError):
            assert issubclass(cls, ValueError), name


def test_the_stages_errors_are_found():
    """The walk above sees the stages' errors (a walk that found none would pass vacuously)."""
    for name in ("sheetkin.kinematics.caps.SceneError", "sheetkin.kinematics.scene.AssemblyError",
                 "sheetkin.xlsx.package.UnusableWorkbook", "sheetkin.xlsx.errors.SpreadsheetError",
                 "sheetkin.views.animate.AnimationError", "sheetkin.studies.synthesis.SynthesisError"):
        assert issubclass(CLASSES[name], InputError), name
    from sheetkin.xlsx.errors import SpreadsheetError
    for name in ("sheetkin.xlsx.parse.ParseError", "sheetkin.xlsx.runs.EvaluationError",
                 "sheetkin.xlsx.package.UnusableWorkbook"):
        assert issubclass(CLASSES[name], SpreadsheetError), name


def _instance(cls: type[BaseException], message: str) -> BaseException:
    """An instance of `cls` saying `message` (UnusableWorkbook takes the path and the problem)."""
    init = cls.__init__
    required = [p for p in inspect.signature(init).parameters.values()
                if p.default is p.empty and p.kind is p.POSITIONAL_OR_KEYWORD][1:] \
        if inspect.isfunction(init) else ["message"]
    return cls("book.xlsx", message) if len(required) == 2 else cls(message)


def _failing(exc: BaseException):
    def command(args):
        raise exc
    return command


INPUT_ERRORS = sorted(n for n, c in CLASSES.items()
                      if issubclass(c, InputError) and not issubclass(c, sheetkin.AssemblyError))


@pytest.mark.parametrize("name", INPUT_ERRORS)
def test_cli_says_an_input_error_of_any_stage_in_one_line_exit_2(capsys, monkeypatch, name):
    exc = _instance(CLASSES[name], "the user's mistake\nsecond line")
    monkeypatch.setattr(commands, "cmd_docs", _failing(exc))
    code, out, err = run(capsys, "docs")
    assert code == 2, (name, err)
    assert err.startswith("sheetkin: error: ") and err.count("\n") == 1, err
    assert "the user's mistake" in err and "internal error" not in err


def test_cli_gives_an_assembly_error_exit_3(capsys, monkeypatch):
    monkeypatch.setattr(commands, "cmd_docs", _failing(sheetkin.AssemblyError("cannot assemble at 30 deg")))
    code, _, err = run(capsys, "docs")
    assert code == 3 and err.count("\n") == 1 and "cannot assemble at 30 deg" in err


@pytest.mark.parametrize("exc", [ValueError("a bug's ValueError"), KeyError("a bug's KeyError"),
                                 ZeroDivisionError("a bug's division")], ids=type)
def test_cli_says_an_unexpected_exception_is_an_internal_error_exit_70(capsys, monkeypatch, exc):
    monkeypatch.delenv("SHEETKIN_DEBUG", raising=False)
    monkeypatch.setattr(commands, "cmd_docs", _failing(exc))
    code, _, err = run(capsys, "docs")
    assert code == 70
    assert err.startswith("sheetkin: internal error: ") and err.count("\n") == 1, err
    assert "a bug's" in err and "please report it" in err


def test_an_option_mistake_is_a_usage_error(capsys):
    """The command line's own option checks raise UsageError (here --range's)."""
    from sheetkin.cli.angles import parse_range
    with pytest.raises(UsageError, match=r"^--range 0:360:0: STEP is 0$"):
        parse_range("0:360:0")
    code, _, err = run(capsys, "compute", "workbooks/fourbar.toml", "--range", "0:360:0")
    assert code == 2 and err == "sheetkin: error: --range 0:360:0: STEP is 0\n"
