"""Every command of the command line from Python: keyword arguments become its options, the
JSON it prints becomes a :class:`Result` (the same numbers, parsed from the same document)."""

from __future__ import annotations

import json
import os
import tempfile
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _native
from ._errors import UsageError, translated
from ._results import Result

_run = translated(_native.run_cli)


def _result(text: bytes) -> Result:
    """A JSON document as a Result (a document that is a list becomes its ``rows``)."""
    doc = json.loads(text)
    return Result(doc if isinstance(doc, dict) else {"rows": doc})


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


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
                argv += [_flag(name), str(v)]
        else:
            argv += [_flag(name), str(value)]
    for name, value in (params or {}).items():
        argv += ["--param", f"{name}={value}"]
    return argv


def run(
    command: Sequence[str],
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    **options: Any,
) -> Result:
    """Run any command (``["behave", "rolling"]``) with ``options`` as its command-line options
    and return its JSON document as a :class:`Result`."""
    from . import Model

    argv = _argv(command, params=params, options=options) + ["--format", "json"]
    if model is None:
        return _result(_run(argv))
    toml = model.toml if isinstance(model, Model) else Model.from_toml(model).toml
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "model.toml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(toml)
        return _result(_run(argv + ["--model", path]))


def behave(
    behaviour: str,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    **options: Any,
) -> Result:
    """One of the paper's behaviours: ``"peristalsis"``, ``"rolling"``, ``"rearing"``,
    ``"hunching"``, ``"self-righting"``; ``options`` are the command's (``momentum``,
    ``periods``, ``force``, ``duration``, ``tolerance``, ``mode_damping``, ``theta0``,
    ``attachment``, ``sweep``, ``beyond_leading``)."""
    return run(["behave", behaviour], model, params, points=points, order=order, **options)


def stats(
    kind: str,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    **options: Any,
) -> Result:
    """Statistics: ``"equipartition"`` (``field``, ``steps``, ``temperature``, ``seed``),
    ``"explore"`` (``beta``, ``samples``, ``seed``) or ``"pair"`` (``omega``, ``beta``,
    ``momentum``, ``samples``, ``seed``)."""
    return run(["stats", kind], model, params, points=points, order=order, **options)


def asymmetry(
    coupling: float,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    **options: Any,
) -> Result:
    """Forward/backward asymmetry of App. C at ``coupling`` (``amplitude``, ``omega``)."""
    return run(["asymmetry"], model, params, coupling=coupling, points=points, **options)


def mathieu(**options: Any) -> Result:
    """The Mathieu stability chart of App. D (``lambda_``, ``ratio_min``, ``ratio_max``,
    ``epsilon_max``, ``columns``, ``rows``)."""
    if "lambda_" in options:
        options["lambda"] = options.pop("lambda_")
    return run(["mathieu"], **options)


def interactions(
    order: int = 4, model: Any = None, density: Optional[str] = None, **options: Any
) -> Result:
    """The interaction terms between fields the requirements admit (``density`` as for
    :func:`parts`)."""
    return run(["interactions"], model, order=order, density=density, **options)


def parts(order: int = 4, model: Any = None, density: Optional[str] = None, **options: Any) -> Result:
    """The density split into kinetic, potential and interaction parts (``density``:
    ``"lagrangian"``, ``"rayleigh"`` or ``"both"``; the command's default without it)."""
    return run(["parts"], model, order=order, density=density, **options)


def count(max_order: int = 8, model: Any = None, basis: str = "powers") -> Result:
    """How many candidate terms there are at each order."""
    return run(["count"], model, max_order=max_order, basis=basis)


def rules(order: int = 4, model: Any = None) -> Result:
    """The rule registry: each requirement and what it does to a term."""
    return run(["rules"], model, order=order)


def figures(
    directory: Union[str, os.PathLike],
    only: Optional[str] = None,
    points: int = 12,
    model: Any = None,
    params: Optional[Mapping[str, float]] = None,
    **options: Any,
) -> List[str]:
    """Write the paper's figures (SVG) into ``directory``; the paths written."""
    from . import Model

    argv = _argv(
        ["figures", "--figures", os.fspath(directory)],
        params=params,
        options=dict(only=only, points=points, **options),
    )
    if model is not None:
        toml = model.toml if isinstance(model, Model) else Model.from_toml(model).toml
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "model.toml")
            with open(path, "w", encoding="utf-8") as f:
                f.write(toml)
            _run(argv + ["--model", path])
    else:
        _run(argv)
    written = sorted(
        os.path.join(os.fspath(directory), n)
        for n in os.listdir(directory)
        if n.endswith(".svg")
    )
    if not written:
        raise UsageError(f"no figure was written into {os.fspath(directory)}")
    return written
