"""The run report: one self-contained HTML file a user can send (layer 4).

``report.html`` holds the scenario (TOML), the summary with the numbers behind the regime (the
fitted growth rates with their standard errors, leading and dominant order, wavelength, passing
frequency, distance to the limit), every figure the run wrote (PNG embedded as base64 data URIs),
the warnings of the run and railwear's version. All text is escaped; nothing is fetched.
"""

import base64
import html
import warnings
from pathlib import Path

import numpy as np

from railwear.results import (PER_10000_KM, defined, growth_note, growth_per_10000_km, is_round, summary,
                              summary_text, write_text)

NAME = "report.html"
STYLE = """body{font-family:sans-serif;max-width:60em;margin:2em auto;padding:0 1em;color:#222}
pre{background:#f4f4f4;padding:.8em;white-space:pre-wrap;overflow-wrap:anywhere;font-size:90%}
table{border-collapse:collapse;margin:.5em 0 1.5em}td,th{border:1px solid #ccc;padding:.25em .6em;text-align:left}
td.n{text-align:right;font-variant-numeric:tabular-nums}img{max-width:100%}
figure{margin:1em 0}.warn{color:#8a4b00}"""


def _e(text):
    return html.escape(str(text), quote=True)


def number(value, digits=4):
    """A number as the report writes it: ``digits`` significant digits, ``-`` for none,
    ``undefined`` for an undefined statistic (NaN or infinite, as the summary says)."""
    if value is None:
        return "-"
    if not defined(value):
        return "undefined"
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value)).lower()
    if isinstance(value, (int, np.integer)):
        return f"{int(value):d}"
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.{digits}g}"
    return str(value)


def _rows(ds):
    """``(label, dataset)`` per batch row of a result (as :func:`railwear.results.summary`)."""
    batch = list(ds.regime.dims) if "regime" in ds else []
    if not batch:
        return [("", ds)]
    return [(f"{batch[0]} {float(ds[batch[0]][i]):g}", ds.isel({batch[0]: i})) for i in range(ds.sizes[batch[0]])]


def growth_rows(d, life_km):
    """The numbers behind the regime of one run ``d``: rows ``(quantity, value, standard error,
    unit)`` of the fitted ln-growth rates (per unit normed time and per 10 000 km), growth factors
    and the orders they belong to."""
    per = PER_10000_KM / life_km if life_km > 0 else None
    rows = []

    def rate(label, value, error):
        rows.append((f"{label}: ln-growth rate", float(value), float(error), "per unit normed time"))
        if per is not None:
            rows.append((f"{label}: ln-growth rate", float(value) * per, float(error) * per, "per 10 000 km"))
            rows.append((f"{label}: growth per 10 000 km", growth_per_10000_km(float(value), life_km) * 100, None, "%"))

    if "out_of_round_growth_rate" in d:
        rate("out-of-round rms", d.out_of_round_growth_rate, d.out_of_round_growth_rate_error)
        rows.append(("out-of-round rms: growth over the run", float(d.out_of_round_growth_factor), None, "factor"))
    shown = set()
    for name, label in (("leading_order", "leading order (fastest of those present at the start)"),
                        ("dominant_order", "dominant order (largest at the end)")):
        if name not in d or (name == "dominant_order" and "peak_to_peak" in d and is_round(float(d.peak_to_peak))):
            continue  # a round wheel has no largest order
        n = int(d[name])
        rows.append((label, n, None, "order" if n not in shown else "order (its rates above)"))
        if n > 0 and "growth_rate" in d and n not in shown:
            shown.add(n)
            note = growth_note(d, n) if "amplitude_initial" in d else None
            if note and note.startswith("not meaningful"):  # a rate of round-off is not the wheel's
                rows.append((f"order {n}: growth", note, None, ""))
            else:
                rate(f"order {n}", d.growth_rate.sel(order=n), d.growth_rate_error.sel(order=n))
    if "leading_growth_factor" in d:
        rows.append(("leading order: growth over the run", float(d.leading_growth_factor), None, "factor"))
    return rows


def polygon_rows(entry):
    """Rows ``(quantity, value, unit)`` of a summary entry in the field's terms."""
    out = []
    for key, label, unit in (("wavelength_mm", "wavelength of the dominant order on the tread", "mm"),
                             ("passing_frequency_hz", "its passing frequency", "Hz"),
                             ("peak_to_peak_initial_um", "peak to peak at the start", "µm"),
                             ("peak_to_peak_um", "peak to peak at the end", "µm"),
                             ("max_removed_depth_mm", "removed at the most worn spot", "mm"),
                             ("distance_km", "distance run", "km"),
                             ("peak_to_peak_limit_mm", "out-of-roundness limit, peak to peak", "mm"),
                             ("limit_distance_km", "distance to the limit", "km"),
                             ("limit_months", "time to the limit at the scenario's daily mileage", "months")):
        if key in entry:
            value = entry[key]
            if key == "limit_distance_km" and value is None:
                value = f"not reached in {entry['distance_km']:,.0f} km"
            elif unit == "km":
                value = f"{value:,.0f}"
            elif unit == "months":
                value = f"{value:.1f}"
            out.append((label, value, unit))
    return out


def _field_value(v):
    """A summary field as the report's table writes it: a list joined, a table as 'key: value; ...'."""
    if isinstance(v, dict):
        return "; ".join(f"{k}: {_field_value(x)}" for k, x in v.items())
    return ", ".join(number(x, 6) for x in v) if isinstance(v, list) else number(v, 6)


def _table(head, rows):
    cells = "".join(f"<th>{_e(h)}</th>" for h in head)
    body = []
    for row in rows:
        body.append("<tr>" + "".join(
            f'<td class="n">{_e(number(c))}</td>' if isinstance(c, (int, float, np.number)) and not isinstance(c, bool)
            else f"<td>{_e(number(c))}</td>" for c in row) + "</tr>")
    return f"<table><tr>{cells}</tr>{''.join(body)}</table>"


def warning_lines(caught=(), compiled=False):
    """One line per distinct warning (``WarningMessage`` or text; repeats counted), and a note
    when kernels were compiled in the run."""
    lines = []
    for w in caught:
        text = (f"{w.category.__name__}: {w.message}" if isinstance(w, warnings.WarningMessage) else str(w))
        text = " ".join(text.split())
        lines.append(text)
    counted = {t: lines.count(t) for t in dict.fromkeys(lines)}
    out = [t if k == 1 else f"{t} ({k} times)" for t, k in counted.items()]
    if compiled:
        out.append("compile: numba compiled kernels in this run (a cold cache: the first run after an install "
                   "or a change); the run's wall time includes it")
    return out


def figure_html(path):
    """An embedded figure: the PNG of ``path`` (its ``.png`` sibling for a PDF or SVG) as a data URI."""
    png = Path(path).with_suffix(".png")
    data = base64.b64encode(png.read_bytes()).decode("ascii")
    return (f'<figure><img src="data:image/png;base64,{data}" alt="{_e(png.stem)}">'
            f"<figcaption>{_e(png.name)}</figcaption></figure>")


def html_report(ds, figures=(), caught=(), compiled=False, warnings_known=True):
    """The report of the result ``ds`` as HTML text: ``figures`` the paths of the figures the run
    wrote, ``caught`` its warnings, ``compiled`` whether it compiled kernels;
    ``warnings_known`` False for a report drawn again from a file (the run's warnings are not
    stored in it)."""
    from railwear import __version__

    s = summary(ds)
    name = ds.attrs.get("scenario_name", "") or "railwear"
    life = float(ds.attrs.get("life_distance_km", 0.0))
    made_with = ds.attrs.get("railwear_version", "")
    parts = [f"<h1>railwear report: {_e(name)}</h1>"]
    description = _scenario_description(ds)
    if description:
        parts.append(f"<p>{_e(description)}</p>")
    parts.append(f"<p>railwear {_e(__version__)}"
                 + (f" (the result was computed by railwear {_e(made_with)})" if made_with and made_with != __version__ else "")
                 + f"; strategy {_e(ds.attrs.get('strategy', '-'))}, body {_e(ds.attrs.get('body', '-'))}; "
                 f"scenario hash <code>{_e(ds.attrs.get('scenario_hash', '-'))}</code></p>")
    parts.append("<h2>Summary</h2>")
    parts.append(f"<pre>{_e(summary_text(s))}</pre>")
    for (label, d), entry in zip(_rows(ds), s["runs"]):
        title = " ".join(x for x in (label, f"{entry.get('speed_kmh', 0):g} km/h", entry.get("regime", "")) if x)
        parts.append(f"<h3>{_e(title)}</h3>")
        if "regime" in d:
            rule = d.regime.attrs.get("rule", "")
            parts.append(f"<p>regime <strong>{_e(entry['regime'])}</strong>" + (f": {_e(rule)}" if rule else "") + "</p>")
            parts.append("<h4>The numbers behind the regime</h4>")
            parts.append(_table(("quantity", "value", "standard error", "unit"), growth_rows(d, life)))
        rows = polygon_rows(entry)
        if rows:
            parts.append("<h4>The wheel in the field's terms</h4>")
            parts.append(_table(("quantity", "value", "unit"), rows))
        parts.append("<h4>Every field of the summary</h4>")
        parts.append(_table(("field", "value"), [(k, _field_value(v)) for k, v in entry.items()]))
    parts.append("<h2>Figures</h2>")
    if figures:
        parts.extend(figure_html(p) for p in figures)
    else:
        parts.append("<p>no figures were written</p>")
    parts.append("<h2>Warnings</h2>")
    lines = warning_lines(caught, compiled)
    if not warnings_known:
        lines.insert(0, "the run's warnings are not stored in the result file this report was drawn from")
    parts.append("<ul>" + "".join(f'<li class="warn">{_e(t)}</li>' for t in lines) + "</ul>" if lines
                 else "<p>none</p>")
    parts.append("<h2>Scenario</h2>")
    parts.append(f"<pre>{_e(ds.attrs.get('scenario', '(not stored in the result)'))}</pre>")
    parts.append(f"<footer><p>written by railwear {_e(__version__)}</p></footer>")
    return _document(f"railwear report: {name}", parts)


def _scenario_description(ds):
    """The scenario's description from the TOML stored with the result, or ''."""
    import tomllib

    try:
        return str(tomllib.loads(ds.attrs.get("scenario", "")).get("description", ""))
    except tomllib.TOMLDecodeError:
        return ""


def page(title, blocks, figures=(), scenario=""):
    """A self-contained HTML page of another command's outputs (``railwear plan``, ``fleet``,
    ``load``) in the run report's style: ``blocks`` are ``(kind, content)`` with kind ``h2``,
    ``p``, ``pre`` (text) or ``table`` (``(head, rows)``), then the ``figures`` embedded, the
    scenario's TOML and the version. All text is escaped; nothing is fetched."""
    from railwear import __version__

    parts = [f"<h1>{_e(title)}</h1>"]
    for kind, content in blocks:
        if kind == "table":
            parts.append(_table(*content))
        elif kind in ("h2", "h3", "p", "pre"):
            parts.append(f"<{kind}>{_e(content)}</{kind}>")
        else:
            raise ValueError(f"page: no block of kind {kind!r}")
    parts.append("<h2>Figures</h2>")
    if figures:
        parts.extend(figure_html(p) for p in figures)
    else:
        parts.append("<p>no figures were written</p>")
    if scenario:
        parts += ["<h2>Scenario</h2>", f"<pre>{_e(scenario)}</pre>"]
    parts.append(f"<footer><p>written by railwear {_e(__version__)}</p></footer>")
    return _document(title, parts)


def _document(title, parts):
    """The HTML document of the body ``parts`` (HTML text) under ``title`` (plain text)."""
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{_e(title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
            + "\n".join(parts) + "\n</body>\n</html>\n")


def write_page(path, title, blocks, figures=(), scenario=""):
    """Write :func:`page` atomically to ``path``; returns the path."""
    return write_text(page(title, blocks, figures, scenario), path)


def write_report(ds, path, figures=(), caught=(), compiled=False, warnings_known=True):
    """Write :func:`html_report` atomically to ``path`` (group-readable under the usual umask);
    returns the path."""
    return write_text(html_report(ds, figures, caught, compiled, warnings_known), path)
