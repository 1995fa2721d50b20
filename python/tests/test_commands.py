"""Every command from Python: the same JSON documents as the command-line binary (run here as a
separate process), modes keyed by field against numpy, results as objects and DataFrames."""

import os
import pathlib

import numpy as np
import pytest

import theory_search as ts

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_every_command_is_a_function():
    for name in ("table", "equations", "active", "operators", "modes", "simulate", "behave", "stats",
                 "asymmetry", "mathieu", "interactions", "parts", "count", "rules", "fit",
                 "figures", "discover", "compare"):
        assert callable(getattr(ts, name)), name
        assert getattr(ts, name).__doc__, name
    assert ts.__version__ == "0.1.0"


@pytest.mark.parametrize(
    "call, args",
    [
        (lambda: ts.behave("rolling", points=9), ["behave", "rolling", "-p", "9"]),
        (lambda: ts.behave("rearing"), ["behave", "rearing", "-p", "12"]),
        (lambda: ts.behave("self-righting"), ["behave", "self-righting", "-p", "12"]),
        (lambda: ts.stats("explore", samples=500, seed=3),
         ["stats", "explore", "--samples", "500", "--seed", "3", "-p", "12"]),
        (lambda: ts.stats("pair", samples=300), ["stats", "pair", "--samples", "300"]),
        (lambda: ts.stats("pair", points=12, samples=300),
         ["stats", "pair", "--samples", "300", "-p", "12"]),
        (lambda: ts.asymmetry(coupling=-0.5), ["asymmetry", "--coupling", "-0.5"]),
        (lambda: ts.asymmetry(coupling=-0.5, points=12),
         ["asymmetry", "--coupling", "-0.5", "-p", "12"]),
        (lambda: ts.mathieu(columns=6, rows=5), ["mathieu", "--columns", "6", "--rows", "5"]),
        (lambda: ts.interactions(order=5), ["interactions", "--order", "5"]),
        (lambda: ts.parts(), ["parts", "--order", "4"]),
        (lambda: ts.parts(density="both"), ["parts", "--order", "4", "--density", "both"]),
        (lambda: ts.count(max_order=5), ["count", "--max-order", "5"]),
        (lambda: ts.rules(), ["rules", "--order", "4"]),
        (lambda: ts.active(model=str(ROOT / "tables/models/crawler.toml"), beyond_leading=1),
         ["active", "--model", str(ROOT / "tables/models/crawler.toml"), "--beyond-leading", "1"]),
        (lambda: ts.behave("hunching", points=8, force=0.03, duration=50.0),
         ["behave", "hunching", "-p", "8", "--force", "0.03", "--duration", "50"]),
        (lambda: ts.behave("self-righting", attachment="pinned", tolerance=0.02),
         ["behave", "self-righting", "--attachment", "pinned", "--tolerance", "0.02"]),
        (lambda: ts.stats("equipartition", steps=3000, temperature=0.2, seed=4),
         ["stats", "equipartition", "--steps", "3000", "--temperature", "0.2", "--seed", "4"]),
        (lambda: ts.stats("pair", omega=2.0, beta=3.0, momentum=0.5),
         ["stats", "pair", "--omega", "2", "--beta", "3", "--momentum", "0.5"]),
        (lambda: ts.asymmetry(0.2, amplitude=0.5, omega=1.5),
         ["asymmetry", "--coupling", "0.2", "--amplitude", "0.5", "--omega", "1.5"]),
        (lambda: ts.mathieu(lambda_=2.0, epsilon_max=0.3, columns=4, rows=3),
         ["mathieu", "--lambda", "2", "--epsilon-max", "0.3", "--columns", "4", "--rows", "3"]),
        (lambda: ts.interactions(order=4, density="rayleigh", beyond_leading=1),
         ["interactions", "--density", "rayleigh", "--beyond-leading", "1"]),
        (lambda: ts.count(max_order=6, basis="monomials"),
         ["count", "--max-order", "6", "--basis", "monomials"]),
        (lambda: ts.rules(order=None), ["rules"]),
    ],
)
def test_results_are_the_binarys_documents(cli, call, args):
    got = call()
    want = cli(*args)
    want = want if isinstance(want, dict) else {"rows": want}
    assert got.to_dict() == want


def test_modes_by_field_are_numpys_eigh_of_the_free_beam():
    m = ts.modes(points=57)
    d4 = next(o["matrix"] for o in ts.operators(57) if o["field"] == "y").astype(float)
    np.testing.assert_allclose(m["y"].eigenvalues, np.linalg.eigvalsh(d4), atol=1e-9)
    v = m["y"].shapes
    assert v.shape == (57, 57)
    np.testing.assert_allclose(d4 @ v, v * m["y"].eigenvalues, atol=1e-8)
    np.testing.assert_allclose(v.T @ v, np.eye(57), atol=1e-9)


def test_results_have_arrays_frames_and_html():
    pd = pytest.importorskip("pandas")
    r = ts.stats("explore", samples=400)
    assert isinstance(r.to_pandas(), pd.DataFrame)
    t = ts.table(order=4)
    frame = t.to_pandas()
    assert isinstance(frame, pd.DataFrame) and set(frame["density"]) == {"lagrangian", "rayleigh"}
    html = t._repr_html_()
    assert "<table>" in html and "(∂ss φ)²" in html
    m = ts.modes(points=12)
    assert len(m.to_pandas()) == sum(len(f.eigenvalues) for f in m.values())
    assert "<table" in m._repr_html_()
    mathieu = ts.mathieu(columns=4, rows=3)
    assert isinstance(mathieu.rows, list) and len(mathieu.to_pandas()) > 0


def test_figures_are_written(tmp_path):
    written = ts.figures(tmp_path, only="mode_shapes")
    assert [os.path.basename(p) for p in written] == ["mode_shapes.svg"]
    assert open(written[0], encoding="utf-8").read().startswith("<svg")


def test_a_model_object_reaches_every_command(tmp_path):
    planar = ts.Model.from_toml(ROOT / "tables" / "models" / "planar.toml")
    r = ts.parts(model=planar)
    assert r["model"] == "planar"


def test_simulate_takes_initial_states_forces_and_drives_as_the_binary(cli):
    # The same run by the command line's own CSV and from Python: initial mode, force, drive.
    a = ts.simulate(points=9, steps=300, every=100, initial={"y:3": (0.5, 0.0)},
                    force={"y:2": 0.2}, drive={"x:1": (0.1, 0.7)})
    doc = cli("simulate", "-p", "9", "--steps", "300", "--every", "100", "--initial",
                   "y:3=0.5,0.0", "--force", "y:2=0.2", "--drive", "x:1=0.1,0.7")
    rows = np.asarray(doc["rows"])
    at = {c: i for i, c in enumerate(doc["columns"])}
    np.testing.assert_array_equal(a["t"], rows[:, at["t"]])
    np.testing.assert_array_equal(a["energy"], rows[:, at["energy"]])
    np.testing.assert_array_equal(a["positions"]["y"][:, 4], rows[:, at["y_4"]])
    np.testing.assert_array_equal(a["modal"]["x"][:, 1], rows[:, at["q_x_1"]])
    # A nonlinear body (the tethered filament) goes the implicit integrator's way.
    tethered = ROOT / "tables" / "models" / "tethered.toml"
    t = ts.simulate(points=8, steps=200, every=50, model=tethered, params={"c4_u": 0.5},
                    initial={"u": 0.7})
    assert t["positions"]["u"].shape == (5, 8) and t["modal"]["u"].shape == (5, 0)
    # A uniform state: no differences for the friction to act on, the energy is held.
    assert np.ptp(t["energy"]) < 1e-9 * t["energy"][0]
    # The plain linear run has its energy too.
    assert ts.simulate(points=8, steps=10)["energy"].shape == (11,)


def test_a_simulation_is_the_commands_csv_as_a_dataframe(cli):
    # The exact modal path (native) and the command line print the same samples.
    sim = ts.simulate(points=7, steps=40, every=10, temperature=0.2, seed=4)
    doc = cli("simulate", "-p", "7", "--steps", "40", "--every", "10", "--temperature", "0.2",
                   "--seed", "4")
    df = sim.to_pandas()
    assert list(df.columns) == doc["columns"]
    np.testing.assert_allclose(df.to_numpy(), np.asarray(doc["rows"]), rtol=1e-12, atol=1e-15)
    assert sim.t is sim["t"] and set(sim.to_dict()) == {"t", "energy", "positions", "modal"}
    # Operators are results too: items as printed, plain data by to_dict().
    op = ts.operators(5)[0]
    assert op.field == op["field"] and op.to_dict()["matrix"] == op["matrix"].tolist()


def test_active_forces_of_a_body_with_a_head():
    r = ts.active(model=str(ROOT / "tables/models/crawler.toml"))
    y = {f["field"]: f for f in r["fields"]}["y"]
    assert [f["term"] for f in y["active"]] == ["∂sss y"]
    assert y["active"][0]["space_parity"] == -1 and y["active"][0]["kind"] == "active"
    assert y["active"][0]["coefficient"] == "a_y"
    with pytest.raises(ts.UsageError, match=r"no \[active\] section"):
        ts.active()
    with pytest.raises(ValueError):
        ts.active(order=0)


def test_a_driven_simulation_carries_the_injected_work_as_the_binary(cli):
    # An active force switched on: the implicit integrator, and the work it injects as a column.
    crawler = str(ROOT / "tables/models/crawler.toml")
    sim = ts.simulate(points=20, steps=200, every=50, dt=0.01, model=crawler,
                      params={"a_y": 0.5}, initial={"y:2": (0.1, 0.0)})
    doc = cli("simulate", "-p", "20", "--steps", "200", "--every", "50", "--dt", "0.01",
                   "--model", crawler, "--param", "a_y=0.5", "--initial", "y:2=0.1,0.0")
    df = sim.to_pandas()
    assert list(df.columns) == doc["columns"] and doc["columns"][:3] == ["t", "energy", "injected"]
    np.testing.assert_allclose(df.to_numpy(), np.asarray(doc["rows"]), rtol=1e-12, atol=1e-15)
    assert sim.injected[-1] != 0.0 and "injected" in sim.to_dict()
    # Off (the default), the run and its columns are the passive body's.
    assert "injected" not in ts.simulate(points=20, steps=10, model=crawler)


WORMPOSE = ROOT.parent / "shared" / "data" / "celegans_wormpose_15fps_52pts.csv"


@pytest.mark.skipif(not WORMPOSE.exists(), reason="the shared recordings are not here")
def test_discover_is_the_binarys_document_from_a_path_or_an_array(cli):
    got = ts.discover(str(WORMPOSE), bootstrap=20)
    want = cli("discover", str(WORMPOSE), "--bootstrap", "20")
    assert got.to_dict() == want
    # The worm's modes do not follow the passive beam: the verdict says so, with the misfit.
    assert got["verdict"]["conclusion"] == "does_not_hold"
    assert got["verdict"]["findings"][0]["finding"] == "misfit"
    assert ts.discover in (getattr(ts, n) for n in ts.__all__)
    import pandas as pd

    frame = pd.read_csv(WORMPOSE)
    midlines = frame.iloc[:, 1:].to_numpy().reshape(len(frame), -1, 2)
    from_array = ts.discover(midlines, t=frame.iloc[:, 0].to_numpy(), bootstrap=20)
    for a, b in zip(from_array["library"], want["library"]):
        assert a["name"] == b["name"]
        assert a["coefficient"] == pytest.approx(b["coefficient"], rel=1e-9)
    # A DataFrame in the recording's layout is the same animal.
    from_frame = ts.discover(frame, bootstrap=20)
    assert from_frame["library"] == from_array["library"]


@pytest.mark.skipif(not WORMPOSE.exists(), reason="the shared recordings are not here")
def test_discover_takes_values_without_files(tmp_path, monkeypatch):
    # Arrays and models go to the library as values: no temporary CSV or model file.
    import tempfile

    import pandas as pd

    empty = tmp_path / "tmp"
    empty.mkdir()
    monkeypatch.setenv("TMPDIR", str(empty))
    monkeypatch.setattr(tempfile, "tempdir", str(empty))
    frame = pd.read_csv(WORMPOSE)
    crawler = ts.Model.from_toml(str(ROOT / "tables" / "models" / "crawler.toml"))
    got = ts.discover(frame, model=crawler, bootstrap=0, time_unit="s")
    assert got["selected"], got.to_dict()
    # The library's checks, in its words: an option discover does not take, a bad value.
    with pytest.raises(ts.UsageError, match="unexpected keyword argument .window."):
        ts.discover(frame, window=64)
    with pytest.raises(ts.UsageError, match="bootstrap"):
        ts.discover(frame, bootstrap=-1)
    assert list(empty.iterdir()) == []


@pytest.mark.skipif(not WORMPOSE.exists(), reason="the shared recordings are not here")
def test_compare_is_the_binarys_comparison(cli, tmp_path):
    # Four pieces of one worm, two a group: the library's numbers, as the command prints them.
    lines = WORMPOSE.read_text().splitlines(keepends=True)
    header, rows = lines[0], lines[1:]
    for group, pieces in (("first", (rows[:400], rows[200:600])), ("second", (rows[-400:], rows[100:500]))):
        (tmp_path / group).mkdir()
        for i, piece in enumerate(pieces):
            (tmp_path / group / f"a{i}.csv").write_text(header + "".join(piece))
    first, second = str(tmp_path / "first"), str(tmp_path / "second")
    got = ts.compare(first, second, permutations=99)
    want = cli("compare", first, second, "--permutations", "99")
    assert got["differences"] == want["differences"]
    assert [g["animals"] for g in got["groups"]] == [2, 2]
    assert got["differences"][0]["quantity"] == "kappa"
    with pytest.raises(ts.UsageError, match="unexpected keyword argument .window."):
        ts.compare(first, second, window=64)
    with pytest.raises(ts.UsageError, match="permutations"):
        ts.compare(first, second, permutations=0)
    with pytest.raises(ts.InputError, match="a comparison needs 2"):
        ts.compare(str(tmp_path / "first" / "a0.csv"), second)
