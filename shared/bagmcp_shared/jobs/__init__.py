"""Jobs: typed kinds in a registry, records in a store (memory or Redis), run to their end once."""

from bagmcp_shared.jobs.kinds import JobKind, JobRegistry
from bagmcp_shared.jobs.models import TERMINAL, Job, JobState
from bagmcp_shared.jobs.progress import Progress, ProgressReporter, ProgressSpan, Unreported, spans
from bagmcp_shared.jobs.run import run_job
from bagmcp_shared.jobs.store import JobStore, MemoryJobStore, RedisJobStore, owned, update

__all__ = [
    "TERMINAL",
    "Job",
    "JobKind",
    "JobRegistry",
    "JobState",
    "JobStore",
    "MemoryJobStore",
    "Progress",
    "ProgressReporter",
    "ProgressSpan",
    "RedisJobStore",
    "Unreported",
    "owned",
    "run_job",
    "spans",
    "update",
]
