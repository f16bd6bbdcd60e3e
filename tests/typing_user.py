"""User code type-checked by ``tests/test_typing.py`` under ``mypy --strict`` (not a test)."""

from __future__ import annotations

import pickle

import foon


def where(e: foon.ParseError) -> str:
    path: str | None = e.path
    line: int = e.line
    column: int = e.column
    reason: str = e.reason
    return f"{path or '<string>'}:{line}:{column}: {reason}"


def load_or_explain(path: str) -> foon.Foon | str:
    try:
        return foon.load(path)
    except foon.ParseError as e:
        return where(e)
    except foon.FoonError as e:
        return str(e)


def rate_of_first_missing(f: foon.Foon, kitchen: foon.Kitchen) -> str | None:
    try:
        f.plan(0, kitchen, "greedy-success", motions={})
    except foon.MissingRateError as e:
        motion: str = e.motion
        return motion
    return None


def plans(f: foon.Foon, goals: list[foon.Object]) -> list[list[int]]:
    p = f.planner(foon.Kitchen(), utensils=[])
    q: foon.Planner = pickle.loads(pickle.dumps(p))
    trees: list[foon.TaskTree] = q.plan_many(goals, "ids", threads=2)
    missing: str | None = trees[0].unrated_motion if trees else None
    del missing
    return [[u.index for u in t] for t in trees]


def goals_of(path: bytes) -> list[foon.Object]:
    return foon.load_goals(path)
