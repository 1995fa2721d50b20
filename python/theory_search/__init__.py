"""theory-search from Python: the symmetry engine, the modes and the fit, numpy in and out.

The functions wrap the Rust library (not the command-line binary). Errors are raised as
``TheorySearchError`` (``UsageError`` for bad arguments, settings or models, ``InputError`` for
unreadable data) with the same one-line messages the command line prints.

>>> import theory_search as ts
>>> m = ts.modes(points=12, k=3)
>>> m[2]["field"], m[2]["eigenvalues"].shape
('y', (3,))
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._native import InputError, TheorySearchError, UsageError

__all__ = [
    "Model",
    "FitResult",
    "TheorySearchError",
    "UsageError",
    "InputError",
    "table",
    "equations",
    "operators",
    "modes",
    "simulate",
    "fit",
]


class Model:
    """A body: its fields, roles, boundaries and symmetry requirements (a model file)."""

    def __init__(self, toml: str) -> None:
        name, fields = _native.check_model(toml)
        self.toml = toml
        self.name = name
        self.fields = fields

    @classmethod
    def larva(cls) -> "Model":
        """The embedded Drosophila larva model."""
        return cls(_native.larva_toml())

    @classmethod
    def from_toml(cls, path_or_text: Union[str, os.PathLike]) -> "Model":
        """A model from a TOML file path or from TOML text."""
        text = str(path_or_text)
        if "\n" not in text and os.path.exists(text):
            with open(text, encoding="utf-8") as f:
                text = f.read()
        return cls(text)

    def __repr__(self) -> str:
        return f"Model({self.name!r}, fields={self.fields!r})"


def _toml(model: Optional[Union[Model, str]]) -> Optional[str]:
    if model is None:
        return None
    if isinstance(model, Model):
        return model.toml
    return Model.from_toml(model).toml


def table(
    order: int = 4,
    model: Optional[Union[Model, str]] = None,
    basis: str = "powers",
    density: str = "both",
) -> Dict[str, Any]:
    """Table 1 (and its Rayleigh twin): per density, ``rows`` (one dict per candidate term with
    its orders, each rule's verdict in ``satisfies`` and the reason of each rejection in
    ``rejected``), ``survivors`` per field, ``densities`` and ``notes``. Each density's dict has
    ``to_pandas()`` when pandas is installed."""
    doc = json.loads(_native.table_json(order, _toml(model), basis, density))
    for key in ("lagrangian", "rayleigh"):
        if key in doc:
            doc[key] = _Density(doc[key])
    return doc


class _Density(dict):
    """One density of :func:`table`: a dict, with the rows as a DataFrame on demand."""

    def to_pandas(self):
        """The rows as a pandas DataFrame (needs pandas)."""
        import pandas as pd

        return pd.json_normalize(self["rows"])


def equations(
    order: int = 4, model: Optional[Union[Model, str]] = None, basis: str = "powers"
) -> Dict[str, Any]:
    """The equations of motion: per field the right-hand side of ∂t²φ, each term with its
    derivative orders, sign, coefficient, exact prefactor and sign claim (or, for survivors that
    are not all quadratic, the exact nonlinear equations with ``"nonlinear": True``)."""
    return json.loads(_native.equations_json(order, _toml(model), basis))


def operators(
    points: int, order: int = 4, model: Optional[Union[Model, str]] = None
) -> List[Dict[str, Any]]:
    """Every discretised operator on ``points`` points: dicts with ``field``, ``density``,
    ``term``, ``boundary``, ``k`` and the exact integer ``matrix`` (numpy int64)."""
    return _native.operators(points, order, _toml(model))


def modes(
    points: int,
    model: Optional[Union[Model, str]] = None,
    params: Optional[Mapping[str, float]] = None,
    shapes: bool = False,
    k: Optional[int] = None,
    order: int = 4,
) -> List[Dict[str, Any]]:
    """Each field's modes on ``points`` points (the ``k`` lowest, or all): numpy arrays
    ``eigenvalues``, ``frequencies``, ``damping_ratios``, ``variance_shares`` and, with
    ``shapes=True``, ``shapes`` (points × modes); ``params`` sets ``omega_<scale>`` and
    ``zeta_<scale>``."""
    return _native.modes(points, order, _toml(model), dict(params or {}), shapes, k)


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
) -> Dict[str, Any]:
    """Integrate the modal equations (Langevin noise at ``temperature``): ``t`` and, per field,
    ``positions[field]`` (samples × points) and ``modal[field]`` (samples × modes)."""
    return _native.simulate(
        points, steps, dt, every, temperature, seed, order, _toml(model), dict(params or {})
    )


class FitResult:
    """A fit: the report's numbers as attributes (lists become numpy arrays), the spectra,
    principal components and mode shapes as arrays, and :meth:`to_dict`."""

    def __init__(self, report: Dict[str, Any], frequencies, psd, components, shapes) -> None:
        self._report = report
        self.frequencies = frequencies
        self.psd = psd
        self.components = components
        self.shapes = shapes
        for key, value in report.items():
            if isinstance(value, list) and value and all(
                isinstance(v, (int, float)) or isinstance(v, list) for v in value
            ) and key not in ("modes", "animals", "subspace", "onward", "warnings"):
                value = np.asarray(value, dtype=float)
            setattr(self, key, value)

    def to_dict(self) -> Dict[str, Any]:
        """The report as plain data (the CLI's ``--format json``)."""
        return json.loads(json.dumps(self._report))

    def __repr__(self) -> str:
        return f"FitResult(frames={self._report['frames']}, omega={self._report['omega']:.6g}, beta={self._report['beta']:.6g})"


def _is_paths(x: Any) -> bool:
    if isinstance(x, (str, os.PathLike)):
        return True
    return isinstance(x, (list, tuple)) and len(x) > 0 and all(
        isinstance(p, (str, os.PathLike)) for p in x
    )


def fit(
    midlines: Any,
    t: Optional[Any] = None,
    fps: Optional[float] = None,
    model: Optional[Union[Model, str]] = None,
    **options: Any,
) -> FitResult:
    """Fit the theory to tracked midlines.

    ``midlines`` is a numpy array (frames × points × 2, NaN where the tracker lost a point), a
    list of such arrays (one per animal), a path, or a list of paths (any format the ``fit``
    command reads: CSV, DeepLabCut, WCON). ``t`` gives the times (one array, or one per animal);
    without it frames are ``1/fps`` apart (or one time unit). ``options`` are the command's:
    ``points``, ``window``, ``fit_modes``, ``omega``, ``fill_gaps``, ``head`` ("first"/"last"),
    ``bootstrap``, ``seed``, ``time_unit``, ``length_unit``, ``kind``, ``field``, ``order``,
    ``min_likelihood``, ``track_column``.
    """
    toml = _toml(model)
    if _is_paths(midlines):
        paths = [midlines] if isinstance(midlines, (str, os.PathLike)) else list(midlines)
        if fps is not None:
            options["fps"] = fps
        out = _native.fit_paths([os.fspath(p) for p in paths], toml, options)
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
        out = _native.fit_arrays(animals, times, toml, options)
    report, frequencies, psd, components, shapes = out
    return FitResult(json.loads(report), frequencies, psd, components, shapes)
