"""kincal from Python: kinematic calibration (docs/python.md).

    import kincal
    report = kincal.simulate(case=3, seed=7)        # kincal simulate --case 3 --seed 7
    report.parameters.estimate                       # numpy array, model order
    report.to_dict()                                 # the program's JSON, exactly

Models (``Model.preset``, ``Model.load``, ``model_from_urdf``), forward and inverse
kinematics over arrays, ``Measurements`` in kincal's CSV format, the workflows ``simulate``,
``calibrate``, ``validate``, ``observability``, ``compare``, ``design``, ``compensate``, ``export``,
``fk`` and ``ik`` (one configuration or a file of them), ``detect`` (images of a target, with OpenCV) and ``html_report`` (the library's, called
directly with typed keyword arguments), the generic
least-squares layer (``LeastSquaresProblem``, ``solve``) and studies on Dask
(``kincal.studies``).
"""

from ._import_check import check_environment as _check_environment

_check_environment()  # numpy, and the Python the extension was built for: a hint, not a traceback

from . import _kincal  # noqa: E402
from ._errors import KincalError, KincalInterrupt
from ._kincal import Model, __version__, load_plugin, loaded_plugins, presets
from ._reports import Report, Table
from .least_squares import LeastSquaresProblem, SolveResult, solve, solvers
from .measurements import Measurements
from .workflows import (
    calibrate,
    compare,
    compensate,
    design,
    detect,
    export,
    fk,
    html_report,
    ik,
    model_from_urdf,
    observability,
    simulate,
    validate,
    verify,
)
from .project import run_project

__all__ = [
    "KincalError",
    "KincalInterrupt",
    "LeastSquaresProblem",
    "Measurements",
    "Model",
    "Report",
    "SolveResult",
    "Table",
    "__version__",
    "calibrate",
    "compare",
    "compensate",
    "design",
    "detect",
    "export",
    "fk",
    "html_report",
    "ik",
    "load_plugin",
    "loaded_plugins",
    "model_from_urdf",
    "observability",
    "presets",
    "run_project",
    "simulate",
    "solve",
    "solvers",
    "validate",
    "verify",
]
