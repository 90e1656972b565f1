"""Catalog resolution and conditional writes."""

from __future__ import annotations

import pytest

from bagmcp_shared.catalog import BagRecord, MemoryCatalog, exact_bag, resolve_bag
from bagmcp_shared.errors import AmbiguousBagError, BagNotFoundError, NameTakenError
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


def test_destructive_calls_take_only_an_exact_id_or_name(catalog: MemoryCatalog) -> None:
    assert exact_bag(catalog, "jackal").id == "0789ab"
    assert exact_bag(catalog, "d4e5f6").name == "husky_indoor"
    with pytest.raises(BagNotFoundError):
        exact_bag(catalog, "jack")


class ListingCounter(MemoryCatalog):
    def __init__(self) -> None:
        super().__init__()
        self.listings = 0

    def all(self) -> list[BagRecord]:
        self.listings += 1
        return super().all()


def test_a_bag_named_exactly_is_found_without_listing_and_forgotten_when_deleted(catalog: MemoryCatalog) -> None:
    counting = ListingCounter()
    for record in catalog.all():
        counting.claim_name(record.name, record.id)
        counting.add(record)
    catalog = counting
    assert resolve_bag(catalog, "husky_indoor").id == "d4e5f6"
    assert exact_bag(catalog, "jackal").id == "0789ab"
    assert counting.listings == 0  # an exact name needs no listing of every record
    catalog.delete("0789ab")
    assert catalog.named("jackal") is None
    with pytest.raises(BagNotFoundError):
        resolve_bag(catalog, "jackal")
    catalog.claim_name("jackal", "1111")
    assert catalog.add(stored_record("1111", "jackal"))  # the name now belongs to another bag
    assert resolve_bag(catalog, "jackal").id == "1111"
