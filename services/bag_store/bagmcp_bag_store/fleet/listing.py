"""The ready bags a query covers, as the catalog lists them, read at most once per ``ttl_s``: a query and the
check that decides whether it runs inline read the catalog once (500 records from Redis take about 50 ms to
parse). A bag deleted through this process is dropped at once (``forget``); one deleted elsewhere may still
be listed for ``ttl_s``, and its files, gone, are reported as missing."""

from __future__ import annotations

import threading
import time

from bagmcp_shared.catalog import BagRecord, Catalog

LISTING_TTL_S = 1.0


class ReadyBags:
    def __init__(self, catalog: Catalog, *, ttl_s: float = LISTING_TTL_S) -> None:
        self._catalog = catalog
        self._ttl_s = ttl_s
        self._listed: tuple[float, list[BagRecord]] | None = None
        self._lock = threading.Lock()

    def __call__(self) -> list[BagRecord]:
        with self._lock:
            if self._listed is not None and time.monotonic() - self._listed[0] < self._ttl_s:
                return self._listed[1]
        ready = [r for r in self._catalog.all() if r.status == "ready" and r.summary is not None]
        with self._lock:
            self._listed = (time.monotonic(), ready)
        return ready

    def forget(self) -> None:
        with self._lock:
            self._listed = None
