"""The Lab's one exception root: every failure a Lab user sees is a LabError whose sentence says what to do."""

from __future__ import annotations

from bagmcp_shared.errors import BagmcpError


class LabError(BagmcpError):
    """A benchmark or chat could not run (bad task file, missing key, unreachable model or MCP server)."""


class TaskFileError(LabError):
    """A YAML task file is malformed."""


class ProviderError(LabError):
    """The model provider refused or failed a request (wrong key, unknown model, server down)."""


class KeyMissingError(LabError):
    """No API key: the environment variable named for it is unset."""


class TooManyRunsError(LabError):
    """A caller already has as many Lab runs going as the server allows."""
