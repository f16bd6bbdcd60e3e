"""The README's code runs as written: every ```python block, in the repository root (so that
``../shared`` resolves), each in a fresh interpreter."""

from __future__ import annotations

import os
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


def test_the_command_line_blocks_run_as_written(tmp_path: Path) -> None:
    """Every ```bash block after the set-up commands, run in order in one shell (later blocks
    use what earlier ones define and write), from a folder beside ``shared/`` as the
    repository is: no usage error, no traceback; a command may exit 1 only where the README
    says it reports a failure (an unsolvable goal, a tree that cannot run, lint findings, a blocked goal explained)."""
    need_shared()
    cli = [code for _, code in blocks("bash")][1:]  # the first block installs and tests
    assert cli, "the README shows no command-line example"
    (tmp_path / "shared").symlink_to(ROOT.parent / "shared")
    work = tmp_path / "work"
    work.mkdir()
    script = "trap 'echo \"EXIT $? $BASH_COMMAND\" >&2' ERR\n" + "\n".join(cli)
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    r = subprocess.run(["bash", "-c", script], check=False, cwd=work, env=env,
                       capture_output=True, text=True, timeout=600)  # fmt: skip
    assert "Traceback" not in r.stderr and "usage:" not in r.stderr, r.stderr
    failed = [line for line in r.stderr.splitlines() if line.startswith("EXIT ")]
    assert all(line.startswith("EXIT 1 foon ") for line in failed), failed
    # The failures are the ones the README describes, and the trees it verifies exist.
    assert {line.split()[3] for line in failed} <= {"plan", "verify", "check", "explain"}, failed
    assert (work / "trees" / "whipped_cream.txt").is_file()
    assert "whipped_cream.txt:56: unit 4 cannot run" in r.stdout or "cannot run" in r.stdout
