"""Shared fixtures: the kincal program built beside the module (KINCAL_PROGRAM, set by
ctest) for the agreement tests, and the source tree (KINCAL_SOURCE_DIR)."""

import json
import os
import subprocess
from pathlib import Path
from typing import Any, Callable, Dict, List

import pytest


@pytest.fixture(scope="session")
def program() -> str:
    path = os.environ.get("KINCAL_PROGRAM")
    if not path and os.environ.get("KINCAL_PROGRAM_NOT_BUILT") == "1":
        # Configured with KINCAL_BUILD_CLI=OFF (python/CMakeLists.txt): the module is built
        # without the program, so the comparisons with it cannot run; pytest lists them as skipped.
        pytest.skip("the kincal program was not built (KINCAL_BUILD_CLI=OFF)")
    if not path or not os.path.exists(path):
        pytest.fail("KINCAL_PROGRAM must name the kincal program (ctest sets it)")
    return path


@pytest.fixture(scope="session")
def source_dir() -> Path:
    return Path(os.environ.get("KINCAL_SOURCE_DIR", Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def cli_json(program: str) -> Callable[..., Dict[str, Any]]:
    """Runs the program with --json - and returns its document."""

    def run(args: List[str], cwd: Any = None, ok_codes: tuple = (0,)) -> Dict[str, Any]:
        p = subprocess.run([program] + args + ["--json", "-"], capture_output=True, text=True, cwd=cwd)
        assert p.returncode in ok_codes, p.stderr
        return json.loads(p.stdout)

    return run


def without_timing(doc: Any) -> Any:
    """The document without wall-clock times (the only fields two runs may differ in)."""
    if isinstance(doc, dict):
        return {k: without_timing(v) for k, v in doc.items() if "seconds" not in k}
    if isinstance(doc, list):
        return [without_timing(v) for v in doc]
    return doc
