"""Celery tasks: serialization and retries only; the work is in ingest.py."""

from __future__ import annotations

from collections.abc import Callable

from celery import Celery, Task

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.ingest import ingest_bag, mark_failed
from bagmcp_bag_store.jobrun import run_job
from bagmcp_shared.errors import BagmcpError, StorageError

INGEST_TASK = "bagmcp.bag_store.ingest"
JOB_TASK = "bagmcp.bag_store.run_job"


def create_celery(redis_url: str, *, visibility_timeout_s: int = 3600) -> Celery:
    """A Celery app on Redis (broker and results) that redelivers tasks of a worker that died.

    Tasks are acknowledged after they finish; a task whose worker vanished is handed to another
    worker once ``visibility_timeout_s`` has passed (every task here is safe to run twice).
    """
    app = Celery("bagmcp", broker=redis_url, backend=redis_url)
    app.conf.update(
        task_acks_late=True,
        task_reject_on_worker_lost=True,
        worker_prefetch_multiplier=1,
        task_serializer="json",
        result_serializer="json",
        accept_content=["json"],
        broker_connection_retry_on_startup=True,
        broker_transport_options={
            "visibility_timeout": visibility_timeout_s,
            # look for abandoned tasks every few seconds (kombu's default is about 100 s)
            "unacked_restore_interval": min(10, max(1, visibility_timeout_s // 5)),
            "unacked_restore_throttle": 1,
        },
        result_expires=24 * 3600,
    )
    return app


def register_tasks(app: Celery, deps: Callable[[], BagStoreDeps]) -> None:
    """Bind the tasks to ``app``; ``deps`` is called lazily in the worker process."""

    @app.task(name=INGEST_TASK, bind=True, max_retries=4)  # type: ignore[untyped-decorator]
    def ingest(self: Task, bag_id: str) -> str:
        try:
            return ingest_bag(deps(), bag_id)
        except StorageError as err:
            if self.request.retries >= self.max_retries:
                mark_failed(deps(), bag_id, f"storage was unavailable while ingesting ({err}); upload it again")
                return "failed"
            raise self.retry(exc=err, countdown=5 * 2**self.request.retries) from err
        except BagmcpError:
            raise
        except Exception as err:  # never leave a bag "ingesting" for good
            mark_failed(deps(), bag_id, f"ingest failed ({type(err).__name__}); see the worker log")
            raise

    @app.task(name=JOB_TASK, bind=True)  # type: ignore[untyped-decorator]
    def job(self: object, job_id: str) -> str:
        return run_job(deps(), job_id)
