"""``report.html``: one self-contained file with the scenario, the summary and the numbers behind
the regime, every figure as an embedded PNG, the warnings and the version."""

import base64
import json
import os
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


BROWSERS = [b for b in ("chromium", "chromium-browser", "google-chrome", "firefox") if shutil.which(b)]


@pytest.mark.skipif(not BROWSERS, reason="no headless browser (chromium, google-chrome, firefox) on this machine")
def test_a_headless_browser_opens_the_report(metro, tmp_path):
    out, _ = metro
    url = (out / "report.html").resolve().as_uri()
    browser = BROWSERS[0]
    if browser == "firefox":
        shot = tmp_path / "shot.png"
        subprocess.run([browser, "--headless", "--screenshot", str(shot), url], check=True, timeout=120,
                       capture_output=True)
        assert shot.read_bytes().startswith(PNG)
        return
    dom = subprocess.run([browser, "--headless", "--disable-gpu", "--no-sandbox", "--dump-dom", url], check=True,
                         timeout=120, capture_output=True, text=True).stdout
    page = Page(dom)
    assert len(page.images) == 4 and all(decoded(i).startswith(PNG) for i in page.images)
    assert "The numbers behind the regime" in page.words
