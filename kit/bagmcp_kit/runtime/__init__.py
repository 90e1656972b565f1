"""The runtime above the library: the Celery app and its worker (with the visibility heartbeat), and the
composition of a process's catalog, bag files, job store, runner and object storage (``resources``)
for each way of running. The library (``bagmcp_shared``) imports no Celery; services and the CLI build
their processes from here."""
