"""Type stubs of theory_search."""

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

class TheorySearchError(Exception):
    """Any error of theory-search (a one-line message)."""

class UsageError(TheorySearchError):
    """A bad argument, setting or model."""

class InputError(TheorySearchError):
    """Unreadable or malformed data."""

class Model:
    """A body: fields, roles, boundaries and requirements (a model file)."""

    toml: str
    name: str
    fields: List[str]
    def __init__(self, toml: str) -> None: ...
    @classmethod
    def larva(cls) -> Model:
        """The embedded Drosophila larva model."""
    @classmethod
    def from_toml(cls, path_or_text: Union[str, os.PathLike[str]]) -> Model:
        """A model from a TOML file path or from TOML text."""

ModelLike = Optional[Union[Model, str, os.PathLike[str]]]

def table(
    order: int = 4, model: ModelLike = None, basis: str = "powers", density: str = "both"
) -> Dict[str, Any]:
    """Table 1 and its Rayleigh twin: rows, verdicts with reasons, survivors per field."""

def equations(order: int = 4, model: ModelLike = None, basis: str = "powers") -> Dict[str, Any]:
    """The equations of motion, each term with its sign claim (or the exact nonlinear ones)."""

def operators(points: int, order: int = 4, model: ModelLike = None) -> List[Dict[str, Any]]:
    """Every discretised operator, with its exact integer matrix as a numpy array."""

def modes(
    points: int,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    shapes: bool = False,
    k: Optional[int] = None,
    order: int = 4,
) -> List[Dict[str, Any]]:
    """Each field's eigenvalues, frequencies, damping ratios, variance shares (and shapes)."""

def simulate(
    points: int = 12,
    steps: int = 1000,
    dt: float = 0.01,
    every: int = 1,
    temperature: float = 0.0,
    seed: int = 1,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
) -> Dict[str, Any]:
    """Times, and per field the positions and modal coordinates as numpy arrays."""

class FitResult:
    """A fit's numbers as attributes, its spectra, components and shapes as arrays."""

    frames: int
    omega: float
    beta: float
    continuum: Optional[Dict[str, Any]]
    modes_fit: List[Dict[str, Any]]
    tests: Dict[str, Dict[str, Any]]
    noise_floor: Optional[float]
    window: Dict[str, Any]
    spacing: float
    pca_variance_share: npt.NDArray[np.float64]
    theory_variance_share: npt.NDArray[np.float64]
    mode_overlap: npt.NDArray[np.float64]
    overlap: npt.NDArray[np.float64]
    recording: Dict[str, int]
    units: Dict[str, Optional[str]]
    subspace: List[Dict[str, float]]
    intervals: Optional[Dict[str, Any]]
    animals: List[Dict[str, Any]]
    warnings: List[str]
    onward: List[str]
    frequencies: npt.NDArray[np.float64]
    psd: npt.NDArray[np.float64]
    components: npt.NDArray[np.float64]
    shapes: npt.NDArray[np.float64]
    def to_dict(self) -> Dict[str, Any]:
        """The report as plain data (the CLI's --format json)."""

def fit(
    midlines: Union[
        npt.ArrayLike, Sequence[npt.ArrayLike], str, os.PathLike[str], Sequence[Union[str, os.PathLike[str]]]
    ],
    t: Optional[Union[npt.ArrayLike, Sequence[npt.ArrayLike]]] = None,
    fps: Optional[float] = None,
    model: ModelLike = None,
    **options: Any,
) -> FitResult:
    """Fit the theory to midlines (arrays frames × points × 2, NaN for lost points) or files."""
