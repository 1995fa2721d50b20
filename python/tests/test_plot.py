"""theory_search.plot: each function returns a matplotlib Figure drawing the result's numbers."""

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pathlib

import theory_search as ts
import theory_search.plot as tp

DATA = pathlib.Path(__file__).resolve().parents[3] / "shared" / "data"


def test_modes_draws_the_shape_columns():
    m = ts.modes(points=20, shapes=True)
    fig = tp.modes(m, field="y", count=3)
    lines = fig.axes[0].get_lines()
    drawn = [l for l in lines if len(l.get_ydata()) == 20]
    assert len(drawn) == 3
    # The first non-zero beam mode (index 2: two zero modes) is column 2 of the shapes.
    np.testing.assert_allclose(drawn[0].get_ydata(), m["y"].shapes[:, 2])


def test_simulation_spectrum_and_verdicts():
    sim = ts.simulate(points=12, steps=500, temperature=0.01)
    fig = tp.simulation(sim, field="y", points=[3])
    np.testing.assert_allclose(fig.axes[0].get_lines()[0].get_ydata(), sim["positions"]["y"][:, 3])
    fit = ts.fit(DATA / "celegans_wormpose_15fps_52pts.csv", window=64)
    # Modes by the report's numbers: row j of psd is mode modes[j]["index"] (2, 3, … here).
    numbers = [m["index"] for m in fit.to_dict()["modes"]]
    fig = tp.spectrum(fit, modes=[numbers[1], numbers[0]])
    curves = [l for l in fig.axes[0].get_lines() if len(l.get_ydata()) == len(fit.frequencies)]
    np.testing.assert_allclose(curves[0].get_ydata(), fit.psd[1])
    np.testing.assert_allclose(curves[1].get_ydata(), fit.psd[0])
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == [f"mode {numbers[1]}", f"mode {numbers[0]}"]
    # Each theory line sits at its own mode's theory frequency.
    theory = [m["theory_angular_frequency"] / (2 * np.pi) for m in fit.to_dict()["modes"]]
    marks = [l.get_xdata()[0] for l in fig.axes[0].get_lines() if len(l.get_xdata()) == 2]
    np.testing.assert_allclose(marks, [theory[1], theory[0]])
    # Mode 0 (a zero mode: no spectrum fitted) draws nothing.
    assert not tp.spectrum(fit, modes=[0]).axes[0].get_lines()
    fig = tp.verdicts(fit)
    labels = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert labels == list(fit.tests)
