"""Plots of theory_search results with matplotlib (an optional extra: ``pip install
theory-search[plot]`` or any matplotlib). Each function takes a result object, draws on a new
figure (or the ``ax`` given) and returns the matplotlib ``Figure``; legends sit outside the
data, text is at least 8 pt at the default size."""

from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from ._docs import shared


def _axes(ax: Any, ncols: int = 1, width: float = 7.0, height: float = 3.2):
    import matplotlib.pyplot as plt

    if ax is not None:
        return ax.figure, [ax] if ncols == 1 else ax
    fig, axes = plt.subplots(1, ncols, figsize=(width, height), constrained_layout=True)
    return fig, list(np.atleast_1d(axes))


@shared
def modes(result: Any, field: str = "y", count: int = 4, ax: Any = None):
    """The first non-zero mode shapes of a field along the body.

    Parameters
    ----------
    result : Modes
        From :func:`theory_search.modes`.
    field : str
        The field id.
    count : int
        How many modes.
    @ax
    @figure
    """
    fm = result[field]
    if fm.shapes is None:
        raise ValueError(f"no mode shapes for {field!r}")
    fig, (axis,) = _axes(ax)
    s = np.linspace(0.0, 1.0, fm.shapes.shape[0])
    nonzero = [i for i, lam in enumerate(fm.eigenvalues) if lam > 1e-9][:count]
    for i in nonzero:
        axis.plot(s, fm.shapes[:, i], label=f"mode {i} (λ = {fm.eigenvalues[i]:.3g})")
    axis.axhline(0.0, color="0.7", lw=0.5)
    axis.set_xlabel("arc length (tail → head)")
    axis.set_ylabel(f"{field} shape")
    axis.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    return fig


@shared
def spectrum(fit: Any, modes: Optional[Sequence[int]] = None, ax: Any = None):
    """The Welch spectra of a fit's mode coordinates, log scale, each with the frequency the
    theory gives it.

    Parameters
    ----------
    fit : FitResult
        From :func:`theory_search.fit`.
    modes : sequence of int, optional
        Which modes, by the numbers the report prints (zero modes counted: the first bending
        mode of a free body is mode 2); the first four fitted ones when None. Row ``j`` of
        ``fit.psd`` is mode ``fit.to_dict()["modes"][j]["index"]``.
    @ax
    @figure
    """
    fig, (axis,) = _axes(ax)
    rows = fit.to_dict().get("modes") or []
    numbers = [m["index"] for m in rows]
    for k in numbers[:4] if modes is None else modes:
        if k not in numbers or numbers.index(k) >= len(fit.psd):
            continue
        j = numbers.index(k)
        (line,) = axis.semilogy(fit.frequencies, fit.psd[j], label=f"mode {k}")
        theory = rows[j].get("theory_angular_frequency")
        if theory:
            axis.axvline(theory / (2 * np.pi), color=line.get_color(), ls=":", lw=1)
    unit = (fit.to_dict().get("units") or {}).get("time")
    axis.set_xlabel(f"frequency (cycles per {unit})" if unit else "frequency (cycles per time unit)")
    axis.set_ylabel("power spectral density")
    if axis.get_lines():
        axis.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    return fig


@shared
def simulation(sim: Any, field: str = "y", points: Optional[Sequence[int]] = None, ax: Any = None):
    """Positions of a field against time.

    Parameters
    ----------
    sim : dict
        From :func:`theory_search.simulate`.
    field : str
        The field id.
    points : sequence of int, optional
        Which points (tail, middle and head when None).
    @ax
    @figure
    """
    fig, (axis,) = _axes(ax)
    q = np.asarray(sim["positions"][field])
    chosen = points if points is not None else sorted({0, q.shape[1] // 2, q.shape[1] - 1})
    for j in chosen:
        axis.plot(sim["t"], q[:, j], lw=1, label=f"{field}_{j}")
    axis.set_xlabel("t")
    axis.set_ylabel(field)
    axis.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    return fig


@shared
def verdicts(fit: Any, ax: Any = None):
    """The fit's tests of the theory's predictions: each exponent with its interval against the
    value the theory predicts, and the verdict.

    Parameters
    ----------
    fit : FitResult
        From :func:`theory_search.fit`.
    @ax
    @figure
    """
    fig, (axis,) = _axes(ax, height=0.6 + 0.5 * max(1, len(fit.tests)))
    names = list(fit.tests)
    for y, name in enumerate(names):
        t = fit.tests[name]
        axis.plot([t["expected"]], [y], "k|", ms=14)
        if t.get("interval"):
            lo, hi = t["interval"]
            axis.plot([lo, hi], [y, y], "-", color="C0", lw=3)
        if t.get("exponent") is not None:
            axis.plot([t["exponent"]], [y], "o", color="C0")
        axis.annotate(t["verdict"], (1.01, y), xycoords=("axes fraction", "data"), va="center", fontsize=9)
    axis.set_yticks(range(len(names)), names)
    axis.set_ylim(-0.5, len(names) - 0.5)
    axis.set_xlabel("exponent (bar: interval; |: the theory's value)")
    return fig
