"""Users' code type-checks against the package: ``tests/typing_user.py`` (which reads the
fields of foon's exceptions, pickles a planner, ...) passes ``mypy --strict``."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("mypy") is None, reason="mypy is not installed (CI installs it)"
)


def mypy(path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--config-file", "",
         str(path)],
        check=False, cwd=ROOT, capture_output=True, text=True, timeout=600,
    )  # fmt: skip


def test_user_code_type_checks_under_strict_mypy() -> None:
    r = mypy(HERE / "typing_user.py")
    assert r.returncode == 0, r.stdout + r.stderr


def test_mypy_does_see_the_exception_fields(tmp_path: Path) -> None:
    # The same check fails on a wrong use, so the test above is not vacuous.
    bad = tmp_path / "bad_user.py"
    bad.write_text(
        "import foon\n\n\ndef f(e: foon.ParseError, m: foon.MissingRateError) -> str:\n"
        "    return e.line + m.motion\n"
    )
    r = mypy(bad)
    assert r.returncode == 1 and 'Unsupported operand types for + ("int" and "str")' in r.stdout, (
        r.stdout + r.stderr
    )
