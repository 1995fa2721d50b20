"""What the tests share: the command-line binary (fixture ``cli``), the oracle the Python functions are checked
against (run as a separate process; the package itself never runs it)."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# Where cargo put it: CARGO_TARGET_DIR when set (relative to the checkout), else target/.
TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", "target"))
BINARY = (TARGET if TARGET.is_absolute() else ROOT / TARGET) / "release" / "theory-search"


def _cli_json(*args):
    """The binary's --format json document (cargo test --release builds it before pytest)."""
    assert BINARY.exists(), f"build the binary first: {BINARY}"
    out = subprocess.run(
        [str(BINARY), *args, "--format", "json"], check=True, capture_output=True, text=True
    )
    return json.loads(out.stdout)


@pytest.fixture
def cli():
    """``cli("modes", "-p", "8")``: the binary's JSON document for those arguments."""
    return _cli_json
