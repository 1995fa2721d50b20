"""Argument and result descriptions the docstrings share, written once: a docstring line that is
only ``@name`` (indented) becomes the entry ``SHARED[name]`` at that indentation (``@shared``)."""

from typing import Callable, TypeVar

SHARED = {
    "model": "model : Model, path or TOML text, optional\n"
    "    The body (the embedded larva when None).",
    "order": "order : int\n    Order of the expansion (1 to 32).",
    "points": "points : int\n    Points along the body.",
    "params": "params : mapping, optional\n"
    '    Scales or coefficients by name, as ``--param`` takes them (``{"omega_b": 2.0}``,\n'
    '    ``{"c_y": 4.0}`` for c = ω², ``{"cp1_x": 0.5}`` on a nonlinear body; defaults ω = 1,\n'
    "    ζ = 0.1).",
    "beyond_leading": "beyond_leading : int, optional\n"
    "    Orders kept beyond the leading one in both densities (the model's own without it).",
    "basis": 'basis : str\n    ``"powers"`` or ``"monomials"``.',
    "density": "density : str, optional\n"
    '    ``"lagrangian"``, ``"rayleigh"`` or ``"both"`` (the command\'s default without it).',
    "term_options": "options\n    The command's other options (``basis``, ``beyond_leading``).",
    "ax": "ax : matplotlib Axes, optional\n    Draw into these axes (a new figure when None).",
    "figure": "\nReturns\n-------\nmatplotlib.figure.Figure\n"
    "    The figure drawn into (``axes`` holds its panels).",
}

F = TypeVar("F", bound=Callable[..., object])


def shared(fn: F) -> F:
    """``fn`` with each ``@name`` line of its docstring replaced by ``SHARED[name]``."""
    lines = []
    for line in (fn.__doc__ or "").split("\n"):
        key = line.strip()
        if key.startswith("@") and key[1:] in SHARED:
            indent = line[: len(line) - len(line.lstrip())]
            lines += [indent + part for part in SHARED[key[1:]].split("\n")]
        else:
            lines.append(line)
    fn.__doc__ = "\n".join(lines)
    return fn
