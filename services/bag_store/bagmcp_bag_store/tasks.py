"""The bag-store's ingest task (Celery): serialization and retries only; the work is in ingest/."""

from __future__ import annotations

from collections.abc import Callable

from celery import Celery, Task

from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.task_refs import INGEST
from bagmcp_shared.errors import BagmcpError, StorageError


def register_ingest_task(app: Celery, ingestor: Callable[[], Ingestor]) -> None:
    """Bind ingest to ``app``; ``ingestor`` is called lazily in the worker process."""

    @app.task(name=INGEST.name, bind=True, max_retries=4)  # type: ignore[untyped-decorator]
    def ingest(self: Task, bag_id: str) -> str:
        try:
            return ingestor().ingest(bag_id)
        except StorageError as err:
            if self.request.retries >= self.max_retries:
                ingestor().mark_failed(bag_id, f"storage was unavailable while ingesting ({err}); upload it again")
                return "failed"
            raise self.retry(exc=err, countdown=5 * 2**self.request.retries) from err
        except BagmcpError:
            raise
        except Exception as err:  # never leave a bag "ingesting" for good
            ingestor().mark_failed(bag_id, f"ingest failed ({type(err).__name__}: {err})")
            raise
