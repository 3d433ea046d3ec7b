"""The spectrum and polar figures of docs/outputs.md: the built-in `polygonalisation` run.

Run: python docs/outputs_figure.py [--output DIRECTORY]   (default docs/figures)

Writes polygonalisation-spectrum.png (amplitude per order with the wavelength axis, and the
one-third-octave band levels in wavelength against the ISO 3095 rail roughness limit) and
polygonalisation-polar.png (the wheel at the start and the end, exaggerated). Returns the end's
band levels and their exceedance of the limit.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("agg")

from railwear import api, plots  # noqa: E402
from railwear.geometry import bands  # noqa: E402


def main(directory):
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    ds = api.run("polygonalisation")
    plots.save(plots.spectrum(ds, limit="iso3095"), directory / "polygonalisation-spectrum.png")
    plots.save(plots.polar(ds), directory / "polygonalisation-polar.png")
    levels = bands.band_levels(ds.u.isel(time=-1).values, 2 * float(ds.nominal_radius))
    return levels, bands.exceedance(levels, bands.iso3095_limit())


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path(__file__).resolve().parent / "figures")
    levels, over = main(parser.parse_args().output)
    print(f"bands above the ISO 3095 limit at the end: {int(over.count)}")
