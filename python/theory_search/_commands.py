"""Every command of the command line from Python: keyword arguments become its options, the
JSON it prints becomes a :class:`Result` (the same numbers, parsed from the same document)."""

from __future__ import annotations

import json
import os
import tempfile
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _native
from ._docs import shared
from ._errors import UsageError, shown, translated
from ._results import Result

_run = translated(_native.run_cli)


def _result(text: bytes) -> Result:
    """A JSON document as a Result (a document that is a list becomes its ``rows``)."""
    doc = json.loads(text)
    return Result(doc if isinstance(doc, dict) else {"rows": doc})


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _word(name: str, value: Any) -> str:
    """An option's value as the command line's word: an integer too long to print (Python's
    ``str`` refuses one over 4300 digits; no option takes one over 80) is refused here."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 256:
        raise UsageError(f"{name} must be a number the command line takes, not {shown(value)}")
    return str(value)


def _argv(
    command: Sequence[str],
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    options: Optional[Mapping[str, Any]] = None,
) -> List[str]:
    """The command line: `command`, then `--name value` per option (a list repeats it, True is
    a bare flag, None and False leave it out), `--param k=v` per parameter, `--model FILE`."""
    argv = list(command)
    for name, value in (options or {}).items():
        if value is None or value is False:
            continue
        if value is True:
            argv.append(_flag(name))
        elif isinstance(value, (list, tuple)):
            for v in value:
                argv += [_flag(name), _word(name, v)]
        else:
            argv += [_flag(name), _word(name, value)]
    for name, value in (params or {}).items():
        argv += ["--param", f"{name}={_word(str(name), value)}"]
    return argv


@shared
def run(
    command: Sequence[str],
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    **options: Any,
) -> Result:
    """Run any command with ``options`` as its command-line options.

    Parameters
    ----------
    command : str or sequence of str
        The command and its positional words, e.g. ``"behave rolling"`` or
        ``["behave", "rolling"]``.
    @model
    @params
    options
        ``name=value`` becomes ``--name value`` (``_`` as ``-``); a list repeats the option,
        ``True`` is a bare flag, ``None``/``False`` leave it out.

    Returns
    -------
    Result
        The command's ``--format json`` document: ``result["key"]`` as printed,
        ``result.key`` with lists of numbers as numpy arrays, ``to_dict()``, ``to_pandas()``.
    """
    from . import Model

    if isinstance(command, str):  # "modes" or "behave rolling": its words
        command = command.split()
    argv = _argv(command, params=params, options=options) + ["--format", "json"]
    if model is None:
        return _result(_run(argv))
    toml = model.toml if isinstance(model, Model) else Model.from_toml(model).toml
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "model.toml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(toml)
        return _result(_run(argv + ["--model", path]))


@shared
def behave(
    behaviour: str,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    **options: Any,
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
    options
        The command's: ``momentum``, ``periods``, ``force``, ``duration``, ``tolerance``,
        ``mode_damping``, ``theta0``, ``attachment``, ``sweep``, ``beyond_leading``.

    Returns
    -------
    Result
        Peristalsis and rolling: ``kind``, ``omega``, ``momentum``, ``amplitude``,
        ``angular_velocity``, ``trajectory``, ``postures``. Rearing and hunching: ``field``,
        ``mode``, ``force``, ``equilibrium``, ``shape``, ``transient``. Self-righting:
        ``attachment_time``, ``righting_time``, ``alignment_times``, ``damping_ratio``,
        ``frames``.
    """
    return run(["behave", behaviour], model, params, points=points, order=order, **options)


@shared
def stats(
    kind: str,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    **options: Any,
) -> Result:
    """Statistics of the body at equilibrium.

    Parameters
    ----------
    kind : str
        ``"equipartition"`` (options ``field``, ``steps``, ``temperature``, ``seed``),
        ``"explore"`` (``beta``, ``samples``, ``seed``) or ``"pair"`` (``omega``, ``beta``,
        ``momentum``, ``samples``, ``seed``).
    @points
    @model
    @params
    @order
    options
        The command's, as listed under ``kind``.

    Returns
    -------
    Result
        Equipartition: ``pca_variance_share``, ``theory_variance_share``, ``overlap``.
        Explore: ``bend_sd``, ``bend_sd_linear``, ``modal_variance``, ``theory_variance``,
        ``fitted_beta``. Pair: ``partition_function``, ``free_energy``,
        ``amplitude_at_minimum``, ``mean_amplitude``, ``samples``.
    """
    return run(["stats", kind], model, params, points=points, order=order, **options)


@shared
def asymmetry(
    coupling: float,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    **options: Any,
) -> Result:
    """Forward/backward asymmetry of App. C.

    Parameters
    ----------
    coupling : float
        The nonlinear coupling c.
    @points
    @model
    @params
    options
        The command's: ``amplitude``, ``omega``.

    Returns
    -------
    Result
        ``coupling``, ``amplitude``, ``omega``, ``forward``, ``backward``, ``ratio``,
        ``simulated_forward``, ``simulated_backward``.
    """
    return run(["asymmetry"], model, params, coupling=coupling, points=points, **options)


def mathieu(**options: Any) -> Result:
    """The Mathieu stability chart of App. D.

    Parameters
    ----------
    options
        The command's: ``lambda_`` (the mode's λ), ``ratio_min``, ``ratio_max``,
        ``epsilon_max``, ``columns``, ``rows``.

    Returns
    -------
    Result
        ``rows``: one dict per grid point (drive frequency ratio, ε, trace, stable).
    """
    if "lambda_" in options:
        options["lambda"] = options.pop("lambda_")
    return run(["mathieu"], **options)


@shared
def interactions(
    order: int = 4, model: Any = None, density: Optional[str] = None, **options: Any
) -> Result:
    """The interaction terms between fields that the requirements admit.

    Parameters
    ----------
    @order
    @model
    @density
    @term_options

    Returns
    -------
    Result
        ``model``, ``analyses`` (per density: the pairs of fields and their coupling terms).
    """
    return run(["interactions"], model, order=order, density=density, **options)


@shared
def parts(order: int = 4, model: Any = None, density: Optional[str] = None, **options: Any) -> Result:
    """The density split into kinetic, potential and interaction parts.

    Parameters
    ----------
    @order
    @model
    @density
    @term_options

    Returns
    -------
    Result
        ``model``, ``order``, ``densities`` (each with its parts and their terms).
    """
    return run(["parts"], model, order=order, density=density, **options)


@shared
def count(max_order: int = 8, model: Any = None, basis: str = "powers") -> Result:
    """How many candidate terms there are at each order.

    Parameters
    ----------
    max_order : int
        The highest order counted.
    @model
    @basis

    Returns
    -------
    Result
        ``model``, ``rows`` (per order: candidates, admitted, survivors).
    """
    return run(["count"], model, max_order=max_order, basis=basis)


@shared
def rules(order: int = 4, model: Any = None) -> Result:
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
    return run(["rules"], model, order=order)


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
    **options: Any,
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
        Resolution of a PNG.
    options
        The command's: ``samples``, ``seed``, ``order``, ``beyond_leading``.

    Returns
    -------
    list of str
        The paths written, in the order made. A figure the body cannot make (a role its model
        lacks) is skipped with a ``UserWarning`` saying why.
    """
    import warnings

    from . import Model

    argv = _argv(
        ["figures", "--figures", os.fspath(directory)],
        params=params,
        options=dict(only=only, points=points, format=format, width=width, dpi=dpi, **options),
    )
    if model is not None:
        toml = model.toml if isinstance(model, Model) else Model.from_toml(model).toml
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "model.toml")
            with open(path, "w", encoding="utf-8") as f:
                f.write(toml)
            out = _run(argv + ["--model", path])
    else:
        out = _run(argv)
    written = []
    text = out if isinstance(out, str) else out.decode("utf-8")
    for line in text.splitlines():
        if line.startswith("wrote "):
            written.append(line[len("wrote ") :])
        elif line.startswith("skipped "):
            warnings.warn(line, UserWarning, stacklevel=2)
    if not written:
        raise UsageError(f"no figure was written into {os.fspath(directory)}")
    return written
