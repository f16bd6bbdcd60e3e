"""The README's code runs as written: every ```python block, in the repository root (so that
``../shared`` resolves), each in a fresh interpreter."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import need_shared

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def blocks(language: str) -> list[tuple[int, str]]:
    """(line, code) of every fenced block of ``language`` in the README."""
    text = README.read_text(encoding="utf-8")
    found = []
    for m in re.finditer(rf"^```{language}\n(.*?)^```$", text, flags=re.MULTILINE | re.DOTALL):
        found.append((text.count("\n", 0, m.start()) + 1, m.group(1)))
    return found


def test_the_readme_has_python_blocks() -> None:
    assert blocks("python"), "the README shows no Python code"


@pytest.mark.parametrize("line,code", blocks("python"), ids=lambda v: str(v)[:12])
def test_python_block_runs(line: int, code: str) -> None:
    need_shared()
    r = subprocess.run(
        [sys.executable, "-W", "error::DeprecationWarning", "-c", code],
        check=False, cwd=ROOT, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert r.returncode == 0, f"README.md:{line}: the block fails:\n{r.stderr}"
    assert "Traceback" not in r.stderr
