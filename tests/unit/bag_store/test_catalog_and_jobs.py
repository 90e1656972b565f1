"""Catalog resolution and conditional writes; job updates that never undo an end or a cancel."""

from __future__ import annotations

import pytest

from bagmcp_bag_store.catalog import resolve_bag
from bagmcp_bag_store.catalog_memory import MemoryCatalog
from bagmcp_bag_store.errors import AmbiguousBagError, BagNotFoundError, NameTakenError
from bagmcp_bag_store.jobs import Job, JobCancelledError, MemoryJobStore, ProgressReporter, update
from tests.fixtures.records import stored_record


@pytest.fixture
def catalog() -> MemoryCatalog:
    catalog = MemoryCatalog()
    for bag_id, name in (("a1b2c3", "husky_outdoor"), ("d4e5f6", "husky_indoor"), ("0789ab", "jackal")):
        catalog.claim_name(name, bag_id)
        assert catalog.add(stored_record(bag_id, name))
    return catalog


def test_bags_resolve_by_id_name_or_unique_prefix(catalog: MemoryCatalog) -> None:
    assert resolve_bag(catalog, "d4e5f6").name == "husky_indoor"
    assert resolve_bag(catalog, "jackal").id == "0789ab"
    assert resolve_bag(catalog, "husky_o").id == "a1b2c3"
    assert resolve_bag(catalog, "07").name == "jackal"


def test_an_ambiguous_prefix_lists_the_candidates(catalog: MemoryCatalog) -> None:
    with pytest.raises(AmbiguousBagError, match=r"husky_indoor.*husky_outdoor|husky_outdoor.*husky_indoor"):
        resolve_bag(catalog, "husky")


def test_an_unknown_bag_suggests_close_names(catalog: MemoryCatalog) -> None:
    with pytest.raises(BagNotFoundError, match="did you mean: jackal"):
        resolve_bag(catalog, "jakal")


def test_names_are_unique_and_adds_and_replaces_are_conditional(catalog: MemoryCatalog) -> None:
    with pytest.raises(NameTakenError):
        catalog.claim_name("jackal", "ffff")
    assert not catalog.add(stored_record("0789ab", "jackal"))
    catalog.delete("0789ab")
    assert not catalog.replace(stored_record("0789ab", "jackal"))  # a deleted bag is not brought back
    catalog.claim_name("jackal", "ffff")  # its name is free again


def test_a_finished_job_is_never_changed_and_a_cancel_survives_progress_updates() -> None:
    store = MemoryJobStore()
    job = Job.new("search", "alice", {})
    store.put(job)
    update(store, job.id, state="running")
    store.request_cancel(job.id)
    update(store, job.id, progress=0.5, message="halfway")
    reporter = ProgressReporter(store, job.id, every_s=0)
    with pytest.raises(JobCancelledError):
        reporter(0.6, "more")
    update(store, job.id, state="succeeded", result={"n": 1})
    assert update(store, job.id, state="running", progress=0.1).state == "succeeded"
    assert store.get(job.id).result == {"n": 1}  # type: ignore[union-attr]
