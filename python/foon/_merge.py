"""Merging many FOONs into one, with provenance and support: ``foon.merge``.

The rules (identity levels, support, the text form with its ``#`` provenance lines) are the
core's (``foon_core::merge``); this module only calls them.
"""

from __future__ import annotations

from foon import _foon

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Sequence

    from foon import Foon, PathLike


class MergeReport:
    """What a merge read, kept and dropped.

    ``units_read`` counts every complete unit of every source; of those, ``faulty`` were
    dropped for an annotation fault, ``duplicates`` repeat an earlier unit exactly,
    ``same_at_level`` repeat one at the chosen level only, and ``below_support`` distinct
    units were found in fewer sources than the minimum; ``kept`` remain.
    """

    __slots__ = (
        "below_support",
        "duplicates",
        "faulty",
        "header",
        "kept",
        "level",
        "min_support",
        "motions",
        "objects",
        "same_at_level",
        "sources",
        "summary",
        "units_read",
    )

    def __init__(self, d: dict[str, int | str]) -> None:
        for k in self.__slots__:
            object.__setattr__(self, k, d[k])

    sources: int
    units_read: int
    faulty: int
    duplicates: int
    same_at_level: int
    below_support: int
    kept: int
    objects: int
    motions: int
    level: int
    min_support: int
    summary: str
    header: str

    def to_dict(self) -> dict[str, int | str]:
        return {k: getattr(self, k) for k in self.__slots__}

    def __repr__(self) -> str:
        return f"MergeReport({self.summary!r})"


def _wrap(native: _foon.Foon) -> Foon:
    from foon import Foon

    return Foon(native)


def _check(level: int, min_support: int) -> None:
    if isinstance(level, bool) or not isinstance(level, int) or level not in (1, 2, 3):
        raise ValueError(f"level must be 1, 2 or 3 (got {level!r})")
    if isinstance(min_support, bool) or not isinstance(min_support, int) or min_support < 1:
        raise ValueError(f"min_support must be an integer of at least 1 (got {min_support!r})")


def merge_report(
    *paths: PathLike,
    level: int = 3,
    min_support: int = 1,
    strict: bool = False,
    out: PathLike | None = None,
    progress: bool = False,
) -> tuple[Foon, MergeReport]:
    """As :func:`merge`, also returning the :class:`MergeReport`. ``progress``: draw a bar of
    the files read on stderr (only wise on a terminal)."""
    if not paths:
        raise ValueError("merge needs at least one file or folder")
    _check(level, min_support)
    native, report = _foon.merge_paths(
        list(paths), level=level, min_support=min_support, strict=strict, out=out, progress=progress
    )
    return _wrap(native), MergeReport(report)


def merge(
    *paths: PathLike,
    level: int = 3,
    min_support: int = 1,
    strict: bool = False,
    out: PathLike | None = None,
) -> Foon:
    """Merge FOON files and folders (a folder: its ``.txt`` and ``.json`` files, sorted by name)
    into one FOON, in the order given, any mix of dialects.

    A unit that repeats an earlier one at ``level`` (3: full identity; 2: ingredients
    ignored; 1: labels only) is dropped; the kept unit is the first copy and records every
    (source, line) it was found at (:meth:`foon.Foon.sources`) and its support, the number of
    distinct sources that hold it (:meth:`foon.Foon.support`). ``min_support`` keeps only the
    units found in at least that many sources. With ``out``, the merged FOON is written there
    as FOON text with its provenance as ``#`` comment lines (atomically; never over an input).
    """
    return merge_report(*paths, level=level, min_support=min_support, strict=strict, out=out)[0]


def merge_texts(
    sources: Sequence[tuple[str, str | bytes]],
    *,
    level: int = 3,
    min_support: int = 1,
    strict: bool = False,
) -> tuple[Foon, MergeReport]:
    """Merge sources given in memory as (name, text) pairs, in order (names must differ)."""
    _check(level, min_support)
    native, report = _foon.merge_texts(
        list(sources), level=level, min_support=min_support, strict=strict
    )
    return _wrap(native), MergeReport(report)


def merged_text(foon: Foon, header: str = "") -> str:
    """The FOON as FOON text with its provenance as ``#`` comment lines."""
    return _foon.merged_text(foon._native, header)


def load_merged(path: PathLike, *, strict: bool = False) -> Foon:
    """Read a FOON file, giving each unit the sources named by its provenance lines (a file
    without them loads as :meth:`foon.Foon.load` does)."""
    return _wrap(_foon.load_merged(path, strict=strict))


def parse_merged(text: str | bytes, *, strict: bool = False, path: PathLike | None = None) -> Foon:
    """As :func:`load_merged`, for text in memory."""
    return _wrap(_foon.parse_merged(text, strict=strict, path=path))


def provenance_lines(foon: Foon) -> str:
    """Where each unit came from, one line per unit: ``unit I: support N: path:line, ...``."""
    return _foon.provenance_text(foon._native)


__all__ = [
    "MergeReport",
    "load_merged",
    "merge",
    "merge_report",
    "merge_texts",
    "merged_text",
    "parse_merged",
    "provenance_lines",
]
