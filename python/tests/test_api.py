"""Each public function against an independent numpy/scipy computation, and the error paths."""

import json
import os
import subprocess
import pathlib

import numpy as np
import pytest
import scipy.linalg

import theory_search as ts

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / ".." / "shared" / "data"


def test_modes_are_the_eigenvalues_of_the_returned_operators():
    points = 30
    ops = {(o["field"], o["density"]): o["matrix"] for o in ts.operators(points)}
    for field, fm in ts.modes(points, shapes=True).items():
        stiffness = ops[(field, "lagrangian")].astype(float)
        expected = scipy.linalg.eigh(stiffness, eigvals_only=True)
        np.testing.assert_allclose(fm.eigenvalues, expected, atol=1e-9, rtol=1e-9)
        # Shapes are eigenvectors as columns (numpy's eigh): D v = λ v.
        v = fm.shapes
        assert v.shape == (stiffness.shape[0], len(fm.eigenvalues))
        np.testing.assert_allclose(stiffness @ v, v * fm.eigenvalues, atol=1e-8)


def test_modes_take_the_lowest_k_and_the_scales():
    full = ts.modes(200, params={"omega_b": 2.0})
    few = ts.modes(200, params={"omega_b": 2.0}, modes=5)
    assert list(full) == ["x", "theta", "y", "z"]
    for field in full:
        np.testing.assert_allclose(
            few[field].eigenvalues, full[field].eigenvalues[:5], rtol=1e-9, atol=1e-12
        )
    y = full["y"]
    assert y.omega == 2.0
    np.testing.assert_allclose(y.frequencies, 2.0 * np.sqrt(y.eigenvalues), atol=1e-12)
    # Shapes not asked for are computed on first read: the k lowest, as asked with shapes=True.
    assert few["y"]._shapes is None
    np.testing.assert_array_equal(
        few["y"].shapes, ts.modes(200, params={"omega_b": 2.0}, modes=5, shapes=True)["y"].shapes
    )
    # One native call computed every field's shapes.
    assert few["y"].shapes.shape == (200, 5) and set(few._with_shapes) == set(few)


def test_table_rows_follow_the_rules_as_stated():
    doc = ts.table()
    rows = doc["lagrangian"]["rows"]
    # Independently: pure powers (∂tᵃ∂sᵇφ)ⁿ with a+b ≤ 4, n ≤ 4, n(a+b) ≤ 4 ... and τ+σ ≤ 4.
    expected = sorted(
        (a, b, n)
        for a in range(5)
        for b in range(5)
        for n in range(1, 5)
        if a + b <= 4 and n * (a + b) <= 4
    )
    got = sorted((r["tau"] // r["epsilon"], r["sigma"] // r["epsilon"], r["epsilon"]) for r in rows)
    assert got == expected
    for r in rows:
        # REF is φ → −φ: even powers only; OST: at most one time derivative.
        assert r["satisfies"]["REF"] == (r["epsilon"] % 2 == 0), r
        assert r["satisfies"]["OST"] == (r["tau"] // r["epsilon"] <= 1), r
        for code, ok in r["satisfies"].items():
            assert ok == (code not in r.get("rejected", {})), r
    assert doc["lagrangian"]["survivors"]["y"] == ["(∂t φ)²", "(∂ss φ)²"]


def test_table_to_pandas():
    pd = pytest.importorskip("pandas")
    frame = ts.table(density="lagrangian")["lagrangian"].to_pandas()
    assert isinstance(frame, pd.DataFrame) and len(frame) == 27


def test_equations_are_the_wave_and_beam_equations():
    eqs = {e["field"]: e for e in ts.equations()["equations"]}
    y = [(t["t"], t["s"], t["sign"]) for t in eqs["y"]["rhs"]]
    assert y == [(0, 4, -1), (1, 4, -1)]
    assert eqs["x"]["rhs"][0]["claim"]["sign"] == "positive"


def test_simulate_reaches_equipartition():
    kt = 1e-3
    out = ts.simulate(points=12, steps=200_000, dt=0.5, every=5, temperature=kt, seed=3,
                      params={"omega_b": 1.0, "zeta_b": 0.2})
    q = out["modal"]["y"][2000:]
    lam = ts.modes(12)["y"].eigenvalues
    # Var Qᵢ = kT/(ω²λᵢ) for the first non-zero modes (independent of the simulator's code).
    for i in (2, 3):
        assert abs(q[:, i].var() * lam[i] / kt - 1.0) < 0.15, (i, q[:, i].var() * lam[i] / kt)
    assert out["positions"]["y"].shape == (len(out["t"]), 12)


def _synthetic(animals=3, frames=6000, kt=1e-4, seed=5):
    out = []
    for a in range(animals):
        sim = ts.simulate(points=12, steps=frames + 499, dt=1.0, every=1, temperature=kt,
                          seed=seed + a, params={"omega_b": 1.0, "zeta_b": 0.05})
        y = sim["positions"]["y"][500:]
        x = np.broadcast_to(np.arange(12, dtype=float), y.shape)
        out.append(np.stack([x, y], axis=-1))
    return out


def test_fit_recovers_omega_and_beta_from_arrays():
    kt = 1e-4
    animals = _synthetic(kt=kt)
    r = ts.fit(animals, head="last", window=512, fit_modes=2)
    assert abs(r.omega - 1.0) < 0.03, r.omega
    assert abs(r.beta * kt - 1.0) < 0.2, r.beta * kt
    assert r.pca_variance_share.shape == (10,)
    assert len(r.animals) == 3
    assert r.to_dict()["frames"] == 3 * 6000
    # A lost point loses its frame: bridged by default (gaps of at most 2 frames), a split
    # without bridging.
    gappy = animals[0].copy()
    gappy[100, 3, 1] = np.nan
    r = ts.fit(gappy, head="last", window=512)
    assert r.recording["frames_lost"] == 1 and r.recording["frames_filled"] == 1
    assert r.recording["runs"] == 1
    r = ts.fit(gappy, head="last", window=512, fill_gaps=0)
    assert r.recording["frames_lost"] == 1 and r.recording["runs"] == 2


def test_fit_reads_recordings_from_paths():
    path = DATA / "celegans_wormpose_15fps_52pts.csv"
    if not path.exists():
        pytest.skip("../shared/data is not beside the repository")
    r = ts.fit(str(path), window=64)
    assert r.recording["frames_lost"] == 280
    assert (r.mode_overlap[:3] > 0.95).all()
    both = ts.fit([str(p) for p in sorted(DATA.glob("*wormpose*.csv"))], window=64)
    assert both.frames == r.frames
    # The verdict, as the command line gives it: the worm is not a passive beam.
    cli = json.loads(
        subprocess.run(
            ["cargo", "run", "--release", "-q", "--", "fit", str(path), "--window", "64", "--format", "json"],
            capture_output=True, text=True, check=True, cwd=ROOT,
        ).stdout
    )
    # The same numbers (to rounding: the module and the binary are compiled apart).
    assert r.window == cli["window"]
    for name, test in cli["tests"].items():
        mine = r.tests[name]
        assert mine["verdict"] == test["verdict"] and mine["modes"] == test["modes"]
        if test["interval"] is None:
            assert mine["interval"] is None
        else:
            assert mine["interval"] == pytest.approx(test["interval"], rel=1e-5)
    assert r.tests["dispersion"]["verdict"] == "rejected"
    assert r.continuum["interval"] == pytest.approx(cli["continuum"]["interval"], rel=1e-5)
    assert r.noise_floor == pytest.approx(cli["noise_floor"], rel=1e-5)
    assert [m["omega"] for m in r.modes_fit] == pytest.approx(
        [m["omega"] for m in cli["modes_fit"]], rel=1e-5
    )
    assert set(r.modes_fit[0]) >= {"mode", "lambda", "omega", "omega_error", "zeta", "zeta_error", "variance", "resolved"}


def test_models_from_text_and_files(tmp_path):
    larva = ts.Model.larva()
    assert larva.fields == ["x", "theta", "y", "z"]
    p = tmp_path / "larva.toml"
    p.write_text(larva.toml)
    assert ts.Model.from_toml(p).name == "larva"
    assert ts.Model.from_toml(str(p)).toml == larva.toml


@pytest.mark.parametrize(
    "call, error",
    [
        (lambda: ts.table(basis="fancy"), ts.UsageError),
        (lambda: ts.table(order=0), ts.UsageError),
        (lambda: ts.Model("name = 1"), ts.UsageError),
        (lambda: ts.modes(12, params={"omega_b": float("nan")}), ts.UsageError),
        (lambda: ts.modes(1), ts.UsageError),
        (lambda: ts.fit("/nonexistent/file.csv"), FileNotFoundError),
        (lambda: ts.Model.from_toml("missing.toml"), FileNotFoundError),
        (lambda: ts.modes(points=0), ValueError),
        (lambda: ts.modes(points=-1), ValueError),
        (lambda: ts.modes(points=10**30), ValueError),
        (lambda: ts.behave("flying"), ValueError),
        (lambda: ts.fit(np.zeros((10, 6, 3))), ts.UsageError),
        (lambda: ts.fit(np.zeros((10, 6, 2)), window=4), ts.UsageError),
        (lambda: ts.fit(np.zeros((20, 6, 2)), nonsense=1), ts.UsageError),
    ],
)
def test_errors_are_one_line_exceptions(call, error):
    with pytest.raises(error) as e:
        call()
    assert isinstance(e.value, ts.TheorySearchError)
    assert "\n" not in str(e.value) and str(e.value)
