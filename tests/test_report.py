"""``report.html``: one self-contained file with the scenario, the summary and the numbers behind
the regime, every figure as an embedded PNG, the warnings and the version."""

import base64
import json
import os
import re
import shutil
import subprocess
import warnings
from html.parser import HTMLParser

import numpy as np
import pytest
from typer.testing import CliRunner

import railwear
from railwear import api, report, results
from railwear.cli import app
from railwear.errors import ResolutionWarning

PNG = b"\x89PNG\r\n\x1a\n"


class Page(HTMLParser):
    """The parts of a page the tests read: images, text, the text of each ``<pre>``, elements."""

    def __init__(self, text):
        super().__init__(convert_charrefs=True)
        self.images, self.pres, self.text, self.tags, self._pre = [], [], [], [], None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        if tag == "img":
            self.images.append(dict(attrs))
        if tag == "pre":
            self._pre = []

    def handle_endtag(self, tag):
        if tag == "pre":
            self.pres.append("".join(self._pre))
            self._pre = None

    def handle_data(self, data):
        self.text.append(data)
        if self._pre is not None:
            self._pre.append(data)

    @property
    def words(self):
        return " ".join(" ".join(self.text).split())


def decoded(image):
    """The bytes of an ``<img>`` whose source is a base64 PNG data URI."""
    head, _, data = image["src"].partition(",")
    assert head == "data:image/png;base64", head
    return base64.b64decode(data, validate=True)


@pytest.fixture(scope="module")
def metro(tmp_path_factory):
    """The default run, as ``railwear run`` writes it, under a umask that lets the group read."""
    out = tmp_path_factory.mktemp("metro")
    old = os.umask(0o022)
    try:
        result = CliRunner().invoke(app, ["run", "-o", str(out)])
    finally:
        os.umask(old)
    assert result.exit_code == 0, result.output
    return out, results.read_netcdf(out / "result.nc")


def test_every_figure_is_embedded_as_the_png_the_run_wrote(metro):
    out, _ = metro
    page = Page((out / "report.html").read_text(encoding="utf-8"))
    written = sorted(out.glob("*.png"))
    assert len(written) == 4
    embedded = {image["alt"]: decoded(image) for image in page.images}
    assert sorted(embedded) == [p.stem for p in written]
    for path in written:
        assert embedded[path.stem].startswith(PNG) and embedded[path.stem] == path.read_bytes()


def test_the_numbers_behind_the_regime_are_in_the_report(metro):
    out, ds = metro
    words = Page((out / "report.html").read_text(encoding="utf-8")).words
    s = json.loads((out / "summary.json").read_text())["runs"][0]
    n, life = s["leading_order"], float(ds.attrs["life_distance_km"])
    assert (n, s["dominant_order"], s["regime"]) == (8, 8, "polygonalising")
    rate, error = float(ds.growth_rate.sel(order=n)), float(ds.growth_rate_error.sel(order=n))
    per = 1e4 / life  # normed time per 10 000 km
    for text in (f"order {n}: ln-growth rate {rate:.4g} {error:.4g} per unit normed time",
                 f"order {n}: ln-growth rate {rate * per:.4g} {error * per:.4g} per 10 000 km",
                 f"out-of-round rms: ln-growth rate {float(ds.out_of_round_growth_rate):.4g} "
                 f"{float(ds.out_of_round_growth_rate_error):.4g} per unit normed time",
                 f"leading order (fastest of those present at the start) {n} - order",
                 f"dominant order (largest at the end) {n} - order (its rates above)",
                 f"wavelength of the dominant order on the tread {s['wavelength_mm']:.4g} mm",
                 f"its passing frequency {s['passing_frequency_hz']:.4g} Hz",
                 f"distance to the limit {s['limit_distance_km']:,.0f} km",
                 ds.regime.attrs["rule"]):
        assert text in words, text
    assert "329.9 mm" in words and "58.95 Hz" in words and "173,878 km" in words  # the README's numbers
    for key, value in s.items():  # every field of the summary, by name and value
        assert f"{key} {report.number(value, 6)}" in words, key


def test_the_scenario_version_and_summary_text_are_in_the_report(metro):
    out, ds = metro
    page = Page((out / "report.html").read_text(encoding="utf-8"))
    assert ds.attrs["scenario"] in page.pres and "[body]" in ds.attrs["scenario"]
    assert (out / "summary.txt").read_text() in page.pres
    assert f"railwear {railwear.__version__}" in page.words
    section = page.words.split(" Warnings ", 1)[1].split(" Scenario ", 1)[0]
    # the default run warns of nothing; the kernels may have been compiled for it (a cold cache)
    assert section == "none" or section.startswith("compile: numba compiled kernels in this run") and "Warning:" not in section


def test_the_report_is_written_like_the_other_outputs(metro):
    out, _ = metro
    assert (out / "report.html").stat().st_mode & 0o777 == (out / "result.nc").stat().st_mode & 0o777 == 0o644
    assert not [p for p in out.iterdir() if p.name.endswith(results.PART)]


def test_the_run_s_warnings_are_in_the_report(tmp_path, monkeypatch):
    run = api.run

    def warning_run(*args, **kwargs):
        warnings.warn("the top of the kept spectrum grew <5 %>", ResolutionWarning)
        warnings.warn("the top of the kept spectrum grew <5 %>", ResolutionWarning)
        return run(*args, **kwargs)

    monkeypatch.setattr(api, "run", warning_run)
    result = CliRunner().invoke(app, ["run", "smoothing", "-o", str(tmp_path), "--no-figures"])
    assert result.exit_code == 0, result.output
    text = (tmp_path / "report.html").read_text(encoding="utf-8")
    page = Page(text)
    assert "ResolutionWarning: the top of the kept spectrum grew <5 %> (2 times)" in page.words
    assert "&lt;5 %&gt;" in text and "<5 %>" not in text  # escaped
    assert not page.images and "no figures were written" in page.words


def test_all_text_is_escaped(metro):
    _, ds = metro
    d = ds.copy()
    d.attrs = {**ds.attrs, "scenario_name": "<script>alert(1)</script>",
               "scenario": 'name = "x"\ndescription = "<img src=x onerror=alert(1)>"\n'}
    page = Page(report.html_report(d, caught=["<b>bold</b>"]))
    assert "script" not in page.tags and "b" not in page.tags and not page.images
    assert "<script>alert(1)</script>" in page.words and "<img src=x onerror=alert(1)>" in page.words
    assert "<b>bold</b>" in page.words


def test_railwear_plot_writes_the_report_again(metro, tmp_path):
    out, _ = metro
    result = CliRunner().invoke(app, ["plot", str(out / "result.nc"), "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert f"wrote {tmp_path / 'report.html'}" in result.output
    page = Page((tmp_path / "report.html").read_text(encoding="utf-8"))
    assert len(page.images) == 4 and all(decoded(i).startswith(PNG) for i in page.images)
    assert "warnings are not stored in the result file" in page.words


BROWSERS = ("chromium", "chromium-headless-shell", "chromium-browser", "google-chrome", "google-chrome-stable")


def browser():
    """A headless Chromium: ``$RAILWEAR_BROWSER``, else the first of :data:`BROWSERS` on the path."""
    given = os.environ.get("RAILWEAR_BROWSER")
    return shutil.which(given) if given else next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)


needs_browser = pytest.mark.skipif(
    browser() is None, reason=f"no headless Chromium on this machine (none of {', '.join(BROWSERS)} on the path, "
                              "nor $RAILWEAR_BROWSER); on Debian: apt-get install chromium-headless-shell")
SHOT = (1000, 4200)  # width, height of the screenshot in CSS pixels (device scale 1): the summary and two figures


def chromium(*arguments, timeout=120):
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--force-device-scale-factor=1",
             "--no-first-run", "--disable-extensions"]
    return subprocess.run([browser(), *flags, *arguments], check=True, timeout=timeout, capture_output=True,
                          text=True)


def screenshot(page, tmp_path, name="shot"):
    """The page rendered by headless Chromium at :data:`SHOT`: an RGB array (0-255)."""
    from matplotlib.image import imread

    shot = tmp_path / f"{name}.png"
    chromium(f"--window-size={SHOT[0]},{SHOT[1]}", f"--screenshot={shot}",
             f"--user-data-dir={tmp_path / (name + '-profile')}", page.resolve().as_uri())
    assert shot.read_bytes().startswith(PNG)
    return np.round(imread(shot)[..., :3] * 255).astype(int)


def problems(image):
    """What is wrong with a screenshot of a report, as a list of lines (empty: a rendered report):
    the size asked for; not blank (at least 3 % of the pixels off the white page); text (dark
    pixels) in its first 600 rows, where the title and summary are; and figures: the blue of the
    lines the figures draw (matplotlib's first colour, #1f77b4; the page's own text is black or
    brown), which a missing or broken image does not show."""
    found = []
    if image.shape[:2] != (SHOT[1], SHOT[0]):
        found.append(f"size {image.shape[1]} x {image.shape[0]}, not {SHOT[0]} x {SHOT[1]}")
    inked = np.mean(np.any(image < 235, axis=-1))
    if inked < 0.03:
        found.append(f"blank: {inked:.2%} of the pixels are not white")
    text = np.sum(np.all(image[:600] < 100, axis=-1))
    if text < 2000:
        found.append(f"no text at the top: {text} dark pixels")
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    blue = np.sum((b > 120) & (b - r > 60) & (b - g > 20))
    if blue < 3000:
        found.append(f"no figure drawn: {blue} blue pixels")
    return found


@needs_browser
def test_the_report_renders_in_a_headless_browser(metro, tmp_path):
    """report.html of a run, rendered by headless Chromium: the screenshot has the size asked
    for, text at the top and the figures drawn; the DOM it parsed holds the four images as PNG.
    The same check finds an empty page and a page whose images are broken."""
    out, _ = metro
    assert problems(screenshot(out / "report.html", tmp_path)) == []
    page = Page(chromium("--dump-dom", f"--user-data-dir={tmp_path / 'dom-profile'}",
                         (out / "report.html").resolve().as_uri()).stdout)
    assert len(page.images) == 4 and all(decoded(i).startswith(PNG) for i in page.images)
    assert "The numbers behind the regime" in page.words
    empty = tmp_path / "empty.html"
    empty.write_text("<!DOCTYPE html><html><head><title>x</title></head><body></body></html>", encoding="utf-8")
    assert any(p.startswith("blank") for p in problems(screenshot(empty, tmp_path, "empty")))
    broken = tmp_path / "broken.html"  # the report with every image's data cut short: broken images
    text = (out / "report.html").read_text(encoding="utf-8")
    broken.write_text(re.sub(r"base64,[A-Za-z0-9+/=]{64}", "base64,AAAA", text), encoding="utf-8")
    assert any(p.startswith("no figure") for p in problems(screenshot(broken, tmp_path, "broken")))
