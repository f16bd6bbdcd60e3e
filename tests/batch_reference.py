"""A slow, obviously correct reference for batches of queries: each query row answered on its
own with the public per-query API (``Foon.plan`` with a ``foon.Kitchen``), the options and
failure codes of ``docs/BATCH.md`` spelled out in plain Python. Rows come back as dicts with
the columns of ``foon._arrow.RESULT_SCHEMA``."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import foon

OPTION_NAMES = ("compat", "count", "objective", "level", "node_limit", "time_limit",
                "default_rate")  # fmt: skip

Row = tuple[Any, str | None, str | None, str | None, str | None]


class Failed(Exception):
    def __init__(self, code: str, message: str | None = None) -> None:
        super().__init__(code)
        self.code = code
        self.message = message


def _options(text: str | None, method: str) -> dict[str, Any]:
    """The row's options as ``Foon.plan`` arguments (``Failed("bad-option")`` when bad)."""
    if text is None or text.strip() in ("", "null"):
        return {}
    try:
        d = json.loads(text)
    except ValueError:
        raise Failed("bad-option") from None
    if not isinstance(d, dict):
        raise Failed("bad-option")
    out: dict[str, Any] = {}
    for k, v in d.items():
        if k not in OPTION_NAMES:
            raise Failed("bad-option")
        if v is None:
            continue
        is_int = isinstance(v, int) and not isinstance(v, bool)
        is_num = is_int or isinstance(v, float)
        if k == "compat":
            if v not in ("course", "sound", "none"):
                raise Failed("bad-option")
            out["compat"] = "course" if v == "course" else None
        elif k == "count":
            if v not in ("nodes", "ingredients"):
                raise Failed("bad-option")
            out["count"] = v
        elif k == "objective":
            if v not in ("units", "success"):
                raise Failed("bad-option")
            out["objective"] = v
        elif k == "level":
            if not is_int or v not in (1, 2, 3):
                raise Failed("bad-option")
            out["level"] = v
        elif k == "node_limit":
            if not is_int or v < 0:
                raise Failed("bad-option")
            out["node_limit"] = v
        elif k == "time_limit":
            if not is_num or not v >= 0:
                raise Failed("bad-option")
            out["time_limit"] = float(v)
        elif k == "default_rate":
            if not is_num or not 0 <= v <= 1:
                raise Failed("bad-option")
            out["default_rate"] = float(v)
    # The objective and the limits are options of optimal-shared (its defaults aside).
    if method != "optimal-shared" and (
        out.get("objective", "units") != "units" or "node_limit" in out or "time_limit" in out
    ):
        raise Failed("bad-option")
    # The optimal methods have no course-compatible form.
    if out.get("compat") == "course" and method.startswith("optimal-"):
        raise Failed("bad-option")
    return out


def _goal(text: str | None) -> foon.Object | str:
    if text is None:
        raise Failed("bad-goal")
    if not text.lstrip().startswith("{"):
        return text
    try:
        d = json.loads(text)
        if not isinstance(d, dict):
            raise Failed("bad-goal")
        return foon.Object.from_dict(d)
    except (ValueError, TypeError):
        raise Failed("bad-goal") from None


def _row(
    f: foon.Foon,
    kitchens: Mapping[str, foon.Kitchen],
    kitchen_id: str | None,
    goal: str | None,
    method: str | None,
    options: str | None,
    motions: foon.MotionRates | None,
    utensils: Sequence[str],
    default_rate: float | None,
) -> dict[str, Any]:
    if kitchen_id is None or kitchen_id not in kitchens:
        raise Failed("unknown-kitchen")
    if method is None or method not in foon.METHODS:
        raise Failed("unknown-method")
    opts = _options(options, method)
    g = _goal(goal)
    opts.setdefault("default_rate", default_rate)
    try:
        t = f.plan(g, kitchens[kitchen_id], method, motions=motions, utensils=utensils, **opts)
    except foon.GoalNotFoundError as e:
        ambiguous = not str(e).startswith("The goal node does not exist")
        raise Failed("goal-ambiguous" if ambiguous else "goal-not-found") from None
    except foon.MissingRateError as e:
        raise Failed("missing-rate", str(e)) from None
    except (foon.FoonError, ValueError) as e:
        raise Failed("error", str(e)) from None
    if t.solved:
        return {
            "solved": True,
            "fu_count": len(t.units),
            "height": t.height,
            "success": t.success,
            "cost": t.cost,
            "leaf_count": t.leaf_inputs,
            "units": list(t.units),
            "failure": None,
            "missing": [],
            "message": None,
        }
    if t.compat == "course":
        code, missing = "unresolved", t.unresolved
    else:
        code, missing = ("cycle" if t.cycle else "not-derivable"), t.missing
    return {**_failed(code, None), "missing": [str(o) for o in missing]}


def _failed(code: str, message: str | None) -> dict[str, Any]:
    return {
        "solved": False,
        "fu_count": None,
        "height": None,
        "success": None,
        "cost": None,
        "leaf_count": None,
        "units": [],
        "failure": code,
        "missing": [],
        "message": message,
    }


def answer(
    f: foon.Foon,
    kitchens: Mapping[str, foon.Kitchen],
    rows: Sequence[Row],
    *,
    motions: foon.MotionRates | None = None,
    utensils: Sequence[str] = (),
    default_rate: float | None = None,
) -> list[dict[str, Any]]:
    """Every row (query id, kitchen id, goal, method, options) answered on its own."""
    out = []
    for qid, kid, goal, method, options in rows:
        try:
            r = _row(f, kitchens, kid, goal, method, options, motions, utensils, default_rate)
        except Failed as e:
            r = _failed(e.code, e.message)
        out.append({"query_id": None if qid is None else str(qid), **r})
    return out


def same(a: dict[str, Any], b: dict[str, Any]) -> bool:
    """Equal rows (floats to the last bit, NaN equal to NaN)."""
    for k in a.keys() | b.keys():
        x, y = a.get(k), b.get(k)
        if isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y):
            continue
        if x != y:
            return False
    return True
