"""foon's exception classes, in one import place."""

from foon._foon import FoonError, GoalNotFoundError, MissingRateError, ParseError

__all__ = ["FoonError", "GoalNotFoundError", "MissingRateError", "ParseError"]
