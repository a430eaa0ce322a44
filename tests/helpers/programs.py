"""External programs the tests need (installed by tests/setup.sh): found, or the test skipped."""
from __future__ import annotations

import os

import pytest


def require(path: str | None, hint: str) -> str:
    """`path`, or skip with `hint`; under CI (env CI set) a missing program fails instead."""
    if path is None:
        if os.environ.get("CI", "").lower() not in ("", "0", "false", "no"):
            pytest.fail(f"{hint} (CI is set: missing programs fail instead of skipping)", pytrace=False)
        pytest.skip(hint)
    return path
