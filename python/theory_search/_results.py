"""Result objects: a command's JSON document with attribute access, numbers as numpy arrays,
``to_dict()``, ``to_pandas()`` and an HTML rendering for Jupyter."""

from __future__ import annotations

import html
import json
from typing import Any, Callable, Dict, Iterator, List, Mapping, Optional

import numpy as np


def _numeric(value: Any) -> bool:
    """A list of numbers, or of equal-length lists of numbers."""
    if not isinstance(value, list) or not value:
        return False
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return True
    return all(
        isinstance(row, list)
        and len(row) == len(value[0])
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in row)
        for row in value
    )


def _arrays(value: Any) -> Any:
    if _numeric(value):
        return np.asarray(value, dtype=float)
    if isinstance(value, dict):
        return {k: _arrays(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_arrays(v) for v in value]
    return value


def _table(doc: Any) -> Optional[List[Dict[str, Any]]]:
    """The document's main table: its first list of objects (searched breadth first)."""
    queue = [doc]
    while queue:
        item = queue.pop(0)
        if isinstance(item, list) and item and all(isinstance(r, dict) for r in item):
            return item
        if isinstance(item, dict):
            queue.extend(item.values())
    return None


class Result(dict):
    """A command's result. Item access gives the JSON document as the command line's
    ``--format json`` prints it; attribute access the same with lists of numbers as numpy
    arrays. ``to_dict()`` is plain data, ``to_pandas()`` the main table as a DataFrame."""

    def __getattr__(self, name: str) -> Any:
        try:
            return _arrays(self[name])
        except KeyError:
            raise AttributeError(name) from None

    def to_dict(self) -> Dict[str, Any]:
        """The document as plain data (a deep copy; numpy arrays as lists)."""
        return json.loads(json.dumps(self, default=lambda a: np.asarray(a).tolist()))

    def to_pandas(self) -> Any:
        """The main table (the first list of records) as a pandas DataFrame (needs pandas)."""
        import pandas as pd

        rows = _table(dict(self))
        return pd.json_normalize(rows if rows is not None else [dict(self)])

    def _repr_html_(self) -> str:
        try:
            return self.to_pandas().to_html(max_rows=60)
        except ImportError:
            return "<pre>" + html.escape(json.dumps(self, indent=1)[:20000]) + "</pre>"


class DiscoverResult(Result):
    """``discover``'s document (a :class:`Result`) whose notebook view leads with the verdict,
    the discovered equation and the selected terms with their intervals."""

    def _repr_html_(self) -> str:
        esc = lambda v: html.escape(str(v))  # noqa: E731
        verdict = self.get("verdict") or {}
        findings = "".join(
            f"<li>{esc(f.get('finding', ''))}: "
            + esc(", ".join(f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}"
                            for k, v in f.items() if k != "finding"))
            + "</li>"
            for f in verdict.get("findings") or []
        )
        out = f"<p><b>the theory: {esc(verdict.get('conclusion', 'undecided'))}</b></p>"
        out += f"<ul>{findings}</ul>" if findings else ""
        out += f"<p>{esc(self.get('equation', ''))}</p>"
        rows = ""
        for t in self.get("selected") or []:
            lo, hi = t.get("interval") or (float("nan"), float("nan"))
            rows += (
                f"<tr><td>{esc(t.get('term', ''))}</td><td>{esc(t.get('name', ''))}</td>"
                f"<td>{t.get('coefficient', float('nan')):.6g}</td><td>[{lo:.6g}, {hi:.6g}]</td>"
                f"<td>{t.get('inclusion', float('nan')):.2f}</td></tr>"
            )
        if rows:
            out += (
                "<table><tr><th>term</th><th>coefficient</th><th>value (body lengths)</th>"
                f"<th>95 % interval</th><th>inclusion</th></tr>{rows}</table>"
            )
        return out


class FieldModes:
    """One field's modes: numpy arrays ``eigenvalues``, ``frequencies``, ``damping_ratios``,
    ``variance_shares`` and ``shapes`` (points × modes, one mode per column like
    ``numpy.linalg.eigh``; computed when first read unless ``modes(shapes=True)`` computed
    them already)."""

    def __init__(
        self,
        record: Mapping[str, Any],
        shapes_of: Optional[Callable[[], Optional[np.ndarray]]] = None,
    ) -> None:
        self.field: str = record["field"]
        self.eigenvalues = np.asarray(record.get("eigenvalues", []), dtype=float)
        self.frequencies = np.asarray(record.get("frequencies", []), dtype=float)
        self.damping_ratios = np.asarray(record.get("damping_ratios", []), dtype=float)
        self.variance_shares = np.asarray(record.get("variance_shares", []), dtype=float)
        shapes = record.get("shapes")
        self._shapes = None if shapes is None else np.asarray(shapes, dtype=float)
        self._shapes_of = shapes_of
        # The operator's order k, the scales ω and ζ, the zero modes and Σλ⁻¹ (absent: None).
        self.k: Optional[int] = record.get("k")
        self.omega: Optional[float] = record.get("omega")
        self.zeta: Optional[float] = record.get("zeta")
        self.nullity: Optional[int] = record.get("nullity")
        self.inverse_trace: Optional[float] = record.get("inverse_trace")
        # A linearisation (a nonlinear body, or damping that is not modal): the equilibrium and
        # the roots λ = −σ ± iω of λ²M + λC + K (decay rates σ, damped frequencies ω).
        self.linearised: bool = bool(record.get("linearised", False))
        self.equilibrium = np.asarray(record.get("equilibrium", []), dtype=float)
        self.decay_rates = np.asarray(record.get("decay_rates", []), dtype=float)
        self.damped_frequencies = np.asarray(record.get("damped_frequencies", []), dtype=float)

    @property
    def shapes(self) -> Optional[np.ndarray]:
        """The mode shapes, points × modes (one unit-norm mode per column); the first read
        computes them (once) when ``modes()`` was called without ``shapes=True``."""
        if self._shapes is None and self._shapes_of is not None:
            self._shapes = self._shapes_of()
            self._shapes_of = None
        return self._shapes

    def to_dict(self) -> Dict[str, Any]:
        """Plain data."""
        out = {
            "field": self.field,
            "eigenvalues": self.eigenvalues.tolist(),
            "frequencies": self.frequencies.tolist(),
            "damping_ratios": self.damping_ratios.tolist(),
            "variance_shares": self.variance_shares.tolist(),
            "shapes": None if self.shapes is None else self.shapes.tolist(),
        }
        if self.linearised:
            out["linearised"] = True
            out["equilibrium"] = self.equilibrium.tolist()
            out["decay_rates"] = self.decay_rates.tolist()
            out["damped_frequencies"] = self.damped_frequencies.tolist()
        return out

    def to_pandas(self) -> Any:
        """One row per mode (needs pandas)."""
        import pandas as pd

        columns = {
            "eigenvalue": self.eigenvalues,
            "frequency": self.frequencies,
            "damping_ratio": self.damping_ratios,
            "variance_share": self.variance_shares,
        }
        # A linearisation has no modal damping ratios or shares: only the columns it has.
        return pd.DataFrame({k: v for k, v in columns.items() if len(v) == len(self.eigenvalues)})

    def __repr__(self) -> str:
        return f"FieldModes({self.field!r}, {len(self.eigenvalues)} modes)"


class Modes(Mapping[str, FieldModes]):
    """Every field's modes, keyed by field id: ``m["y"].eigenvalues``, ``m["y"].shapes``.
    ``load_shapes`` (when given) computes every field's records with shapes, once, the first
    time a field's ``shapes`` is read."""

    def __init__(
        self,
        records: List[Mapping[str, Any]],
        load_shapes: Optional[Callable[[], List[Mapping[str, Any]]]] = None,
    ) -> None:
        self._load_shapes = load_shapes
        self._with_shapes: Optional[Dict[str, Any]] = None
        self._fields = {
            r["field"]: FieldModes(
                r, None if load_shapes is None or r.get("shapes") is not None else self._loader(r["field"])
            )
            for r in records
        }

    def _loader(self, field: str) -> Callable[[], Optional[np.ndarray]]:
        return lambda: self._shapes_for(field)

    def _shapes_for(self, field: str) -> Optional[np.ndarray]:
        if self._with_shapes is None and self._load_shapes is not None:
            self._with_shapes = {r["field"]: r.get("shapes") for r in self._load_shapes()}
        shapes = (self._with_shapes or {}).get(field)
        return None if shapes is None else np.asarray(shapes, dtype=float)

    def __getitem__(self, field: str) -> FieldModes:
        return self._fields[field]

    def __iter__(self) -> Iterator[str]:
        return iter(self._fields)

    def __len__(self) -> int:
        return len(self._fields)

    def to_dict(self) -> Dict[str, Any]:
        """Plain data, field by field."""
        return {k: v.to_dict() for k, v in self._fields.items()}

    def to_pandas(self) -> Any:
        """One row per field and mode (needs pandas)."""
        import pandas as pd

        frames = []
        for k, v in self._fields.items():
            df = v.to_pandas()
            df.insert(0, "mode", range(len(df)))
            df.insert(0, "field", k)
            frames.append(df)
        return pd.concat(frames, ignore_index=True)

    def _repr_html_(self) -> str:
        try:
            return self.to_pandas().to_html(max_rows=60)
        except ImportError:
            return "<pre>" + html.escape(repr(self)) + "</pre>"

    def __repr__(self) -> str:
        inner = ", ".join(f"{k!r}: {len(v.eigenvalues)} modes" for k, v in self._fields.items())
        return f"Modes({{{inner}}})"


class Simulation(dict):
    """A simulation: ``t`` and ``energy`` (one value per sample), ``injected`` (the work the
    active forces have done since t = 0; a body with active forces only), ``positions`` (field →
    samples × points) and ``modal`` (field → samples × modes; empty for a nonlinear body), as
    items or attributes. ``to_pandas()`` is the command line's CSV as a DataFrame (columns
    ``t``, ``energy``, ``injected`` when present, ``<field>_<point>``, ``q_<field>_<mode>``)."""

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def to_dict(self) -> Dict[str, Any]:
        """Plain data: arrays as lists."""
        out: Dict[str, Any] = {
            "t": np.asarray(self["t"]).tolist(),
            "energy": np.asarray(self["energy"]).tolist(),
        }
        if "injected" in self:
            out["injected"] = np.asarray(self["injected"]).tolist()
        return {
            **out,
            "positions": {f: np.asarray(a).tolist() for f, a in self["positions"].items()},
            "modal": {f: np.asarray(a).tolist() for f, a in self["modal"].items()},
        }

    def to_pandas(self) -> Any:
        """One row per sample, the CSV's columns (needs pandas)."""
        import pandas as pd

        columns: Dict[str, Any] = {"t": self["t"], "energy": self["energy"]}
        if "injected" in self:
            columns["injected"] = self["injected"]
        for kind, prefix in (("positions", ""), ("modal", "q_")):
            for field, values in self[kind].items():
                values = np.asarray(values)
                for j in range(values.shape[1]):
                    columns[f"{prefix}{field}_{j}"] = values[:, j]
        return pd.DataFrame(columns)

    def _repr_html_(self) -> str:
        try:
            return self.to_pandas().to_html(max_rows=20, max_cols=12)
        except ImportError:
            return "<pre>" + html.escape(repr(self)) + "</pre>"

    def __repr__(self) -> str:
        shapes = ", ".join(f"{f}: {np.shape(a)}" for f, a in self["positions"].items())
        return f"Simulation({len(self['t'])} samples; positions {shapes})"
