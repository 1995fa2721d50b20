"""help() of every public function lists each of its arguments and what it returns, and every
attribute its Returns section names exists on what a call really returns."""

import inspect
import re
import tempfile
from collections.abc import Mapping
from pathlib import Path

import matplotlib
import pytest

import theory_search as ts
import theory_search.plot as tp

matplotlib.use("Agg")

WORM = Path(__file__).resolve().parents[3] / "shared" / "data" / "celegans_wormpose_15fps_52pts.csv"

FUNCTIONS = [getattr(ts, n) for n in ts.__all__ if inspect.isfunction(getattr(ts, n))]
FUNCTIONS += [ts.Model.larva, ts.Model.from_toml]
FUNCTIONS += [tp.modes, tp.spectrum, tp.simulation, tp.verdicts]


def _section(doc: str, title: str) -> str:
    """The body of numpy-doc section ``title`` (empty when absent)."""
    m = re.search(rf"^{title}\n-+\n(.*?)(?=^\w[\w ]*\n-+\n|\Z)", doc, re.S | re.M)
    return m.group(1) if m else ""


@pytest.mark.parametrize("fn", FUNCTIONS, ids=lambda f: f.__qualname__)
def test_help_lists_every_argument_and_the_result(fn):
    doc = inspect.getdoc(fn) or ""
    params = [
        ("options" if p.kind is p.VAR_KEYWORD else name)
        for name, p in inspect.signature(fn).parameters.items()
        if name not in ("self", "cls")
    ]
    listed = _section(doc, "Parameters")
    for name in params:
        assert re.search(rf"^{name}( :|$)", listed, re.M), f"{fn.__qualname__}: {name} undocumented"
    returns = _section(doc, "Returns")
    assert returns.strip(), f"{fn.__qualname__}: no Returns section"


def _has(obj, name: str, depth: int = 4) -> bool:
    """``name`` is an attribute or key of ``obj``, or of what it holds a few levels down (a
    density's rows, a mapping of field results, a list of dicts)."""
    if depth == 0 or isinstance(obj, (int, float, str, bytes)) or obj is None:
        return False
    if isinstance(obj, Mapping):
        return name in obj or any(_has(v, name, depth - 1) for v in obj.values())
    if isinstance(obj, list):
        return bool(obj) and _has(obj[0], name, depth - 1)
    return type(obj).__module__.startswith("theory_search") and hasattr(obj, name)


def _names(fn) -> list:
    """The ``names`` in a Returns section that name attributes (not values or calls)."""
    text = _section(inspect.getdoc(fn) or "", "Returns")
    return [
        n
        for n in re.findall(r"``([A-Za-z_][A-Za-z0-9_]*)``", text)
        if n[0].islower()  # class names (``FieldModes``) are not attributes
    ]


@pytest.fixture(scope="module")
def fitted():
    return ts.fit(str(WORM), window=64)


def test_every_returned_attribute_named_exists(fitted):
    calls = {
        ts.table: lambda: ts.table(order=4),
        ts.equations: lambda: ts.equations(),
        ts.active: lambda: ts.active(
            model=str(Path(__file__).resolve().parents[2] / "tables" / "models" / "crawler.toml")
        ),
        ts.modes: lambda: ts.modes(12, shapes=True),
        ts.simulate: lambda: ts.simulate(steps=20),
        ts.asymmetry: lambda: ts.asymmetry(0.1),
        ts.mathieu: lambda: ts.mathieu(columns=5, rows=5),
        ts.interactions: lambda: ts.interactions(),
        ts.parts: lambda: ts.parts(),
        ts.count: lambda: ts.count(max_order=4),
        ts.rules: lambda: ts.rules(),
        ts.fit: lambda: fitted,
        ts.Model.larva: ts.Model.larva,
        ts.Model.from_toml: lambda: ts.Model.from_toml(ts.Model.larva().toml),
    }
    checked = 0
    for fn, call in calls.items():
        result = call()
        for name in _names(fn):
            assert _has(result, name), f"{fn.__qualname__}: returns no {name!r}"
            checked += 1
    # Each kind of a command with several: every name must exist on one of them.
    tethered = Path(__file__).resolve().parents[2] / "tables" / "models" / "tethered.toml"
    for fn, results in {
        # A linear body's exact operators, a nonlinear body's linearisation.
        ts.operators: [ts.operators(8), ts.operators(8, model=ts.Model.from_toml(tethered))],
        ts.behave: [ts.behave(b) for b in ("peristalsis", "rearing", "self-righting")],
        ts.stats: [
            ts.stats("equipartition", steps=2000),
            ts.stats("explore", samples=200),
            ts.stats("pair", samples=200),
        ],
    }.items():
        for name in _names(fn):
            assert any(_has(r, name) for r in results), f"{fn.__qualname__}: no {name!r}"
            checked += 1
    with tempfile.TemporaryDirectory() as d:
        assert ts.figures(d, only="spectrum")
    assert checked > 80, checked
