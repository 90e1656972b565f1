"""The static files under ``static/`` and one-document bundles of them.

An MCP Apps viewer is a single HTML document the host renders in a sandboxed iframe that cannot load
files from our server, so its scripts and styles are inlined; the console loads the same files by URL.
Bundling reads about 120 KB from the package once per process (cached)."""

from __future__ import annotations

import html
from collections.abc import Sequence
from functools import cache
from pathlib import Path

STATIC_DIR = Path(__file__).resolve().parent / "static"


class MissingAssetError(LookupError):
    """A page names a static file the package does not ship (a packaging mistake)."""


@cache
def asset_text(relative: str) -> str:
    """The text of ``static/<relative>``; only files inside ``static/`` can be named."""
    path = (STATIC_DIR / relative).resolve()
    if STATIC_DIR not in path.parents or not path.is_file():
        raise MissingAssetError(f"no static asset {relative!r} in {STATIC_DIR}")
    return path.read_text(encoding="utf-8")


def _inline_script(relative: str) -> str:
    # A script body may not contain "</script"; escaping the slash keeps the JavaScript meaning.
    body = asset_text(relative).replace("</script", "<\\/script")
    return f"<script>/* {relative} */\n{body}\n</script>"


def bundle(*, title: str, styles: Sequence[str], scripts: Sequence[str], body: str) -> str:
    """One self-contained HTML document: ``styles`` and ``scripts`` (paths under ``static/``) inlined in
    order, ``body`` (trusted markup) in the page."""
    css = "\n".join(asset_text(s) for s in styles).replace("</style", "<\\/style")
    code = "\n".join(_inline_script(s) for s in scripts)
    return (
        '<!doctype html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{html.escape(title)}</title><style>{css}</style></head>"
        f"<body>{body}\n{code}</body></html>"
    )
