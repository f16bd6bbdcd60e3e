"""Query batches: a small synthetic data set written as Parquet, CSV and JSON lines, and a
slow, obviously correct reference that answers each query with the public per-query API
(:meth:`foon.Foon.plan`), for comparison with :func:`foon.batch`."""

from __future__ import annotations

import json
import random
from pathlib import Path
from typing import Any

import foon

#: The result columns the reference computes (the others are texts: messages, missing).
KEY_COLUMNS = ("query_id", "solved", "fu_count", "height", "success", "leaf_count", "units",
               "failure")  # fmt: skip

METHODS = ("ids", "greedy-success", "optimal-units", "optimal-success")


class Data:
    """A 300-unit synthetic FOON as a .foonidx, three kitchens, a motion table, and
    ``n`` queries (with a few bad ones) in three file formats."""

    def __init__(self, folder: Path, n: int = 600, units: int = 300, seed: int = 3) -> None:
        import pyarrow as pa
        import pyarrow.csv as pcsv
        import pyarrow.parquet as pq

        self.folder = folder
        text = folder / "synth.txt"
        foon.synth(units, seed, path=text)
        self.index = folder / "synth.foonidx"
        foon.load(text).write_index(self.index)
        self.foon = foon.load(self.index)
        kitchen = foon.synth_kitchen(units, seed)
        items = list(kitchen)
        self.motions = foon.synth_motions()
        self.motions_path = folder / "motions.txt"
        foon.synth_motions(path=self.motions_path)
        rng = random.Random(seed)
        sets = {
            "full": items,
            "less": [o for o in items if rng.random() > 0.15],
            "half": [o for o in items if rng.random() > 0.5],
        }
        self.kitchen_items = sets
        self.kitchens_path = folder / "kitchens.json"
        self.kitchens_path.write_text(
            json.dumps({k: [o.to_dict() for o in v] for k, v in sets.items()})
        )
        self.kitchens = foon.KitchenSet.load(self.kitchens_path)
        goals = foon.synth_goals(units, seed, 20)
        # Labels stand for a goal only where one object has them.
        unique = {g.label for g in goals if len(self.foon.with_label(g.label)) == 1}
        self._planners: dict[tuple[str, int], foon.Planner] = {}
        rows: list[dict[str, Any]] = []
        for i in range(n):
            g = rng.choice(goals)
            goal = g.label if i % 3 == 0 and g.label in unique else json.dumps(g.to_dict())
            opts = None
            if i % 7 == 0:
                opts = json.dumps({"level": 3})
            rows.append({
                "query_id": f"q{i:05d}",
                "kitchen_id": rng.choice(list(sets)),
                "goal": goal,
                "method": rng.choice(METHODS),
                "options": opts,
            })  # fmt: skip
        # One defect each: an unknown kitchen, a goal no object has, an unknown method, an
        # unknown option.
        rows[5]["kitchen_id"] = "no-such-kitchen"
        rows[23]["options"] = json.dumps({"no_such_option": 1})
        rows[11]["goal"] = "no such dish"
        rows[17]["method"] = "no-such-method"
        self.rows = rows
        self.table = pa.Table.from_pylist(rows, schema=query_schema())
        self.parquet = folder / "queries.parquet"
        pq.write_table(self.table, self.parquet, row_group_size=97)
        self.csv = folder / "queries.csv"
        pcsv.write_csv(self.table, self.csv)
        self.jsonl = folder / "queries.jsonl"
        with open(self.jsonl, "w", encoding="utf-8") as f:
            f.writelines(
                json.dumps({k: v for k, v in r.items() if v is not None}) + "\n" for r in rows
            )

    def path(self, kind: str) -> Path:
        return {"parquet": self.parquet, "csv": self.csv, "jsonl": self.jsonl}[kind]


def query_schema() -> Any:
    import pyarrow as pa

    return pa.schema([(c, pa.string()) for c in ("query_id", "kitchen_id", "goal", "method",
                                                 "options")])  # fmt: skip


def reference_row(data: Data, row: dict[str, Any]) -> dict[str, Any]:
    """The key columns of one query's answer, from :meth:`foon.Foon.plan`."""
    out: dict[str, Any] = dict.fromkeys(KEY_COLUMNS)
    out.update(query_id=row["query_id"], solved=False, units=[])
    if row["kitchen_id"] not in data.kitchen_items:
        out["failure"] = "unknown-kitchen"
        return out
    if row["method"] not in foon.METHODS:
        out["failure"] = "unknown-method"
        return out
    opts = json.loads(row["options"]) if row["options"] else {}
    if set(opts) - {"level"}:
        out["failure"] = "bad-option"
        return out
    goal: Any = row["goal"]
    if goal.startswith("{"):
        goal = foon.Object.from_dict(json.loads(goal))
    key = (row["kitchen_id"], opts.get("level", 3))
    planner = data._planners.get(key)
    if planner is None:
        planner = data._planners[key] = data.foon.planner(
            data.kitchen_items[key[0]], motions=data.motions, level=key[1]
        )
    try:
        t = planner.plan(goal, row["method"])
    except foon.GoalNotFoundError:
        out["failure"] = "goal-not-found"
        return out
    if t.solved:
        out.update(
            solved=True,
            fu_count=t.fu_count,
            height=t.height,
            success=t.success,
            leaf_count=t.leaf_inputs,
            units=list(t.units),
        )
    else:
        out["failure"] = "cycle" if t.cycle else "not-derivable"
    return out


def key_rows(table: Any) -> list[dict[str, Any]]:
    """The key columns of a result table, as rows."""
    return table.select(list(KEY_COLUMNS)).to_pylist()  # type: ignore[no-any-return]


def read_parts(out: Path) -> Any:
    """Every partition of a batch's output folder, in partition order, as one table."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    parts = sorted(out.glob("part-*.parquet"))
    return pa.concat_tables([pq.read_table(p) for p in parts])
