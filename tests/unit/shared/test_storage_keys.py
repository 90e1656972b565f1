"""validate_key: which object keys the stores accept, and that the error names the bad key."""

from __future__ import annotations

import pytest

from bagmcp_shared.errors import InvalidKeyError, StorageError
from bagmcp_shared.storage import validate_key
from bagmcp_shared.storage.base import is_valid_key, validate_prefix

GOOD_KEYS = [
    "a",
    "bags/2024/run_01.mcap",
    "indexes/3f2a/summary.json",
    "A-b_c.d",
    "x" * 1024,
    "0/1/2/3",
    "v1..2",
]
BAD_KEYS = [
    "",
    "/abs",
    "../etc/passwd",
    "a/../../b",
    "a/./b",
    ".",
    "..",
    "a//b",
    "a/",
    "a\\b",
    ".hidden",
    ".tmp-abc123",
    "-leading-dash",
    "a/_private",
    "with space",
    "tab\tkey",
    "new\nline",
    "caf\u00e9",
    "a:b",
    "x" * 1025,
]


@pytest.mark.parametrize("key", GOOD_KEYS)
def test_well_formed_keys_are_returned_unchanged(key: str) -> None:
    assert validate_key(key) == key
    assert is_valid_key(key)


@pytest.mark.parametrize("key", BAD_KEYS)
def test_malformed_or_escaping_keys_are_rejected_with_the_key_in_the_message(key: str) -> None:
    with pytest.raises(InvalidKeyError) as caught:
        validate_key(key)
    assert repr(key)[:60] in str(caught.value)
    assert not is_valid_key(key)


def test_invalid_key_errors_are_storage_errors() -> None:
    with pytest.raises(StorageError):
        validate_key("../x")


def test_a_1024_character_key_of_many_segments_is_the_longest_accepted() -> None:
    key = "/".join(["abc"] * 256)[:1024]
    assert len(key) == 1023
    assert validate_key(key + "d") == key + "d"
    with pytest.raises(InvalidKeyError):
        validate_key(key + "de")


@pytest.mark.parametrize("prefix", ["", "bags/", "bags/2024/"])
def test_listing_prefixes_are_empty_or_a_key_with_a_trailing_slash(prefix: str) -> None:
    assert validate_prefix(prefix) == prefix


@pytest.mark.parametrize("prefix", ["bags", "/", "bags//", "../", "/bags/", "a\\b/"])
def test_listing_prefixes_without_trailing_slash_or_escaping_are_rejected(prefix: str) -> None:
    with pytest.raises(InvalidKeyError):
        validate_prefix(prefix)
