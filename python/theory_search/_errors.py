"""The exceptions of theory_search: each a ``TheorySearchError`` and the builtin Python code
catches for its kind, with the command line's one-line message."""

from __future__ import annotations

import functools
import re
import operator
from typing import Any, Callable, Tuple, Type, TypeVar

from . import _native


class TheorySearchError(Exception):
    """Any error of theory-search (a one-line message)."""


class UsageError(TheorySearchError, ValueError):
    """A bad argument, setting or model (the command line's exit code 2)."""


class InputError(TheorySearchError, ValueError):
    """Unreadable or malformed data (the command line's exit code 1)."""


class MissingFileError(TheorySearchError, FileNotFoundError):
    """A file that does not exist."""


class OutputError(TheorySearchError, OSError):
    """Output that cannot be written."""


class NumericalError(TheorySearchError, ArithmeticError):
    """A computation that failed on valid input: no convergence, no equilibrium, overflow (the
    command line's exit code 3)."""


# Each native exception and the Python one it becomes (most specific first).
_KINDS: Tuple[Tuple[Type[BaseException], Type[BaseException]], ...] = (
    (_native.UsageError, UsageError),
    (_native.MissingError, MissingFileError),
    (_native.OutputError, OutputError),
    (_native.NumericalError, NumericalError),
    (_native.InputError, InputError),
    (_native.TheorySearchError, TheorySearchError),
)

F = TypeVar("F", bound=Callable[..., Any])


def _pythonic(message: str) -> str:
    """The command line's message in a Python user's words: no ``--help`` to see, ranges as
    words, options as keyword arguments."""
    message = message.replace(" (see --help)", "")
    message = re.sub(r"(-?\d+) is not in (-?\d+)\.\.=(-?\d+)", r"\1 is not between \2 and \3", message)
    return re.sub(r"'--([a-z][a-z-]*)(?: <[A-Z_]+>)?'", lambda m: m.group(1).replace("-", "_") + "=", message)


def translated(fn: F) -> F:
    """``fn`` with the native exceptions raised as the Python ones above."""

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except _native.TheorySearchError as e:
            for native, python in _KINDS:
                if isinstance(e, native):
                    raise python(_pythonic(str(e))) from None
            raise

    return call  # type: ignore[return-value]


def count(name: str, value: Any, least: int = 0, most: int = 2**63 - 1) -> int:
    """A whole number argument, checked as the command line checks it."""
    if isinstance(value, bool):
        raise UsageError(f"{name} must be a whole number, not {value!r}")
    try:
        value = operator.index(value)  # int, numpy integers
    except TypeError:
        raise UsageError(f"{name} must be a whole number, not {str(value)[:80]!r}") from None
    if not least <= value <= most:
        raise UsageError(f"{name} must be between {least} and {most}, not {value}")
    return value


def number(name: str, value: Any) -> float:
    """A real number argument, or a ``UsageError`` that quotes at most 80 characters of it."""
    if isinstance(value, bool):
        raise UsageError(f"{name} must be a number, not {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        shown = str(value)
        shown = shown if len(shown) <= 80 else shown[:77] + "…"
        raise UsageError(f"{name} must be a number, not {shown!r}") from None
