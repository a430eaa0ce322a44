"""Shared fixtures: external programs the tests need (installed by tests/setup.sh)."""
from __future__ import annotations

import os
import shutil

import pytest
from helpers.engines import GNUMERIC_HINT, ssconvert_path
from helpers.libreoffice import SETUP_HINT, soffice_path
from helpers.programs import require
from hypothesis import settings

# Under CI the property tests draw the same examples every run (a red CI names a real
# failure, reproducible with CI=true); elsewhere they explore new examples each run.
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI", "").lower() not in ("", "0", "false", "no"):
    settings.load_profile("ci")

# The tests read the English messages: a Russian or Ukrainian locale would make `validate`'s
# and `variants`' help and errors speak it (issue 34, sheetkin/cli/platform.py user_lang);
# the tests of that set the locale themselves.
for _var in ("LC_ALL", "LC_MESSAGES", "LANG"):
    if os.environ.get(_var, "").split(".")[0].split("_")[0].lower() in ("ru", "uk"):
        os.environ[_var] = "C.UTF-8"


@pytest.fixture(scope="session")
def soffice() -> str:
    """Path of LibreOffice's soffice."""
    return require(soffice_path(), SETUP_HINT)


@pytest.fixture(scope="session")
def ssconvert() -> str:
    """Path of Gnumeric's ssconvert (the third spreadsheet engine, `ssconvert --recalc`; also
    books re-saved as Gnumeric saves them)."""
    return require(ssconvert_path(), GNUMERIC_HINT)


@pytest.fixture(scope="session")
def pdftoppm() -> str:
    """Path of poppler's pdftoppm (renders README pictures)."""
    return require(shutil.which("pdftoppm"), "pdftoppm not found: run `bash tests/setup.sh` (poppler-utils)")


# Markers from what a test needs, so `pytest -m "not libreoffice and not browser and not gnumeric"`
# is the fast lane (CI still runs every test). A test that asks for the `soffice` fixture runs
# LibreOffice; one that asks for `ssconvert` runs Gnumeric; the *_browser modules drive Chromium.
_NEEDS = {"soffice": "libreoffice", "ssconvert": "gnumeric"}


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        for fixture, marker in _NEEDS.items():
            if fixture in getattr(item, "fixturenames", ()):
                item.add_marker(marker)
        if item.path.stem.endswith("_browser"):
            item.add_marker("browser")
