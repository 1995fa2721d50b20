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
    "trackers": "keypoints : sequence of str, optional\n"
    "    A tracker's keypoints (nodes, body parts) along the body, head first (default: all,\n"
    "    in the tracker's order).\n"
    "individuals : sequence of str, optional\n"
    "    Which of a tracker's individuals (tracks) to take, each one animal (default: all).",
    "recording": "points : int, optional\n"
    "    Model points N the midlines are projected on (default 12; fewer tracked points are\n"
    "    interpolated, with a warning).\n"
    "kind : str, optional\n"
    '    ``\"midline\"`` (default) or ``\"lengths\"`` (segment lengths, the axial field).\n'
    "field : str, optional\n"
    "    The model's field the data observe (default: the lateral field, or the axial one for\n"
    "    lengths).\n"
    "order : int, optional\n"
    "    Order of the theory whose operator the data are projected on (default 4).\n"
    "ring : int, optional\n"
    "    Lengths only: segments around the whole body when only the first K were measured.\n"
    "fill_gaps : int, optional\n"
    "    Gaps of at most this many lost frames are bridged linearly; longer ones split runs.\n"
    "head : str, optional\n"
    '    ``\"first\"`` (default: the data list the head first) or ``\"last\"``.\n'
    "min_likelihood : float, optional\n"
    "    DeepLabCut points tracked below this likelihood (0 to 1) count as lost.\n"
    "input_format : str, optional\n"
    '    ``\"auto\"`` (default), ``\"csv\"``, ``\"wcon\"`` or ``\"hdf5\"`` (SLEAP analysis, DeepLabCut .h5).\n'
    "track_column : bool, optional\n"
    "    The first CSV column is a track id: each track is one animal.\n"
    "time_unit : str, optional\n"
    "    The recordings' time unit, as reports print it (``\"s\"``; overrides a WCON file's).\n"
    "length_unit : str, optional\n"
    "    The recordings' length unit (``\"mm\"``; overrides a WCON file's).",
    "figure_page": "figures : str or path, optional\n"
    "    A folder: the figures are written there.\n"
    "figure_format : str, optional\n"
    '    ``\"svg\"`` (default), ``\"png\"`` or ``\"pdf\"`` (needs ``figures``).\n'
    "figure_width : float, optional\n"
    "    Printed width in millimetres (default 180; needs ``figures``).\n"
    "figure_dpi : float, optional\n"
    "    Resolution of a PNG in dots per inch (default 300; needs ``figures``).",
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
