"""The commands that are one library call each, as typed functions: the behaviours, the
statistics, the term tables, the rule registry and the figures. Each calls the library once
(never the command line, never a temporary file) and returns the document the command's
``--format json`` prints as a :class:`Result`."""

from __future__ import annotations

import math
import os
import warnings
from typing import Any, List, Mapping, Optional, Sequence, Union

from . import _native
from ._docs import shared
from ._errors import UsageError, translated
from ._results import Result

_native_call = {
    name: translated(getattr(_native, name))
    for name in (
        "count_json", "rules_json", "terms_json", "asymmetry_json",
        "mathieu_json", "stats_json", "behave_json", "figures",
    )
}


def _result(doc: Any) -> Result:
    """A document as a Result (a document that is a list becomes its ``rows``)."""
    return Result(doc if isinstance(doc, dict) else {"rows": doc})


def _toml(model: Any) -> Optional[str]:
    from . import _toml  # type: ignore[attr-defined]  # (the package's own, not public)

    return _toml(model)


def _params(params: Any) -> Optional[dict]:
    from . import _body_args  # type: ignore[attr-defined]

    return _body_args(4, None, None, params)[3]


@shared
def behave(
    behaviour: str,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
    momentum: float = 0.1,
    periods: float = 100.0,
    force: float = 0.02,
    duration: float = 2000.0,
    tolerance: float = 0.01,
    mode_damping: Optional[float] = None,
    theta0: float = math.pi,
    attachment: str = "paper",
    sweep: Sequence[float] = (),
) -> Result:
    """One of the paper's behaviours.

    Parameters
    ----------
    behaviour : str
        ``"peristalsis"``, ``"rolling"``, ``"rearing"``, ``"hunching"`` or ``"self-righting"``.
    @points
    @model
    @params
    @order
    @beyond_leading
    momentum : float
        Peristalsis and rolling: the pair's conserved momentum M (units of ω × amplitude²).
    periods : float
        Peristalsis and rolling: how long to run, in periods of the pair.
    force : float
        Rearing and hunching: the constant force on the mode (units where ω = 1 and the body
        length is 1).
    duration : float
        Rearing and hunching: how long to run, in units of 1/ω.
    tolerance : float
        Self-righting: the angle (radians) within which the head counts as attached and a
        segment as aligned.
    mode_damping : float, optional
        Self-righting: ζ₁ of the first torsional mode (default: the model's ζ when ``params``
        sets it, else critical damping, 1).
    theta0 : float
        Self-righting: every segment's initial angle (radians; π is upside down).
    attachment : str
        Self-righting: ``"paper"`` (App. H: the free first mode relaxes) or ``"pinned"``
        (the whole chain with the head held).
    sweep : sequence of float
        Self-righting: also the righting time at each of these ζ₁.

    Returns
    -------
    Result
        Peristalsis and rolling: ``kind``, ``omega``, ``momentum``, ``amplitude``,
        ``angular_velocity``, ``trajectory``, ``postures``. Rearing and hunching: ``field``,
        ``mode``, ``force``, ``equilibrium``, ``shape``, ``transient``. Self-righting:
        ``attachment_time``, ``righting_time``, ``alignment_times``, ``damping_ratio``,
        ``frames``.
    """
    ask = dict(momentum=momentum, periods=periods, force=force, duration=duration,
               tolerance=tolerance, mode_damping=mode_damping, theta0=theta0,
               attachment=attachment, sweep=list(sweep))
    return _result(_native_call["behave_json"](
        behaviour, points, order, beyond_leading, _toml(model), _params(params), ask))


@shared
def stats(
    kind: str,
    points: Optional[int] = None,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
    beta: Optional[float] = None,
    samples: Optional[int] = None,
    seed: int = 1,
    field: Optional[str] = None,
    steps: int = 200_000,
    temperature: float = 0.5,
    momentum: float = 0.0,
    omega: Optional[float] = None,
) -> Result:
    """Statistics of the body at equilibrium.

    Parameters
    ----------
    kind : str
        ``"equipartition"`` (a Langevin run's PCA beside the modes, App. B), ``"explore"``
        (Gaussian postures and the 3-point bend, §3.3.4) or ``"pair"`` (a degenerate pair at
        fixed momentum, App. J).
    points : int, optional
        Points along the body (12 when None; for ``"pair"``, naming a body whose first axial
        pair sets ω).
    @model
    @params
    @order
    @beyond_leading
    beta : float, optional
        Inverse temperature: of the whole body for ``"explore"`` (default 10000, units where
        ω = 1 and the body length is 1), of the pair for ``"pair"`` (default 1).
    samples : int, optional
        Draws (``"explore"``: default 100000; ``"pair"``: a Metropolis run only when given).
    seed : int
        Seed of the draws or of the noise.
    field : str, optional
        ``"equipartition"``: the field (id); default the model's lateral field.
    steps : int
        ``"equipartition"``: time steps of 0.5 (units of 1/ω; a tenth are burn-in).
    temperature : float
        ``"equipartition"``: thermal energy kT (units where ω = 1 and the body length is 1).
    momentum : float
        ``"pair"``: the conserved momentum M.
    omega : float, optional
        ``"pair"``: the pair's ω (default: the first axial pair of the body ``model``,
        ``points`` or ``params`` name, else 1); not with ``params``.

    Returns
    -------
    Result
        Equipartition: ``pca_variance_share``, ``theory_variance_share``, ``overlap``.
        Explore: ``bend_sd``, ``bend_sd_linear``, ``modal_variance``, ``theory_variance``,
        ``fitted_beta``. Pair: ``partition_function``, ``free_energy``,
        ``amplitude_at_minimum``, ``mean_amplitude``, ``samples``.
    """
    ask = dict(beta=beta, samples=samples, seed=seed, field=field, steps=steps,
               temperature=temperature, momentum=momentum, omega=omega)
    return _result(_native_call["stats_json"](
        kind, points, order, beyond_leading, _toml(model), _params(params), ask))


@shared
def asymmetry(
    coupling: float,
    points: Optional[int] = None,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    amplitude: float = 1.0,
    omega: Optional[float] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
) -> Result:
    """Forward/backward asymmetry of App. C.

    Parameters
    ----------
    coupling : float
        The nonlinear coupling c.
    points : int, optional
        Points of the body whose first axial pair sets ω (12 when a model or params is given).
    @model
    @params
    amplitude : float
        The wave's amplitude A (units of the body length).
    omega : float, optional
        The pair's ω (radians per unit time); default the body's first axial pair, else 1.
    @order
    @beyond_leading

    Returns
    -------
    Result
        ``coupling``, ``amplitude``, ``omega``, ``forward``, ``backward``, ``ratio``,
        ``simulated_forward``, ``simulated_backward``.
    """
    return _result(_native_call["asymmetry_json"](
        coupling, amplitude, omega, points, order, beyond_leading, _toml(model), _params(params)))


def mathieu(
    lambda_: float = 1.0,
    ratio_min: float = 0.5,
    ratio_max: float = 4.5,
    epsilon_max: float = 0.5,
    columns: int = 81,
    rows: int = 21,
) -> Result:
    """The Mathieu stability chart of App. D.

    Parameters
    ----------
    lambda_ : float
        The mode's λ (its squared frequency, units of ω²).
    ratio_min : float
        The chart's lowest drive frequency over the mode's.
    ratio_max : float
        The chart's highest drive frequency over the mode's.
    epsilon_max : float
        The largest drive amplitude ε (dimensionless).
    columns : int
        Grid points across (drive frequency ratios).
    rows : int
        Grid points up (drive amplitudes ε).

    Returns
    -------
    Result
        ``rows``: one dict per grid point (drive frequency ratio, ε, trace, stable).
    """
    return _result(_native_call["mathieu_json"](
        lambda_, ratio_min, ratio_max, epsilon_max, columns, rows))


@shared
def interactions(
    order: int = 4,
    model: Any = None,
    density: Optional[str] = None,
    beyond_leading: Optional[int] = None,
) -> Result:
    """The interaction terms between fields that the requirements admit.

    Parameters
    ----------
    @order
    @model
    @density
    @beyond_leading

    Returns
    -------
    Result
        ``model``, ``analyses`` (per density: the pairs of fields and their coupling terms).
    """
    return _result(_native_call["terms_json"]("interactions", order, beyond_leading, _toml(model), density))


@shared
def parts(
    order: int = 4,
    model: Any = None,
    density: Optional[str] = None,
    beyond_leading: Optional[int] = None,
) -> Result:
    """The density split into kinetic, potential and interaction parts.

    Parameters
    ----------
    @order
    @model
    @density
    @beyond_leading

    Returns
    -------
    Result
        ``model``, ``order``, ``densities`` (each with its parts and their terms).
    """
    return _result(_native_call["terms_json"]("parts", order, beyond_leading, _toml(model), density))


@shared
def count(max_order: int = 8, model: Any = None, basis: str = "powers") -> Result:
    """How many candidate terms there are at each order.

    Parameters
    ----------
    max_order : int
        The highest order counted (1 to 32).
    @model
    @basis

    Returns
    -------
    Result
        ``model``, ``rows`` (per order: candidates, admitted, survivors).
    """
    return _result(_native_call["count_json"](max_order, _toml(model), basis))


@shared
def rules(order: Optional[int] = 4, model: Any = None) -> Result:
    """The rule registry: each requirement and what it does to a term.

    Parameters
    ----------
    @order
    @model

    Returns
    -------
    Result
        ``rules`` (each requirement's name, transformation and reason), ``requirements``.
    """
    return _result(_native_call["rules_json"](order, _toml(model)))


@shared
def figures(
    directory: Union[str, os.PathLike],
    only: Optional[str] = None,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    format: str = "svg",
    width: float = 180.0,
    dpi: float = 300.0,
    samples: int = 100_000,
    seed: int = 1,
    order: int = 4,
    beyond_leading: Optional[int] = None,
) -> List[str]:
    """Write the paper's figures into ``directory`` (created if missing).

    Parameters
    ----------
    directory : str or path
        Where the files go.
    only : str, optional
        One figure (``"mode_shapes"``, ``"spectrum"``, ``"self_righting"``, …).
    @points
    @model
    @params
    format : str
        ``"svg"``, ``"png"`` or ``"pdf"``.
    width : float
        Printed width in millimetres (60 to 600); text prints at 7.4 pt at any width.
    dpi : float
        Resolution of a PNG, in dots per inch.
    samples : int
        Draws of the sampled figures (pair density, 3-point bend).
    seed : int
        Seed of those draws.
    @order
    @beyond_leading

    Returns
    -------
    list of str
        The paths written, in the order made. A figure the body cannot make (a role its model
        lacks) is skipped with a ``UserWarning`` saying why.
    """
    written, skipped = _native_call["figures"](
        os.fspath(directory), only, points, order, beyond_leading, _toml(model), _params(params),
        format, width, dpi, samples, seed,
    )
    for name, why in skipped:
        warnings.warn(f"skipped {name}: {why}", UserWarning, stacklevel=2)
    if not written:
        raise UsageError(f"no figure was written into {os.fspath(directory)}")
    return written
