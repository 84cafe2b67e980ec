"""Every advertised public name exists, and the advertised lists are sorted (STYLE.md §1)."""

import importlib

import pytest

PACKAGES = ["bifurcation", "bifurcation.analysis", "bifurcation.bench", "bifurcation.engine", "bifurcation.laws",
            "bifurcation.models", "bifurcation.models.chain", "bifurcation.models.rate_state",
            "bifurcation.report", "bifurcation.run", "bifurcation.store", "bifurcation.theory",
            "bifurcation.workflow"]


@pytest.mark.parametrize("name", PACKAGES)
def test_all_names_exist_and_are_sorted(name):
    module = importlib.import_module(name)
    assert module.__all__ == sorted(module.__all__)
    missing = [n for n in module.__all__ if not hasattr(module, n)]
    assert not missing


def test_cli_help_does_not_import_the_heavy_parts():
    import subprocess
    import sys

    code = ("import sys; from bifurcation.cli import cli; "
            "print(any(m in sys.modules for m in ('heyoka', 'dask', 'xarray', 'matplotlib', 'zarr')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_lazy_names_survive_their_submodules_being_imported_first():
    # Regression: the module engine/limit.py was bound over the function `limit` once imported, and
    # `bifurcation limit` failed with "'module' object is not callable" depending on import order.
    import subprocess
    import sys

    code = ("import importlib, pkgutil, types, bifurcation.engine as e\n"
            "for m in pkgutil.iter_modules(e.__path__): importlib.import_module('bifurcation.engine.' + m.name)\n"
            "import bifurcation as b\n"
            "bad = [n for n in e.__all__ if isinstance(getattr(e, n), types.ModuleType)]\n"
            "bad += [n for n in b.__all__ if isinstance(getattr(b, n), types.ModuleType)]\n"
            "print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_lazy_packages_advertise_exactly_their_lazy_names():
    import bifurcation
    import bifurcation.engine

    for package in (bifurcation, bifurcation.engine):
        assert package.__all__ == sorted(package._LAZY)
