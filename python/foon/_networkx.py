"""networkx graphs of FOONs and task trees (the optional extra ``pip install foon[networkx]``).

A graph is read from the core's GraphML (``write("graphml")``), so it has exactly the nodes,
edges and attributes of the GraphML file: the object-motion bipartite ``networkx.DiGraph``
with nodes ``o<object id>`` (``kind="object"``) and ``m<unit index>`` (``kind="motion"``),
edges input -> motion -> output, ``states`` and ``ingredients`` as JSON arrays of strings.
networkx is imported only when a graph is asked for.
"""

from __future__ import annotations

import importlib
from typing import Any

_MISSING = "{what} needs networkx, an optional extra: pip install 'foon[networkx]'"


def _module(what: str) -> Any:
    try:
        return importlib.import_module("networkx")
    except ImportError:
        raise ImportError(_MISSING.format(what=what), name="networkx") from None


def from_graphml(text: str, what: str) -> Any:
    """The ``networkx.DiGraph`` of one GraphML document of one graph (``what`` names the
    caller in the error raised when networkx is missing)."""
    return _module(what).parse_graphml(text)
