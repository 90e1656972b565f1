"""The web front end's files: the vendored uPlot is the npm release the lock names, the lock records no
download address, every file a page names is shipped, and an Apps viewer is one self-contained document."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from bagmcp_kit.web.assets import STATIC_DIR, MissingAssetError, asset_text, bundle
from bagmcp_kit.web.viewers import VIEW_SCRIPTS, VIEW_STYLES, viewer_document

ROOT = Path(__file__).resolve().parents[3]
NODE_UPLOT = ROOT / "node_modules" / "uplot" / "dist"


@pytest.mark.parametrize("name", ["uPlot.iife.min.js", "uPlot.min.css"])
def test_the_vendored_uplot_is_the_locked_npm_release(name: str) -> None:
    if not NODE_UPLOT.is_dir():
        pytest.skip("node_modules is absent (make install runs npm ci)")
    assert (STATIC_DIR / "vendor" / name).read_bytes() == (NODE_UPLOT / name).read_bytes()
    locked = json.loads((ROOT / "package-lock.json").read_text())["packages"]["node_modules/uplot"]["version"]
    assert f"(v{locked})" in (STATIC_DIR / "vendor" / "uPlot.iife.min.js").read_text()[:80]


def test_the_npm_lock_records_no_download_address() -> None:
    text = (ROOT / "package-lock.json").read_text()
    assert '"resolved"' not in text
    assert "omit-lockfile-registry-resolved=true" in (ROOT / ".npmrc").read_text()


def test_every_file_the_console_page_names_is_shipped() -> None:
    page = asset_text("console/index.html")
    named = re.findall(r'(?:src|href)="/static/([^"]+)"', page)
    assert len(named) > 15
    assert [n for n in named if not (STATIC_DIR / n).is_file()] == []
    assert "<script>" not in page  # no inline script: the CSP allows only files from this server


def test_a_viewer_is_one_document_with_every_view_inlined() -> None:
    document = viewer_document()
    assert "<script src" not in document
    assert "<link" not in document
    assert document.count("<script>") == document.count("</script>") == len(VIEW_SCRIPTS) + 2
    for name in (*VIEW_SCRIPTS, "apps/bridge.js", "apps/viewer.js"):
        assert f"/* {name} */" in document
    for name in VIEW_STYLES:
        assert asset_text(name)[:200] in document
    assert 80_000 < len(document.encode()) < 200_000


def test_a_bundled_script_cannot_close_its_own_tag(tmp_path: Path) -> None:
    made = bundle(title="<x>", styles=[], scripts=["views/format.js"], body="<p>hi</p>")
    assert "<title>&lt;x&gt;</title>" in made
    assert made.count("</script>") == 1


def test_only_files_inside_static_can_be_named() -> None:
    with pytest.raises(MissingAssetError):
        asset_text("../assets.py")
    with pytest.raises(MissingAssetError):
        asset_text("views/nothing.js")
