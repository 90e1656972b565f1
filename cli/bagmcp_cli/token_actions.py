"""What `bagmcp token create|list|revoke` do: on this machine (an embedded server's data directory) or against
a running gateway (``--url URL --token ADMIN_TOKEN``, through its admin routes). Imported when a token command
runs, not to print help (token_commands.py builds the parser)."""

from __future__ import annotations

import argparse
import json
from datetime import UTC, datetime
from pathlib import Path

import httpx

from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.access.profiles import DEFAULT_PROFILES
from bagmcp_gateway.access.tokens.admin import TokenRequest, create_token, list_tokens, revoke_token
from bagmcp_gateway.access.tokens.models import NewToken, TokenInfo
from bagmcp_gateway.access.tokens.store import FileTokenStore
from bagmcp_shared.errors import BagmcpError

TOKENS_FILE = "tokens.json"


class TokenCommandError(BagmcpError):
    """The gateway refused a token command or could not be reached."""


def tokens_file(data_dir: Path) -> Path:
    return data_dir / TOKENS_FILE


def _local_store(args: argparse.Namespace) -> FileTokenStore:
    if args.data is None and args.bags is None:
        raise TokenCommandError(
            "say where the tokens live: --url URL --token ADMIN (a gateway), --data DIR or --bags DIR"
        )
    data = args.data or EmbeddedSettings.from_env(Path(args.bags), None).data_dir
    return FileTokenStore(tokens_file(data))


def _remote(args: argparse.Namespace, method: str, path: str, body: dict[str, object] | None = None) -> object:
    try:
        response = httpx.request(
            method,
            f"{args.url.rstrip('/')}/api/v1/{path}",
            json=body,
            headers={"Authorization": f"Bearer {args.token}"},
            timeout=30,
        )
    except httpx.HTTPError as err:
        raise TokenCommandError(f"cannot reach {args.url}: {err}") from err
    if response.status_code >= 400:
        try:
            message = response.json()["error"]["message"]
        except (ValueError, KeyError, TypeError):
            message = response.text[:200]
        raise TokenCommandError(f"the gateway refused ({response.status_code}): {message}")
    return response.json() if response.content else None


def _when(stamp: float | None) -> str:
    return datetime.fromtimestamp(stamp, tz=UTC).strftime("%Y-%m-%d %H:%M UTC") if stamp else "never"


def create(args: argparse.Namespace) -> int:
    request = TokenRequest(
        name=args.name,
        scopes=[s.strip() for s in args.scopes.split(",") if s.strip()],
        profile=args.profile,
        allow=args.allow or [],
        deny=args.deny or [],
        expires=args.expires,
    )
    if args.url:
        made = NewToken.model_validate(_remote(args, "POST", "tokens", request.model_dump()))
    else:
        made = create_token(_local_store(args), request, profiles=list(DEFAULT_PROFILES))
    if args.json:
        print(made.model_dump_json())
    else:
        print(made.token)
        print(
            f"token {made.name}: scopes {','.join(made.scopes)}, profile {made.profile or 'full'}, "
            f"expires {_when(made.expires_at)} (shown once: keep it now)"
        )
    return 0


def listed(args: argparse.Namespace) -> int:
    if args.url:
        raw = _remote(args, "GET", "tokens")
        tokens = [TokenInfo.model_validate(t) for t in raw] if isinstance(raw, list) else []
    else:
        tokens = list_tokens(_local_store(args))
    if args.json:
        print(json.dumps([t.model_dump(mode="json") for t in tokens]))
        return 0
    for t in tokens:
        state = "EXPIRED" if t.expired else f"expires {_when(t.expires_at)}"
        limits = "".join(f" allow={g}" for g in t.allow) + "".join(f" deny={g}" for g in t.deny)
        print(f"{t.name}  scopes={','.join(t.scopes)} profile={t.profile or 'full'}{limits}  {state}")
    return 0


def revoke(args: argparse.Namespace) -> int:
    if args.url:
        _remote(args, "DELETE", f"tokens/{args.name}")
    else:
        revoke_token(_local_store(args), args.name)
    print(f"token {args.name} revoked")
    return 0
