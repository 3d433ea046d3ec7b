"""numba's on-disk cache keyed on every source a compiled function can reach.

numba's ``cache=True`` stamps a function's cache with its own file only, so a compiled function
that calls one in another file (``integrators.integrate`` calling ``kernels.rhs``) or reads a
constant from there would keep running its old machine code after only that other file changed.
Importing this module puts a cache locator in front of numba's for the files of the registered
packages (``railwear`` itself on import). It keeps the directory numba would choose
(``NUMBA_CACHE_DIR`` if set, else the ``__pycache__`` beside the source if writable, else the
user-wide cache directory) and stamps the cache with ``source_key(file)``: a SHA-256 of the file
and of every file of the package it imports, transitively (``import`` / ``from ... import``
anywhere in a file, relative ones too; ``from package import name`` brings the package's
``__init__`` and what that imports, since the name may be re-exported there; the import of this
module itself is skipped). numba loads an index only when its stamp is equal, so an edited dependency means a recompile,
which overwrites the old entries; an unchanged tree loads from the cache as before. A file that
imports no other file of its package keeps numba's own stamp (the same cache whether or not this
module was imported first).

A compiled module is covered when this module is imported before its ``@njit(cache=True)``
decorators run: ``railwear.contact`` and ``railwear.dynamics`` import it first thing in their
``__init__``; another subpackage adopts it with the line

    from railwear import _numba_cache  # noqa: F401  (numba caches keyed on the sources)

at the top of its ``__init__.py``. ``NUMBA_CACHE_LOCATOR_CLASSES``, where set, replaces numba's
list of locators and with it this one.
"""

from __future__ import annotations

import ast
import hashlib
import os
import re
from functools import lru_cache

from numba.core import caching

__all__ = ["SourceKeyedLocator", "dependencies", "register", "source_key"]

_ROOTS: dict[str, str] = {}  # package name -> its directory (absolute)


def register(package_dir, name=None) -> None:
    """Key the caches of the compiled functions in the package at ``package_dir`` (its import
    name ``name``, default the folder's name) on their sources."""
    package_dir = os.path.abspath(package_dir)
    _ROOTS[name or os.path.basename(package_dir)] = package_dir


def _module_of(path):
    """``(module name, package for relative imports)`` of a file in a registered package, or None."""
    path = os.path.abspath(path)
    for name, root in _ROOTS.items():
        if path.startswith(root + os.sep):
            parts = [name] + os.path.relpath(path, root)[:-len(".py")].split(os.sep)
            if parts[-1] == "__init__":
                parts.pop()
                return ".".join(parts), ".".join(parts)
            return ".".join(parts), ".".join(parts[:-1])
    return None


def _file_of(module):
    """The file of the dotted ``module`` in a registered package, or None (not ours, or no file)."""
    top, _, rest = module.partition(".")
    if top not in _ROOTS:
        return None
    base = os.path.join(_ROOTS[top], *rest.split(".")) if rest else _ROOTS[top]
    for candidate in (os.path.join(base, "__init__.py"), base + ".py"):
        if os.path.isfile(candidate):
            return candidate
    return None


# an import statement at the start of a line, with its parenthesised or backslash-continued rest;
# cheaper than parsing the whole file, and a match in a docstring only adds a dependency
_IMPORT = re.compile(r"^[ \t]*((?:from[ \t]+\S+[ \t]+)?import[ \t]+(?:\([^)]*\)|(?:[^\n\\]|\\\n)*))", re.M)


@lru_cache(maxsize=None)
def _direct_imports(path, mtime_ns, size):
    """The registered-package files that ``path``'s import statements name (memoised per version
    of the file)."""
    module, package = _module_of(path)
    with open(path, encoding="utf-8") as f:
        source = f.read()
    named = []
    for match in _IMPORT.finditer(source):
        if "_numba_cache" in match.group(1):  # the line that adopts this module is no dependency
            continue
        try:
            statements = ast.parse(match.group(1).replace("\\\n", " ")).body
        except SyntaxError:  # prose that looks like an import
            continue
        for node in statements:
            if isinstance(node, ast.Import):
                for alias in node.names:  # ``import a.b.c`` reaches a, a.b and a.b.c
                    parts = alias.name.split(".")
                    named += [".".join(parts[:i]) for i in range(1, len(parts) + 1)]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    anchor = package.split(".")
                    anchor = anchor[:len(anchor) - node.level + 1]
                    base = ".".join(anchor + ([node.module] if node.module else []))
                else:
                    base = node.module
                named.append(base)
                named += [f"{base}.{alias.name}" for alias in node.names]  # submodules among the names
    files = {_file_of(name) for name in named}
    return tuple(sorted(os.path.abspath(f) for f in files if f is not None))


def _stat_key(path):
    st = os.stat(path)
    return path, st.st_mtime_ns, st.st_size


def dependencies(path) -> tuple:
    """``path`` and every file of a registered package it imports, transitively (sorted)."""
    seen, todo = set(), [os.path.abspath(path)]
    while todo:
        current = todo.pop()
        if current not in seen:
            seen.add(current)
            todo += _direct_imports(*_stat_key(current))
    return tuple(sorted(seen))


def source_key(path) -> str:
    """SHA-256 (hex) of ``dependencies(path)``: their names within the package and their bytes."""
    return _hash(tuple(_stat_key(dep) for dep in dependencies(path)))


@lru_cache(maxsize=None)
def _hash(stats):
    """``source_key`` of the files in ``stats`` (``_stat_key`` each: memoised per version)."""
    digest = hashlib.sha256()
    for dep, _, _ in stats:
        module, _ = _module_of(dep)
        with open(dep, "rb") as f:
            content = f.read()
        digest.update(f"{module}\0{len(content)}\0".encode())
        digest.update(content)
    return digest.hexdigest()


class SourceKeyedLocator(caching._CacheLocator):
    """numba cache locator: the directory of the first of numba's own locators that accepts the
    function, the stamp ``source_key`` of its file (for files of registered packages only)."""

    def __init__(self, inner, stamp):
        self._inner = inner
        self._stamp = stamp

    def ensure_cache_path(self):
        self._inner.ensure_cache_path()

    def get_cache_path(self):
        return self._inner.get_cache_path()

    def get_source_stamp(self):
        return self._stamp

    def get_disambiguator(self):
        return self._inner.get_disambiguator()

    @classmethod
    def from_function(cls, py_func, py_file):
        if _module_of(py_file) is None or not os.path.isfile(py_file):
            return None
        for other in _LOCATORS:
            if other is not cls:
                inner = other.from_function(py_func, py_file)
                if inner is not None:
                    if dependencies(py_file) == (os.path.abspath(py_file),):  # numba's own stamp suffices
                        return cls(inner, inner.get_source_stamp())
                    return cls(inner, "sources-sha256:" + source_key(py_file))
        return None


_LOCATORS = (getattr(caching, "CacheImpl", None) or caching._CacheImpl)._locator_classes  # newer / older numba
if not any(c.__name__ == SourceKeyedLocator.__name__ for c in _LOCATORS):
    _LOCATORS.insert(0, SourceKeyedLocator)
register(os.path.dirname(os.path.abspath(__file__)), "railwear")
