"""Hostile values into every function: each call either works or raises an exception Python
code catches (a TheorySearchError, ValueError, TypeError, OSError or ArithmeticError) with one
bounded line; never a Rust panic (pyo3's PanicException is a BaseException), never a hang."""

import tempfile
from pathlib import Path

import numpy as np
import pytest

import theory_search as ts

BAD = [0, -1, 2**70, 2**64, float("nan"), float("inf"), -1e308, 1e308, 1e-200, "", "x\ny",
       "x" * 100000, None, [], {"a": 1}]
TETHERED = str(Path(__file__).resolve().parents[2] / "tables" / "models" / "tethered.toml")
CRAWLER = str(Path(__file__).resolve().parents[2] / "tables" / "models" / "crawler.toml")
# The private native layer raises its own exception family (the package translates it).
ALLOWED = (ts.TheorySearchError, ts._native.TheorySearchError, ValueError, TypeError, OSError,
           ArithmeticError)


def _calls(tmp):
    return {
        "modes.points": lambda v: ts.modes(points=v),
        "modes.params": lambda v: ts.modes(12, params={"omega_b": v}),
        "modes.modes": lambda v: ts.modes(12, modes=v),
        "simulate.dt": lambda v: ts.simulate(points=6, steps=5, dt=v),
        "simulate.temperature": lambda v: ts.simulate(points=6, steps=5, temperature=v),
        "simulate.initial": lambda v: ts.simulate(points=6, steps=5, initial={"y:2": v}),
        "table.order": lambda v: ts.table(order=v),
        "equations.order": lambda v: ts.equations(order=v),
        "active.order": lambda v: ts.active(order=v, model=CRAWLER),
        "operators.points": lambda v: ts.operators(v),
        "behave.momentum": lambda v: ts.behave("rolling", momentum=v),
        "behave.kind": lambda v: ts.behave(v),
        "stats.beta": lambda v: ts.stats("pair", beta=v, samples=100),
        "asymmetry.coupling": lambda v: ts.asymmetry(v),
        "mathieu.epsilon_max": lambda v: ts.mathieu(epsilon_max=v, columns=4, rows=4),
        "fit.array": lambda v: ts.fit(np.full((40, 6, 2), v) if isinstance(v, float) else v),
        "fit.fps": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)), fps=v),
        "figures.width": lambda v: ts.figures(tmp, only="spectrum", width=v),
        "figures.format": lambda v: ts.figures(tmp, only="spectrum", format=v),
        "model": lambda v: ts.Model.from_toml(v if isinstance(v, str) else str(v)),
        "count.max_order": lambda v: ts.count(max_order=v),
        "run.command": lambda v: ts.run([v] if isinstance(v, str) else v),
        # Hostile III: nonlinear bodies, fit options, array shapes.
        "tethered.params": lambda v: ts.modes(4, model=TETHERED, params={"c4_u": v}),
        "tethered.operators": lambda v: ts.operators(4, model=TETHERED, params={"c3_u": v}),
        "tethered.initial": lambda v: ts.simulate(5, steps=2, model=TETHERED, initial={"u": v}),
        "tethered.drive": lambda v: ts.simulate(5, steps=3, model=TETHERED, drive={"u:1": (v, v)}),
        "fit.points": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)), points=v),
        "fit.window": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)), window=v),
        "fit.t": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)),
                                  t=np.zeros((64, 2)) if v is None else np.arange(64) * (v if isinstance(v, float) else 1.0)),
        "native.operators": lambda v: ts._native.operators(v, 4, None, None, None),
        "fit.time_unit": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)),
                                          time_unit=v if v is not None else "<b>"),
    }


@pytest.mark.parametrize("name", sorted(_calls("").keys()))
def test_hostile_values_raise_catchable_errors(name, tmp_path):
    call = _calls(str(tmp_path))[name]
    for value in BAD:
        try:
            call(value)
        except ALLOWED as e:
            assert str(e) and "\n" not in str(e).strip(), f"{name}({value!r}): {e!r}"
            assert len(str(e)) <= 1000, f"{name}: unbounded message of {len(str(e))} characters"
        except BaseException as e:  # a panic or anything else Python code would not catch
            pytest.fail(f"{name}({value!r}) raised {type(e).__name__}: {e}")
