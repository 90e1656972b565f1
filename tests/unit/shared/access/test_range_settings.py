"""The range-read settings: defaults, and a cache too small for its reads refused at start."""

from __future__ import annotations

import pytest

from bagmcp_shared.errors import SettingsError
from bagmcp_shared.settings import Env, RangeReads


def test_defaults_are_one_mebibyte_blocks_a_four_gibibyte_cache_and_eight_mebibytes_ahead() -> None:
    assert RangeReads.from_env(Env({})) == RangeReads(2**20, 4 * 2**30, 8 * 2**20)
    chosen = {"BAGMCP_BLOCK_BYTES": "65536", "BAGMCP_BLOCK_CACHE_BYTES": "1048576", "BAGMCP_READ_AHEAD_BYTES": "0"}
    assert RangeReads.from_env(Env(chosen)) == RangeReads(65536, 1048576, 0)


@pytest.mark.parametrize(
    ("env", "said"),
    [
        ({"BAGMCP_BLOCK_BYTES": "100"}, "BAGMCP_BLOCK_BYTES must be at least 4096"),
        ({"BAGMCP_BLOCK_CACHE_BYTES": "10000000"}, "BAGMCP_BLOCK_CACHE_BYTES must hold at least four reads"),
    ],
)
def test_unusable_settings_are_refused_with_what_to_change(env: dict[str, str], said: str) -> None:
    with pytest.raises(SettingsError, match=said):
        RangeReads.from_env(Env(env))
