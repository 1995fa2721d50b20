"""The README's Python example runs as shown (from the repository root, as CI runs pytest)."""
import contextlib
import io
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]


def python_blocks():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def test_the_readme_python_example_runs_and_prints_what_it_says(monkeypatch):
    blocks = python_blocks()
    assert blocks, "the README shows Python"
    monkeypatch.chdir(ROOT)
    for block in blocks:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(block, "README.md", "exec"), {})
        printed = out.getvalue()
        # Each commented claim the block makes about what it prints.
        for claim in re.findall(r"#\s*(\(\d+, \d+\))", block):
            assert claim in printed, f"README claims {claim}; printed {printed!r}"
