"""When to draw a progress bar: the core counts, the bindings draw (on stderr, by indicatif),
and this one rule says whether they may."""

from __future__ import annotations

import os
import sys


def wanted(quiet: bool = False) -> bool:
    """A bar is drawn only on a terminal: never with ``-q``, in CI (``CI`` set), with
    ``TERM=dumb``, or when stderr is not a terminal (piped, redirected, closed)."""
    if quiet or os.environ.get("CI") or os.environ.get("TERM") == "dumb":
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False
