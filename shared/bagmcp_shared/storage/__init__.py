"""Object storage for bags and indexes: a local directory or an S3 bucket behind one protocol."""

from bagmcp_shared.storage.base import ObjectInfo, ObjectStore, validate_key
from bagmcp_shared.storage.local import LocalStore
from bagmcp_shared.storage.s3 import S3Store

__all__ = ["LocalStore", "ObjectInfo", "ObjectStore", "S3Store", "validate_key"]
