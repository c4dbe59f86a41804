"""``import kincal`` under a Python that cannot run it says what to do in one line (issue 40):
numpy missing, or the extension built for another Python version."""

import subprocess
import sys


def _import_error(prelude: str) -> str:
    p = subprocess.run([sys.executable, "-c", prelude + "\nimport kincal"], capture_output=True,
                       text=True)
    assert p.returncode != 0
    return p.stderr.strip().splitlines()[-1]


def test_without_numpy_the_error_says_to_install_it():
    line = _import_error("import sys; sys.modules['numpy'] = None")
    assert line.startswith("ImportError: kincal needs numpy"), line
    assert "apt install python3-numpy" in line


def test_another_python_version_is_named():
    line = _import_error(
        "import sysconfig\n"
        "real = sysconfig.get_config_var\n"
        "sysconfig.get_config_var = lambda k: '.cpython-399-x86_64-linux-gnu.so' "
        "if k == 'EXT_SUFFIX' else real(k)")
    assert "kincal's extension was built for Python 3." in line, line
    assert "/usr/bin/python3" in line
