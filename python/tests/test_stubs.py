"""The type stubs (theory_search/__init__.pyi) match the package: every public name is in them,
and every function's parameters (names, kinds, defaults) are the runtime's."""

import ast
import inspect
import pathlib

import theory_search as ts

STUB = pathlib.Path(ts.__file__).with_name("__init__.pyi")


def stub_definitions():
    tree = ast.parse(STUB.read_text(encoding="utf-8"))
    functions, names = {}, set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            functions[node.name] = node
            names.add(node.name)
        elif isinstance(node, ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
    return functions, names


def test_every_public_name_is_in_the_stubs():
    _, names = stub_definitions()
    missing = [n for n in ts.__all__ if n not in names]
    assert not missing, missing


def test_function_signatures_match():
    functions, _ = stub_definitions()
    for name, node in functions.items():
        runtime = inspect.signature(getattr(ts, name))
        args = node.args
        stub = [a.arg for a in args.posonlyargs + args.args]
        defaults = [ast.literal_eval(d) if not isinstance(d, ast.Name) else None for d in args.defaults]
        params = [p for p in runtime.parameters.values() if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]
        assert [p.name for p in params] == stub, (name, [p.name for p in params], stub)
        with_default = [p.default for p in params if p.default is not inspect.Parameter.empty]
        assert with_default == defaults, (name, with_default, defaults)
        assert (args.kwarg is not None) == any(
            p.kind == p.VAR_KEYWORD for p in runtime.parameters.values()
        ), name


def test_mypy_stubtest_finds_the_stubs_true():
    """mypy's stubtest: every stub (the public package and the native module) against the
    installed package at runtime: names, signatures, classes, `__all__`."""
    import subprocess
    import sys
    import tempfile

    config = pathlib.Path(__file__).resolve().parents[2] / "pyproject.toml"
    with tempfile.TemporaryDirectory() as cwd:  # away from the source tree
        run = subprocess.run(
            [sys.executable, "-m", "mypy.stubtest", "theory_search", "--mypy-config-file", str(config)],
            cwd=cwd,
            capture_output=True,
            text=True,
        )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Success" in run.stdout
