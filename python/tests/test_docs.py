"""docs/python.md: every Python block runs (from the repository root), its asserts included."""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_every_python_block_of_the_python_page_runs(monkeypatch):
    text = (ROOT / "docs" / "python.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    monkeypatch.chdir(ROOT)
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/python.md block {i}", "exec"), {})
