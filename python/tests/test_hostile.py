"""Hostile values into every function: each call either works or raises an exception Python
code catches (a TheorySearchError, ValueError, TypeError or OSError) with a one-line message;
never a Rust panic (pyo3's PanicException is a BaseException), never a hang."""

import tempfile

import numpy as np
import pytest

import theory_search as ts

BAD = [0, -1, 2**70, float("nan"), float("inf"), -1e308, "", "x\ny", None, [], {"a": 1}]


def _calls(tmp):
    return {
        "modes.points": lambda v: ts.modes(points=v),
        "modes.params": lambda v: ts.modes(12, params={"omega_b": v}),
        "modes.k": lambda v: ts.modes(12, k=v),
        "simulate.dt": lambda v: ts.simulate(points=6, steps=5, dt=v),
        "simulate.temperature": lambda v: ts.simulate(points=6, steps=5, temperature=v),
        "simulate.initial": lambda v: ts.simulate(points=6, steps=5, initial={"y:2": v}),
        "table.order": lambda v: ts.table(order=v),
        "equations.order": lambda v: ts.equations(order=v),
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
    }


@pytest.mark.parametrize("name", sorted(_calls("").keys()))
def test_hostile_values_raise_catchable_errors(name, tmp_path):
    call = _calls(str(tmp_path))[name]
    for value in BAD:
        try:
            call(value)
        except (ts.TheorySearchError, ValueError, TypeError, OSError) as e:
            assert str(e) and "\n" not in str(e).strip(), f"{name}({value!r}): {e!r}"
        except BaseException as e:  # a panic or anything else Python code would not catch
            pytest.fail(f"{name}({value!r}) raised {type(e).__name__}: {e}")
