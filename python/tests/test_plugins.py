"""Plug-ins from Python: the test plug-ins the C++ suite builds (tests/plugins), loaded with
kincal.load_plugin, are usable by name as built-in types are; bad ones are refused."""

from pathlib import Path

import numpy as np
import pytest

import kincal


@pytest.fixture(scope="module")
def plugins(program: str) -> Path:
    folder = Path(program).resolve().parents[1] / "tests" / "plugins"
    if not (folder / "libtest_plugin_five_bar.so").exists():
        pytest.fail(f"{folder}: the test plug-ins are not built (ctest builds them)")
    return folder


def test_a_plugins_preset_is_usable_by_name_after_load_plugin(plugins):
    names = [name for name, _ in kincal.presets()]
    if "five-bar-demo" not in names:  # another test of this process may have loaded it
        with pytest.raises(ValueError, match="unknown model preset 'five-bar-demo'"):
            kincal.Model.preset("five-bar-demo")
    kincal.load_plugin(str(plugins / "libtest_plugin_five_bar.so"))
    kincal.load_plugin(str(plugins / "libtest_plugin_five_bar.so"))  # again: nothing happens
    assert str((plugins / "libtest_plugin_five_bar.so").resolve()) in kincal.loaded_plugins()
    assert "five-bar-demo" in [name for name, _ in kincal.presets()]
    model = kincal.Model.preset("five-bar-demo")
    assert model.free.sum() == 10
    report = kincal.simulate(preset="five-bar-demo", noise_half_width="0", seed=2)
    assert report.termination == "converged"
    assert report.parameter_rms_error_mm < 1e-6
    assert np.isfinite(report.parameters.estimate).all()


def test_a_plugin_for_another_version_or_clashing_names_is_refused(plugins):
    with pytest.raises(ValueError, match="version"):
        kincal.load_plugin(str(plugins / "libtest_plugin_wrong_version.so"))
    with pytest.raises(ValueError, match="puma560"):
        kincal.load_plugin(str(plugins / "libtest_plugin_clash.so"))
    with pytest.raises(ValueError):
        kincal.load_plugin(str(plugins / "no-such-plugin.so"))
