"""One-third-octave band levels of a wheel's radius deviation in wavelength (EN 15610), limit
spectra (ISO 3095) and their exceedance (layer 1).

Definitions (EN 15610:2009, 3.3 and Annex C; ISO 3 for the R10 preferred numbers):

- the level of a band is ``L = 10 lg(r_rms² / r0²)`` dB with ``r0 = 1 µm``;
- band ``k`` is centred on the wavenumber ``10^(k/10)`` cycles per metre, its edges lie at
  ``10^((k ± 1/2)/10)``, and it is named by its nominal wavelength, the R10 preferred number
  nearest ``10^(-k/10)`` m (band 9 is 0.125 m, band 25 is 3.15 mm);
- a narrow-band line of width ``γ`` counts in a band for the fraction of ``γ`` that lies inside
  the band on the linear wavenumber axis, so a line that straddles an edge is shared between
  the two bands in proportion (Annex C, formula C.1).

A wheel's deviation ``u`` sampled at ``N`` equal angles is one record of length ``L = π D``
(the circumference, ``D`` the diameter). Its discrete Fourier transform has the lines
``n = 1 .. N/2`` at the wavenumbers ``n / L`` with the width ``γ = 1 / L``; order ``n`` has the
wavelength ``π D / n``. A band whose centre wavelength exceeds ``L / 4`` is narrower than a line
(orders below about 4): its level is reported but flagged as not resolved (EN 15610, 7.5: a
record resolves wavelengths up to a quarter of its length).
"""

from dataclasses import dataclass
from importlib import resources

import numpy as np

from railwear.errors import ScenarioError
from railwear.geometry.roundness import ROUGHNESS_REFERENCE, harmonic_amplitudes

R10 = (1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0)  # ISO 3 preferred numbers, one decade
HALF_BAND = 0.05  # decades: the edges of a band lie 10^(±1/20) either side of its centre
RESOLVED_FRACTION = 0.25  # EN 15610 7.5: a record of length L resolves wavelengths up to L/4
ISO3095_FILE = "iso3095_2013_rail_roughness_limit.csv"


def band_index(wavelength):
    """Index ``k = round(-10 lg λ)`` of the band a wavelength (m) names (array or scalar)."""
    return np.rint(-10.0 * np.log10(np.asarray(wavelength, float))).astype(int)


def nominal_wavelength(index):
    """Nominal centre wavelength (m) of band ``index``: the R10 number nearest ``10^(-k/10)``."""
    k = np.atleast_1d(np.asarray(index, int))
    decade, mantissa = np.divmod(-k, 10)
    out = np.asarray(R10)[mantissa] * 10.0 ** decade.astype(float)
    return out if np.ndim(index) else float(out[0])


def exact_wavelength(index):
    """Exact centre wavelength ``10^(-k/10)`` (m) of band ``index``."""
    return 10.0 ** (-np.asarray(index, float) / 10.0)


def band_edges(index):
    """Lower and upper wavenumber edges (cycles per metre) of consecutive bands ``index``.

    Neighbouring bands share their edge bit for bit (one array of edges)."""
    k = np.asarray(index, int)
    exponents = np.concatenate([k - 0.5, [k[-1] + 0.5]]) / 10.0 if k.size else np.zeros(0)
    if k.size and np.any(np.diff(k) != 1):
        raise ScenarioError("band indices must be consecutive and increasing")
    edges = 10.0**exponents
    return edges[:-1], edges[1:]


def order_wavelength(orders, diameter):
    """Wavelength ``π D / n`` (m) of wheel order ``n`` on a wheel of diameter ``D`` (m)."""
    return np.pi * float(diameter) / np.asarray(orders, float)


def order_amplitudes(u):
    """Orders ``n = 1 .. N/2`` and their amplitudes ``A_n`` (m) of ``u`` (m) along the last axis,
    ``u = mean + Σ A_n cos(n x + φ_n)``."""
    amp = harmonic_amplitudes(u)
    return np.arange(1, amp.shape[-1]), amp[..., 1:]


def order_mean_squares(u):
    """Orders ``n = 1 .. N/2`` and the mean square (m²) each adds to ``u - mean(u)``, along the
    last axis (``A_n²/2``, and ``A²`` for the alternating order ``N/2`` of an even ``N``)."""
    u = np.asarray(u, float)
    n = u.shape[-1]
    power = np.abs(np.fft.rfft(u, axis=-1)[..., 1:]) ** 2 * (2.0 / n**2)
    if n % 2 == 0:
        power[..., -1] /= 2
    return np.arange(1, power.shape[-1] + 1), power


def _band_of_wavenumber(kappa):
    return int(np.floor(10.0 * np.log10(kappa) + 0.5))


def line_shares(orders, circumference, index):
    """Share of each line's width in each band, shape ``(orders, bands)`` (Annex C).

    Line ``n`` covers the wavenumbers ``[(n - 1/2)/L, (n + 1/2)/L]``; its share in a band is the
    length of the overlap over ``1/L``. Rows sum to 1 where the bands cover the line."""
    orders = np.asarray(orders, float)
    lo, hi = band_edges(index)
    a = (orders[:, None] - 0.5) / circumference
    b = (orders[:, None] + 0.5) / circumference
    return np.clip(np.minimum(hi, b) - np.maximum(lo, a), 0.0, None) * circumference


@dataclass(frozen=True)
class BandLevels:
    """One-third-octave band levels in wavelength of a wheel (arrays over the last axis: bands).

    ``index`` band numbers ``k``; ``wavelength`` nominal centre (m); ``exact`` ``10^(-k/10)`` (m);
    ``lower``/``upper`` wavenumber edges (cycles per m); ``mean_square`` (m²) and ``level``
    (dB re 1 µm; ``-inf`` for an empty band); ``resolved`` centre wavelength at most ``L/4``;
    ``circumference`` ``L = π D`` (m)."""

    index: np.ndarray
    wavelength: np.ndarray
    exact: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    mean_square: np.ndarray
    level: np.ndarray
    resolved: np.ndarray
    circumference: float

    @classmethod
    def from_levels(cls, index, level, circumference):
        """The levels ``level`` (dB re 1 µm, NaN or ``-inf`` for an empty band; last axis over the
        consecutive bands ``index``) of a record of length ``circumference`` (m), as stored in a
        result: the mean squares ``(1 µm)² 10^(L/10)`` (0 for an empty band) and the rest from the
        band numbers."""
        index = np.asarray(index, int)
        level = np.asarray(level, float)
        lower, upper = band_edges(index)
        with np.errstate(invalid="ignore"):
            mean_square = np.where(np.isfinite(level), ROUGHNESS_REFERENCE**2 * 10.0 ** (level / 10.0), 0.0)
        exact = exact_wavelength(index)
        return cls(index, nominal_wavelength(index), exact, lower, upper, mean_square, level,
                   exact <= RESOLVED_FRACTION * circumference, float(circumference))

    def to_dataset(self):
        """The levels as an ``xarray.Dataset`` over ``wavelength`` (CF units)."""
        import xarray as xr

        dims = tuple(f"dim_{i}" for i in range(self.level.ndim - 1)) + ("wavelength",)
        return xr.Dataset(
            {"level": (dims, self.level, {"units": "dB", "long_name": "one-third-octave band level re 1 um"}),
             "mean_square": (dims, self.mean_square, {"units": "m2", "long_name": "band mean square"}),
             "resolved": ("wavelength", self.resolved, {"long_name": "centre wavelength at most a quarter of the record"})},
            coords={"wavelength": ("wavelength", self.wavelength, {"units": "m", "long_name": "nominal band centre"}),
                    "band": ("wavelength", self.index, {"long_name": "band number k (wavenumber 10^(k/10) per m)"})},
            attrs={"circumference": self.circumference, "reference": "EN 15610: L = 10 lg(r_rms^2 / (1 um)^2)"})


def _levels(orders, mean_square, diameter, bands):
    if not (np.isfinite(diameter) and diameter > 0):
        raise ScenarioError(f"the wheel diameter must be positive, not {diameter}")
    circumference = np.pi * float(diameter)
    orders = np.asarray(orders, float)
    if bands is None:
        bands = np.arange(_band_of_wavenumber((orders.min() - 0.5) / circumference),
                          _band_of_wavenumber((orders.max() + 0.5) / circumference) + 1)
    index = np.asarray(bands, int)
    lower, upper = band_edges(index)
    mean = np.asarray(mean_square, float) @ line_shares(orders, circumference, index)
    with np.errstate(divide="ignore"):
        level = 10.0 * np.log10(mean / ROUGHNESS_REFERENCE**2)
    return BandLevels(index, nominal_wavelength(index), exact_wavelength(index), lower, upper, mean, level,
                      exact_wavelength(index) <= RESOLVED_FRACTION * circumference, circumference)


def band_levels(u, diameter, bands=None):
    """Band levels of the radius deviation ``u`` (m, equal angles over one turn, last axis) of a
    wheel of diameter ``diameter`` (m). ``bands``: consecutive band numbers (default every band
    that a line of ``u`` reaches, so the band mean squares add up to the variance of ``u``)."""
    orders, mean_square = order_mean_squares(u)
    return _levels(orders, mean_square, diameter, bands)


def band_levels_of_orders(orders, amplitudes, diameter, bands=None):
    """Band levels of the harmonics ``A_n cos(n x + φ_n)`` (``amplitudes`` in m, last axis over
    ``orders``, integers at least 1) on a wheel of diameter ``diameter`` (m)."""
    orders = np.asarray(orders)
    if orders.ndim != 1 or orders.size == 0 or np.any(orders < 1) or np.any(orders != np.round(orders)):
        raise ScenarioError("orders must be whole numbers of at least 1")
    amplitudes = np.asarray(amplitudes, float)
    return _levels(orders, amplitudes**2 / 2.0, diameter, bands)


@dataclass(frozen=True)
class LimitSpectrum:
    """A limit in one-third-octave bands: ``wavelength`` nominal centres (m), ``level`` (dB re
    1 µm), ``index`` band numbers, with a ``name`` and where it comes from (``source``)."""

    index: np.ndarray
    wavelength: np.ndarray
    level: np.ndarray
    name: str = "limit"
    source: str = ""


def limit_spectrum(wavelengths, levels, name="limit", source=""):
    """A :class:`LimitSpectrum` from a table of wavelengths (m) and levels (dB re 1 µm).

    Each wavelength names a band: it must lie within a quarter of a band (0.025 decade) of the
    band's exact centre, as printed nominal values do (0.032 m for 3.15 cm); no band twice."""
    wl = np.atleast_1d(np.asarray(wavelengths, float))
    lv = np.atleast_1d(np.asarray(levels, float))
    if wl.ndim != 1 or wl.size == 0 or wl.size != lv.size:
        raise ScenarioError(f"limit {name!r}: give as many levels as wavelengths (at least one)")
    if not (np.all(np.isfinite(wl)) and np.all(wl > 0) and np.all(np.isfinite(lv))):
        raise ScenarioError(f"limit {name!r}: wavelengths must be positive and levels finite")
    index = band_index(wl)
    off = np.abs(np.log10(wl) - np.log10(exact_wavelength(index)))
    if np.any(off > HALF_BAND / 2):
        bad = wl[np.argmax(off)]
        raise ScenarioError(f"limit {name!r}: {bad:g} m is not a one-third-octave band centre")
    if np.unique(index).size != index.size:
        raise ScenarioError(f"limit {name!r}: a band is given twice")
    order = np.argsort(index)
    return LimitSpectrum(index[order], nominal_wavelength(index[order]), lv[order], name, source)


def iso3095_limit():
    """The rail roughness limit of ISO 3095:2013 Figure 2 (40 cm to 3.15 mm, dB re 1 µm),
    shipped in ``data/iso3095_2013_rail_roughness_limit.csv`` with its source note."""
    text = (resources.files("railwear.geometry") / "data" / ISO3095_FILE).read_text(encoding="utf-8")
    rows = [line.split(",") for line in text.splitlines() if line.strip() and not line.startswith("#")]
    table = np.array(rows[1:], float)  # the first row names the columns
    return limit_spectrum(table[:, 0], table[:, 1], name="ISO 3095:2013 rail roughness limit",
                          source="ISO 3095:2013 Figure 2; the same numbers in EN 15610:2009 Annex B.9.2")


@dataclass(frozen=True)
class Exceedance:
    """Band levels against a limit over the bands the limit gives: ``index``, ``wavelength`` (m),
    ``level`` and ``limit`` (dB re 1 µm), ``excess = level - limit`` (dB), ``exceeds``
    (``excess > 0``); ``level``, ``excess`` and ``exceeds`` keep the levels' leading axes. Bands
    of the limit the levels do not cover are ``nan`` (not compared, never exceeding)."""

    index: np.ndarray
    wavelength: np.ndarray
    level: np.ndarray
    limit: np.ndarray
    excess: np.ndarray
    exceeds: np.ndarray

    @property
    def count(self):
        """Number of bands above the limit (along the last axis)."""
        return np.sum(self.exceeds, axis=-1)


def exceedance(levels, limit):
    """Compare :class:`BandLevels` with a :class:`LimitSpectrum` band by band (EN 15610 clause 8:
    no band may lie above the limit)."""
    position = {int(k): i for i, k in enumerate(levels.index)}
    level = np.full(levels.level.shape[:-1] + (limit.index.size,), np.nan)
    for j, k in enumerate(limit.index):
        if int(k) in position:
            level[..., j] = levels.level[..., position[int(k)]]
    excess = level - limit.level
    with np.errstate(invalid="ignore"):
        exceeds = excess > 0
    return Exceedance(limit.index, limit.wavelength, level, limit.level, excess, exceeds)
