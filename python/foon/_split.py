"""Success profiles and the robot/human split (:meth:`foon.Foon.split`): :class:`Profile`,
:class:`Profiles` and the result classes. The algorithm is in the core
(``foon_core::search::split``; ``docs/METHODS.md``, "The robot/human split")."""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from foon import _foon

if TYPE_CHECKING:
    from foon import Foon, GoalLike, MotionRates, PathLike, Planner

__all__ = ["FixedPoint", "Profile", "Profiles", "SplitPoint", "SplitResult", "SplitStep"]

Actor = Literal["robot", "human"]


@dataclass(frozen=True)
class Profile:
    """One success profile: a motion table, a default rate for motions it lacks, and per-unit
    overrides (unit index -> rate) that win over both. ``overrides_path`` is the override
    file they were read from (its lines appear in errors)."""

    rates: MotionRates | None = None
    default_rate: float | None = None
    overrides: Mapping[int, float] = field(default_factory=dict)
    overrides_path: str | None = None
    _lines: tuple[tuple[int, float, int], ...] = field(default=(), repr=False, compare=False)

    @classmethod
    def certain(cls) -> Profile:
        """Every unit at rate 1 (the human's profile when none is given)."""
        return cls(default_rate=1.0)

    def with_overrides(self, overrides: Mapping[int, float] | PathLike) -> Profile:
        """This profile with per-unit overrides: a mapping, or a file of ``unit<TAB>rate``
        lines (``docs/FORMATS.md``)."""
        if isinstance(overrides, str | bytes | os.PathLike):
            triples = tuple(_foon.load_overrides(overrides))
            path = os.fsdecode(overrides)
        else:
            triples = tuple((int(u), r, 0) for u, r in overrides.items())
            path = None
        return Profile(
            self.rates,
            self.default_rate,
            {u: r for u, r, _ in triples},
            path,
            triples,
        )

    def _native(self) -> tuple[Any, ...]:
        lines = self._lines or tuple((u, r, 0) for u, r in self.overrides.items())
        rates = None if self.rates is None else list(self.rates.items())
        return (rates, self.default_rate, list(lines), self.overrides_path)


class Profiles(Mapping[str, Profile]):
    """Named success profiles (``robot``, ``human``, ...), chosen per query.

    ``tables`` maps names to motion tables (a :class:`~foon.MotionRates`, a path, a mapping
    of motion to rate) or to :class:`Profile` objects; ``overrides`` maps names to per-unit
    overrides (a mapping or an override file); ``default_rates`` to a default rate."""

    def __init__(
        self,
        tables: Mapping[str, Any] | None = None,
        *,
        overrides: Mapping[str, Mapping[int, float] | PathLike] | None = None,
        default_rates: Mapping[str, float] | None = None,
    ) -> None:
        from foon import _as_rates

        self._profiles: dict[str, Profile] = {}
        for name, t in (tables or {}).items():
            self._profiles[name] = t if isinstance(t, Profile) else Profile(_as_rates(t))
        for name, r in (default_rates or {}).items():
            p = self._profiles.get(name, Profile())
            self._profiles[name] = Profile(p.rates, r, p.overrides, p.overrides_path, p._lines)
        for name, o in (overrides or {}).items():
            self._profiles[name] = self._profiles.get(name, Profile()).with_overrides(o)

    @classmethod
    def parse(cls, specs: Iterable[str], overrides: Iterable[str] = ()) -> Profiles:
        """Profiles from ``NAME=FILE`` texts (the command line's ``--profile``), with
        ``NAME=FILE`` override files (``--override``)."""
        return cls(
            dict(_name_file(s, "--profile") for s in specs),
            overrides=dict(_name_file(s, "--override") for s in overrides),
        )

    def __getitem__(self, name: str) -> Profile:
        return self._profiles[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._profiles)

    def __len__(self) -> int:
        return len(self._profiles)

    def __repr__(self) -> str:
        return f"Profiles({', '.join(self._profiles)})"


def _name_file(spec: str, option: str) -> tuple[str, str]:
    name, sep, path = spec.partition("=")
    if not sep or not name.strip() or not path:
        raise ValueError(f"{option} {spec!r}: expected NAME=FILE")
    return name.strip(), path


@dataclass(frozen=True)
class SplitStep:
    """One making of a split tree: ``unit`` makes ``object`` (budget ``budget`` for it and
    everything below it), done by ``actor``, ``times`` times (a sub-goal used twice is made
    twice, as tree cost counts it)."""

    unit: int
    object: int
    actor: Actor
    budget: int
    times: int


@dataclass(frozen=True)
class SplitPoint:
    """A point of the Pareto front: ``human`` human steps (counted with ``times``), the
    success, and the tree (makings in execution order; ``units``: its distinct units)."""

    human: int
    success: float
    steps: tuple[SplitStep, ...]
    units: tuple[int, ...]


@dataclass(frozen=True)
class FixedPoint:
    """The lab's fixed-tree method at a budget: the best robot tree (as tree cost counts it)
    with its ``human`` step instances of lowest robot rate done by the human. ``steps``:
    (unit, who, times) in execution order."""

    human: int
    success: float
    steps: tuple[tuple[int, Actor, int], ...]


@dataclass(frozen=True)
class SplitResult:
    """What :meth:`foon.Foon.split` returns.

    ``best[m]``: the best success with at most ``m`` human steps (None: no tree);
    ``front``: the budgets that improve on every smaller one, with their trees; ``fixed``:
    with ``fixed_tree=True``, the lab's method for m = 0..min(M, units of its tree);
    ``missing``/``cycle``: why an unsolved goal cannot be made."""

    goal: int
    max_human: int
    solved: bool
    best: tuple[float | None, ...]
    front: tuple[SplitPoint, ...]
    fixed: tuple[FixedPoint, ...] | None
    missing: tuple[int, ...]
    cycle: tuple[int, ...]
    cycle_units: tuple[int, ...]
    expanded: int
    _native: _foon.Split | None = field(default=None, repr=False, compare=False)

    def __getstate__(self) -> dict[str, Any]:
        # The core's copy is not pickled: a copy or an unpickled split has none to draw.
        return {k: v for k, v in self.__dict__.items() if k != "_native"}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for k, v in state.items():
            object.__setattr__(self, k, v)
        object.__setattr__(self, "_native", None)

    def write(self, format: str, *, title: str | None = None) -> str:
        """The split as a self-contained page (``format`` html): the front as a chart of
        success against human steps, the best success per budget, and each front point's
        steps (who does what)."""
        if self._native is None:
            raise ValueError("this split was copied or unpickled: split the goal again to write it")
        return self._native.write(format, title=title).decode("utf-8")

    def to_dict(self, foon: Foon | None = None) -> dict[str, Any]:
        """A JSON-ready dict (with ``foon``, each step also gives its motion)."""

        def motion(u: int) -> dict[str, Any]:
            return {} if foon is None else {"motion": foon.fu(u).motion}

        d: dict[str, Any] = {
            "goal": self.goal,
            "max_human": self.max_human,
            "solved": self.solved,
            "best": list(self.best),
            "front": [
                {
                    "human": p.human,
                    "success": p.success,
                    "units": list(p.units),
                    "steps": [
                        {
                            "unit": s.unit,
                            **motion(s.unit),
                            "object": s.object,
                            "actor": s.actor,
                            "budget": s.budget,
                            "times": s.times,
                        }
                        for s in p.steps
                    ],
                }
                for p in self.front
            ],
        }
        if self.fixed is not None:
            d["fixed_tree"] = [
                {
                    "human": p.human,
                    "success": p.success,
                    "steps": [
                        {"unit": u, **motion(u), "actor": a, "times": t} for u, a, t in p.steps
                    ],
                }
                for p in self.fixed
            ]
        if not self.solved:
            d["missing"] = list(self.missing)
            d["cycle"] = list(self.cycle)
            d["cycle_units"] = list(self.cycle_units)
        return d


def _result(d: dict[str, Any]) -> SplitResult:
    front = tuple(
        SplitPoint(h, s, tuple(SplitStep(*t) for t in steps), tuple(units))
        for h, s, steps, units in d["front"]
    )
    fixed = (
        None
        if d["fixed"] is None
        else tuple(
            FixedPoint(h, s, tuple((u, a, t) for u, a, t in steps)) for h, s, steps in d["fixed"]
        )
    )
    e = d["explanation"] or ((), (), ())
    return SplitResult(
        goal=d["goal"],
        max_human=d["max_human"],
        solved=d["solved"],
        best=tuple(d["best"]),
        front=front,
        fixed=fixed,
        missing=tuple(e[0]),
        cycle=tuple(e[1]),
        cycle_units=tuple(e[2]),
        expanded=d["expanded"],
        _native=d["native"],
    )


def split(
    planner: Planner,
    goal: GoalLike,
    profiles: Profiles | Mapping[str, Any],
    max_human: int,
    *,
    robot: str = "robot",
    human: str = "human",
    fixed_tree: bool = False,
) -> SplitResult:
    """See :meth:`foon.Foon.split` (the planner's kitchen and utensils; its own rates are not
    used)."""
    if not isinstance(profiles, Profiles):
        profiles = Profiles(profiles)
    if isinstance(max_human, bool) or not isinstance(max_human, int):
        raise TypeError(f"max_human must be an int, not {type(max_human).__name__}")
    if not 0 <= max_human < 2**32 - 1:
        raise ValueError(f"max_human must be between 0 and {2**32 - 2}, not {max_human}")
    if robot not in profiles:
        known = ", ".join(profiles) or "none"
        raise ValueError(f"no profile named {robot!r} for the robot (profiles: {known})")
    if human not in profiles and human != "human":
        raise ValueError(f"no profile named {human!r} for the human")
    rp = profiles[robot]
    hp = profiles[human] if human in profiles else Profile.certain()
    if hp.default_rate is None:
        # The human's rate is 1 for whatever their table does not list.
        hp = Profile(hp.rates, 1.0, hp.overrides, hp.overrides_path, hp._lines)
    d = _foon.plan_split(
        planner._native,
        planner.goal_id(goal),
        rp._native(),
        hp._native(),
        max_human,
        fixed_tree,
    )
    return _result(d)
