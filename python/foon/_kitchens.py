"""Named kitchens for batches of queries: :class:`KitchenSet`.

A handle on the core's kitchen set; the formats it reads are in ``docs/BATCH.md``
("Formats")."""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from typing import TYPE_CHECKING, Any

from foon import Kitchen, _as_kitchen, _foon, _kitchen, _type

if TYPE_CHECKING:
    from foon import KitchenLike, ObjectLike, PathLike


class KitchenSet:
    """Named kitchens, in the order they were given (ids unique).

    Built from a mapping of id to kitchen, read from a file or folder
    (:meth:`load`), or made from one base kitchen with per-id additions and removals
    (:meth:`with_deltas`). It pickles by its compact bytes; its ``fingerprint`` names the
    ids and kitchens on any machine."""

    __slots__ = ("_native",)

    _native: _foon.KitchenSet

    def __init__(self, mapping: Mapping[str, KitchenLike]) -> None:
        if not isinstance(mapping, Mapping):
            raise TypeError(f"kitchens must be a mapping of id to kitchen, not {_type(mapping)}")
        pairs = []
        for k, v in mapping.items():
            if not isinstance(k, str):
                raise TypeError(f"kitchen ids must be str, not {_type(k)}")
            pairs.append((k, _as_kitchen(v)._native))
        self._native = _foon.KitchenSet(pairs)

    @classmethod
    def load(cls, path: PathLike) -> KitchenSet:
        """From a JSON object of id to items, a JSON object with a base and per-id deltas,
        or a folder of kitchen files (id: the file name without its extension)."""
        return _kitchen_set(_foon.KitchenSet.load(path))

    @classmethod
    def from_text(cls, text: str | bytes) -> KitchenSet:
        """From the JSON text of a kitchen set (a base given as a path is relative to the
        current folder)."""
        return _kitchen_set(_foon.KitchenSet.parse(text))

    @classmethod
    def with_deltas(
        cls,
        base: KitchenLike,
        deltas: Mapping[str, tuple[Iterable[ObjectLike], Iterable[ObjectLike]]],
    ) -> KitchenSet:
        """Kitchens made from ``base``: for each id, the base without the items of its
        removals, then its additions (``deltas[id] = (add, remove)``)."""
        if not isinstance(deltas, Mapping):
            raise TypeError(f"deltas must be a mapping of id to (add, remove), not {_type(deltas)}")
        b = _as_kitchen(base)
        items = []
        for k, pair in deltas.items():
            if not isinstance(k, str):
                raise TypeError(f"kitchen ids must be str, not {_type(k)}")
            if not isinstance(pair, tuple) or len(pair) != 2:
                raise TypeError(f"deltas[{k!r}] must be a pair (add, remove), not {_type(pair)}")
            add, remove = pair
            items.append((k, _as_kitchen(add)._native, _as_kitchen(remove)._native))
        return _kitchen_set(_foon.KitchenSet.with_deltas(b._native, items))

    @property
    def ids(self) -> list[str]:
        """The ids, in order."""
        return self._native.ids

    @property
    def fingerprint(self) -> str:
        """32 hex digits naming the ids and kitchens, in order, the same on every machine."""
        return self._native.fingerprint

    def is_delta(self, id: str) -> bool:
        """Whether the kitchen of ``id`` was given as a base plus a delta."""
        return self._native.is_delta(id)

    def __len__(self) -> int:
        return len(self._native)

    def __iter__(self) -> Iterator[str]:
        return iter(self._native.ids)

    def __contains__(self, id: object) -> bool:
        return isinstance(id, str) and id in self._native

    def __getitem__(self, id: str) -> Kitchen:
        if not isinstance(id, str):
            raise TypeError(f"kitchen ids are str, not {_type(id)}")
        return _kitchen(self._native.get(id))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, KitchenSet) and self.fingerprint == other.fingerprint

    def __hash__(self) -> int:
        return hash(self.fingerprint)

    def to_bytes(self) -> bytes:
        """The set's compact, platform-independent bytes."""
        return self._native.to_bytes()

    @classmethod
    def from_bytes(cls, data: bytes) -> KitchenSet:
        """A set from :meth:`to_bytes` (anything else is a ``ValueError``)."""
        return _kitchen_set(_foon.KitchenSet.from_bytes(data))

    def __reduce__(self) -> tuple[Any, ...]:
        return (_kitchen_set_of_bytes, (self._native.to_bytes(),))

    def __repr__(self) -> str:
        n = len(self)
        return f"KitchenSet({n} kitchen{'' if n == 1 else 's'})"


def _kitchen_set(native: _foon.KitchenSet) -> KitchenSet:
    s = KitchenSet.__new__(KitchenSet)
    s._native = native
    return s


def _kitchen_set_of_bytes(data: bytes) -> KitchenSet:
    """A pickled kitchen set, from its bytes."""
    return _kitchen_set(_foon.KitchenSet.from_bytes(data))
