"""Shared fixtures: where the real data lives, and small helpers.

The real FOON data (course set, lab history, subgraphs, golden outputs) is read from
``../shared`` beside the repository and never copied in. Tests that need it skip with a
clear reason when it is absent; with ``FOON_REQUIRE_DATA=1`` (set by ``.ci/run``) a missing
data set fails instead, so CI can never pass by skipping.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import foon
import pytest

SHARED = Path(__file__).resolve().parents[1].parent / "shared"
DATA = SHARED / "data" / "foon"
GOLDEN = SHARED / "data" / "golden-course"


def need_shared() -> None:
    """Skips the calling test when ../shared is absent (fails under FOON_REQUIRE_DATA)."""
    if (DATA / "FOON.txt").is_file():
        return
    if os.environ.get("FOON_REQUIRE_DATA"):
        pytest.fail(f"FOON_REQUIRE_DATA is set but the shared data is missing: {DATA}")
    pytest.skip(f"the real FOON data is not beside the repository ({DATA} is missing)")


class Course:
    """The course data set, loaded once."""

    def __init__(self) -> None:
        self.foon = foon.load(DATA / "FOON.txt")
        self.kitchen = foon.Kitchen.load(DATA / "kitchen.json")
        self.motions = foon.MotionRates.load(DATA / "motion.txt")
        self.utensils = foon.load_utensils(DATA / "utensils.txt")
        self.goals5 = [
            foon.Object.from_dict(d) for d in json.loads((DATA / "goal_nodes.json").read_text())
        ]
        self.goals25 = [
            foon.Object.from_dict(d) for d in json.loads((DATA / "goal_nodes_25.json").read_text())
        ]


@pytest.fixture(scope="session")
def course() -> Course:
    need_shared()
    return Course()


def golden_name(label: str) -> str:
    return label.replace(" ", "_") + ".txt"


def need_program(*names: str) -> str:
    """The first of ``names`` found on PATH; skips the calling test when none is (fails
    under CI, which installs them)."""
    import shutil

    for n in names:
        path = shutil.which(n)
        if path:
            return path
    if os.environ.get("CI"):
        pytest.fail(f"CI is set but {' / '.join(names)} is not installed")
    pytest.skip(f"{' / '.join(names)} is not installed")
