"""Bag access: local files of catalogued bags, the bounded cache of opened bags, and opening them."""

from bagmcp_shared.access.files import BagFiles, CachedBagFiles, FolderBagFiles, IndexPublisher
from bagmcp_shared.access.opened import BagAccess, KnownBag, OpenBag
from bagmcp_shared.access.readers import ReaderCache
from bagmcp_shared.access.remote import RangedBagFiles

__all__ = [
    "BagAccess",
    "BagFiles",
    "CachedBagFiles",
    "FolderBagFiles",
    "IndexPublisher",
    "KnownBag",
    "OpenBag",
    "RangedBagFiles",
    "ReaderCache",
]
