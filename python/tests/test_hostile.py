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
        "stats.kind": lambda v: ts.stats(v, samples=10),
        "mathieu.columns": lambda v: ts.mathieu(columns=v, rows=3),
        "parts.density": lambda v: ts.parts(density=v),
        "behave.attachment": lambda v: ts.behave("self-righting", points=6, attachment=v),
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


# Hostile input IV: every error is a TheorySearchError (docs/python.md), a UsageError for a bad
# argument, even where a conversion (Python's str of a huge integer, numpy's reshape or float
# conversion, pyo3's unsigned extraction) refuses it before the library sees it.
HUGE = 10**5000


def _frame_with_text_time():
    import pandas as pd

    rng = np.random.default_rng(2)
    df = pd.DataFrame(rng.normal(size=(40, 12)), columns=[f"{a}{i}" for i in range(1, 7) for a in "xy"])
    df.insert(0, "t", ["t%d" % i for i in range(40)])
    return df


def _issue_calls(tmp):
    csv = Path(tmp) / "f.csv"
    rng = np.random.default_rng(1)
    arr = rng.normal(size=(64, 6, 2))
    lines = ["t," + ",".join(f"x{i},y{i}" for i in range(1, 7))]
    lines += [",".join([str(k)] + [str(v) for v in arr[k].ravel() + np.tile([0.0, 0.0], 6)]) for k in range(64)]
    csv.write_text("\n".join(lines) + "\n")
    return {
        "modes(huge)": lambda: ts.modes(HUGE),
        "active(huge)": lambda: ts.active(order=HUGE, model=CRAWLER),
        "simulate(huge)": lambda: ts.simulate(HUGE),
        "simulate(steps=huge)": lambda: ts.simulate(6, steps=HUGE),
        "discover(bootstrap=huge)": lambda: ts.discover(str(csv), bootstrap=HUGE),
        "behave(params huge)": lambda: ts.behave("rearing", params={"omega_b": HUGE}, points=6),
        "modes(params huge)": lambda: ts.modes(6, params={"omega_b": HUGE}),
        "discover(empty)": lambda: ts.discover(np.zeros((0, 12, 2))),
        "discover(text array)": lambda: ts.discover(np.array([["a", "b"]])),
        "discover(text time column)": lambda: ts.discover(_frame_with_text_time()),
        "discover(fps=0)": lambda: ts.discover(arr, fps=0),
        "fit(bytes)": lambda: ts.fit(b"abc"),
        "fit(dict)": lambda: ts.fit({"a": 1}),
        "fit(figures=5)": lambda: ts.fit(str(csv), figures=5),
        "fit(fps text)": lambda: ts.fit(arr, fps="thirty"),
        "fit(fps=0)": lambda: ts.fit(arr, fps=0),
        "fit(fps=-1)": lambda: ts.fit(arr, fps=-1),
        "fit(window=-5)": lambda: ts.fit(str(csv), window=-5),
        "fit(empty list)": lambda: ts.fit([]),
        "fit(text time column)": lambda: ts.fit(_frame_with_text_time()),
        "fit(t text)": lambda: ts.fit(arr, t=["a"] * 64),
        "Model(bytes)": lambda: ts.Model(b"name = 'x'"),
    }


@pytest.mark.parametrize("name", sorted(_issue_calls(tempfile.gettempdir()).keys()))
def test_every_error_is_a_theory_search_error(name, tmp_path):
    call = _issue_calls(str(tmp_path))[name]
    with pytest.raises(ts.TheorySearchError) as caught:
        call()
    text = str(caught.value)
    assert text and "\n" not in text.strip() and len(text) <= 1000, f"{name}: {text!r}"
    assert "Exceeds the limit" not in text, text
    assert "can't convert" not in text, text


def test_bad_arguments_are_usage_errors_in_words(tmp_path):
    rng = np.random.default_rng(1)
    arr = rng.normal(size=(64, 6, 2))
    for call, needle in [
        (lambda: ts.modes(HUGE), "digits"),
        (lambda: ts.fit(arr, fps=0), "fps must be a finite number above 0"),
        (lambda: ts.fit(arr, fps="thirty"), "fps must be a number"),
        (lambda: ts.fit(str(tmp_path / "f.csv"), window=-5), "window must be between 0"),
        (lambda: ts.fit(str(tmp_path / "f.csv"), figures=5), "figures must be a folder's path"),
        (lambda: ts.fit(b"abc"), "midlines must be an array of numbers"),
        (lambda: ts.discover(np.zeros((0, 12, 2))), "no frames"),
    ]:
        with pytest.raises(ts.TheorySearchError, match=needle):
            call()


def test_fuzz_python_calls_raise_only_theory_search_errors(tmp_path):
    """The Python family of the fuzz suite: seeded random calls of every function with wrong
    types, huge integers, empty and text arrays; each works or raises a TheorySearchError of
    one bounded line."""
    import os

    # TS_FUZZ_SEED and TS_FUZZ_CASES run a longer campaign (docs/budgets.md).
    rng = np.random.default_rng(int(os.environ.get("TS_FUZZ_SEED", "53")))
    values = [0, -1, 2**64, HUGE, -HUGE, 1.5, float("nan"), float("inf"), "", "30", "x" * 5000,
              b"abc", None, [], {}, {"a": 1}, (1, 2), object(), np.zeros((0, 12, 2)),
              np.array([["a"]]), np.zeros((3, 0, 2)), np.full((20, 6, 2), np.nan), True]
    calls = {
        "modes": lambda v: ts.modes(v),
        "modes.modes": lambda v: ts.modes(6, modes=v),
        "modes.model": lambda v: ts.modes(6, model=v),
        "modes.params": lambda v: ts.modes(6, params=v),
        "active": lambda v: ts.active(order=v, model=CRAWLER),
        "active.beyond": lambda v: ts.active(model=CRAWLER, beyond_leading=v),
        "equations": lambda v: ts.equations(order=v),
        "operators": lambda v: ts.operators(v),
        "simulate.points": lambda v: ts.simulate(v, steps=2),
        "simulate.dt": lambda v: ts.simulate(6, steps=2, dt=v),
        "simulate.initial": lambda v: ts.simulate(6, steps=2, initial=v),
        "fit": lambda v: ts.fit(v),
        "fit.fps": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)), fps=v),
        "fit.t": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)), t=v),
        "fit.points": lambda v: ts.fit(np.random.default_rng(1).normal(size=(64, 6, 2)), points=v),
        "discover": lambda v: ts.discover(v, bootstrap=0),
        "discover.bootstrap": lambda v: ts.discover(np.random.default_rng(1).normal(size=(64, 6, 2)), bootstrap=v),
        "discover.fps": lambda v: ts.discover(np.random.default_rng(1).normal(size=(64, 6, 2)), fps=v, bootstrap=0),
        "behave": lambda v: ts.behave("rolling", momentum=v),
        "count": lambda v: ts.count(max_order=v),
        "stats": lambda v: ts.stats("explore", beta=v, samples=10),
        "model": lambda v: ts.Model(v),
        "from_toml": lambda v: ts.Model.from_toml(v),
    }
    names = sorted(calls)
    for _ in range(int(os.environ.get("TS_FUZZ_CASES", "150"))):
        name = names[rng.integers(len(names))]
        value = values[rng.integers(len(values))]
        try:
            calls[name](value)
        except ts.TheorySearchError as e:
            text = str(e)
            assert text and "\n" not in text.strip(), f"{name}({value!r:.80}): {text!r:.300}"
            assert len(text) <= 1000, f"{name}: {len(text)} characters"
        except BaseException as e:
            pytest.fail(f"{name}({value!r:.80}) raised {type(e).__name__}: {str(e)[:300]}")
