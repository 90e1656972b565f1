"""YAML that a user wrote (a bag directory's metadata.yaml, a connection's offered QoS profiles), loaded
without aliases.

An alias repeats a node without repeating its text, so nested aliases are an exponential bomb: 800 bytes
of ``lN: &lN [*lN-1, ... ten times]`` for N up to 7 cost 634 MB to load, one level more over 3 GB.
rosbag2 never writes an alias, so any alias is refused before a node is built, with a sentence naming
where it is; the text itself is bounded too (:data:`MAX_YAML_BYTES`).
"""

from __future__ import annotations

from pathlib import Path

import yaml

MAX_YAML_BYTES = 4 << 20  # a metadata.yaml of 1,000 split files and 500 topics is about 300 KB
# libyaml's parser and loader (PyYAML's own when built without it): a drive bag's 7.5 KB metadata.yaml took
# 18 ms with PyYAML's Python SafeLoader, 2.7 ms with libyaml's (alias check 0.7 ms + load 2 ms), measured;
# every open of a ROS 2 bag directory reads it.
_SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class UserYamlError(ValueError):
    """YAML refused before it was built; ``str(err)`` is a sentence fragment naming what and where."""


def _alias_error(event: yaml.AliasEvent) -> UserYamlError:
    line = f" at line {event.start_mark.line + 1}" if event.start_mark is not None else ""
    return UserYamlError(f"uses the YAML alias *{event.anchor}{line}")


def _bounded(text: str) -> str:
    if len(text) > MAX_YAML_BYTES:
        raise UserYamlError(f"holds {len(text):,} characters of YAML, more than the {MAX_YAML_BYTES:,} accepted")
    return text


def load_user_yaml(text: str) -> object:
    """The YAML document in ``text``; raises :class:`UserYamlError` for an alias or an oversized text and
    ``yaml.YAMLError`` for a syntax error. Aliases are refused on parser events before any node is built."""
    return yaml.load(refuse_aliases(text), Loader=_SAFE_LOADER)


def read_user_yaml(path: Path) -> object:
    """The YAML document in the file at ``path``, its size checked before it is read (see :func:`load_user_yaml`;
    also ``OSError`` and ``UnicodeDecodeError``)."""
    if (size := path.stat().st_size) > MAX_YAML_BYTES:
        raise UserYamlError(f"holds {size:,} bytes of YAML, more than the {MAX_YAML_BYTES:,} accepted")
    return load_user_yaml(path.read_text(encoding="utf-8"))


def refuse_aliases(text: str) -> str:
    """``text`` unchanged when it holds no alias (checked on parser events, which build nothing), so that
    another YAML library may load it; raises :class:`UserYamlError` otherwise. Syntax errors are left for
    that library to report."""
    try:
        for event in yaml.parse(_bounded(text), Loader=_SAFE_LOADER):
            if isinstance(event, yaml.AliasEvent):
                raise _alias_error(event)
    except yaml.YAMLError:
        pass
    return text
