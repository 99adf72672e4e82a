"""The golden-image report: one HTML page a person opens in a browser after a run
(`pytest --golden-report DIR`, `wgpu-shading check --report FILE.html`).

Failures come first, each with expected | actual | diff (the log-scale diff of images.py),
a slider and a blink comparison of expected and actual, zoom to single pixels, a read-out
of the pixel under the pointer, the metrics against the tolerance, the diagnosis
(diagnosis.py) and the command that accepts the new image; checks that passed (or wrote a
reference) are listed below. The page is self-contained: images are embedded as data URIs,
the style and the script (report.css, report.js beside this module) are inlined, nothing is
fetched, so it works from a CI artifact opened with file://.

An entry is plain data (`ReportEntry`, JSON-serialisable): pytest-xdist workers send theirs
to the controller in their test reports, and the controller writes the page.
"""

from __future__ import annotations

import base64
import html
import json
from dataclasses import asdict, dataclass, field
from datetime import datetime, timezone
from importlib import resources
from pathlib import Path

from .comparison import Comparison
from .golden import CheckResult
from .tolerance import GoldenError, percent

IMAGE_KINDS = ("expected", "actual", "diff", "flip")  # the failure images, by their file names' middle part
FAILED = ("failed", "missing")  # statuses shown as failures (the rest are listed as passes)


@dataclass(frozen=True)
class ReportEntry:
    """One comparison with a reference, as the report shows it.

    status: "failed", "missing" (no reference; only the actual image), "passed", "created",
    "updated". metrics: rows of (what, measured, allowed, verdict "ok" | "fail" | "").
    images: kind (IMAGE_KINDS) → path of the PNG written for this failure. accept: the
    command that makes the actual image the reference."""

    name: str
    reference: str
    status: str
    summary: str = ""
    metrics: tuple[tuple[str, str, str, str], ...] = ()
    failures: tuple[str, ...] = ()
    diagnosis: tuple[str, ...] = ()
    tolerance: str = ""
    images: dict[str, str] = field(default_factory=dict)
    diff_scale: str = ""
    accept: str = ""

    @property
    def failed(self) -> bool:
        return self.status in FAILED

    def to_json(self) -> str:
        return json.dumps(asdict(self), ensure_ascii=False)

    @classmethod
    def from_json(cls, text: str) -> "ReportEntry":
        data = json.loads(text)
        data["metrics"] = tuple(tuple(row) for row in data.get("metrics", ()))
        for key in ("failures", "diagnosis"):
            data[key] = tuple(data.get(key, ()))
        return cls(**data)


def entry_for_result(name: str, result: CheckResult, accept: str) -> ReportEntry:
    """The entry of a `check_image` outcome; `accept` is the command that accepts the actual image."""
    comparison = result.comparison
    images = {}
    for path in result.written:
        kind = path.name.rsplit(".", 2)[-2] if path.name.count(".") >= 2 else ""
        if kind in IMAGE_KINDS and result.status == "failed":
            images[kind] = str(Path(path).resolve())
    if comparison is None:
        return ReportEntry(name, str(result.reference), result.status, summary=result.report(), images=images)
    return ReportEntry(
        name=name,
        reference=str(result.reference),
        status=result.status,
        summary=comparison.summary(),
        metrics=metric_rows(comparison),
        failures=() if comparison.size_mismatch else comparison.failures,
        diagnosis=comparison.diagnosis,
        tolerance=comparison.tolerance.describe(),
        images=images,
        diff_scale=result.diff_scale,
        accept=accept if result.status == "failed" else "",
    )


def entry_for_missing(name: str, reference, actual_image, accept: str) -> ReportEntry:
    """The entry of a check whose reference does not exist (only the actual image)."""
    return ReportEntry(
        name, str(reference), "missing", summary=f"the reference {reference} does not exist",
        images={"actual": str(Path(actual_image).resolve())}, accept=accept,
    )


def metric_rows(comparison: Comparison) -> tuple[tuple[str, str, str, str], ...]:
    """Each measured value next to what the tolerance allows (what, measured, allowed, verdict)."""
    if comparison.size_mismatch:
        return (("image size", comparison.size_mismatch, "the same size", "fail"),)
    c, t = comparison, comparison.tolerance
    allowed = t.allowed_count(c.pixel_count)
    verdict = lambda ok: "ok" if ok else "fail"  # noqa: E731
    largest = f"{c.max_difference}/255"
    if c.max_location is not None and c.max_difference > 0:
        largest += f" at row {c.max_location[0]}, col {c.max_location[1]} ({c.max_channel})"
    rows = [
        (
            f"pixels differing by more than {t.threshold}/255",
            f"{c.over_count} of {c.pixel_count} ({percent(c.over_fraction)})",
            f"at most {allowed} ({percent(t.max_fraction)})",
            verdict(c.over_count <= allowed),
        ),
        (
            "largest difference",
            largest,
            "no cap" if t.max_difference is None else f"at most {t.max_difference}/255",
            "" if t.max_difference is None else verdict(c.max_difference <= t.max_difference),
        ),
        ("largest difference per channel", ", ".join(f"{k} {v}" for k, v in c.channel_max.items()), "", ""),
        ("99.9th percentile of the per-pixel difference", f"{c.percentile}/255", "", ""),
    ]
    if t.flip_mean is not None and c.flip_mean is not None:
        rows.append(("mean FLIP error", f"{c.flip_mean:.4f}", f"at most {t.flip_mean:g}", verdict(c.flip_mean <= t.flip_mean)))
    return tuple(rows)


# --------------------------------------------------------------------------- the page


def write_report(path, entries, *, title: str = "Golden-image report", context: str = "") -> Path:
    """Write the page for `entries` (failures first, in the order given; then the rest)
    atomically (assets/atomic.py). `context` is a line under the title (the command run)."""
    from ..assets.atomic import atomic_write

    path = Path(path)
    page = render_page(list(entries), title=title, context=context)
    atomic_write(path, page.encode("utf-8"), "golden report", GoldenError)
    return path


def render_page(entries: list[ReportEntry], *, title: str, context: str = "") -> str:
    failed = [e for e in entries if e.failed]
    others = [e for e in entries if not e.failed]
    counts = f"{len(failed)} failed, {len(others)} passed" if entries else "no golden-image checks ran"
    written = sum(e.status in ("created", "updated") for e in others)
    if written:
        counts += f" ({written} of them wrote a reference)"
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        '<link rel="icon" href="data:,">',  # no favicon request (a console error on file://)
        f"<title>{_e(title)}: {_e(counts)}</title>",
        f"<style>{_asset('report.css')}</style>",
        "</head><body>",
        f"<header><h1>{_e(title)}</h1><p class=\"counts\">{_e(counts)} · {_e(stamp)}</p>",
    ]
    if context:
        parts.append(f"<p class=\"context\"><code>{_e(context)}</code></p>")
    if failed:
        parts.append("<nav><ol>" + "".join(
            f'<li><a href="#failure-{i}">{_e(e.name)}</a> <span class="ref">{_e(Path(e.reference).name)}</span></li>'
            for i, e in enumerate(failed, 1)) + "</ol></nav>")
    parts.append("</header><main>")
    if failed:
        parts.append(f'<section id="failures"><h2>Failures ({len(failed)})</h2>')
        parts += [_failure(i, e) for i, e in enumerate(failed, 1)]
        parts.append("</section>")
    parts.append(f'<section id="passes"><h2>Passed ({len(others)})</h2>')
    if others:
        parts.append("<table class=\"passes\"><thead><tr><th>check</th><th>reference</th><th>status</th><th>metrics</th></tr></thead><tbody>")
        parts += [
            f"<tr class=\"{_e(e.status)}\"><td>{_e(e.name)}</td><td>{_e(e.reference)}</td><td>{_e(e.status)}</td><td>{_e(e.summary)}</td></tr>"
            for e in others
        ]
        parts.append("</tbody></table>")
    else:
        parts.append("<p>none</p>")
    parts.append("</section></main>")
    parts.append(f"<script>{_asset('report.js')}</script></body></html>")
    return "\n".join(parts)


def _failure(index: int, entry: ReportEntry) -> str:
    images = {kind: _data_uri(path) for kind, path in entry.images.items()}
    out = [
        f'<article class="failure" id="failure-{index}">',
        f"<h3><span class=\"status\">{_e(entry.status.upper())}</span> {_e(entry.name)}</h3>",
        f"<p class=\"reference\">reference <code>{_e(entry.reference)}</code></p>",
        f"<p class=\"summary\">{_e(entry.summary)}</p>",
    ]
    if entry.metrics:
        out.append("<table class=\"metrics\"><thead><tr><th></th><th>measured</th><th>tolerance</th><th></th></tr></thead><tbody>")
        for what, measured, allowed, verdict in entry.metrics:
            out.append(f"<tr class=\"{_e(verdict)}\"><th>{_e(what)}</th><td>{_e(measured)}</td><td>{_e(allowed)}</td><td>{_e(verdict)}</td></tr>")
        out.append("</tbody></table>")
        if entry.tolerance:
            out.append(f"<p class=\"tolerance\">tolerance: {_e(entry.tolerance)}</p>")
    if entry.failures or entry.diagnosis:
        out.append("<ul class=\"diagnosis\">")
        out += [f"<li class=\"rule\">failed: {_e(line)}</li>" for line in entry.failures]
        out += [f"<li>looks like: {_e(line)}</li>" for line in entry.diagnosis]
        out.append("</ul>")
    if entry.accept:
        out.append(
            "<div class=\"accept\">to accept the actual image as the new reference (then review it): "
            f"<code class=\"command\">{_e(entry.accept)}</code> <button type=\"button\" class=\"copy\">copy</button></div>"
        )
    out.append(
        "<div class=\"toolbar\"><label>zoom <select class=\"zoom\">"
        + "".join(f'<option value="{z}">{z}×</option>' for z in (1, 2, 4, 8, 16, 32))
        + "</select></label> <span class=\"pixel\" aria-live=\"polite\">point at a pixel to read its values</span></div>"
    )
    out.append("<div class=\"panels\">")
    for kind, caption in (("expected", "expected (the reference)"), ("actual", "actual (drawn now)"), ("diff", "difference"), ("flip", "FLIP error")):
        if kind in images:
            note = f"<figcaption>{_e(caption)}" + (f" — {_e(entry.diff_scale)}" if kind == "diff" and entry.diff_scale else "") + "</figcaption>"
            out.append(f"<figure class=\"{kind}\">{note}<div class=\"view\">{_img(images[kind], kind)}</div></figure>")
        elif kind in ("expected", "actual"):
            out.append(f"<figure class=\"{kind}\"><figcaption>{_e(caption)}</figcaption><p class=\"absent\">no image</p></figure>")
    out.append("</div>")
    if "expected" in images and "actual" in images:
        out.append(
            "<div class=\"compare\"><div class=\"modes\">compare: "
            "<label><input type=\"radio\" value=\"slider\" checked> slider</label> "
            "<label><input type=\"radio\" value=\"blink\"> blink</label> "
            "<span class=\"showing\">left of the line: actual · right: expected</span></div>"
            "<input type=\"range\" class=\"split\" min=\"0\" max=\"100\" value=\"50\" aria-label=\"slider position\">"
            "<div class=\"view\"><div class=\"stack\">"
            f"{_img(images['expected'], 'under')}{_img(images['actual'], 'over')}<div class=\"split-line\"></div>"
            "</div></div></div>"
        )
    out.append("</article>")
    return "\n".join(out)


def _img(source: str | None, role: str) -> str:
    if source is None:
        return "<p class=\"absent\">image missing</p>"
    return f'<img class="{role}" data-role="{role}" src="{source}" alt="{role}">'


def _data_uri(path: str) -> str | None:
    try:
        data = Path(path).read_bytes()
    except OSError:
        return None
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _asset(name: str) -> str:
    return resources.files(__package__).joinpath(name).read_text(encoding="utf-8")


def _e(text: object) -> str:
    return html.escape(str(text), quote=True)

