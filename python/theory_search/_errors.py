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
    message = re.sub(r"'--([a-z][a-z-]*)(?: <[A-Z_]+>)?'", lambda m: m.group(1).replace("-", "_") + "=", message)
    # A flag named in the library's words (``--samples must be …``) is the keyword argument.
    return re.sub(r"(?<![\w'-])--([a-z][a-z0-9-]*)", lambda m: m.group(1).replace("-", "_"), message)


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


def shown(value: Any) -> str:
    """``value`` as an error quotes it: at most 80 characters, and an integer too long to print
    (Python refuses ``str`` of one over 4300 digits) by its number of digits."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 256:
        return f"a whole number of about {int(value.bit_length() * 0.30103) + 1} digits"
    try:
        text = repr(value) if isinstance(value, (str, bytes)) else str(value)
    except Exception:  # a str() that fails is no reason to fail differently
        text = f"a {type(value).__name__}"
    text = " ".join(text.split())  # an array's str spans lines
    return text if len(text) <= 80 else text[:77] + "…"


def count(name: str, value: Any, least: int = 0, most: int = 2**63 - 1) -> int:
    """A whole number argument, checked as the command line checks it."""
    if isinstance(value, bool):
        raise UsageError(f"{name} must be a whole number, not {value!r}")
    try:
        value = operator.index(value)  # int, numpy integers
    except TypeError:
        raise UsageError(f"{name} must be a whole number, not {shown(value)}") from None
    if not least <= value <= most:
        raise UsageError(f"{name} must be between {least} and {most}, not {shown(value)}")
    return value


def number(name: str, value: Any) -> float:
    """A real number argument, or a ``UsageError`` that quotes at most 80 characters of it."""
    if isinstance(value, bool):
        raise UsageError(f"{name} must be a number, not {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        raise UsageError(f"{name} must be a number, not {shown(value)}") from None


def positive(name: str, value: Any) -> float:
    """A finite number above zero (a rate, a step), or a ``UsageError``."""
    x = number(name, value)
    if not (x > 0 and x < float("inf")):
        raise UsageError(f"{name} must be a finite number above 0, not {shown(value)}")
    return x


def array(name: str, value: Any) -> Any:
    """``value`` as a numpy array of floats, or a ``UsageError`` saying what it holds."""
    import numpy as np

    if isinstance(value, (str, bytes, dict)) or value is None:
        raise UsageError(f"{name} must be an array of numbers, not {type(value).__name__}")
    try:
        return np.ascontiguousarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as e:
        raise UsageError(f"{name} must be an array of numbers: {shown_line(e)}") from None


def guarded(fn: F) -> F:
    """``fn`` whose every error is a ``TheorySearchError``: an argument of the wrong type or
    value that a conversion (numpy's, pyo3's, Python's own) refuses before the library sees
    it becomes a ``UsageError`` with its one-line message, bounded (docs/python.md)."""

    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except TheorySearchError:
            raise
        except (TypeError, ValueError, OverflowError, IndexError, KeyError, AttributeError) as e:
            raise UsageError(f"{fn.__name__}: {shown_line(e)}") from e

    return call  # type: ignore[return-value]


def shown_line(e: BaseException) -> str:
    """An exception's message on one line of at most 300 characters."""
    try:
        text = str(e)
    except Exception:
        text = type(e).__name__
    text = " ".join(text.split()) or type(e).__name__
    return text if len(text) <= 300 else text[:297] + "…"
