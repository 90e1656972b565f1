"""The catalog: bag records (memory or Redis) and resolving what a caller calls a bag."""

from bagmcp_shared.catalog.memory_catalog import MemoryCatalog
from bagmcp_shared.catalog.models import BagRecord, BagStatus, CatalogSummary, TopicStats
from bagmcp_shared.catalog.protocol import Catalog
from bagmcp_shared.catalog.redis_catalog import RedisCatalog
from bagmcp_shared.catalog.resolve import exact_bag, ready_record, resolve_bag

__all__ = [
    "BagRecord",
    "BagStatus",
    "Catalog",
    "CatalogSummary",
    "MemoryCatalog",
    "RedisCatalog",
    "TopicStats",
    "exact_bag",
    "ready_record",
    "resolve_bag",
]
