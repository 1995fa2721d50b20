"""theory-search from Python: the symmetry engine, the modes and the fit, numpy in and out.

The functions wrap the Rust library (not the command-line binary): every command, with its
options as keyword arguments. Errors are ``TheorySearchError`` and the builtin Python code
catches: ``UsageError`` is a ``ValueError`` (bad arguments, settings or models), a missing file a
``FileNotFoundError`` (``MissingFileError``), ``InputError`` a ``ValueError`` (malformed data),
``OutputError`` an ``OSError``; each with the one-line message the command line prints.

>>> import theory_search as ts
>>> m = ts.modes(points=12, k=3)
>>> m["y"].eigenvalues.shape
(3,)
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._commands import (
    asymmetry,
    behave,
    count,
    figures,
    interactions,
    mathieu,
    parts,
    rules,
    run,
    stats,
)
from ._docs import shared
from ._errors import (
    InputError,
    MissingFileError,
    OutputError,
    TheorySearchError,
    UsageError,
    count as _count,
    translated as _translated,
)
from ._results import FieldModes, Modes, Result, Simulation

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
    "Simulation",
    "TheorySearchError",
    "UsageError",
    "InputError",
    "MissingFileError",
    "OutputError",
    "table",
    "equations",
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
    "run",
]

# Native calls raise the Python exceptions of `_errors`.
_native_call = {
    name: _translated(getattr(_native, name))
    for name in (
        "check_model",
        "table_json",
        "equations_json",
        "operators",
        "modes",
        "simulate",
        "fit_arrays",
        "fit_paths",
        "is_quadratic",
    )
}


class Model:
    """A body: its fields, roles, boundaries and symmetry requirements (a model file)."""

    def __init__(self, toml: str) -> None:
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
            if not os.path.exists(text):
                raise MissingFileError(f"cannot read {text}: no such file")
            with open(text, encoding="utf-8") as f:
                text = f.read()
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
    _count("order", order, 1, 32)
    doc = json.loads(_native_call["table_json"](order, _toml(model), basis, density))
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
    _count("order", order, 1, 32)
    return Result(json.loads(_native_call["equations_json"](order, _toml(model), basis)))


@shared
def operators(
    points: int, order: int = 4, model: Optional[Union[Model, str]] = None
) -> List[Result]:
    """Every discretised operator on ``points`` points, as exact integers.

    Parameters
    ----------
    @points
    @order
    @model

    Returns
    -------
    list of Result
        One per operator: ``field``, ``density``, ``term``, ``boundary``, ``k`` and the
        ``matrix`` (numpy int64, points × points); ``to_dict()``.
    """
    _count("points", points, 1, 2000)
    _count("order", order, 1, 32)
    return [Result(d) for d in _native_call["operators"](points, order, _toml(model))]


@shared
def modes(
    points: int,
    model: Optional[Union[Model, str]] = None,
    params: Optional[Mapping[str, float]] = None,
    shapes: bool = False,
    k: Optional[int] = None,
    order: int = 4,
) -> Modes:
    """Each field's modes: eigenvalues and shapes of its discretised operator.

    Parameters
    ----------
    @points
    @model
    params : mapping, optional
        ``omega_<scale>`` and ``zeta_<scale>`` (defaults ω = 1, ζ = 0.1).
    shapes : bool
        Compute the mode shapes now (otherwise the first read of a field's ``shapes``
        computes them, once, for every field).
    k : int, optional
        Only the ``k`` lowest modes of each field.
    @order

    Returns
    -------
    Modes
        A mapping field id → ``FieldModes`` with ``eigenvalues``, ``frequencies``,
        ``damping_ratios``, ``variance_shares``, ``nullity``, ``omega``, ``zeta`` and
        ``shapes`` (points × modes: one mode per column, as ``numpy.linalg.eigh``);
        ``to_pandas()`` on each.
    """
    _count("points", points, 1, 10_000_000)
    _count("order", order, 1, 32)
    if k is not None:
        _count("k", k, 1)
    args = (points, order, _toml(model), dict(params or {}))
    return Modes(
        _native_call["modes"](*args, shapes, k),
        load_shapes=lambda: _native_call["modes"](*args, True, k),
    )


def _assignments(values: Any) -> List[str]:
    """``{"y:2": (1.0, 0.0)}`` or ``["y:2=1,0"]`` as the command line's ``KEY=A[,B…]`` texts."""
    if values is None:
        return []
    if isinstance(values, Mapping):
        out = []
        for key, v in values.items():
            parts = v if isinstance(v, (list, tuple)) else [v]
            out.append(f"{key}=" + ",".join(repr(float(x)) for x in parts))
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
    params : mapping, optional
        Scales (``omega_<scale>``, ``zeta_<scale>``) or the coefficients ``equations`` prints.
    @order
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
    _count("points", points, 1, 2000)
    _count("steps", steps, 1)
    _count("every", every, 1)
    _count("seed", seed, 0)
    _count("order", order, 1, 32)
    simple = initial is None and force is None and drive is None and not (
        params and any(not k.startswith(("omega_", "zeta_")) for k in params)
    )
    if simple and _native_call["is_quadratic"](order, _toml(model)):
        return Simulation(
            _native_call["simulate"](
                points, steps, dt, every, temperature, seed, order, _toml(model), dict(params or {})
            )
        )
    doc = run(
        ["simulate"],
        model,
        params,
        points=points,
        steps=steps,
        dt=dt,
        every=every,
        temperature=temperature,
        seed=seed,
        order=order,
        initial=_assignments(initial),
        force=_assignments(force),
        drive=_assignments(drive),
    )
    columns, rows = doc["columns"], np.asarray(doc["rows"], dtype=float).reshape(-1, len(doc["columns"]))
    fields = (model if isinstance(model, Model) else Model.from_toml(model) if model else Model.larva()).fields
    out: Dict[str, Any] = {"t": rows[:, 0], "energy": rows[:, 1], "positions": {}, "modal": {}}
    for f in fields:
        pos = [i for i, c in enumerate(columns) if c.rsplit("_", 1)[0] == f and c.rsplit("_", 1)[1].isdigit()]
        mod = [i for i, c in enumerate(columns) if c.startswith(f"q_{f}_") and c[len(f) + 3:].isdigit()]
        out["positions"][f] = rows[:, pos]
        out["modal"][f] = rows[:, mod]
    return Simulation(out)


class FitResult:
    """A fit: the report's numbers as attributes (lists become numpy arrays), the spectra,
    principal components and mode shapes as arrays, and :meth:`to_dict`."""

    def __init__(self, report: Dict[str, Any], frequencies, psd, components, shapes) -> None:
        self._report = report
        self.frequencies = frequencies
        self.psd = psd
        self.components = components
        # Points × modes, one mode per column (as `modes()` and `numpy.linalg.eigh`).
        self.shapes = np.asarray(shapes).T
        # Always present, empty when the report has none.
        self.warnings: List[str] = []
        self.animals: List[Dict[str, Any]] = []
        self.intervals: Optional[Dict[str, Any]] = None
        for key, value in report.items():
            if isinstance(value, list) and value and all(
                isinstance(v, (int, float)) or isinstance(v, list) for v in value
            ) and key not in ("modes", "animals", "subspace", "onward", "warnings"):
                value = np.asarray(value, dtype=float)
            setattr(self, key, value)

    def to_dict(self) -> Dict[str, Any]:
        """The report as plain data (the CLI's ``--format json``)."""
        return json.loads(json.dumps(self._report))

    def to_pandas(self):
        """One row per fitted mode (needs pandas)."""
        import pandas as pd

        return pd.json_normalize(self._report.get("modes") or [])

    def _repr_html_(self) -> str:
        import html

        head = html.escape(repr(self))
        try:
            table = self.to_pandas().to_html(max_rows=40)
        except ImportError:
            table = ""
        notes = "".join(f"<li>{html.escape(str(w))}</li>" for w in self.warnings)
        return f"<p><b>{head}</b></p>{table}" + (f"<ul>{notes}</ul>" if notes else "")

    def __repr__(self) -> str:
        return f"FitResult(frames={self._report['frames']}, omega={self._report['omega']:.6g}, beta={self._report['beta']:.6g})"


def _is_paths(x: Any) -> bool:
    if isinstance(x, (str, os.PathLike)):
        return True
    return isinstance(x, (list, tuple)) and len(x) > 0 and all(
        isinstance(p, (str, os.PathLike)) for p in x
    )


@shared
def fit(
    midlines: Any,
    t: Optional[Any] = None,
    fps: Optional[float] = None,
    model: Optional[Union[Model, str]] = None,
    **options: Any,
) -> FitResult:
    """Fit the theory to tracked midlines.

    Parameters
    ----------
    midlines : array, list of arrays, path or list of paths
        A numpy array (frames × points × 2, NaN where the tracker lost a point), one per
        animal, or files the ``fit`` command reads (CSV, DeepLabCut, WCON).
    t : array or list of arrays, optional
        The frames' times (one array per animal); without it frames are ``1/fps`` apart.
    fps : float, optional
        Frames per second (one time unit per frame without it or ``t``).
    @model
    options
        The command's: ``points``, ``window``, ``fit_modes``, ``omega``, ``fill_gaps``,
        ``head`` ("first"/"last"), ``bootstrap``, ``seed``, ``time_unit``, ``length_unit``,
        ``kind``, ``field``, ``order``, ``min_likelihood``, ``track_column``.

    Returns
    -------
    FitResult
        The report's numbers as attributes: ``omega``, ``beta``, ``frames``, ``modes``,
        ``modes_fit``, ``tests`` (each prediction's exponent, interval and verdict),
        ``warnings``, ``animals``, ``intervals`` (always present), ``pca_variance_share``,
        ``theory_variance_share``, ``mode_overlap``; the arrays ``frequencies``, ``psd``
        (modes × frequencies), ``components`` and ``shapes`` (points × modes); ``to_dict()``,
        ``to_pandas()``.
    """
    toml = _toml(model)
    if _is_paths(midlines):
        paths = [midlines] if isinstance(midlines, (str, os.PathLike)) else list(midlines)
        if fps is not None:
            options["fps"] = fps
        out = _native_call["fit_paths"]([os.fspath(p) for p in paths], toml, options)
    else:
        animals = midlines if isinstance(midlines, (list, tuple)) else [midlines]
        animals = [np.ascontiguousarray(a, dtype=float) for a in animals]
        if any(a.ndim != 3 for a in animals):
            raise UsageError("midlines must be an array of frames × points × 2")
        if t is None:
            step = 1.0 / fps if fps else 1.0
            times = [np.arange(len(a), dtype=float) * step for a in animals]
        else:
            times = t if isinstance(t, (list, tuple)) else [t]
            times = [np.ascontiguousarray(x, dtype=float) for x in times]
        out = _native_call["fit_arrays"](animals, times, toml, options)
    report, frequencies, psd, components, shapes = out
    return FitResult(json.loads(report), frequencies, psd, components, shapes)
