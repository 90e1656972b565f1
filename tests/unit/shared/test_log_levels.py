"""Tests of ROS 1 / ROS 2 log level names and parsing."""

from __future__ import annotations

import pytest

from bagmcp_shared.log_levels import LEVEL_NAMES, level_name, parse_level


@pytest.mark.parametrize("ros2", [False, True])
def test_exact_levels_have_their_names(ros2: bool) -> None:
    values = (10, 20, 30, 40, 50) if ros2 else (1, 2, 4, 8, 16)
    assert tuple(level_name(value, ros2=ros2) for value in values) == LEVEL_NAMES


@pytest.mark.parametrize(
    ("raw", "ros2", "name"),
    [(25, True, "INFO"), (49, True, "ERROR"), (99, True, "FATAL"), (0, True, "DEBUG"), (5, True, "DEBUG")],
)
def test_ros2_values_between_levels_round_down(raw: int, ros2: bool, name: str) -> None:
    assert level_name(raw, ros2=ros2) == name


@pytest.mark.parametrize(("raw", "name"), [(3, "INFO"), (7, "WARN"), (12, "ERROR"), (32, "FATAL"), (0, "DEBUG")])
def test_ros1_values_between_levels_round_down(raw: int, name: str) -> None:
    assert level_name(raw, ros2=False) == name


@pytest.mark.parametrize(
    ("value", "name"),
    [
        ("warn", "WARN"),
        ("Warning", "WARN"),
        (" err ", "ERROR"),
        ("critical", "FATAL"),
        ("DEBUG", "DEBUG"),
        (4, "WARN"),
        (30, "WARN"),
        ("16", "FATAL"),
        ("40", "ERROR"),
    ],
)
def test_names_aliases_and_numbers_of_either_scheme_parse(value: str | int, name: str) -> None:
    assert parse_level(value, ros2=True) == name
    assert parse_level(value, ros2=False) == name


@pytest.mark.parametrize("value", ["loud", 25, "3", True, ""])
def test_unknown_levels_list_the_valid_names(value: str | int) -> None:
    with pytest.raises(ValueError, match="DEBUG, INFO, WARN, ERROR, FATAL"):
        parse_level(value, ros2=True)


def test_error_message_suggests_the_numbers_of_the_given_scheme() -> None:
    with pytest.raises(ValueError, match="ROS 1 numbers 1, 2, 4, 8, 16"):
        parse_level("nope", ros2=False)
