"""The compiled module (Rust, pyo3): what the Python package calls. Not a public API."""

from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "TheorySearchError",
    "UsageError",
    "InputError",
    "MissingError",
    "OutputError",
    "NumericalError",
    "count_json",
    "rules_json",
    "terms_json",
    "asymmetry_json",
    "mathieu_json",
    "stats_json",
    "behave_json",
    "figures",
    "limits",
    "larva_toml",
    "check_model",
    "table_json",
    "equations_json",
    "active_json",
    "operators",
    "modes",
    "simulate",
    "fit_arrays",
    "fit_paths",
    "discover_json",
    "compare_json",
]

class TheorySearchError(Exception): ...
class UsageError(TheorySearchError): ...
class InputError(TheorySearchError): ...
class MissingError(TheorySearchError): ...
class OutputError(TheorySearchError): ...
class NumericalError(TheorySearchError): ...

_FitOut = Tuple[
    Dict[str, Any],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    List[str],
]

def count_json(max_order: int, model: Optional[str], basis: str) -> Any: ...
def rules_json(order: Optional[int], model: Optional[str]) -> Any: ...
def terms_json(
    table: str,
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    density: Optional[str],
) -> Any: ...
def asymmetry_json(
    coupling: float,
    amplitude: float,
    omega: Optional[float],
    points: Optional[int],
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
) -> Any: ...
def mathieu_json(
    lambda_: float, ratio_min: float, ratio_max: float, epsilon_max: float, columns: int, rows: int
) -> Any: ...
def stats_json(
    kind: str,
    points: Optional[int],
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
    ask: Mapping[str, Any],
) -> Any: ...
def behave_json(
    behaviour: str,
    points: int,
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
    ask: Mapping[str, Any],
) -> Any: ...
def figures(
    directory: str,
    only: Optional[str],
    points: int,
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
    format: str,
    width: float,
    dpi: float,
    samples: int,
    seed: int,
) -> Tuple[List[str], List[Tuple[str, str]]]: ...
def limits() -> Dict[str, int]: ...
def larva_toml() -> str: ...
def check_model(toml: str) -> Tuple[str, List[str]]: ...
_Group = Tuple[Sequence[str], Sequence[NDArray[np.float64]], Sequence[NDArray[np.float64]]]

def compare_json(
    first: _Group,
    second: _Group,
    names: Tuple[str, str],
    model: Optional[str],
    options: Optional[Mapping[str, Any]],
) -> Tuple[Dict[str, Any], List[str]]: ...
def table_json(order: int, model: Optional[str], basis: str, density: str) -> Any: ...
def equations_json(order: int, model: Optional[str], basis: str) -> Any: ...
def active_json(order: int, beyond_leading: Optional[int], model: Optional[str]) -> Any: ...
def operators(
    points: int,
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
) -> List[Dict[str, Any]]: ...
def modes(
    points: int,
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
    shapes: bool,
    k: Optional[int],
) -> List[Dict[str, Any]]: ...
def simulate(
    points: int,
    steps: int,
    dt: float,
    every: int,
    temperature: float,
    seed: int,
    order: int,
    beyond_leading: Optional[int],
    model: Optional[str],
    params: Optional[Mapping[str, float]],
    start: Tuple[List[str], List[str], List[str]],
) -> Dict[str, Any]: ...
def fit_arrays(
    animals: Sequence[NDArray[np.float64]],
    times: Sequence[NDArray[np.float64]],
    model: Optional[str],
    options: Optional[Mapping[str, Any]],
) -> _FitOut: ...
def fit_paths(
    paths: Sequence[str], model: Optional[str], options: Optional[Mapping[str, Any]]
) -> _FitOut: ...
def discover_json(
    paths: Sequence[str],
    animals: Sequence[NDArray[np.float64]],
    times: Sequence[NDArray[np.float64]],
    model: Optional[str],
    model_path: Optional[str],
    options: Optional[Mapping[str, Any]],
) -> Tuple[Dict[str, Any], List[str]]: ...
