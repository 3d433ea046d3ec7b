"""numba caches keyed on the sources a compiled function reaches (``railwear._numba_cache``)."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import railwear
from railwear import _numba_cache

PACKAGE = Path(railwear.__file__).parent

KERNEL = """
from numba import njit
{imports}

@njit(cache=True)
def kernel():
    return helper() + 10 * SCALE
"""
RUN = """
import sys
sys.path.insert(0, sys.argv[1])
{register}
from pkgx.kernel import kernel
print(kernel(), sum(kernel.stats.cache_hits.values()))
"""


def _package(root, relative=False):
    pkg = root / "pkgx"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("from pkgx.sub.helper import helper  # noqa: F401\n")
    (pkg / "sub" / "helper.py").write_text("from numba import njit\n\n\n@njit(cache=True)\ndef helper():\n    return 1\n")
    (pkg / "constants.py").write_text("SCALE = 1\n")
    (pkg / "unrelated.py").write_text("X = 0\n")
    imports = ("from .sub import \\\n    helper\nfrom . import constants\nSCALE = constants.SCALE" if relative else
               "from pkgx.sub import (\n    helper,\n)\nfrom pkgx.constants import SCALE")
    (pkg / "kernel.py").write_text(KERNEL.format(imports=imports))
    return pkg


def test_the_key_follows_the_imports_and_nothing_else(tmp_path):
    for relative in (False, True):
        pkg = _package(tmp_path / str(relative), relative)
        _numba_cache.register(pkg)
        try:
            kernel = pkg / "kernel.py"
            deps = {Path(p).relative_to(pkg).as_posix() for p in _numba_cache.dependencies(kernel)}
            # the helper through the subpackage's re-export, the constant, not the unrelated file
            # (``from . import constants`` may take a name from the package: its ``__init__`` too)
            assert deps == {"kernel.py", "sub/__init__.py", "sub/helper.py", "constants.py"} | (
                {"__init__.py"} if relative else set())
            key = _numba_cache.source_key(kernel)
            (pkg / "unrelated.py").write_text("X = 1\n")
            assert _numba_cache.source_key(kernel) == key
            (pkg / "sub" / "helper.py").write_text((pkg / "sub" / "helper.py").read_text().replace("1", "2"))
            assert _numba_cache.source_key(kernel) != key
        finally:
            del _numba_cache._ROOTS["pkgx"]


def test_railwears_integrators_are_keyed_on_the_kernels():
    deps = set(_numba_cache.dependencies(PACKAGE / "dynamics" / "integrators.py"))
    assert str(PACKAGE / "dynamics" / "kernels.py") in deps
    assert str(PACKAGE / "dynamics" / "simulation.py") not in deps  # a Python driver is no dependency
    assert str(PACKAGE / "contact" / "kalker.py") in _numba_cache.dependencies(PACKAGE / "contact" / "fastsim.py")


def _run(pkg, register):
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "NUMBA_CACHE_LOCATOR_CLASSES")}
    code = RUN.format(register=f"from railwear import _numba_cache; _numba_cache.register({str(pkg)!r})"
                      if register else "")
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(code), str(pkg.parent)], capture_output=True,
                         text=True, check=True, env=env).stdout.split()
    return int(out[0]), int(out[1])


def test_an_edited_dependency_is_recompiled_not_run_stale(tmp_path):
    """Edit the helper a cached kernel calls, and the constant it reads, and run again in a fresh
    process: with the locator the new code runs, and an unchanged tree loads from the cache; numba
    alone runs the stale machine code (why the locator is there)."""
    for register in (True, False):
        pkg = _package(tmp_path / str(register))
        assert _run(pkg, register) == (11, 0)  # compiled
        assert _run(pkg, register) == (11, 1)  # loaded from the cache
        (pkg / "sub" / "helper.py").write_text((pkg / "sub" / "helper.py").read_text().replace("1", "2"))
        (pkg / "constants.py").write_text("SCALE = 3\n")
        if register:
            assert _run(pkg, register) == (32, 0)  # recompiled against the new sources
            assert _run(pkg, register) == (32, 1)
        else:
            assert _run(pkg, register) == (11, 1)  # stale: numba's stamp is the kernel's own file


def test_the_cache_goes_where_numba_would_put_it(tmp_path, monkeypatch):
    """NUMBA_CACHE_DIR if set; else beside the source; where that is read-only (simulated: root
    may write anywhere), the user's cache directory. The stamp is the key wherever it goes."""
    from numba.core import caching, config

    pkg = _package(tmp_path / "tree")
    _numba_cache.register(pkg)
    try:
        kernel = str(pkg / "kernel.py")

        def func():
            pass

        here = _numba_cache.SourceKeyedLocator.from_function(func, kernel)
        assert here.get_cache_path() == str(pkg / "__pycache__")
        assert here.get_source_stamp() == "sources-sha256:" + _numba_cache.source_key(kernel)
        monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path / "numba-cache-dir"))
        assert _numba_cache.SourceKeyedLocator.from_function(func, kernel).get_cache_path().startswith(
            str(tmp_path / "numba-cache-dir"))
        monkeypatch.setattr(config, "CACHE_DIR", "")

        def read_only(self):
            raise PermissionError(self.get_cache_path())

        monkeypatch.setattr(caching.InTreeCacheLocator, "ensure_cache_path", read_only)
        monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "user-cache"))
        elsewhere = _numba_cache.SourceKeyedLocator.from_function(func, kernel)
        assert elsewhere.get_cache_path() == caching.UserWideCacheLocator(func, kernel).get_cache_path()
        assert elsewhere.get_cache_path().startswith(str(tmp_path / "user-cache")) or sys.platform != "linux"
        assert elsewhere.get_source_stamp() == here.get_source_stamp()
        assert _numba_cache.SourceKeyedLocator.from_function(func, str(PACKAGE.parent / "setup.py")) is None
    finally:
        del _numba_cache._ROOTS["pkgx"]
