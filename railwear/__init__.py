"""railwear: long-term wear of railway wheels and the growth of polygonal wheels."""

from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("railwear")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = ["__version__", "figure", "fit", "forecast", "load_scenario", "run", "simulate", "stability",
           "track_receptance"]

# The public entry points live in layer 4; importing them lazily keeps `import railwear` (and the
# command line's start-up) light. `railwear.forecast` is the module (its `forecast` on arrays,
# `forecast_file` on a CSV file and `report`), as `from railwear import forecast` has always given.
_LAZY = {"load_scenario": "api", "run": "api", "simulate": "api",
         "figure": "analysis", "fit": "analysis", "stability": "analysis", "track_receptance": "analysis"}


def __getattr__(name):
    from importlib import import_module

    if name in _LAZY:
        return getattr(import_module(f"railwear.{_LAZY[name]}"), name)
    if name == "forecast":
        return import_module("railwear.forecast")
    raise AttributeError(f"module 'railwear' has no attribute {name!r}")
