"""theory-search from Python: the symmetry engine, the modes and the fit, numpy in and out.

The functions wrap the Rust library (not the command-line binary): every command, with its
options as keyword arguments. Errors are ``TheorySearchError`` and the builtin Python code
catches: ``UsageError`` is a ``ValueError`` (bad arguments, settings or models), a missing file a
``FileNotFoundError`` (``MissingFileError``), ``InputError`` a ``ValueError`` (malformed data),
``OutputError`` an ``OSError``, ``NumericalError`` (a computation that failed on valid input)
an ``ArithmeticError``; each with the one-line message the command line prints.

>>> import theory_search as ts
>>> m = ts.modes(points=12, modes=3)
>>> m["y"].eigenvalues.shape
(3,)
"""

from __future__ import annotations

import copy
import json
import os
import warnings
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _formats, _native
from ._commands import (
    asymmetry,
    behave,
    count,
    figures,
    interactions,
    mathieu,
    parts,
    rules,
    stats,
)
from ._docs import shared
from ._errors import (
    InputError,
    MissingFileError,
    NumericalError,
    OutputError,
    TheorySearchError,
    UsageError,
    array as _array,
    count as _count,
    guarded as _guarded,
    number as _number,
    positive as _positive,
    translated as _translated,
)
from ._results import DiscoverResult, FieldModes, Modes, Result, Simulation

try:
    from importlib.metadata import PackageNotFoundError, version as _version

    try:
        __version__ = _version("theory-search")
    except PackageNotFoundError:  # run from a source tree without installing
        __version__ = "0.1.0"
except ImportError:  # pragma: no cover (Python < 3.8)
    __version__ = "0.1.0"

__all__ = [
    "__version__",
    "Model",
    "ModelLike",
    "Result",
    "Modes",
    "FieldModes",
    "FitResult",
    "DiscoverResult",
    "Simulation",
    "TheorySearchError",
    "UsageError",
    "InputError",
    "MissingFileError",
    "OutputError",
    "NumericalError",
    "table",
    "equations",
    "active",
    "operators",
    "modes",
    "simulate",
    "behave",
    "stats",
    "asymmetry",
    "mathieu",
    "interactions",
    "parts",
    "count",
    "rules",
    "figures",
    "fit",
    "discover",
    "compare",
]

# The library's limits (order, points), read from it rather than copied.
_LIMITS = _native.limits()

# Native calls raise the Python exceptions of `_errors`.
_native_call = {
    name: _translated(getattr(_native, name))
    for name in (
        "check_model",
        "table_json",
        "equations_json",
        "active_json",
        "operators",
        "modes",
        "simulate",
        "fit_arrays",
        "fit_paths",
        "discover_json",
        "compare_json",
    )
}


class Model:
    """A body: its fields, roles, boundaries and symmetry requirements (a model file)."""

    def __init__(self, toml: str) -> None:
        if not isinstance(toml, str):
            raise UsageError(f"a model is TOML text, not {type(toml).__name__}")
        name, fields = _native_call["check_model"](toml)
        self.toml = toml
        self.name = name
        self.fields = fields

    @classmethod
    def larva(cls) -> "Model":
        """The embedded Drosophila larva model.

        Returns
        -------
        Model
            With ``toml`` (the model file's text), ``name`` and ``fields`` (field ids).
        """
        return cls(_native.larva_toml())

    @classmethod
    def from_toml(cls, path_or_text: Union[str, os.PathLike]) -> "Model":
        """A model from a TOML file or from TOML text, validated.

        Parameters
        ----------
        path_or_text : str or path
            A path to a model file, or the file's text.

        Returns
        -------
        Model
            With ``toml`` (the model file's text), ``name`` and ``fields`` (field ids).
        """
        text = os.fspath(path_or_text) if isinstance(path_or_text, os.PathLike) else str(path_or_text)
        looks_like_path = "\n" not in text and "=" not in text and "[" not in text
        if isinstance(path_or_text, os.PathLike) or looks_like_path:
            shown = text if len(text) <= 80 else text[:77] + "…"
            if not os.path.exists(text):
                raise MissingFileError(f"cannot read {shown}: no such file")
            # As the command line: at most 1 MiB (a model of eight fields is a few kilobytes),
            # so /dev/zero or /dev/urandom is refused, not read without end.
            limit = _LIMITS["text_file"]
            try:
                with open(text, "rb") as f:
                    data = f.read(limit + 1)
            except OSError as e:
                raise InputError(f"cannot read {shown}: {e.strerror or e}") from None
            if len(data) > limit:
                raise InputError(f"{shown}: larger than {limit} bytes, not a model file")
            try:
                text = data.decode("utf-8")
            except UnicodeDecodeError:
                raise InputError(f"{shown}: not UTF-8 text, not a model file") from None
        return cls(text)

    def __repr__(self) -> str:
        return f"Model({self.name!r}, fields={self.fields!r})"


# What every `model=` argument takes: a Model, a model file's path or its TOML text.
ModelLike = Union[Model, str, "os.PathLike[str]", None]


def _toml(model: Optional[Union[Model, str]]) -> Optional[str]:
    if model is None:
        return None
    if isinstance(model, Model):
        return model.toml
    return Model.from_toml(model).toml


@shared
def table(
    order: int = 4,
    model: Optional[Union[Model, str]] = None,
    basis: str = "powers",
    density: str = "both",
) -> Dict[str, Any]:
    """Table 1 (and its Rayleigh twin): every candidate term and each requirement's verdict.

    Parameters
    ----------
    @order
    @model
    @basis
    density : str
        ``"lagrangian"``, ``"rayleigh"`` or ``"both"``.

    Returns
    -------
    Table
        A dict with ``order``, ``model`` and per density (``lagrangian``, ``rayleigh``) a dict
        of ``rows`` (one per candidate term: its orders, each rule's verdict in ``satisfies``,
        each rejection's reason in ``rejected``), ``survivors`` per field, ``densities`` and
        ``notes``. ``to_pandas()`` gives one row per term; Jupyter renders it as HTML.
    """
    _count("order", order, 1, _LIMITS["order"])
    doc = _native_call["table_json"](order, _toml(model), basis, density)
    for key in ("lagrangian", "rayleigh"):
        if key in doc:
            doc[key] = _Density(doc[key])
    return Table(doc)


class Table(dict):
    """Table 1 and its Rayleigh twin: a dict by density (``t["lagrangian"]["rows"]``), a
    DataFrame of every row by ``to_pandas()``, rendered as HTML in Jupyter."""

    def to_pandas(self):
        """Every row of every density, with a ``density`` column (needs pandas)."""
        import pandas as pd

        frames = []
        for key in ("lagrangian", "rayleigh"):
            if key in self:
                df = self[key].to_pandas()
                df.insert(0, "density", key)
                frames.append(df)
        return pd.concat(frames, ignore_index=True)

    def to_dict(self) -> Dict[str, Any]:
        """Plain data."""
        return json.loads(json.dumps(self))

    def _repr_html_(self) -> str:
        import html

        parts = []
        for key in ("lagrangian", "rayleigh"):
            if key not in self:
                continue
            rows = self[key]["rows"]
            columns = [c for c in ("term", "delta", "epsilon", "tau", "sigma") if rows and c in rows[0]]
            head = "".join(f"<th>{html.escape(c)}</th>" for c in columns + ["kept"])
            body = "".join(
                "<tr>"
                + "".join(f"<td>{html.escape(str(r.get(c, '')))}</td>" for c in columns)
                + f"<td>{'✓' if not r.get('rejected') else html.escape('; '.join(map(str, r['rejected'])) if isinstance(r['rejected'], list) else str(r['rejected']))}</td>"
                + "</tr>"
                for r in rows
            )
            parts.append(f"<h4>{key}</h4><table><tr>{head}</tr>{body}</table>")
        return "".join(parts)


class _Density(dict):
    """One density of :func:`table`: a dict, with the rows as a DataFrame on demand."""

    def to_pandas(self):
        """The rows as a pandas DataFrame (needs pandas)."""
        import pandas as pd

        return pd.json_normalize(self["rows"])


@shared
def equations(
    order: int = 4, model: Optional[Union[Model, str]] = None, basis: str = "powers"
) -> Dict[str, Any]:
    """The equations of motion, each term with its sign and the reason for it.

    Parameters
    ----------
    @order
    @model
    @basis

    Returns
    -------
    Result
        ``order``, ``equations`` (per field the right-hand side of ∂t²φ: each term's
        derivative orders, sign, coefficient, exact prefactor and sign claim; the exact
        nonlinear equation with ``"nonlinear": True`` where survivors are not all quadratic),
        ``notes``.
    """
    _count("order", order, 1, _LIMITS["order"])
    return Result(_native_call["equations_json"](order, _toml(model), basis))


@shared
def active(
    order: int = 4,
    model: Optional[Union[Model, str]] = None,
    beyond_leading: Optional[int] = None,
) -> Result:
    """The active forces a model's ``[active]`` section allows (``theory-search active``):
    force terms f of ∂t²φ = … + f that the symmetry requirements keep and that no Lagrangian
    or Rayleigh density gives. A model without an ``[active]`` section raises
    :class:`UsageError`.

    Parameters
    ----------
    @order
    @model
    @beyond_leading

    Returns
    -------
    Result
        ``model``, ``order``, ``fields``: per field its id, the candidates enumerated, the
        covariant ones and their counts by class (conservative, gyroscopic, dissipative,
        active), and the lowest-order active and gyroscopic forces, each with its term, class,
        parities under t → −t and s → −s (+1 even, −1 odd) and why it is in its class.
    """
    _count("order", order, 1, _LIMITS["order"])
    if beyond_leading is not None:
        _count("beyond_leading", beyond_leading, 0, _LIMITS["beyond_leading"])
    return Result(
        _native_call["active_json"](order, beyond_leading, _toml(model))
    )


@shared
def operators(
    points: int,
    order: int = 4,
    model: Optional[Union[Model, str]] = None,
    params: Optional[Mapping[str, float]] = None,
    beyond_leading: Optional[int] = None,
) -> List[Result]:
    """Every discretised operator on ``points`` points: exact integers for a linear body, the
    linearisation's matrices for a nonlinear one (as ``theory-search operators``).

    Parameters
    ----------
    @points
    @order
    @model
    @params
    @beyond_leading

    Returns
    -------
    list of Result
        A linear body: one per operator, ``field``, ``density``, ``term``, ``boundary``, ``k``
        and the ``matrix`` (numpy int64, points × points). A nonlinear body: one per field,
        ``field``, ``boundary``, ``equilibrium``, ``residual`` and the ``stiffness``,
        ``damping`` and ``mass`` matrices of its linearisation (``linearised`` is True).
    """
    _count("points", points, 1, _LIMITS["operator_points"])
    _count("order", order, 1, _LIMITS["order"])
    args = _body_args(order, beyond_leading, model, params)
    return [Result(d) for d in _native_call["operators"](points, *args)]


def _body_args(order: int, beyond_leading: Optional[int], model: Any, params: Any) -> tuple:
    """The native body arguments: order, beyond_leading, model text, params as floats."""
    if beyond_leading is not None:
        _count("beyond_leading", beyond_leading, 0, _LIMITS["beyond_leading"])
    if params is not None and not isinstance(params, Mapping):
        raise UsageError(f"params must be a mapping of names to numbers, not {type(params).__name__}")
    values = {}
    for name, value in (params or {}).items():
        values[str(name)] = _number(f"parameter {str(name)[:80]!r}", value)
    return (order, beyond_leading, _toml(model), values)


@shared
def modes(
    points: int,
    model: Optional[Union[Model, str]] = None,
    params: Optional[Mapping[str, float]] = None,
    shapes: bool = False,
    modes: Optional[int] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
    k: Optional[int] = None,
) -> Modes:
    """Each field's modes: eigenvalues and shapes of its discretised operator.

    Parameters
    ----------
    @points
    @model
    @params
    shapes : bool
        Compute the mode shapes now (otherwise the first read of a field's ``shapes``
        computes them, once, for every field).
    modes : int, optional
        Only this many lowest modes of each field (the command line's ``--modes``).
    @order
    @beyond_leading
    k : int, optional
        The old name of ``modes`` (deprecated: it warns).

    Returns
    -------
    Modes
        A mapping field id → ``FieldModes`` with ``eigenvalues``, ``frequencies``,
        ``damping_ratios``, ``variance_shares``, ``nullity``, ``omega``, ``zeta`` and
        ``shapes`` (points × modes: one mode per column, as ``numpy.linalg.eigh``);
        ``to_pandas()`` on each. Frequencies are in radians per unit of time (1/ω). A
        nonlinear body, or one whose damping is not modal, gives the modes of its
        linearisation (``linearised``, ``equilibrium``; frequencies NaN where an eigenvalue
        is negative: an unstable direction) and the roots λ = −σ ± iω of λ²M + λC + K as
        ``decay_rates`` σ and ``damped_frequencies`` ω.
    """
    _count("points", points, 1, _LIMITS["points"])
    _count("order", order, 1, _LIMITS["order"])
    if k is not None:
        # The old name, kept working: the command line says --modes.
        warnings.warn("modes(k=…) is now modes(modes=…), as the command line's --modes",
                      DeprecationWarning, stacklevel=2)
        if modes is None:
            modes = k
    if modes is not None:
        _count("modes", modes, 1)
    count = modes
    args = (points, *_body_args(order, beyond_leading, model, params))
    return Modes(
        _native_call["modes"](*args, shapes, count),
        load_shapes=lambda: _native_call["modes"](*args, True, count),
    )


def _assignments(values: Any) -> List[str]:
    """``{"y:2": (1.0, 0.0)}`` or ``["y:2=1,0"]`` as the command line's ``KEY=A[,B…]`` texts."""
    if values is None:
        return []
    if isinstance(values, Mapping):
        out = []
        for key, v in values.items():
            parts = v if isinstance(v, (list, tuple)) else [v]
            out.append(f"{key}=" + ",".join(repr(_number(str(key)[:80], x)) for x in parts))
        return out
    return [str(v) for v in values]


@shared
def simulate(
    points: int = 12,
    steps: int = 1000,
    dt: float = 0.01,
    every: int = 1,
    temperature: float = 0.0,
    seed: int = 1,
    model: Optional[Union[Model, str]] = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    initial: Any = None,
    force: Any = None,
    drive: Any = None,
    beyond_leading: Optional[int] = None,
) -> Simulation:
    """Integrate the equations of motion, with Langevin noise at ``temperature``.

    Parameters
    ----------
    @points
    steps : int
        Time steps.
    dt : float
        Step length (units of 1/ω).
    every : int
        Keep every ``every``-th step.
    temperature : float
        kT of the noise (0: none).
    seed : int
        Seed of the noise.
    @model
    @params
    @order
    @beyond_leading
    initial : mapping, optional
        ``{"y:2": (Q, V)}`` (a mode) or ``{"u": Q}`` (every point), as ``--initial``.
    force : mapping, optional
        ``{"y:2": F}``: a constant force on a mode, as ``--force``.
    drive : mapping, optional
        ``{"x:1": (F0, Ω[, φ])}``: a sinusoidal force on a mode, as ``--drive``.

    Returns
    -------
    Simulation
        A dict with attribute access: ``t`` (samples), ``energy`` (samples), ``positions``
        (field → samples × points) and ``modal`` (field → samples × modes; empty for a
        nonlinear body); ``to_pandas()`` gives the command line's CSV columns, ``to_dict()``.
    """
    _count("points", points, 1, _LIMITS["simulate_points"])
    _count("steps", steps, 1)
    _count("every", every, 1)
    _count("seed", seed, 0)
    _count("order", order, 1, _LIMITS["order"])
    start = (_assignments(initial), _assignments(force), _assignments(drive))
    body = _body_args(order, beyond_leading, model, params)
    return Simulation(
        _native_call["simulate"](
            points, steps, _number("dt", dt), every, _number("temperature", temperature), seed,
            *body, start,
        )
    )


class FitResult:
    """A fit: the report's numbers as attributes (lists become numpy arrays), the spectra,
    principal components and mode shapes as arrays, and :meth:`to_dict`."""

    def __init__(
        self, report: Dict[str, Any], frequencies, psd, components, shapes, figures=None
    ) -> None:
        self._report = report
        # The paths of the figures written (``fit(..., figures=DIR)``), else empty.
        self.figures: List[str] = list(figures or [])
        self.frequencies = frequencies
        self.psd = psd
        self.components = components
        # Points × modes, one mode per column (as `modes()` and `numpy.linalg.eigh`).
        self.shapes = np.asarray(shapes).T
        # Always present, empty when the report has none.
        self.warnings: List[str] = []
        self.animals: List[Dict[str, Any]] = []
        self.intervals: Optional[Dict[str, Any]] = None
        # With several animals: how much their constants differ (the JSON's ``spread``).
        self.spread: Optional[Dict[str, Any]] = None
        for key, value in report.items():
            if isinstance(value, list) and value and all(
                isinstance(v, (int, float)) or isinstance(v, list) for v in value
            ) and key not in ("modes", "animals", "subspace", "onward", "warnings"):
                value = np.asarray(value, dtype=float)
            setattr(self, key, value)

    def to_dict(self) -> Dict[str, Any]:
        """The report as plain data (the CLI's ``--format json``)."""
        return copy.deepcopy(self._report)

    def to_pandas(self):
        """One row per fitted mode (needs pandas)."""
        import pandas as pd

        return pd.json_normalize(self._report.get("modes") or [])

    def _repr_html_(self) -> str:
        """The notebook view: κ with its interval, each law's verdict, the modes, warnings."""
        import html

        esc = lambda v: html.escape(str(v))  # noqa: E731
        head = f"<p><b>{esc(repr(self))}</b></p>"
        c = self._report.get("continuum") or {}
        if c.get("constant") is not None:
            lo, hi = c.get("interval") or (None, None)
            span = f" [{lo:.6g}, {hi:.6g}] (95 %, {esc(c.get('interval_from', ''))})" if lo is not None else ""
            head += f"<p>κ = {c['constant']:.6g}{span} {esc(c.get('unit', ''))}</p>"
        laws = ""
        for law, t in (self._report.get("tests") or {}).items():
            lo, hi = t.get("interval") or (float("nan"), float("nan"))
            laws += (
                f"<tr><td>{esc(law)}</td><td>{t.get('exponent', float('nan')):.4g}</td>"
                f"<td>[{lo:.4g}, {hi:.4g}]</td><td>{t.get('expected', float('nan')):.4g}</td>"
                f"<td><b>{esc(t.get('verdict', ''))}</b></td><td>{esc(t.get('note', ''))}</td></tr>"
            )
        if laws:
            head += (
                "<table><tr><th>law</th><th>exponent</th><th>95 % interval</th>"
                f"<th>theory</th><th>verdict</th><th>note</th></tr>{laws}</table>"
            )
        try:
            table = self.to_pandas().to_html(max_rows=40)
        except ImportError:
            table = ""
        notes = "".join(f"<li>{esc(w)}</li>" for w in self.warnings)
        return head + table + (f"<ul>{notes}</ul>" if notes else "")

    def __repr__(self) -> str:
        return f"FitResult(frames={self._report['frames']}, omega={self._report['omega']:.6g}, beta={self._report['beta']:.6g})"


def _from_frame(frame: Any, t: Any) -> tuple:
    """A DataFrame in a recording's own layout (``t``, then ``x1, y1, …, xK, yK``, as
    ``pandas.read_csv`` gives it) as midlines (frames × K × 2) and times."""
    try:
        data = np.asarray(frame.to_numpy(dtype=float))
    except (TypeError, ValueError) as e:
        raise UsageError(f"a DataFrame of midlines holds numbers only: {e}") from None
    first = str(frame.columns[0]).strip().lower() if len(frame.columns) else ""
    if first in ("t", "time"):
        t = data[:, 0] if t is None else t
        data = data[:, 1:]
    if data.ndim != 2 or data.shape[1] < 4 or data.shape[1] % 2:
        raise UsageError(
            "a DataFrame of midlines has a t column, then x1, y1, …, xK, yK (two per point)"
        )
    return data.reshape(len(data), -1, 2), t


# The recording options fit, discover and compare share (the library's RecordingSettings).
_RECORDING = (
    "points", "kind", "field", "order", "ring", "fill_gaps", "head", "min_likelihood",
    "input_format", "track_column", "time_unit", "length_unit",
)
_PAGE = ("figures", "figure_format", "figure_width", "figure_dpi")


def _given(values: Mapping[str, Any], names: Sequence[str]) -> Dict[str, Any]:
    """The options among ``names`` a caller gave (not None): the library's defaults for the
    rest, and its checks for all."""
    return {n: values[n] for n in names if values[n] is not None}


def _tracker_arrays(
    data: Any,
    t: Any,
    fps: Optional[float],
    keypoints: Optional[Sequence[str]],
    individuals: Optional[Sequence[str]],
    options: Dict[str, Any],
) -> tuple:
    """A tracker's object (a ``movement`` dataset, a ``sleap_io.Labels``, a DeepLabCut
    DataFrame) or a DataFrame in a recording's layout as arrays, one per animal, and times;
    anything else as given. The format's own time unit is used unless ``time_unit`` is given."""
    if _formats.is_tracker_object(data):
        least = options.get("min_likelihood", _LIMITS["min_likelihood"])
        least = _number("min_likelihood", least)
        if fps is not None:
            fps = _positive("fps", fps)
        animals, times, stated = _formats.midlines(data, t, fps, keypoints, individuals, least)
        for key, value in stated.items():
            options.setdefault(key, value)
        return animals, times
    if keypoints is not None or individuals is not None:
        raise UsageError(
            "keypoints and individuals choose among a tracker's (movement, SLEAP, DeepLabCut) data"
        )
    if hasattr(data, "columns") and hasattr(data, "to_numpy"):
        return _from_frame(data, t)
    return data, t


def _is_paths(x: Any) -> bool:
    if isinstance(x, (str, os.PathLike)):
        return True
    return isinstance(x, (list, tuple)) and len(x) > 0 and all(
        isinstance(p, (str, os.PathLike)) for p in x
    )


def _arrays(midlines: Any, t: Any, fps: Optional[float]) -> tuple:
    """Animals' midlines (each frames × points × 2) and their frames' times, as float arrays:
    ``t`` when given (one array per animal), else frames ``1/fps`` apart."""
    animals = midlines if isinstance(midlines, (list, tuple)) else [midlines]
    if not animals:
        raise UsageError("midlines must be an array of frames × points × 2, not an empty list")
    animals = [_array("midlines", a) for a in animals]
    if any(a.ndim != 3 for a in animals):
        raise UsageError("midlines must be an array of frames × points × 2")
    if t is None:
        step = 1.0 / fps if fps else 1.0
        times = [np.arange(len(a), dtype=float) * step for a in animals]
    else:
        times = t if isinstance(t, (list, tuple)) else [t]
        times = [_array("t", x) for x in times]
        if any(x.ndim != 1 for x in times):
            raise UsageError("t must be one array of times per animal (one time per frame)")
    return animals, times


@shared
def fit(
    midlines: Any,
    t: Optional[Any] = None,
    fps: Optional[float] = None,
    model: Optional[Union[Model, str]] = None,
    keypoints: Optional[Sequence[str]] = None,
    individuals: Optional[Sequence[str]] = None,
    points: Optional[int] = None,
    kind: Optional[str] = None,
    field: Optional[str] = None,
    order: Optional[int] = None,
    ring: Optional[int] = None,
    fill_gaps: Optional[int] = None,
    head: Optional[str] = None,
    min_likelihood: Optional[float] = None,
    input_format: Optional[str] = None,
    track_column: Optional[bool] = None,
    time_unit: Optional[str] = None,
    length_unit: Optional[str] = None,
    window: Optional[int] = None,
    estimator: Optional[str] = None,
    fit_modes: Optional[int] = None,
    omega: Optional[float] = None,
    bootstrap: Optional[int] = None,
    seed: Optional[int] = None,
    figures: Optional[Union[str, os.PathLike]] = None,
    figure_format: Optional[str] = None,
    figure_width: Optional[float] = None,
    figure_dpi: Optional[float] = None,
) -> FitResult:
    """Fit the theory to tracked midlines.

    Parameters
    ----------
    midlines : array, list of arrays, DataFrame, tracker's object, path or list of paths
        A numpy array (frames × points × 2, NaN where the tracker lost a point), one per
        animal; a DataFrame in a recording's layout (``t``, ``x1``, ``y1``, …, as
        ``pandas.read_csv`` reads one); a ``movement`` poses dataset, a ``sleap_io.Labels``
        or a DeepLabCut DataFrame (``pandas.read_hdf`` of its ``.h5``, or ``read_csv`` with
        ``header=[0, 1, 2]``; multi-animal too), each individual one animal; or files, directories or patterns the ``fit`` command
        reads (CSV, DeepLabCut, WCON).
    t : array or list of arrays, optional
        The frames' times (one array per animal); without it frames are ``1/fps`` apart.
    fps : float, optional
        Frames per second (one time unit per frame without it or ``t``).
    @model
    @trackers
    @recording
    window : int, optional
        Welch window in frames (8 or more; default: chosen from the slowest mode).
    estimator : str, optional
        ``"peak"`` (default) or ``"centroid"``: how a mode's frequency is read off its line.
    fit_modes : int, optional
        How many modes to fit (default 10).
    omega : float, optional
        The time scale ω (radians per time unit) to fix instead of fitting it.
    bootstrap : int, optional
        Replicates of the block bootstrap behind the intervals.
    seed : int, optional
        Seed of the bootstrap.
    @figure_page

    Returns
    -------
    FitResult
        The report's numbers as attributes: ``omega``, ``beta``, ``frames``, ``modes``,
        ``modes_fit``, ``tests`` (each prediction's exponent, interval and verdict),
        ``warnings``, ``animals``, ``intervals`` (always present), ``spread`` (several animals:
        how much their constants differ, see docs/fit.md), ``pca_variance_share``,
        ``theory_variance_share``, ``mode_overlap``; the arrays ``frequencies`` (cycles per
        time unit of the recording), ``psd`` (modes × frequencies, Q² per cycle per time unit; row 0
        is the first non-zero mode, ``modes[0].index``: mode 2 of a free body), ``components``
        and ``shapes`` (points × modes); ``figures`` (the paths written, or empty);
        ``to_dict()``, ``to_pandas()``. ``omega`` and each ``modes_fit`` Ω are in radians per
        time unit; ``beta`` in time unit².
    """
    options = _given(locals(), _RECORDING + _PAGE + (
        "window", "estimator", "fit_modes", "omega", "bootstrap", "seed"))
    toml = _toml(model)
    midlines, t = _tracker_arrays(midlines, t, fps, keypoints, individuals, options)
    if "figures" in options and options["figures"] is not None:
        if not isinstance(options["figures"], (str, os.PathLike)):
            raise UsageError(f"figures must be a folder's path, not {type(options['figures']).__name__}")
        options["figures"] = os.fspath(options["figures"])
    # Whole-number options checked here, in words (pyo3 would say "can't convert negative int").
    for name in ("points", "window", "fit_modes", "fill_gaps", "bootstrap", "seed", "order"):
        if options.get(name) is not None:
            options[name] = _count(name, options[name], 0)
    if fps is not None:
        fps = _positive("fps", fps)
    if _is_paths(midlines):
        paths = [midlines] if isinstance(midlines, (str, os.PathLike)) else list(midlines)
        if fps is not None:
            options["fps"] = fps
        out = _native_call["fit_paths"]([os.fspath(p) for p in paths], toml, options)
    else:
        animals, times = _arrays(midlines, t, fps)
        out = _native_call["fit_arrays"](animals, times, toml, options)
    report, frequencies, psd, components, shapes, written = out
    return FitResult(report, frequencies, psd, components, shapes, written)


@shared
def discover(
    recordings: Any,
    model: Optional[Union[Model, str]] = None,
    t: Optional[Any] = None,
    fps: Optional[float] = None,
    keypoints: Optional[Sequence[str]] = None,
    individuals: Optional[Sequence[str]] = None,
    points: Optional[int] = None,
    kind: Optional[str] = None,
    field: Optional[str] = None,
    order: Optional[int] = None,
    ring: Optional[int] = None,
    fill_gaps: Optional[int] = None,
    head: Optional[str] = None,
    min_likelihood: Optional[float] = None,
    input_format: Optional[str] = None,
    track_column: Optional[bool] = None,
    time_unit: Optional[str] = None,
    length_unit: Optional[str] = None,
    active: Optional[bool] = None,
    beyond_leading: Optional[int] = None,
    estimator: Optional[str] = None,
    bootstrap: Optional[int] = None,
    seed: Optional[int] = None,
    figures: Optional[Union[str, os.PathLike]] = None,
    figure_format: Optional[str] = None,
    figure_width: Optional[float] = None,
    figure_dpi: Optional[float] = None,
) -> Result:
    """Which terms of the engine's library the recordings' field needs (``discover``).

    Parameters
    ----------
    recordings : path, list of paths, array, list of arrays, DataFrame or tracker's object
        Files, directories or patterns as ``fit`` reads them; or midlines as arrays (frames ×
        points × 2, head first, NaN where the tracker lost a point), one per animal; or a
        DataFrame in a recording's layout (``t``, ``x1``, ``y1``, …); or a ``movement``
        dataset, a ``sleap_io.Labels`` or a DeepLabCut DataFrame, each individual one animal.
    @model
    t : array or list of arrays, optional
        The arrays' frame times (without it frames are ``1/fps`` apart).
    fps : float, optional
        Frames per second of the arrays (one time unit per frame without it or ``t``), or of
        DeepLabCut files (refused for files with a time column).
    @trackers
    @recording
    active : bool, optional
        True puts the model's active forces in the library.
    @beyond_leading
    estimator : str, optional
        ``"auto"`` (default: the exact state-space likelihood wherever the library is linear,
        each mode's or, for forces that couple the modes, their joint one; the weak form for
        nonlinear forces), ``"weak"`` or ``"exact"``.
    bootstrap : int, optional
        Draws behind the inclusion frequencies and intervals (default 200).
    seed : int, optional
        Seed of the draws.
    @figure_page

    Returns
    -------
    Result
        ``equation``, ``selected`` and ``library`` (each term's ``term``, ``name``, ``kind``,
        ``coefficient`` in body lengths, ``on_points`` on the ``replay_points`` grid the
        onward line runs, ``interval``, ``inclusion``, ``selected``), ``comparison`` (each theory's ``model``, ``terms``, ``cv_residual``,
        ``criterion``), ``r2``, ``noise``, ``selection`` (the rule that chose the terms:
        ``median_probability``, ``elimination`` or ``no_model``), ``goodness`` (exact estimator:
        the modes' misfit ``j``, ``dof``, ``scale``, ``p``), ``verdict`` (``conclusion``:
        ``holds``, ``does_not_hold`` or ``undecided``, and its ``findings``), ``simulate`` (the
        onward command line, or ``None`` with ``onward_refused``),
        ``not_estimated`` (kinetic coefficients named but not regressed); for several
        recordings ``animals`` (each animal answered alone) and ``between`` (each pooled
        coefficient's spread between animals); with ``figures`` (a
        folder) also ``figures`` (the paths written) and ``replay`` (observed and simulated
        spectra and variances).
    """
    options = _given(locals(), _RECORDING + _PAGE + (
        "active", "beyond_leading", "estimator", "bootstrap", "seed"))
    # A model file is named as itself in the onward `simulate` line.
    model_path = None
    if isinstance(model, (str, os.PathLike)) and os.path.isfile(model):
        model_path = os.fspath(model)
    toml = _toml(model)
    if fps is not None:
        fps = _positive("fps", fps)
    recordings, t = _tracker_arrays(recordings, t, fps, keypoints, individuals, options)
    if "figures" in options and options["figures"] is not None:
        options["figures"] = os.fspath(options["figures"])
    paths: List[str] = []
    animals: List[Any] = []
    times: List[Any] = []
    if _is_paths(recordings):
        items = [recordings] if isinstance(recordings, (str, os.PathLike)) else recordings
        paths = [os.fspath(p) for p in items]
        if fps is not None:
            options["fps"] = fps
    else:
        animals, times = _arrays(recordings, t, fps)
    report, written = _native_call["discover_json"](
        paths, animals, times, toml, model_path, options
    )
    doc = report
    if options.get("figures") is not None:
        doc["figures"] = written
    return DiscoverResult(doc)


@shared
def compare(
    first: Any,
    second: Any,
    model: Optional[Union[Model, str]] = None,
    fps: Optional[float] = None,
    points: Optional[int] = None,
    kind: Optional[str] = None,
    field: Optional[str] = None,
    order: Optional[int] = None,
    ring: Optional[int] = None,
    fill_gaps: Optional[int] = None,
    head: Optional[str] = None,
    min_likelihood: Optional[float] = None,
    input_format: Optional[str] = None,
    track_column: Optional[bool] = None,
    time_unit: Optional[str] = None,
    length_unit: Optional[str] = None,
    permutations: Optional[int] = None,
    seed: Optional[int] = None,
    discover: Optional[bool] = None,
    figures: Optional[Union[str, os.PathLike]] = None,
    figure_format: Optional[str] = None,
    figure_width: Optional[float] = None,
    figure_dpi: Optional[float] = None,
) -> Result:
    """Two groups of animals compared (``compare``): each animal fitted alone.

    Parameters
    ----------
    first : path, list of paths, array, list of arrays, or tracker's object
        The first group's animals: files, directories or patterns (each file one animal), or
        midlines as arrays (frames × points × 2, each one animal; frames ``1/fps`` apart), or a
        ``movement`` dataset, ``sleap_io.Labels`` or DeepLabCut DataFrame (each individual one
        animal).
    second : path, list of paths, array, list of arrays, or tracker's object
        The second group's, in any of the same forms. Differences are the second group's mean less
        the first's.
    @model
    fps : float, optional
        Frames per second of arrays and DeepLabCut data (their rows are frames, not times).
    @recording
    permutations : int, optional
        Permutations behind the p-values (default 9999).
    seed : int, optional
        Seed of the permutations.
    discover : bool, optional
        Also discover each animal's equation and compare its coefficients (a term an animal's
        selection left out counts as 0).
    @figure_page

    Returns
    -------
    Result
        ``groups`` (each group's ``name``, ``animals`` and per law the animals ``consistent``,
        ``rejected``, ``undetermined``), ``differences`` (per quantity: ``kappa`` and each
        compared mode's ``Omega_<mode>`` and ``zeta_<mode>``, the groups' ``means``, the
        ``estimate``, Welch's 95 % ``interval``, the ``ratio`` and the permutation ``p``),
        ``animals`` (one row per animal and quantity), ``excluded`` (animals whose fit failed,
        with ``why``), ``modes``; each difference also has each group's ``group_intervals``;
        with ``figures`` (a folder) also ``figures`` (the path written).
    """
    options = _given(locals(), _RECORDING + _PAGE + ("permutations", "seed", "discover"))
    if options.get("figures") is not None:
        options["figures"] = os.fspath(options["figures"])
    if fps is not None:
        fps = _positive("fps", fps)
    toml = _toml(model)
    groups, names = [], []
    for group in (first, second):
        if _is_paths(group):
            items = [group] if isinstance(group, (str, os.PathLike)) else list(group)
            paths = [os.fspath(p) for p in items]
            groups.append((paths, [], []))
            names.append(", ".join(paths))
            if fps is not None:
                options["fps"] = fps  # DeepLabCut files' rows are frames
            continue
        # Arrays, a DataFrame or a tracker's object: each animal (individual) its own.
        data, t = _tracker_arrays(group, None, fps, None, None, options)
        if data is None or isinstance(data, (str, bytes, dict)):
            raise UsageError("compare takes each group as paths, arrays or a tracker's object")
        animals, times = _arrays(data, t, fps)
        groups.append(([], animals, times))
        names.append(f"{len(animals)} array(s)")
    if names[0] == names[1]:
        names = [f"first ({names[0]})", f"second ({names[1]})"]
    doc, written = _native_call["compare_json"](groups[0], groups[1], tuple(names), toml, options)
    if written:
        doc["figures"] = written
    return Result(doc)


# Every public function's errors are TheorySearchError (docs/python.md): an argument that a
# conversion (numpy's, pyo3's, Python's) refuses before the library sees it is a UsageError.
for _name in (
    "table", "equations", "active", "operators", "modes", "simulate", "fit", "discover",
    "behave", "stats", "asymmetry", "mathieu", "interactions", "parts", "count",
    "rules", "figures", "compare",
):
    globals()[_name] = _guarded(globals()[_name])
del _name
Model.from_toml = classmethod(_guarded(Model.from_toml.__func__))  # type: ignore[method-assign]
