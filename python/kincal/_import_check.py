"""What ``import kincal`` needs, checked first so that a wrong interpreter gets one clear line
instead of a traceback from deep inside numpy or the extension loader (issue 40)."""

import glob
import os
import sys
import sysconfig


def _built_for() -> str:
    """The Python version the extension was built for ("3.11"), from its file name."""
    here = os.path.dirname(os.path.abspath(__file__))
    for path in glob.glob(os.path.join(here, "_kincal.*")):
        name = os.path.basename(path)
        if name.startswith("_kincal.cpython-"):
            tag = name.split(".")[1].split("-")[1]  # "311"
            return tag[0] + "." + tag[1:]
    return ""


def check_environment() -> None:
    """Raises ImportError with what to do when numpy is missing or the extension was built for
    another Python than this one."""
    here = "Python %d.%d (%s)" % (sys.version_info[0], sys.version_info[1], sys.executable)
    built = _built_for()
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ""
    if built and not suffix.startswith(".cpython-%s" % built.replace(".", "")):
        raise ImportError(
            "kincal's extension was built for Python %s, and this is %s: run it with the Python "
            "it was built with (Debian 12: /usr/bin/python3), or rebuild kincal with this one"
            % (built, here))
    try:
        import numpy  # noqa: F401
    except ImportError as e:
        raise ImportError(
            "kincal needs numpy, which %s cannot import (%s): install it (Debian: apt install "
            "python3-numpy) or use the Python kincal was built with (/usr/bin/python3)"
            % (here, e)) from None
