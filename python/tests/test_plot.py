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
    fig = tp.spectrum(fit, modes=[1])
    np.testing.assert_allclose(fig.axes[0].get_lines()[0].get_ydata(), fit.psd[1])
    fig = tp.verdicts(fit)
    labels = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert labels == list(fit.tests)
