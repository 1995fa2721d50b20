"""One body, one path: ``modes``, ``operators`` and ``simulate`` from Python give the command
line's numbers on every shipped model (the nonlinear tethered filament and the larva at the next
order included), and ``params`` takes every name ``--param`` takes."""

from pathlib import Path

import numpy as np
import pytest

import theory_search as ts

MODELS = Path(__file__).resolve().parents[2] / "tables" / "models"
BODIES = [
    (None, None, {}),
    (None, 1, {"c2_x": 1.0, "cp1_x": 0.5}),
    ("tethered.toml", None, {"c2_u": 1.0, "c4_u": 0.5}),
] + [(p.name, None, {}) for p in sorted(MODELS.glob("*.toml")) if p.name != "tethered.toml"]


def _cli_args(model, beyond_leading, params):
    args = [w for k, v in params.items() for w in ("--param", f"{k}={v!r}")]
    if model:
        args += ["--model", str(MODELS / model)]
    if beyond_leading is not None:
        args += ["--beyond-leading", str(beyond_leading)]
    return args


def _py_options(model, beyond_leading, params):
    return {
        "model": str(MODELS / model) if model else None,
        "beyond_leading": beyond_leading,
        "params": params,
    }


@pytest.mark.parametrize("model,beyond_leading,params", BODIES)
def test_modes_are_the_command_lines(cli, model, beyond_leading, params):
    cli = cli("modes", "-p", "12", *_cli_args(model, beyond_leading, params))
    py = ts.modes(points=12, **_py_options(model, beyond_leading, params))
    assert [f["field"] for f in cli["fields"]] == list(py)
    for f in cli["fields"]:
        got = py[f["field"]]
        np.testing.assert_array_equal(got.eigenvalues, np.asarray(f["eigenvalues"], float))
        want = np.array([np.nan if w is None else w for w in f["frequencies"]], float)
        np.testing.assert_array_equal(got.frequencies, want)
        if "damped" in f:  # a linearisation: the roots of λ²M + λC + K too
            np.testing.assert_array_equal(got.decay_rates, [r["decay_rate"] for r in f["damped"]])
            np.testing.assert_array_equal(
                got.damped_frequencies, [r["frequency"] for r in f["damped"]]
            )
            assert len(got.to_pandas()) == len(got.eigenvalues)


@pytest.mark.parametrize("model,beyond_leading,params", BODIES)
def test_operators_are_the_command_lines(cli, model, beyond_leading, params):
    cli = cli("operators", "-p", "8", *_cli_args(model, beyond_leading, params))
    py = ts.operators(points=8, **_py_options(model, beyond_leading, params))
    if cli.get("linearised"):
        assert len(py) == len(cli["fields"])
        for got, want in zip(py, cli["fields"]):
            assert got["field"] == want["field"] and got["linearised"]
            for key in ("stiffness", "damping", "mass"):
                np.testing.assert_array_equal(got[key], np.asarray(want[key], float))
    else:
        assert len(py) == len(cli["operators"])
        for got, want in zip(py, cli["operators"]):
            assert (got["field"], got["term"]) == (want["field"], want["term"])
            np.testing.assert_array_equal(got["matrix"], np.asarray(want["matrix"]))


@pytest.mark.parametrize("model,beyond_leading,params", BODIES)
def test_a_run_is_the_command_lines(cli, model, beyond_leading, params):
    ids = ts.Model.from_toml(MODELS / model).fields if model else ts.Model.larva().fields
    field = ids[-1]
    start = {"initial": [f"{field}:2=0.3,0.1"], "drive": [f"{ids[0]}:1=0.05,1.3"]}
    cli = cli(
        "simulate", "-p", "9", "--steps", "40", "--every", "10", "--temperature", "0.01",
        "--seed", "3", "--initial", start["initial"][0], "--drive", start["drive"][0],
        *_cli_args(model, beyond_leading, params),
    )
    py = ts.simulate(
        points=9, steps=40, every=10, temperature=0.01, seed=3,
        **start, **_py_options(model, beyond_leading, params),
    )
    rows = np.asarray(cli["rows"], float)
    np.testing.assert_array_equal(py.t, rows[:, 0])
    np.testing.assert_array_equal(py.energy, rows[:, 1])
    np.testing.assert_array_equal(py.to_pandas().to_numpy(), rows)


def test_params_take_every_name_the_command_line_takes():
    # c_y = ω² is omega_b = 2 on the linear path; cp_y = ζω then sets zeta_b.
    by_names = ts.modes(points=12, params={"c_y": 4.0, "cp_y": 0.6})
    by_scales = ts.modes(points=12, params={"omega_b": 2.0, "zeta_b": 0.3})
    np.testing.assert_allclose(by_names["y"].frequencies, by_scales["y"].frequencies, rtol=1e-15)
    np.testing.assert_allclose(
        by_names["y"].damping_ratios, by_scales["y"].damping_ratios, rtol=1e-15
    )
    # Printed (primed, Greek) and ASCII names are one coefficient.
    a = ts.simulate(points=8, steps=20, beyond_leading=1, params={"c'1_x": 0.5, "c2_x": 1.0},
                    initial={"x:1": 0.3})
    b = ts.simulate(points=8, steps=20, beyond_leading=1, params={"cp1_x": 0.5, "c2_x": 1.0},
                    initial={"x:1": 0.3})
    np.testing.assert_array_equal(a.positions["x"], b.positions["x"])


def test_errors_are_typed_by_kind():
    tethered = MODELS / "tethered.toml"
    with pytest.raises(ts.NumericalError) as e:
        ts.operators(points=4, model=tethered, params={"c4_u": 1e308})
    assert isinstance(e.value, ArithmeticError) and "\n" not in str(e.value)
    with pytest.raises(ts.UsageError) as e:
        ts.modes(points=12, params={"nope": 1.0})
    assert len(str(e.value)) < 400
    with pytest.raises(ts.UsageError):
        ts.simulate(points=12, initial={"y": 1.0})  # a uniform state is for a nonlinear body
    # numpy integers are whole numbers.
    assert len(ts.modes(points=np.int64(12), modes=np.int32(3))["y"].eigenvalues) == 3


def test_what_a_notebook_user_passes(tmp_path):
    # Every command is a function of its own, with typed keywords (no argv runner).
    assert not hasattr(ts, "run")
    assert ts.behave("rearing", points=8)
    # A directory of recordings, as the command line takes it.
    worm = Path(__file__).resolve().parents[3] / "shared" / "data" / "celegans_wormpose_15fps_52pts.csv"
    (tmp_path / "a.csv").symlink_to(worm)
    (tmp_path / "notes.md").write_text("not a recording")
    by_dir = ts.fit(str(tmp_path), window=64)
    by_file = ts.fit(str(worm), window=64)
    assert by_dir.omega == by_file.omega
    # Messages in Python's words: no "--help", ranges as words.
    with pytest.raises(ts.UsageError) as e:
        ts.modes(points=0)
    assert "--help" not in str(e.value) and "..=" not in str(e.value)


def test_a_dataframe_and_figures_from_a_notebook(tmp_path):
    import pandas as pd

    worm = Path(__file__).resolve().parents[3] / "shared" / "data" / "celegans_wormpose_15fps_52pts.csv"
    by_file = ts.fit(str(worm), window=64)
    # The CSV's own layout as pandas reads it: t, then x1, y1, … (NaN rows are lost frames).
    by_frame = ts.fit(pd.read_csv(worm), window=64)
    np.testing.assert_allclose(by_frame.omega, by_file.omega, rtol=1e-9)
    assert by_file.figures == []
    drawn = ts.fit(str(worm), window=64, figures=tmp_path / "figs", figure_format="png",
                   figure_width=85)
    assert drawn.figures and all(Path(p).is_file() and p.endswith(".png") for p in drawn.figures)
    with pytest.raises(ts.UsageError):
        ts.fit(str(worm), window=64, figure_format="png")  # without figures= it would do nothing


def test_modes_takes_the_command_lines_name_and_the_old_one_warns():
    new = ts.modes(points=12, modes=3)["y"].eigenvalues
    with pytest.warns(DeprecationWarning, match="--modes"):
        old = ts.modes(points=12, k=3)["y"].eigenvalues
    assert len(new) == 3 and list(new) == list(old)
