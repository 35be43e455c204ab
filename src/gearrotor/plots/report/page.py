"""The HTML page: header (model, versions, command), navigation, the summary with the verdicts
and notes, the sections' parts (the first one the model, sections/model.py), the list of files;
the plotly.js bundle inline."""

from __future__ import annotations

import datetime as _dt

from .blocks import _e
from .verdicts import result_badge

_CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 0; color: #222; }
header { background: #24364b; color: white; padding: 14px 28px; }
header h1 { margin: 0; font-size: 1.4em; }
header p { margin: 4px 0 0; opacity: 0.85; font-size: 0.9em; }
nav { position: sticky; top: 0; background: #eef2f6; padding: 6px 28px; z-index: 10;
      border-bottom: 1px solid #cdd6e0; font-size: 0.9em; }
nav a { margin-right: 14px; color: #24364b; text-decoration: none; }
main { padding: 0 28px 40px; max-width: 1300px; }
section { margin-top: 26px; }
h2 { border-bottom: 2px solid #24364b; padding-bottom: 3px; font-size: 1.2em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 8px 0 14px; }
th, td { border: 1px solid #ccd; padding: 3px 8px; text-align: right; }
th { background: #eef2f6; }
td.l, th.l { text-align: left; }
tr.bad td { background: #fde2e2; }
tr.warn td { background: #fff4d6; }
tr.od td { color: #888; }
.ok { color: #1a7f37; font-weight: 600; }
.fail { color: #c62828; font-weight: 600; }
.na { color: #8a6d00; font-weight: 600; }
.note { background: #fff8e1; border-left: 4px solid #f0b400; padding: 6px 10px; }
.plot { margin: 10px 0 18px; border: 1px solid #e3e7ec; }
"""


def _page(train, sections, summary, figures, notes, *, source, command) -> str:
    import plotly
    from plotly.offline import get_plotlyjs

    from ... import __version__

    now = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    verdicts = summary.get("verdicts", [])
    vt = ["<table><tr><th class='l'>check</th><th>result</th><th class='l'>detail</th></tr>"]
    for v in verdicts:
        vt.append(
            f"<tr class='{'bad' if v['ok'] is False else ''}'><td class='l'>"
            f"{_e(v['check'])}</td><td>{result_badge(v['result'])}</td>"
            f"<td class='l'>{_e(v['detail'])}</td></tr>"
        )
    vt.append("</table>")
    if not verdicts:
        vt = ["<p>No stability or API check was requested.</p>"]
    secs = [
        (
            "summary",
            "Summary",
            "".join(vt) + "".join(f"<p class='note'>{_e(n)}</p>" for n in notes),
        ),
        *sections,
    ]
    files = "".join(f"<li><a href='{_e(p.name)}'>{_e(p.name)}</a></li>" for p in figures)
    secs.append(
        (
            "files",
            "Static figures and data",
            "<p>Files written next to this report (PNG, and the numbers as "
            "<a href='report.json'>report.json</a>):</p><ul>" + files + "</ul>",
        )
    )
    nav = "".join(f"<a href='#{i}'>{_e(t)}</a>" for i, t, _ in secs)
    body = "\n".join(f"<section id='{i}'><h2>{_e(t)}</h2>\n{h}\n</section>" for i, t, h in secs)
    sub = " · ".join(
        x
        for x in (
            f"model {_e(source)}" if source else "",
            f"gearrotor {__version__}",
            f"plotly {plotly.__version__}",
            now,
        )
        if x
    )
    cmd = f"<p>Command: <code>{_e(command)}</code></p>" if command else ""
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>{_e(train.name)} – gearrotor report</title>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<style>{_CSS}</style>\n"
        f"<script type='text/javascript'>{get_plotlyjs()}</script>\n</head><body>"
        f"<header><h1>{_e(train.name)}</h1><p>{sub}</p>{cmd}</header>"
        f"<nav>{nav}</nav><main>{body}</main></body></html>\n"
    )
