"""mypy on the package, its hand-written stubs and the examples; the examples run."""

import os
import subprocess
import sys
from pathlib import Path

import pytest


def test_mypy_passes_on_the_package_stubs_and_examples(source_dir):
    package = Path(__import__("kincal").__file__).parent
    examples = sorted(str(p) for p in (source_dir / "examples" / "python").glob("*.py"))
    assert examples
    p = subprocess.run(
        [sys.executable, "-m", "mypy", "--ignore-missing-imports", "--no-incremental",
         "--python-version", f"{sys.version_info.major}.{sys.version_info.minor}", str(package)] + examples,
        capture_output=True, text=True,
    )
    assert p.returncode == 0, p.stdout + p.stderr


def test_the_stubs_cover_every_public_name_of_the_module():
    import kincal._kincal as compiled

    stub = (Path(compiled.__file__).parent / "_kincal.pyi").read_text()
    for name in dir(compiled):
        if not name.startswith("__"):
            assert f" {name}" in stub or f"class {name}" in stub, f"{name} has no stub"


def test_every_public_function_has_a_docstring():
    import kincal
    import kincal.sensors
    import kincal.studies

    for module in (kincal, kincal.studies, kincal.sensors):
        for name in getattr(module, "__all__", dir(module)):
            obj = getattr(module, name)
            if callable(obj) and not name.startswith("_"):
                assert obj.__doc__, f"{module.__name__}.{name} has no docstring"


@pytest.mark.parametrize(
    "script, args",
    [
        ("custom_problem.py", []),
        ("calibrate_ur5.py", []),
        ("paper_study.py", ["3", "{tmp}/study.png"]),
        ("study_on_dask.py", ["3"]),
    ],
)
def test_example_runs(source_dir, tmp_path, script, args):
    path = source_dir / "examples" / "python" / script
    p = subprocess.run([sys.executable, str(path)] + [a.format(tmp=tmp_path) for a in args],
                       capture_output=True, text=True, cwd=tmp_path, env=os.environ, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    if script == "paper_study.py":
        assert (tmp_path / "study.png").stat().st_size > 1000
