"""Type stubs of theory_search."""

import os
from typing import Any, Callable, Dict, Iterator, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__all__ = [
    "__version__",
    "Model",
    "ModelLike",
    "Result",
    "Modes",
    "FieldModes",
    "FitResult",
    "DiscoverResult",
    "Simulation",
    "TheorySearchError",
    "UsageError",
    "InputError",
    "MissingFileError",
    "OutputError",
    "NumericalError",
    "table",
    "equations",
    "active",
    "operators",
    "modes",
    "simulate",
    "behave",
    "stats",
    "asymmetry",
    "mathieu",
    "interactions",
    "parts",
    "count",
    "rules",
    "figures",
    "fit",
    "discover",
    "compare",
]

class TheorySearchError(Exception):
    """Any error of theory-search (a one-line message)."""

class UsageError(TheorySearchError, ValueError):
    """A bad argument, setting or model."""

class InputError(TheorySearchError, ValueError):
    """Malformed data."""

class MissingFileError(TheorySearchError, FileNotFoundError):
    """A file that does not exist."""

class OutputError(TheorySearchError, OSError):
    """Output that cannot be written."""

class NumericalError(TheorySearchError, ArithmeticError):
    """A computation that failed on valid input (exit code 3)."""

__version__: str

class Result(Dict[str, Any]):
    """A command's JSON document: items as printed, attributes with numpy arrays."""

    def __getattr__(self, name: str) -> Any: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def to_pandas(self) -> Any: ...
    def _repr_html_(self) -> str: ...

class DiscoverResult(Result):
    """discover's document; its notebook view leads with the verdict and the selected terms."""

    def _repr_html_(self) -> str: ...

class FieldModes:
    """One field's modes; shapes are points × modes (columns), computed on first read."""

    def __init__(
        self,
        record: Mapping[str, Any],
        shapes_of: Optional[Callable[[], Optional[npt.NDArray[np.float64]]]] = None,
    ) -> None: ...
    field: str
    eigenvalues: npt.NDArray[np.float64]
    frequencies: npt.NDArray[np.float64]
    damping_ratios: npt.NDArray[np.float64]
    variance_shares: npt.NDArray[np.float64]
    @property
    def shapes(self) -> Optional[npt.NDArray[np.float64]]: ...
    k: Optional[int]
    omega: Optional[float]
    zeta: Optional[float]
    nullity: Optional[int]
    inverse_trace: Optional[float]
    linearised: bool
    equilibrium: npt.NDArray[np.float64]
    decay_rates: npt.NDArray[np.float64]
    damped_frequencies: npt.NDArray[np.float64]
    def to_dict(self) -> Dict[str, Any]: ...
    def to_pandas(self) -> Any: ...

class Modes(Mapping[str, FieldModes]):
    """Every field's modes, keyed by field id."""

    def __init__(
        self,
        records: List[Mapping[str, Any]],
        load_shapes: Optional[Callable[[], List[Mapping[str, Any]]]] = None,
    ) -> None: ...
    def __getitem__(self, field: str) -> FieldModes: ...
    def __iter__(self) -> Iterator[str]: ...
    def __len__(self) -> int: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def to_pandas(self) -> Any: ...
    def _repr_html_(self) -> str: ...

class Table(Dict[str, Any]):
    """Table 1 and its Rayleigh twin, by density."""

    def to_dict(self) -> Dict[str, Any]: ...
    def to_pandas(self) -> Any: ...
    def _repr_html_(self) -> str: ...

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
) -> Table:
    """Table 1 and its Rayleigh twin: rows, verdicts with reasons, survivors per field."""

def equations(order: int = 4, model: ModelLike = None, basis: str = "powers") -> Result:
    """The equations of motion, each term with its sign claim (or the exact nonlinear ones)."""

def active(
    order: int = 4, model: ModelLike = None, beyond_leading: Optional[int] = None
) -> Result:
    """The active forces a model's ``[active]`` section allows (``theory-search active``)."""

def operators(
    points: int,
    order: int = 4,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    beyond_leading: Optional[int] = None,
) -> List[Result]:
    """Every discretised operator (exact integers), or a nonlinear body's linearisation."""

def modes(
    points: int,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    shapes: bool = False,
    modes: Optional[int] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
    k: Optional[int] = None,
) -> Modes:
    """Each field's modes keyed by field id (shapes as points × modes columns)."""

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
    initial: Any = None,
    force: Any = None,
    drive: Any = None,
    beyond_leading: Optional[int] = None,
) -> Simulation:
    """Times, energies, and per field the positions and modal coordinates as numpy arrays."""

class Simulation(Dict[str, Any]):
    """A simulation: t, energy, injected (with active forces only), positions and modal."""

    t: npt.NDArray[np.float64]
    energy: npt.NDArray[np.float64]
    injected: npt.NDArray[np.float64]
    positions: Dict[str, npt.NDArray[np.float64]]
    modal: Dict[str, npt.NDArray[np.float64]]
    def __getattr__(self, name: str) -> Any: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def to_pandas(self) -> Any: ...
    def _repr_html_(self) -> str: ...

class FitResult:
    """A fit's numbers as attributes, its spectra, components and shapes as arrays."""

    def __init__(
        self,
        report: Dict[str, Any],
        frequencies: npt.NDArray[np.float64],
        psd: npt.NDArray[np.float64],
        components: npt.NDArray[np.float64],
        shapes: npt.NDArray[np.float64],
        figures: Optional[Sequence[str]] = None,
    ) -> None: ...
    figures: List[str]
    frames: int
    omega: float
    beta: float
    continuum: Optional[Dict[str, Any]]
    modes_fit: List[Dict[str, Any]]
    tests: Dict[str, Dict[str, Any]]
    noise_floor: Optional[float]
    window: Dict[str, Any]
    tracking_noise: Optional[Dict[str, Any]]
    spacing: float
    pca_variance_share: npt.NDArray[np.float64]
    theory_variance_share: npt.NDArray[np.float64]
    mode_overlap: npt.NDArray[np.float64]
    overlap: npt.NDArray[np.float64]
    recording: Dict[str, int]
    units: Dict[str, Optional[str]]
    subspace: List[Dict[str, float]]
    intervals: Optional[Dict[str, Any]]
    spread: Optional[Dict[str, Any]]
    animals: List[Dict[str, Any]]
    warnings: List[str]
    held_movement: Optional[float]
    onward: List[str]
    frequencies: npt.NDArray[np.float64]
    psd: npt.NDArray[np.float64]
    components: npt.NDArray[np.float64]
    shapes: npt.NDArray[np.float64]
    def to_dict(self) -> Dict[str, Any]:
        """The report as plain data (the CLI's --format json)."""
    def to_pandas(self) -> Any: ...
    def _repr_html_(self) -> str: ...

def fit(
    midlines: Any,  # arrays, paths, a DataFrame, or a tracker's object (movement, SLEAP, DeepLabCut)
    t: Optional[Union[npt.ArrayLike, Sequence[npt.ArrayLike]]] = None,
    fps: Optional[float] = None,
    model: ModelLike = None,
    keypoints: Optional[Sequence[str]] = None,
    individuals: Optional[Sequence[str]] = None,
    points: Optional[int] = None,
    kind: Optional[str] = None,
    field: Optional[str] = None,
    order: Optional[int] = None,
    ring: Optional[int] = None,
    fill_gaps: Optional[int] = None,
    head: Optional[str] = None,
    min_likelihood: Optional[float] = None,
    input_format: Optional[str] = None,
    track_column: Optional[bool] = None,
    time_unit: Optional[str] = None,
    length_unit: Optional[str] = None,
    window: Optional[int] = None,
    estimator: Optional[str] = None,
    fit_modes: Optional[int] = None,
    omega: Optional[float] = None,
    bootstrap: Optional[int] = None,
    seed: Optional[int] = None,
    figures: Optional[Union[str, os.PathLike[str]]] = None,
    figure_format: Optional[str] = None,
    figure_width: Optional[float] = None,
    figure_dpi: Optional[float] = None,
) -> FitResult:
    """Fit the theory to midlines (arrays frames × points × 2, NaN for lost points) or files."""

def discover(
    recordings: Any,  # paths, arrays, a DataFrame, or a tracker's object (movement, SLEAP, DeepLabCut)
    model: ModelLike = None,
    t: Optional[npt.ArrayLike] = None,
    fps: Optional[float] = None,
    keypoints: Optional[Sequence[str]] = None,
    individuals: Optional[Sequence[str]] = None,
    points: Optional[int] = None,
    kind: Optional[str] = None,
    field: Optional[str] = None,
    order: Optional[int] = None,
    ring: Optional[int] = None,
    fill_gaps: Optional[int] = None,
    head: Optional[str] = None,
    min_likelihood: Optional[float] = None,
    input_format: Optional[str] = None,
    track_column: Optional[bool] = None,
    time_unit: Optional[str] = None,
    length_unit: Optional[str] = None,
    active: Optional[bool] = None,
    beyond_leading: Optional[int] = None,
    estimator: Optional[str] = None,
    bootstrap: Optional[int] = None,
    seed: Optional[int] = None,
    figures: Optional[Union[str, os.PathLike[str]]] = None,
    figure_format: Optional[str] = None,
    figure_width: Optional[float] = None,
    figure_dpi: Optional[float] = None,
) -> DiscoverResult:
    """Which terms of the engine's library the recordings' field needs: the discovered
    equation, every candidate with its interval and inclusion, the nested theories scored, and
    whether the theory holds (``verdict``)."""

def compare(
    first: Any,  # paths, arrays, or a tracker's object (movement, SLEAP, DeepLabCut)
    second: Any,
    model: ModelLike = None,
    fps: Optional[float] = None,
    points: Optional[int] = None,
    kind: Optional[str] = None,
    field: Optional[str] = None,
    order: Optional[int] = None,
    ring: Optional[int] = None,
    fill_gaps: Optional[int] = None,
    head: Optional[str] = None,
    min_likelihood: Optional[float] = None,
    input_format: Optional[str] = None,
    track_column: Optional[bool] = None,
    time_unit: Optional[str] = None,
    length_unit: Optional[str] = None,
    permutations: Optional[int] = None,
    seed: Optional[int] = None,
    discover: Optional[bool] = None,
    figures: Optional[Union[str, os.PathLike[str]]] = None,
    figure_format: Optional[str] = None,
    figure_width: Optional[float] = None,
    figure_dpi: Optional[float] = None,
) -> Result:
    """Two groups of animals compared, each animal fitted alone: the difference of the groups'
    κ, Ω and ζ with Welch's 95 % interval and a permutation p-value, the laws per group."""

def behave(
    behaviour: str,
    points: int = 12,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
    momentum: float = 0.1,
    periods: float = 100.0,
    force: float = 0.02,
    duration: float = 2000.0,
    tolerance: float = 0.01,
    mode_damping: Optional[float] = None,
    theta0: float = 3.141592653589793,
    attachment: str = "paper",
    sweep: Sequence[float] = (),
) -> Result:
    """One of the paper's behaviours (peristalsis, rolling, rearing, hunching, self-righting):
    momentum M and periods for the orbits, force and duration (1/ω) for the steps, tolerance
    (rad), mode_damping ζ₁, theta0 (rad), attachment and a ζ₁ sweep for self-righting."""

def stats(
    kind: str,
    points: Optional[int] = None,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
    beta: Optional[float] = None,
    samples: Optional[int] = None,
    seed: int = 1,
    field: Optional[str] = None,
    steps: int = 200_000,
    temperature: float = 0.5,
    momentum: float = 0.0,
    omega: Optional[float] = None,
) -> Result:
    """Statistics: equipartition (field, steps of 0.5/ω, temperature kT), explore (beta,
    samples) or pair (omega, beta, momentum, samples)."""

def asymmetry(
    coupling: float,
    points: Optional[int] = None,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    amplitude: float = 1.0,
    omega: Optional[float] = None,
    order: int = 4,
    beyond_leading: Optional[int] = None,
) -> Result:
    """Forward/backward asymmetry (App. C): amplitude in body lengths, omega in rad per time."""

def mathieu(
    lambda_: float = 1.0,
    ratio_min: float = 0.5,
    ratio_max: float = 4.5,
    epsilon_max: float = 0.5,
    columns: int = 81,
    rows: int = 21,
) -> Result:
    """The Mathieu stability chart (App. D)."""

def interactions(
    order: int = 4,
    model: ModelLike = None,
    density: Optional[str] = None,
    beyond_leading: Optional[int] = None,
) -> Result:
    """The interaction terms between fields."""

def parts(
    order: int = 4,
    model: ModelLike = None,
    density: Optional[str] = None,
    beyond_leading: Optional[int] = None,
) -> Result:
    """The densities split into parts."""

def count(max_order: int = 8, model: ModelLike = None, basis: str = "powers") -> Result:
    """Candidate terms per order."""

def rules(order: Optional[int] = 4, model: ModelLike = None) -> Result:
    """The rule registry."""

def figures(
    directory: Union[str, os.PathLike[str]],
    only: Optional[str] = None,
    points: int = 12,
    model: ModelLike = None,
    params: Optional[Mapping[str, float]] = None,
    format: str = "svg",
    width: float = 180.0,
    dpi: float = 300.0,
    samples: int = 100_000,
    seed: int = 1,
    order: int = 4,
    beyond_leading: Optional[int] = None,
) -> List[str]:
    """Write the paper's figures (SVG, PNG or PDF at a printed width in mm, dpi) into a
    directory; the paths written."""
