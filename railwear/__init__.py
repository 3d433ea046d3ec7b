"""railwear: long-term wear of railway wheels and the growth of polygonal wheels."""

from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("railwear")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = ["__version__", "load_scenario", "run"]


def __getattr__(name):
    # The public entry points live in layer 4; importing them lazily keeps `import railwear`
    # (and the command line's start-up) light.
    if name in ("load_scenario", "run"):
        from railwear import api

        return getattr(api, name)
    raise AttributeError(f"module 'railwear' has no attribute {name!r}")
