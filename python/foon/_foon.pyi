"""Private native module (Rust, PyO3). Use the public API in ``foon`` instead."""

import os
import threading
from collections.abc import Iterable, Sequence
from typing import Any, Literal, TypeAlias, final

__all__ = [
    "MAX_PICTURE_NODES",
    "Explanation",
    "FindIndex",
    "Foon",
    "FoonError",
    "GoalNotFoundError",
    "Kitchen",
    "MissingRateError",
    "OutputError",
    "ParseError",
    "Paths",
    "Plan",
    "Planner",
    "Split",
    "TreeWriter",
    "__version__",
    "check",
    "check_json",
    "check_rates",
    "explain",
    "explanation",
    "formats",
    "goal_at_level",
    "load_objects",
    "load_overrides",
    "load_rates",
    "load_utensils",
    "max_threads",
    "methods",
    "object_fields",
    "object_fields_of_mapping",
    "object_identity",
    "object_text",
    "objects_json",
    "parse_objects",
    "parse_overrides",
    "parse_rates",
    "parse_utensils",
    "plan_k",
    "plan_split",
    "split_pddl",
    "stats_json",
    "verify_json",
    "write_comparison",
    "write_foon",
    "write_tree",
]

__version__: str
MAX_PICTURE_NODES: int

_Obj: TypeAlias = tuple[str, list[str], list[str], str | None]
_Fields: TypeAlias = tuple[str, tuple[str, ...], tuple[str, ...], str | None]
_Path: TypeAlias = str | bytes | os.PathLike[str] | os.PathLike[bytes]

class FoonError(Exception): ...

class ParseError(FoonError):
    """An input file is malformed; `path`, `line`, `column` and `reason` say where and why."""

    path: str | None
    line: int
    column: int
    reason: str
    kind: str

class GoalNotFoundError(FoonError): ...

class MissingRateError(FoonError):
    motion: str

class OutputError(FoonError): ...

@final
class Foon:
    @staticmethod
    def load(path: _Path, *, strict: bool = False, progress: bool = False) -> Foon: ...
    @staticmethod
    def from_text(
        text: str | bytes, *, strict: bool = False, path: _Path | None = None
    ) -> Foon: ...
    @staticmethod
    def load_sources(
        paths: list[_Path], *, strict: bool = False, progress: bool = False
    ) -> Foon: ...
    @staticmethod
    def reopen(path: _Path, fingerprint: str) -> Foon: ...
    def write_index(self, path: _Path) -> None: ...
    def verify_checksum(self) -> None: ...
    @property
    def fingerprint(self) -> str: ...
    @property
    def index_path(self) -> str | None: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> Foon: ...
    def __reduce__(self) -> tuple[Any, ...]: ...
    def __copy__(self) -> Foon: ...
    def __deepcopy__(self, memo: Any, /) -> Foon: ...
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...
    @property
    def fu_count(self) -> int: ...
    @property
    def object_count(self) -> int: ...
    @property
    def source(self) -> str | None: ...
    def stats(self) -> dict[str, int]: ...
    def warnings(self) -> list[tuple[str | None, int, int, str, str]]: ...
    def duplicates(self) -> list[tuple[int, int]]: ...
    def object(self, o: int) -> _Obj: ...
    def fu(self, f: int) -> tuple[str, list[int], list[int], int]: ...
    def fu_text(self, f: int) -> str: ...
    def tree_text(self, units: list[int]) -> str: ...
    def to_text(self) -> str: ...
    def find(
        self, label: str, states: list[str], ingredients: list[str], container: str | None
    ) -> int | None: ...
    def goal_id(self, goal: int | str | _Fields) -> int: ...
    def objects_with_label(self, label: str) -> list[int]: ...
    def producers(self, o: int) -> list[int]: ...
    def consumers(self, o: int) -> list[int]: ...
    def verify_tree(
        self, tree: Foon, kitchen: Kitchen, utensils: list[str], goal: _Obj
    ) -> dict[str, Any]: ...

@final
class Plan:
    @property
    def goal(self) -> int: ...
    @property
    def method(self) -> str: ...
    @property
    def compat(self) -> str: ...
    @property
    def count(self) -> str: ...
    @property
    def solved(self) -> bool: ...
    @property
    def units(self) -> list[int]: ...
    @property
    def unresolved(self) -> list[int]: ...
    @property
    def missing(self) -> list[int]: ...
    @property
    def cycle(self) -> list[int]: ...
    @property
    def cycle_units(self) -> list[int]: ...
    @property
    def height(self) -> int | None: ...
    @property
    def success(self) -> float | None: ...
    @property
    def cost(self) -> float | None: ...
    @property
    def bound(self) -> float | None: ...
    @property
    def proven(self) -> bool | None: ...
    @property
    def gap(self) -> float | None: ...
    @property
    def objective(self) -> str | None: ...
    @property
    def leaf_inputs(self) -> int: ...
    @property
    def expanded(self) -> int: ...
    @property
    def peak_frontier(self) -> int: ...
    @property
    def seconds(self) -> float: ...
    @property
    def unrated(self) -> int | None: ...
    def __eq__(self, other: object, /) -> bool: ...
    def __reduce__(self) -> tuple[Any, ...]: ...
    @staticmethod
    def _from_state(state: tuple[Any, ...]) -> Plan: ...

@final
class Kitchen:
    """A set of object identities in the order of first appearance (immutable)."""

    def __new__(cls, items: list[_Obj] = ...) -> Kitchen: ...
    @staticmethod
    def load(path: _Path) -> Kitchen: ...
    @staticmethod
    def parse(text: str | bytes, path: _Path | None = None) -> Kitchen: ...
    def __len__(self) -> int: ...
    def get(self, i: int) -> _Obj: ...
    def slice(self, start: int, stop: int) -> list[_Obj]: ...
    def tuples(self) -> list[_Obj]: ...
    def contains(self, o: _Obj) -> bool: ...
    def equals(self, other: Kitchen) -> bool: ...
    @property
    def fingerprint(self) -> str: ...
    def without(self, drop: Kitchen) -> Kitchen: ...
    def with_items(self, add: Kitchen) -> Kitchen: ...
    def with_steps(self, steps: list[tuple[Kitchen, Kitchen]]) -> Kitchen: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> Kitchen: ...
    def to_json(self) -> str: ...
    def heap_bytes(self) -> int: ...

@final
class Planner:
    def __new__(
        cls,
        foon: Foon,
        kitchen: Kitchen,
        utensils: list[str],
        rates: list[tuple[str, float]] | None = None,
        default_rate: float | None = None,
        level: int = 3,
    ) -> Planner: ...
    def plan(
        self,
        goals: list[int],
        method: str,
        compat: str,
        count: str,
        threads: int | None = None,
        objective: str | None = None,
        node_limit: int | None = None,
        time_limit: float | None = None,
    ) -> list[Plan]:
        """Plans every goal in order on `threads` worker threads: always honoured, capped to
        the available parallelism (`max_threads()`) and to the number of goals; None means
        the FOON_THREADS environment variable, else all cores. `objective` (`units` or
        `success`), `node_limit` and `time_limit` (seconds) are the options of
        `optimal-shared`."""
    def check_tree(
        self, units: list[int], goal: int
    ) -> tuple[bool, int | None, tuple[int, list[int]] | None]: ...
    def ranks(self) -> list[int | None]: ...
    def finish_updates(self) -> None: ...
    def kitchen_objects(self) -> list[int]: ...

def plan_k(
    planner: Planner, goal: int, method: str, k: int, diverse: bool = False
) -> list[Plan]: ...

@final
class Paths:
    def __new__(
        cls,
        planner: Planner,
        goal: int,
        max_trees: int | None = None,
        max_height: int | None = None,
    ) -> Paths: ...
    def __iter__(self) -> Paths: ...
    def __next__(self) -> Plan: ...

def object_fields(
    label: str, states: Iterable[str], ingredients: Iterable[str], container: str | None
) -> _Fields: ...
def object_fields_of_mapping(d: Any) -> _Fields: ...
def object_identity(
    label: str, states: Sequence[str], ingredients: Sequence[str], container: str | None
) -> tuple[str, list[str], list[str], str | None]: ...
def object_text(
    label: str, states: Sequence[str], ingredients: Sequence[str], container: str | None
) -> str: ...
def load_objects(path: _Path, kind: str) -> list[_Obj]: ...
def parse_objects(text: str | bytes, kind: str, path: _Path | None = None) -> list[_Obj]: ...
def load_rates(path: _Path) -> list[tuple[str, float]]: ...
def parse_rates(text: str | bytes, path: _Path | None = None) -> list[tuple[str, float]]: ...
def check_rates(pairs: Iterable[tuple[str, float]]) -> list[tuple[str, float]]: ...
def load_utensils(path: _Path) -> list[str]: ...
def parse_utensils(text: str | bytes, path: _Path | None = None) -> list[str]: ...
def methods() -> list[str]: ...
def max_threads() -> int:
    """The cap on worker threads: the available parallelism of this process."""

def check(
    paths: list[_Path],
    kitchen: Kitchen | None = None,
    rates: list[tuple[str, float]] | None = None,
    utensils: list[str] = ...,
    rates_file: _Path | None = None,
) -> list[tuple[str | None, int, int, str, str, str]]: ...
def formats() -> list[tuple[str, str, str, bool, bool, bool, bool, bool]]:
    """Every format: (name, extension, MIME type, binary, needs `dot`, writes a tree, writes
    a FOON, writes a comparison)."""

def write_tree(
    planner: Planner,
    plan: Plan,
    format: str,
    *,
    title: str | None = None,
    max_nodes: int | None = None,
    cost_scale: int | None = None,
) -> bytes: ...
def write_foon(
    foon: Foon,
    format: str,
    *,
    units: list[int] | None = None,
    focus: Any = None,
    depth: int | None = None,
    planner: Planner | None = None,
    title: str | None = None,
    max_nodes: int | None = None,
    cost_scale: int | None = None,
) -> bytes: ...
def write_comparison(
    foon: Foon,
    rows: Sequence[
        tuple[str, Plan]
        | tuple[str, str, str]
        | tuple[str, int, bool, int | None, float | None, int, float]
    ],
    format: str,
    *,
    title: str | None = None,
    level: int = 3,
    split: tuple[int, dict[int, tuple[float | None, float | None]]] | None = None,
) -> bytes: ...
def explanation(foon: Foon, plan: Plan) -> str: ...
def explain(
    planner: Planner, goal: int, method: str, count: str
) -> tuple[
    Literal["in-kitchen", "derivable", "blocked"],
    int | None,
    Plan | None,
    bool,
    list[int],
    list[tuple[int, list[tuple[int, Literal["missing", "cycle", "not-derivable"], bool]]]],
    list[int],
    list[int],
    list[tuple[int, bool]],
    str,
    Explanation,
]: ...

@final
class Explanation:
    def write(
        self, format: str, *, title: str | None = None, max_nodes: int | None = None
    ) -> bytes: ...

@final
class Split:
    def write(self, format: str, *, title: str | None = None) -> bytes: ...

def goal_at_level(
    planner: Planner, goal: str | tuple[str, list[str], list[str], str | None], level: int
) -> int: ...

@final
class FindIndex:
    def __new__(cls, foon: Foon) -> FindIndex: ...
    def find(self, text: str, k: int) -> list[tuple[int, float]]: ...

@final
class TreeWriter:
    def __new__(
        cls,
        format: str,
        many: bool,
        *,
        title: str | None = None,
        max_nodes: int | None = None,
        cost_scale: int | None = None,
    ) -> TreeWriter: ...
    def begin(self) -> bytes: ...
    def tree(self, planner: Planner, plan: Plan) -> bytes: ...
    def failed(self, goal: _Obj, label_only: bool, method: str, error: str) -> bytes: ...
    def end(self) -> bytes: ...

def objects_json(items: list[_Obj]) -> str: ...
def verify_json(
    foon: Foon, tree: Foon, kitchen: Kitchen, utensils: list[str], goal: _Obj
) -> str: ...
def check_json(findings: Sequence[tuple[str | None, int, int, str, str, str]]) -> str: ...
def stats_json(rows: Sequence[tuple[str, Foon]]) -> str: ...
def split_pddl(text: str) -> tuple[str, str]: ...

# Synthetic FOONs (foon_core::synth).
def synth_text(units: int, seed: int, threads: int | None = None) -> str: ...
def synth_write(
    units: int,
    seed: int,
    path: _Path | None = None,
    threads: int | None = None,
    progress: Any = None,
    bar: bool = False,
) -> tuple[int, int, int]: ...
def synth_kitchen(units: int, seed: int) -> Kitchen: ...
def synth_goals(units: int, seed: int, count: int) -> list[_Obj]: ...
def synth_motions() -> list[tuple[str, float]]: ...
def synth_side(
    units: int, seed: int, what: str, count: int = 25, path: _Path | None = None
) -> str | None: ...

__all__ += [
    "synth_goals",
    "synth_kitchen",
    "synth_motions",
    "synth_side",
    "synth_text",
    "synth_write",
]

# Merging (foon_core::merge).
def merge_paths(
    paths: Sequence[_Path],
    *,
    level: int = 3,
    min_support: int = 1,
    strict: bool = False,
    out: _Path | None = None,
    progress: bool = False,
) -> tuple[Foon, dict[str, int | str]]: ...
def merge_texts(
    sources: Sequence[tuple[str, str | bytes]],
    *,
    level: int = 3,
    min_support: int = 1,
    strict: bool = False,
) -> tuple[Foon, dict[str, int | str]]: ...
def merged_text(foon: Foon, header: str = "") -> str: ...
def parse_merged(text: str | bytes, *, strict: bool = False, path: _Path | None = None) -> Foon: ...
def load_merged(path: _Path, *, strict: bool = False) -> Foon: ...
def fu_sources(foon: Foon, fu: int) -> list[tuple[str, int]]: ...
def fu_support(foon: Foon, fu: int) -> int: ...
def provenance_text(foon: Foon) -> str: ...

__all__ += [
    "fu_sources",
    "fu_support",
    "load_merged",
    "merge_paths",
    "merge_texts",
    "merged_text",
    "parse_merged",
    "provenance_text",
]

def load_overrides(path: _Path) -> list[tuple[int, float, int]]: ...
def parse_overrides(
    text: str | bytes, path: _Path | None = None
) -> list[tuple[int, float, int]]: ...
def plan_split(
    planner: Planner,
    goal: int,
    robot: tuple[Any, ...],
    human: tuple[Any, ...],
    max_human: int,
    fixed_tree: bool = False,
) -> dict[str, Any]: ...

# Many kitchens at once.
__all__ += ["MatchedKitchens", "derivable_many", "match_kitchens"]

@final
class MatchedKitchens:
    """Kitchens matched to one FOON's objects at one level (opaque)."""

    def __len__(self) -> int: ...
    @property
    def level(self) -> int: ...

def match_kitchens(foon: Foon, kitchens: list[Kitchen], level: int = 3) -> MatchedKitchens: ...
def derivable_many(
    foon: Foon,
    kitchens: list[Kitchen] | MatchedKitchens,
    goals: list[int],
    utensils: list[str],
    level: int = 3,
    ranks: bool = False,
    threads: int | None = None,
    mode: str = "lanes",
) -> list[list[bool]] | list[list[int | None]]: ...

# Queries in, results out.
__all__ += [
    "KitchenSet",
    "batch_cache_stats",
    "clear_batch_cache",
    "failure_codes",
    "plan_query_columns",
]

@final
class KitchenSet:
    """Named kitchens (immutable)."""

    def __new__(cls, kitchens: list[tuple[str, Kitchen]]) -> KitchenSet: ...
    @staticmethod
    def with_deltas(base: Kitchen, deltas: list[tuple[str, Kitchen, Kitchen]]) -> KitchenSet: ...
    @staticmethod
    def load(path: _Path) -> KitchenSet: ...
    @staticmethod
    def parse(text: str | bytes, path: _Path | None = None) -> KitchenSet: ...
    @property
    def ids(self) -> list[str]: ...
    def __len__(self) -> int: ...
    def __contains__(self, key: str, /) -> bool: ...
    def get(self, id: str) -> Kitchen: ...
    def is_delta(self, id: str) -> bool: ...
    @property
    def fingerprint(self) -> str: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> KitchenSet: ...

def plan_query_columns(
    foon: Foon,
    kitchens: KitchenSet,
    n: int,
    kitchen_ids: tuple[int, bytes | None, bytes, bytes, bool],
    goals: tuple[int, bytes | None, bytes, bytes, bool],
    methods: tuple[int, bytes | None, bytes, bytes, bool],
    options: tuple[int, bytes | None, bytes, bytes, bool] | None = None,
    threads: int | None = None,
    utensils: list[str] | None = None,
    rates: list[tuple[str, float]] | None = None,
    default_rate: float | None = None,
    deltas: str | None = None,
    cancel: threading.Event | None = None,
) -> tuple[Any, ...]: ...
def failure_codes() -> list[str]: ...
def batch_cache_stats() -> tuple[int, int, int, int, int, int]: ...
def clear_batch_cache() -> None: ...

# Incremental kitchens.
__all__ += ["planner_with_changes"]

def planner_with_changes(
    planner: Planner, add: Kitchen, remove: Kitchen, kitchen: Kitchen | None
) -> Planner:
    """A planner for `planner`'s kitchen without the items of `remove` and with those of
    `add` (`kitchen`: that new kitchen, needed at levels 1 and 2 only), over the same FOON, utensils, rates and level,
    prepared incrementally from `planner`'s preparation. Its results equal a new planner's."""
