"""Synthetic merged FOONs of any size: :func:`synth` writes (or returns) the FOON text,
:func:`synth_kitchen`, :func:`synth_goals` and :func:`synth_motions` give the matching
kitchen, goals and motion table. The generator lives in the core (``foon_core::synth``);
the same ``(units, seed)`` always gives the same bytes, on any number of threads.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, overload

from foon import _foon

if TYPE_CHECKING:
    from collections.abc import Callable

    from foon import Kitchen, MotionRates, Object, PathLike

__all__ = [
    "MAX_SYNTH_UNITS",
    "SYNTH_TEXT_LIMIT",
    "SynthReport",
    "synth",
    "synth_goals",
    "synth_kitchen",
    "synth_motions",
]

#: The largest FOON :func:`synth` makes (object and unit ids are 32-bit).
MAX_SYNTH_UNITS: int = 2**32 - 1
#: The largest FOON :func:`synth` returns as text; larger ones need ``path``.
SYNTH_TEXT_LIMIT: int = 1_000_000


@dataclass(frozen=True)
class SynthReport:
    """What :func:`synth` wrote to a file: units, bytes, recipes merged, and the path."""

    units: int
    bytes: int
    recipes: int
    path: str | None


def _seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise TypeError(f"seed must be an int, not {type(seed).__name__}")
    if not 0 <= seed < 2**64:
        raise ValueError(f"seed must be between 0 and {2**64 - 1}, not {seed}")
    return seed


def _units(units: object) -> int:
    if isinstance(units, bool) or not isinstance(units, int):
        raise TypeError(f"units must be an int, not {type(units).__name__}")
    return units


@overload
def synth(units: int, seed: int = 0, *, path: None = None, threads: int | None = None) -> str: ...
@overload
def synth(
    units: int,
    seed: int = 0,
    *,
    path: PathLike,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
) -> SynthReport: ...
def synth(
    units: int,
    seed: int = 0,
    *,
    path: PathLike | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
) -> str | SynthReport:
    """A realistic merged FOON of exactly ``units`` functional units (course dialect),
    made from ``seed``. Without ``path``, its text (at most :data:`SYNTH_TEXT_LIMIT`
    units); with ``path``, it is streamed to that file atomically (never a partial file)
    and a :class:`SynthReport` is returned; ``progress(done, total)`` is then called as
    units are written. ``threads`` never changes the bytes. The model is documented in
    ``foon_core::synth`` (docs/METHODS.md)."""
    n = _units(units)
    s = _seed(seed)
    if path is None:
        if progress is not None:
            raise ValueError("progress is only reported when writing to a path")
        if SYNTH_TEXT_LIMIT < n <= MAX_SYNTH_UNITS:
            raise ValueError(
                f"units={n} is too many to return as text (at most {SYNTH_TEXT_LIMIT}); "
                "give path= to write a file"
            )
        return _foon.synth_text(n, s, threads)
    done, size, recipes = _foon.synth_write(n, s, path, threads, progress)
    return SynthReport(done, size, recipes, os.fsdecode(os.fspath(path)))


def synth_kitchen(units: int, seed: int = 0, *, path: PathLike | None = None) -> Kitchen:
    """The kitchen of :func:`synth`'s FOON for the same ``(units, seed)``: every raw object
    but a few withheld ingredients (about 95% of its dishes are derivable). With ``path``,
    also written there as kitchen JSON, atomically."""
    import foon

    n, s = _units(units), _seed(seed)
    if path is not None:
        _foon.synth_side(n, s, "kitchen", 0, path)
    return foon._kitchen(_foon.synth_kitchen(n, s))


def synth_goals(
    units: int, seed: int = 0, count: int = 25, *, path: PathLike | None = None
) -> list[Object]:
    """Up to ``count`` goals for :func:`synth`'s FOON: the dishes of recipes spread evenly
    over it. With ``path``, also written there as a goal file (JSON), atomically."""
    import foon

    n, s = _units(units), _seed(seed)
    if isinstance(count, bool) or not isinstance(count, int):
        raise TypeError(f"count must be an int, not {type(count).__name__}")
    if count < 0:
        raise ValueError(f"count must be at least 0, not {count}")
    if path is not None:
        _foon.synth_side(n, s, "goals", count, path)
    return [foon._object(t) for t in _foon.synth_goals(n, s, count)]


def synth_motions(*, path: PathLike | None = None) -> MotionRates:
    """The motion table of synthetic FOONs: every course motion with its course rate. With
    ``path``, also written there (``motion<TAB>rate`` lines), atomically."""
    import foon

    if path is not None:
        _foon.synth_side(1, 0, "motions", 0, path)
    return foon.MotionRates(_foon.synth_motions())
