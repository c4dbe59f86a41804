# Hand-written type stubs of the compiled module (python/src/*.cpp); checked by mypy in the
# test suite (python/tests/test_typing.py) against the package and the examples.
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]

class OutputError(ValueError): ...
class InvalidSolverOptions(ValueError): ...

class Model:
    @staticmethod
    def preset(name: str) -> Model: ...
    @staticmethod
    def load(path: str) -> Model: ...
    @staticmethod
    def from_json(text: str, source: str = ...) -> Model: ...
    def to_json(self, values: Optional[ArrayLike] = ...) -> str: ...
    def copy(self) -> Model: ...
    def with_values(self, values: ArrayLike) -> Model: ...
    @property
    def source(self) -> str: ...
    @property
    def parameter_names(self) -> List[str]: ...
    @property
    def parameter_units(self) -> List[str]: ...
    @property
    def nominal(self) -> FloatArray: ...
    @property
    def free(self) -> npt.NDArray[np.bool_]: ...
    @property
    def prior_std(self) -> FloatArray: ...
    def set_free(self, pattern: str, free: bool = ...) -> int: ...
    @property
    def actuator_names(self) -> List[str]: ...
    @property
    def actuator_units(self) -> List[str]: ...
    @property
    def reading_names(self) -> List[str]: ...
    @property
    def reading_units(self) -> List[str]: ...
    def forward_kinematics(
        self, actuators: ArrayLike
    ) -> Tuple[FloatArray, FloatArray, List[str], List[str]]: ...
    def inverse_kinematics(
        self, poses: ArrayLike
    ) -> Tuple[FloatArray, FloatArray, List[str], List[str]]: ...

def presets() -> List[Tuple[str, str]]: ...
def load_plugin(path: str) -> None: ...
def loaded_plugins() -> List[str]: ...
def _array_address(value: ArrayLike, argument: str, cols: int) -> int: ...
def _sigint_received() -> bool: ...
def read_measurements(
    path: str, model: Model, allow_no_readings: bool = ...
) -> Tuple[FloatArray, FloatArray, List[str]]: ...
def calibration_residuals(
    model: Model, actuators: ArrayLike, readings: ArrayLike, values: Optional[ArrayLike] = ...
) -> Tuple[FloatArray, FloatArray, List[str]]: ...
def measurements_to_csv(
    actuators: ArrayLike, readings: ArrayLike, model: Model, comment: str = ...
) -> str: ...
def check_measurements(
    actuators: ArrayLike, readings: ArrayLike, actuator_names: List[str], reading_names: List[str]
) -> None: ...
def write_measurements(
    path: str,
    actuators: ArrayLike,
    readings: ArrayLike,
    actuator_names: List[str],
    reading_names: List[str],
    comment: str = ...,
) -> None: ...

class LeastSquaresProblem:
    def __init__(
        self,
        residuals: Callable[[FloatArray], ArrayLike],
        jacobian: Callable[[FloatArray], ArrayLike],
        num_parameters: int,
        num_residuals: int,
        parameter_names: Sequence[str] = ...,
    ) -> None: ...
    @property
    def num_parameters(self) -> int: ...
    @property
    def num_residuals(self) -> int: ...
    @property
    def parameter_names(self) -> List[str]: ...

def _solve(
    problem: LeastSquaresProblem,
    x0: ArrayLike,
    solver: str,
    max_iterations: int,
    function_tolerance: float,
    parameter_tolerance: float,
    gradient_tolerance: float,
    lower: Optional[ArrayLike],
    upper: Optional[ArrayLike],
    backend_options: Dict[str, str],
    loss: str,
    verbosity: int,
    catch_sigint: bool,
) -> Dict[str, Any]: ...
def solvers() -> List[Tuple[str, str]]: ...

TrialTuple = Tuple[str, int, float, float, Tuple[float, ...], Tuple[float, ...], List[Tuple[float, ...]]]

def reproduce_trials(
    spec: Dict[str, Any], tasks: Sequence[Tuple[int, int]], threads: int = ..., catch_sigint: bool = ...
) -> List[Optional[TrialTuple]]: ...
def reproduce_report(
    spec: Dict[str, Any], trials: int, results: List[List[Any]], out: str
) -> Tuple[str, str, str, str, str]: ...
def check_reproduce_directory(path: str) -> None: ...
def write_reproduce_directory(path: str, summary: str, trials: str, trace: str) -> None: ...

def _with_sensors(model: Model, sensors: List[Any]) -> Model: ...
def _python_model(mechanism: Any, sensors: List[Any]) -> Model: ...
def _check_mechanism(model: Model) -> List[Tuple[str, bool, float, float, str]]: ...
def _check_sensors(model: Model, seed: int = ...) -> Dict[str, float]: ...
def _simulate_direct(
    model: Model,
    poses: int,
    noise_mm: float,
    noise_rad: float,
    seed: int,
    solver: str,
    catch_sigint: bool,
) -> Dict[str, Any]: ...
def _calibrate(
    model: Model, data_path: Optional[str], actuators: Any, readings: Any, solver: str,
    max_iterations: int, solver_options: Dict[str, str], loss: str, free: List[str],
    fix: List[str], prior_std: List[str], noise_std: str, folds: int, starts: int, seed: int,
    rcond: float, allow_rank_deficient: bool, formulation: str, skip_bad_rows: bool,
    threads: int, out: str, json: str, html: str, model_path: str, inputs: List[str],
    catch_sigint: bool, tolerance_priors: str, images: str, steps: List[str],
) -> Dict[str, Any]: ...
def _validate(
    model: Model, data_path: Optional[str], actuators: Any, readings: Any,
    report_json: Optional[str], report_name: str, before: Optional[Model], before_name: str,
    noise_std: str, skip_bad_rows: bool, json: str, html: str, model_path: str,
    inputs: List[str],
) -> Dict[str, Any]: ...
def _export(model: Model, format: str, model_path: str, out: str) -> str: ...
def _detect(
    target: str,
    poses: str,
    images: str,
    out: str,
    camera: str,
    gate_px: float,
    start_model: str,
    mounting: str,
    mechanism: Optional[Model],
    intrinsics: List[float],
    json: str,
    catch_sigint: bool,
) -> Dict[str, Any]: ...
def _model_from_urdf(path: str, tip: str, base: str, sensor: str, point: List[float],
                     compliance: str, payload_column: bool,
                     payload_centre: List[float], frame: List[float],
                     target: List[float]) -> Model: ...
def _compensate(model: Model, targets: str, nominal: Optional[Model], near: List[float],
                payload: Optional[float], tolerance: float, out: str, json: str,
                inputs: List[str]) -> Dict[str, Any]: ...
def _observability(
    model: Model, data_path: Optional[str], actuators: Any, readings: Any, poses: int, seed: int,
    rcond: float, config_range: str, free: List[str], fix: List[str], prior_std: List[str],
    noise_std: str, skip_bad_rows: bool, json: str, html: str, model_path: str,
    inputs: List[str],
) -> Dict[str, Any]: ...
def _compare(
    truth: Model, model: Model, data_path: Optional[str], actuators: Any, poses: int, seed: int,
    json: str, html: str, truth_path: str, model_path: str, inputs: List[str],
) -> Dict[str, Any]: ...
def _simulate(
    model: Model, model_name: str, case_id: int, poses: Optional[int],
    noise_half_width: Optional[str], noise_std: Optional[str], param_error: str,
    config_range: Optional[str], seed: int, validation: int, solver: str, max_iterations: int,
    solver_options: Dict[str, str], threads: int, formulation: str, design: str,
    design_candidates: int, prior_std: List[str], configs_path: Optional[str],
    configs_actuators: Any, configs_readings: Any, truth: Optional[Model], truth_name: str,
    write_data: str, allow_rank_deficient: bool, starts: int, json: str, trace: str,
    inputs: List[str], catch_sigint: bool,
) -> Dict[str, Any]: ...
def _design(
    model: Model, count: int, criterion: str, candidates: int, seed: int,
    singularity_margin: float, orientation_length: str, config_range: str, free: List[str],
    fix: List[str], prior_std: List[str], noise_std: str, existing_path: Optional[str],
    existing_actuators: Any, existing_readings: Any, bound: bool, out: str, json: str,
    html: str, model_path: str, inputs: List[str], catch_sigint: bool, within: Any,
    candidate_configurations: Any,
) -> Dict[str, Any]: ...
