"""Python through library values only: every public function, called with a model given as
text, arrays and paths, leaves the temporary directory empty (no model file, no CSV, no
command line run), and refuses bad keywords in the library's words."""

import html
import inspect
import pathlib
import subprocess
import sys
import textwrap

import pytest

import theory_search as ts

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "tables" / "examples" / "midlines.csv"


def test_no_function_writes_a_temporary_file_or_runs_the_command_line(tmp_path):
    empty = tmp_path / "tmp"
    empty.mkdir()
    out = tmp_path / "figures"
    groups = tmp_path / "groups"
    lines = EXAMPLE.read_text().splitlines(keepends=True)
    header, rows = lines[:2], lines[2:]
    for g, pieces in (("a", (rows[:1500], rows[750:2250])), ("b", (rows[1500:], rows[300:1800]))):
        (groups / g).mkdir(parents=True)
        for i, piece in enumerate(pieces):
            (groups / g / f"{i}.csv").write_text("".join(header + piece))
    # A fresh interpreter whose TMPDIR is the empty folder, and whose PATH has no binary: any
    # temporary file lands there, any command-line run fails.
    script = textwrap.dedent(
        f"""
        import warnings
        import numpy as np
        import pandas as pd
        import theory_search as ts

        larva = ts.Model.larva().toml  # a model as text: no file of its own
        crawler = ts.Model.from_toml({str(ROOT / "tables/models/crawler.toml")!r})
        calls = {{
            "table": lambda: ts.table(order=4, model=larva),
            "equations": lambda: ts.equations(model=larva),
            "active": lambda: ts.active(model=crawler),
            "operators": lambda: ts.operators(6, model=larva),
            "modes": lambda: ts.modes(6, model=larva),
            "simulate": lambda: ts.simulate(6, steps=5, model=larva),
            "behave": lambda: [ts.behave(b, points=6, model=larva, duration=20.0, periods=2.0)
                               for b in ("peristalsis", "rolling", "rearing", "hunching",
                                         "self-righting")],
            "stats": lambda: [ts.stats("explore", points=6, samples=100, model=larva),
                              ts.stats("equipartition", points=6, steps=500, model=larva),
                              ts.stats("pair", points=6, samples=100, model=larva)],
            "asymmetry": lambda: ts.asymmetry(0.1, points=6, model=larva),
            "mathieu": lambda: ts.mathieu(columns=3, rows=3),
            "interactions": lambda: ts.interactions(model=larva),
            "parts": lambda: ts.parts(model=larva),
            "count": lambda: ts.count(max_order=4, model=larva),
            "rules": lambda: ts.rules(model=larva),
            "figures": lambda: ts.figures({str(out)!r}, only="spectrum", points=6, model=larva),
            "fit": lambda: ts.fit(pd.read_csv({str(EXAMPLE)!r}, comment="#"), model=larva),
            "discover": lambda: ts.discover({str(EXAMPLE)!r}, bootstrap=0, model=larva),
            "compare": lambda: ts.compare({str(groups / "a")!r}, {str(groups / "b")!r},
                                          model=larva, permutations=9),
        }}
        missing = sorted(set(ts.__all__) - set(calls) - {{
            "Model", "Result", "DiscoverResult", "Modes", "FieldModes", "Simulation", "FitResult",
            "TheorySearchError", "UsageError", "InputError", "MissingFileError", "OutputError",
            "NumericalError", "plot", "limits", "__version__", "ModelLike",
        }})
        assert not missing, f"functions this test does not call: {{missing}}"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for name, call in calls.items():
                try:
                    call()
                except ts.NumericalError:
                    pass  # a computation that fails on this body is still a library call
        print("called", len(calls))
        """
    )
    env = {"TMPDIR": str(empty), "PATH": str(tmp_path), "HOME": str(tmp_path)}
    run = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "called" in run.stdout
    assert list(empty.iterdir()) == []
    assert [p.name for p in out.iterdir()] == ["spectrum.svg"]


def test_no_native_function_runs_the_command_line():
    assert not hasattr(ts._native, "run_cli")
    assert not hasattr(ts, "run")


def test_every_keyword_is_typed_and_documented():
    # No **options where a command's options are known: an editor offers each one.
    for name in ("behave", "stats", "asymmetry", "mathieu", "interactions", "parts", "count",
                 "rules", "figures", "fit", "discover", "compare"):
        fn = getattr(ts, name)
        params = inspect.signature(fn).parameters.values()
        assert not any(p.kind == p.VAR_KEYWORD for p in params), name
        for p in params:
            assert p.annotation is not inspect.Parameter.empty, (name, p.name)
            assert f"{p.name} :" in fn.__doc__, (name, p.name)


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda: ts.stats("walk"), "not \"walk\""),
        (lambda: ts.behave("self-righting", points=6, attachment="glued"), "attachment"),
        (lambda: ts.count(max_order=40), "from 1 to 32"),
        (lambda: ts.parts(density="kinetic"), "density"),
        (lambda: ts.figures("unused", format="gif"), "svg"),
        (lambda: ts.stats("pair", omega=2.0, params={"omega_t": 2.0}), "no effect"),
        (lambda: ts.stats("equipartition", points=6, steps=10, field="q"), "no field"),
        (lambda: ts.behave("rearing", points=5000), "at most 2000 points"),
        (lambda: ts.interactions(beyond_leading=99), "beyond_leading"),
        (lambda: ts.stats("pair", samples=5), "samples must be between"),
    ],
)
def test_the_library_refuses_in_its_words(call, words):
    with pytest.raises(ts.UsageError) as e:
        call()
    assert words in str(e.value)
    assert "\n" not in str(e.value).strip()
    assert "--" not in str(e.value), "a keyword argument, not the command line's flag"


def test_notebook_views_lead_with_verdicts_kappa_and_terms():
    fit = ts.fit(str(EXAMPLE))
    page = fit._repr_html_()
    kappa = fit.continuum
    assert f"κ = {kappa['constant']:.6g} [{kappa['interval'][0]:.6g}" in page
    for law, t in fit.tests.items():
        assert law in page and f"<b>{t['verdict']}</b>" in page
    found = ts.discover(str(EXAMPLE), bootstrap=20)
    assert isinstance(found, ts.DiscoverResult) and isinstance(found, ts.Result)
    page = found._repr_html_()
    assert f"the theory: {found['verdict']['conclusion']}" in page
    for t in found["selected"]:
        assert html.escape(t["name"]) in page and f"{t['coefficient']:.6g}" in page
    # Text from a recording is escaped in markup.
    found["equation"] = "<script>"
    assert "<script>" not in found._repr_html_()
