"""Type stubs of the Rust extension `quatrot._native` (checked against the
built module by mypy's stubtest in `make test`)."""

from collections.abc import Callable, Sequence
from os import PathLike
from typing import Any

import numpy as np
import numpy.typing as npt

from quatrot import quaternion as quaternion

__all__ = [
    "__version__",
    "dlm_dipoles",
    "multipole_evaluate",
    "bodies_evaluate",
    "gear_corrections_table",
    "quaternion",
    "run",
    "builtin_scenes",
    "SceneError",
    "BlowUpError",
    "orientational_correlations",
    "angular_velocity_correlation",
    "order_parameters",
    "total_dipole",
    "mean_squared_displacement",
    "radial_distribution",
    "block_average",
    "dielectric_constant",
    "write_gsd",
    "cli_main",
    "run_dielectric_constant",
    "MAX_THREADS",
    "_panic_for_tests",
]
__version__: str
MAX_THREADS: int

_Array = npt.ArrayLike
_F64 = npt.NDArray[np.float64]
_Path = str | PathLike[str]

class SceneError(ValueError): ...

class BlowUpError(RuntimeError):
    result: dict[str, Any]

def dlm_dipoles(
    sites: _Array,
    dipoles_body: _Array,
    inertia: _Array,
    orientations: _Array,
    omega_body: _Array,
    field: _Array | None,
    dt: float,
    steps: int,
    split: bool,
) -> dict[str, _F64]: ...
def multipole_evaluate(
    sites: _Array,
    orientations: _Array,
    dipoles_body: _Array | None = None,
    quadrupoles_body: _Array | None = None,
    field: _Array | None = None,
    field_gradient: _Array | None = None,
    box_lengths: _Array | None = None,
    cutoff: float | None = None,
    sum: str | None = None,
    accuracy: float | None = None,
    surface: str | None = None,
    method: str | None = None,
    details: bool = False,
) -> tuple[Any, ...]: ...
def bodies_evaluate(
    body_types: Sequence[dict[str, Any]],
    positions: _Array,
    orientations: _Array,
    *,
    kinds: Sequence[int] | None = None,
    velocities: _Array | None = None,
    box_lengths: _Array | None = None,
    lj_cutoff: float | None = None,
    truncation: str | None = None,
    mixing: str | None = None,
    electrostatic_cutoff: float | None = None,
    electrostatics: dict[str, Any] | None = None,
    units: str | None = None,
) -> dict[str, Any]: ...
def gear_corrections_table(
    sites: _Array,
    inertia: _Array,
    orientations: _Array,
    omega_body: _Array,
    *,
    dipoles: _Array | None = None,
    quadrupoles: _Array | None = None,
    field: _Array | None = None,
    box_lengths: _Array | None = None,
    cutoff: float | None = None,
    dt: float = 0.02,
    t_energy: float = 100.0,
    t_error: float = 5.0,
    t_stability: float = 20.0,
    sample_every: int | None = None,
) -> list[dict[str, Any]]: ...
def run(
    scene: str | _Path | dict[str, Any],
    *,
    out_dir: _Path | None = None,
    dt: float | None = None,
    steps: int | None = None,
    integrator: str | None = None,
    no_thermostat: bool = False,
    restart: _Path | None = None,
    threads: int | None = None,
    progress: bool = False,
    on_progress: Callable[[int, int], object] | None = None,
) -> dict[str, Any]: ...
def builtin_scenes() -> dict[str, str]: ...
def orientational_correlations(
    orientations: _Array, dt: float, axes: _Array | None = None, max_lag: int | None = None
) -> dict[str, _F64]: ...
def angular_velocity_correlation(omega: _Array, dt: float, max_lag: int | None = None) -> dict[str, _F64]: ...
def order_parameters(orientations: _Array, axis: _Array | None = None, direction: _Array | None = None) -> dict[str, Any]: ...
def total_dipole(orientations: _Array, dipoles_body: _Array) -> _F64: ...
def mean_squared_displacement(
    positions: _Array,
    dt: float,
    images: _Array | None = None,
    box_lengths: _Array | None = None,
    max_lag: int | None = None,
    fit_window: _Array | None = None,
) -> dict[str, Any]: ...
def radial_distribution(
    positions: _Array, box_lengths: _Array, r_max: float | None = None, bins: int | None = None
) -> dict[str, _F64]: ...
def block_average(series: _Array) -> dict[str, Any]: ...
def dielectric_constant(dipoles: _Array, volume: float, temperature: float, boundary: str | None = None) -> dict[str, Any]: ...
def write_gsd(
    path: _Path, sites: _Array, orientations: _Array, steps: _Array, box_lengths: _Array | None = None, margin: float = 1.0
) -> None: ...
def cli_main(argv: Sequence[str | PathLike[str]]) -> int: ...
def run_dielectric_constant(
    run: dict[str, Any] | _Path, *, series: str | None = None, temperature: float | None = None
) -> dict[str, Any]: ...

# Private: panics in Rust, for the test of the package's guard (InternalError).
def _panic_for_tests(message: str) -> None: ...
