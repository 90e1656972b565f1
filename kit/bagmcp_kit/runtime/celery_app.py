"""Team mode's background work: a Celery app on Redis whose workers take one service's queue (the runner that
sends tasks to it, ``sender.CeleryRunner``, makes its app from here on the first task sent). The embedded
thread runner and the task names stay in the library (``bagmcp_shared.tasks``); Celery lives only here, in
the kit's runtime.
"""

from __future__ import annotations

from celery import Celery

from bagmcp_kit.runtime.heartbeat import VisibilityHeartbeat


def create_celery(redis_url: str, *, queue: str, visibility_timeout_s: int = 60) -> Celery:
    """A Celery app on Redis (broker and results) whose workers take only ``queue``.

    Tasks are acknowledged after they finish. A task whose worker vanished (killed outright, its machine
    gone) is handed to another worker once ``visibility_timeout_s`` has passed; a live worker keeps the tasks
    it holds from being handed out again however long they run (``VisibilityHeartbeat``). Every task here is
    safe to run twice.
    """
    app = Celery(f"bagmcp-{queue}", broker=redis_url, backend=redis_url)
    app.conf.update(
        task_default_queue=queue,
        task_queues=None,
        task_create_missing_queues=True,
        task_acks_late=True,
        task_reject_on_worker_lost=True,
        worker_prefetch_multiplier=1,
        task_serializer="json",
        result_serializer="json",
        accept_content=["json"],
        task_ignore_result=True,
        broker_connection_retry_on_startup=True,
        broker_transport_options={
            "visibility_timeout": visibility_timeout_s,
            # look for abandoned tasks every few seconds (kombu's default is about 100 s)
            "unacked_restore_interval": min(10, max(1, visibility_timeout_s // 5)),
            "unacked_restore_throttle": 1,
        },
    )
    app.steps["consumer"].add(VisibilityHeartbeat)
    return app
