"""foon's exception classes, in one import place."""

from foon._foon import FoonError, GoalNotFoundError, MissingRateError, OutputError, ParseError

__all__ = ["FoonError", "GoalNotFoundError", "MissingRateError", "OutputError", "ParseError"]
