"""What the course benchmarks share: the course FOON, kitchen, motion rates, utensils and the
25 goals (from ``--data``, ``../shared/data/foon`` by default), and timing helpers."""

from __future__ import annotations

import argparse
import json
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

import foon

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "foon"
T = TypeVar("T")


def data_arg(ap: argparse.ArgumentParser) -> None:
    """The ``--data DIR`` option of every course benchmark."""
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA,
                    help="the course data (FOON.txt, kitchen.json, motion.txt, utensils.txt, "
                         "goal_nodes_25.json)")  # fmt: skip


@dataclass
class Course:
    foon: foon.Foon
    kitchen: foon.Kitchen
    motions: foon.MotionRates
    utensils: list[str]
    goals: list[foon.Object]

    @classmethod
    def load(cls, d: Path) -> Course:
        goals = json.loads((d / "goal_nodes_25.json").read_text(encoding="utf-8"))
        return cls(
            foon.load(d / "FOON.txt"),
            foon.Kitchen.load(d / "kitchen.json"),
            foon.MotionRates.load(d / "motion.txt"),
            foon.load_utensils(d / "utensils.txt"),
            [foon.Object.from_dict(g) for g in goals],
        )

    def planner(self, rated: bool = True) -> foon.Planner:
        """A planner of the course kitchen and utensils, with the motion rates unless not
        ``rated`` (the split takes its rates from its profiles)."""
        return self.foon.planner(
            self.kitchen, motions=self.motions if rated else None, utensils=self.utensils
        )


def timed(fn: Callable[[], T]) -> tuple[float, T]:
    """Wall time of one call, and its result."""
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def median_time(fn: Callable[[], object], runs: int = 5) -> float:
    """The median wall time of ``runs`` calls."""
    return statistics.median(timed(fn)[0] for _ in range(runs))
