"""A quick start: `import sheetkin`, `sheetkin --help` and `sheetkin compute` of a small scene
load only what they use (checked in fresh processes through sys.modules, not by timing):
pandas, openpyxl, matplotlib and mpmath load lazily, and numpy only with a scene (the group
kinds' registry, sheetkin.groups, imports a kind's numpy kernels on first use)."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("pandas", "openpyxl", "matplotlib", "mpmath", "scipy", "pyarrow", "polars")

PROBE = """
import json, sys
{setup}
print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {heavy!r})))
"""


def loaded(setup: str) -> set[str]:
    code = PROBE.format(setup=setup, heavy=HEAVY + ("numpy",))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                          timeout=120, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 0, proc.stderr
    return {m.split(".")[0] for m in json.loads(proc.stdout.splitlines()[-1])}


def test_import_sheetkin_loads_nothing_heavy():
    assert loaded("import sheetkin") == set()


@pytest.mark.parametrize("argv", [["--help"], ["compute", "--help"], ["validate", "--help"],
                                  ["workbook", "--help"], ["--version"]])
def test_help_loads_nothing_heavy_not_even_numpy(argv):
    setup = ("from sheetkin.cli.commands import main\n"
             "import contextlib, io\n"
             "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
             f"    try: main({argv!r})\n"
             "    except SystemExit as e: assert e.code == 0\n"
             "assert 'sheetkin' in out.getvalue() or '0.' in out.getvalue()")
    assert loaded(setup) == set()


def test_the_registry_imports_a_kind_on_first_use():
    setup = ("import sys\n"
             "from sheetkin.groups import KINDS\n"
             "assert list(KINDS) == ['RRR', 'RRP', 'RPR', 'PRP', 'RPP'] and 'RPR' in KINDS\n"
             "assert 'numpy' not in sys.modules and 'sheetkin.groups.rrr' not in sys.modules\n"
             "assert KINDS['RRR'].KIND == 'RRR' and KINDS['RRR'] is KINDS['RRR']\n"
             "assert 'sheetkin.groups.rpp' not in sys.modules")
    assert loaded(setup) == {"numpy"}


@pytest.mark.parametrize("fmt", ["table", "csv", "json"])
def test_compute_command_loads_numpy_only(fmt):
    # CSV is written by polars since issue 24 (faster than our formatter on the same arrays)
    setup = ("from sheetkin.cli.commands import main\n"
             "import contextlib, io\n"
             "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
             f"    assert main(['compute', 'workbooks/fourbar.toml', '--format', '{fmt}']) == 0")
    assert loaded(setup) == ({"numpy", "polars"} if fmt == "csv" else {"numpy"})


def test_the_api_still_gives_a_dataframe():
    setup = ("import sheetkin\n"
             "df = sheetkin.compute('workbooks/fourbar.toml')\n"
             "assert type(df).__name__ == 'DataFrame' and len(df) == 13\n"
             "import sheetkin.kinematics.table\n"
             "assert callable(sheetkin.compute) and sheetkin.solve and sheetkin.Gap")
    assert "pandas" in loaded(setup)


@pytest.mark.parametrize("fmt", ["table", "csv", "json"])
def test_evaluate_command_loads_numpy_only(fmt):
    # issue 24: pandas (and pyarrow through it) and openpyxl were 0.3-0.6 s of a 1.6 s
    # `sheetkin evaluate`; the formula tokenizer is openpyxl's file loaded alone
    setup = ("from sheetkin.cli.commands import main\n"
             "import contextlib, io\n"
             "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
             f"    assert main(['evaluate', 'workbooks/fourbar.xlsx', '--format', '{fmt}']) == 0\n"
             "assert 'phi_1' in out.getvalue()")
    assert loaded(setup) == {"numpy"}


def test_validate_command_loads_no_pandas():
    # openpyxl stays: the reference of a variant is the workbook sheetkin generates for it,
    # built once per structure by sheetkin.sheet.workbook (openpyxl)
    setup = ("from sheetkin.cli.commands import main\n"
             "import contextlib, io\n"
             "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
             "    assert main(['validate', 'workbooks/fourbar.xlsx']) == 0")
    assert loaded(setup) == {"numpy", "openpyxl"}


def sheetkin_modules(setup: str) -> set[str]:
    """The sheetkin modules loaded after `setup`, in a fresh process."""
    code = setup + "\nimport json, sys\nprint(json.dumps(sorted(m for m in sys.modules if m.startswith('sheetkin'))))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                          timeout=120, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 0, proc.stderr
    return set(json.loads(proc.stdout.splitlines()[-1]))


def test_import_sheetkin_loads_no_stage_and_names_load_on_use():
    # issue 32: the package's public names load on first use (PEP 562), the scene reader too
    assert sheetkin_modules("import sheetkin") <= {"sheetkin", "sheetkin.errors", "sheetkin.lazy"}
    loaded_ = sheetkin_modules("import sheetkin\nassert sheetkin.Scene.__name__ == 'Scene'\n"
                               "from sheetkin import load_scene, AssemblyError")
    assert "sheetkin.kinematics.scene" in loaded_ and "sheetkin.kinematics.solver" not in loaded_


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_evaluate_command_loads_no_kinematics(fmt):
    # issue 32: `sheetkin evaluate` is the engine (xlsx) and the command line, no scene reader
    # or solver (the table format alone loads the output module's number formatting)
    setup = ("from sheetkin.cli.commands import main\n"
             "import contextlib, io\n"
             "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
             f"    assert main(['evaluate', 'workbooks/fourbar.xlsx', '--format', '{fmt}']) == 0")
    mods = sheetkin_modules(setup)
    assert not {m for m in mods if m.startswith(("sheetkin.kinematics.", "sheetkin.views", "sheetkin.groups"))
                and m != "sheetkin.kinematics.caps"}, mods



def _program(code: str, **env: str) -> subprocess.CompletedProcess:
    """`code` run in a fresh process, then sheetkin.cli.run() with the probe below as main:
    as `python -m sheetkin` ends, with the program's setup and exit."""
    probe = ("import os, sys\n" + code + "\nimport sheetkin.cli as cli\n"
             "def probe():\n"
             "    import numpy\n"
             "    import gc\n"
    "    print(len(os.listdir('/proc/self/task')), gc.get_threshold()[0], flush=True)\n"
             "    return int(os.environ.get('PROBE_CODE', '0'))\n"
             "cli.main = probe\n"
             "cli.run()\n")
    return subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT, timeout=120,
                          env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", **env})


def _threads(code: str = "", **env: str) -> int:
    proc = _program(code, **env)
    assert proc.returncode == 0, proc.stderr
    return int(proc.stdout.split()[0])


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="counts threads through /proc")
def test_the_program_runs_numpy_on_one_blas_thread_unless_the_user_chose():
    # OpenBLAS's spinning workers cost `sheetkin evaluate` 0.10-0.14 s of CPU on 2 cores
    # (issue 32, item 5): the program sets one thread before numpy loads
    many = _threads(OPENBLAS_NUM_THREADS="4")
    if many == 1:
        pytest.skip("this numpy starts no BLAS threads")
    assert _threads() == 1


def test_the_program_collects_cycles_less_often():
    # 59 collections scanned the shaper's book while it was read and evaluated (issue 32)
    proc = _program("")
    assert proc.returncode == 0 and int(proc.stdout.split()[1]) == 100_000, proc
    # a notebook's import of sheetkin changes nothing: only the program sets it
    out = subprocess.run([sys.executable, "-c", "import os, sheetkin.cli, sheetkin.cli.commands; "
                          "print(os.environ.get('OPENBLAS_NUM_THREADS'))"], capture_output=True, text=True,
                         cwd=ROOT, timeout=120, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert out.stdout.strip() == "None", out.stderr


def test_the_program_ends_quickly_but_keeps_what_the_teardown_does():
    # the exit without the interpreter's teardown (issue 32, item 5) still runs the atexit
    # functions (a temporary folder removed), flushes both streams and keeps the code
    code = ("import atexit\n"
            "atexit.register(lambda: print('atexit ran', flush=False))\n"
            "import tempfile\n"
            "kept = tempfile.TemporaryDirectory(); open(kept.name + '/x', 'w').close()\n"
            "print(kept.name, flush=True)\n"
            "sys.stderr.write('to stderr')\n")
    proc = _program(code, PROBE_CODE="3")
    assert proc.returncode == 3, proc.stderr
    assert proc.stdout.splitlines()[-1] == "atexit ran"
    assert proc.stderr == "to stderr"
    assert not Path(proc.stdout.split()[0]).exists()      # a temporary folder's finalizer ran
    # another thread alive: the ordinary exit, which waits for it
    code = ("import threading, time\n"
            "threading.Thread(target=lambda: (time.sleep(0.3), print('thread done', flush=True))).start()\n")
    proc = _program(code)
    assert proc.returncode == 0 and proc.stdout.splitlines()[-1] == "thread done", proc
