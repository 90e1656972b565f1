"""The settings of a `make stack` directory: its ports (the defaults when free, else free ones) and its
secrets (random), chosen on first start and kept in ``<stack dir>/stack.env`` (mode 0600), then printed as
shell ``export`` lines with the ``BAGMCP_*`` settings derived from them.

``python -m bagmcp_cli.stack.environment start`` chooses (the stack is about to start);
``... command`` reuses what the running stack chose (to run `bagmcp` commands with its settings).
"""

from __future__ import annotations

import fcntl
import os
import secrets
import shlex
import socket
import sys
from collections.abc import Iterable, Mapping
from pathlib import Path

from bagmcp_cli.stack.leftovers import stop_leftovers
from bagmcp_shared.errors import SettingsError
from bagmcp_shared.settings import Env

DEFAULT_PORTS = {
    "GATEWAY_PORT": 8080,
    "BAG_STORE_PORT": 8001,
    "ANALYSIS_PORT": 8002,
    "PLOTTING_PORT": 8003,
    "LAB_PORT": 8004,
    "REDIS_PORT": 6390,
    "S3_PORT": 8333,
}
# The S3 server (weed) also needs its master, volume server and filer, and a gRPC port for each part.
WEED_PORTS = {
    "WEED_MASTER_PORT": 1,
    "WEED_VOLUME_PORT": 2,
    "WEED_FILER_PORT": 3,
    "S3_GRPC_PORT": 10001,
    "WEED_MASTER_GRPC_PORT": 10002,
    "WEED_VOLUME_GRPC_PORT": 10003,
    "WEED_FILER_GRPC_PORT": 10004,
}
SECRETS = ("BAGMCP_SERVICE_TOKEN", "BAGMCP_S3_SECRET_KEY", "BAGMCP_REDIS_PASSWORD", "WEED_JWT_KEY")
SAVED = "stack.env"
LOCK = "stack.lock"


def _free(port: int) -> bool:
    with socket.socket() as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


def ports_of(name: str, port: int) -> list[int]:
    """Every port a setting occupies (the S3 server's block for S3_PORT)."""
    return [port, *(port + offset for offset in WEED_PORTS.values())] if name == "S3_PORT" else [port]


def ports_free(name: str, port: int, taken: set[int]) -> bool:
    wanted = ports_of(name, port)
    return max(wanted) < 65536 and not taken & set(wanted) and all(_free(p) for p in wanted)


def _any_free(name: str, taken: set[int]) -> int:
    """A free port (for S3_PORT, the start of a free block, low enough for its gRPC ports)."""
    for _ in range(500):
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            port = int(probe.getsockname()[1])
        if name == "S3_PORT":
            port = 20000 + port % 35000
        if ports_free(name, port, taken):
            return port
    raise SettingsError(f"no free port found for {name}")


def choose_ports(env: Env, saved: Mapping[str, str], *, starting: bool) -> dict[str, int]:
    """A port for each setting: as given in the environment; else (starting) the one saved, then the default,
    when free, else any free one; or (a command) the one the running stack saved."""
    chosen: dict[str, int] = {}
    taken: set[int] = set()
    for name, default in DEFAULT_PORTS.items():
        given = env.optional(name)
        if given is not None:
            port = env.integer(name, default)
        elif not starting:
            if name not in saved:
                raise SettingsError("no stack has started in this directory yet; run `make stack` first")
            port = int(saved[name])
        else:
            candidates = [int(saved[name])] if name in saved else []
            port = next((p for p in [*candidates, default] if ports_free(name, p, taken)), 0) or _any_free(name, taken)
        chosen[name] = port
        taken.update(ports_of(name, port))
    return chosen


def choose_secrets(env: Env, saved: Mapping[str, str]) -> dict[str, str]:
    """Each secret as given in the environment, else the saved one, else a new random one."""
    return {name: env.optional(name) or saved.get(name) or secrets.token_urlsafe(32) for name in SECRETS}


def read_saved(path: Path) -> dict[str, str]:
    if not path.is_file():
        return {}
    lines = [line for line in path.read_text().splitlines() if "=" in line and not line.startswith("#")]
    return dict(line.split("=", 1) for line in lines)


def write_saved(path: Path, values: Mapping[str, object]) -> None:
    """Kept readable by the owner only: it holds the stack's secrets."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w") as out:
        out.write("# chosen by `make stack` on its first start; edit or delete to choose again\n")
        out.writelines(f"{key}={value}\n" for key, value in values.items())
    path.chmod(0o600)


def derived(stack_dir: Path, ports: Mapping[str, int], chosen: Mapping[str, str], env: Env) -> dict[str, str]:
    """The BAGMCP_* settings of every process, as docker-compose.yml gives them."""
    bag_store, gateway = f"http://127.0.0.1:{ports['BAG_STORE_PORT']}", f"http://127.0.0.1:{ports['GATEWAY_PORT']}"
    analysis, plotting = f"http://127.0.0.1:{ports['ANALYSIS_PORT']}", f"http://127.0.0.1:{ports['PLOTTING_PORT']}"
    dev_token = env.text("BAGMCP_DEV_TOKEN", "bagmcp-dev-token")
    return {
        "BAGMCP_STACK_DIR": str(stack_dir),
        **{name: str(port) for name, port in ports.items()},
        **{name: str(ports["S3_PORT"] + offset) for name, offset in WEED_PORTS.items()},
        **chosen,
        "BAGMCP_DEV_TOKEN": dev_token,
        "BAGMCP_TOKENS": env.text("BAGMCP_TOKENS", dev_token),
        "BAGMCP_S3_ACCESS_KEY": env.text("BAGMCP_S3_ACCESS_KEY", "bagmcp"),
        "BAGMCP_S3_ENDPOINT": f"127.0.0.1:{ports['S3_PORT']}",
        "BAGMCP_S3_BUCKET": env.text("BAGMCP_S3_BUCKET", "bagmcp"),
        "BAGMCP_REDIS_URL": f"redis://:{chosen['BAGMCP_REDIS_PASSWORD']}@127.0.0.1:{ports['REDIS_PORT']}/0",
        "BAGMCP_UPSTREAMS": f"bag-store={bag_store}/mcp,analysis={analysis}/mcp,plotting={plotting}/mcp",
        "BAGMCP_REST_ROUTES": f"bags={bag_store},query={bag_store},artifacts={plotting},lab=http://127.0.0.1:{ports['LAB_PORT']}",
        "BAGMCP_ARTIFACT_BASE_URL": gateway,
        "BAGMCP_LAB_GATEWAY_URL": f"{gateway}/mcp",
    }


def running_pid(stack_dir: Path) -> int | None:
    """The supervisor's process id when a stack runs in ``stack_dir`` (it holds the lock file)."""
    lock = stack_dir / LOCK
    if not lock.is_file():
        return None
    with lock.open("a+") as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.seek(0)
            return int(handle.read().strip() or 0) or -1
        fcntl.flock(handle, fcntl.LOCK_UN)
    return None


def stack_settings(env: Env, *, starting: bool) -> dict[str, str]:
    stack_dir = Path(env.text("BAGMCP_STACK_DIR", ".stack")).resolve()
    if starting and (pid := running_pid(stack_dir)) is not None:
        raise SettingsError(f"a stack runs in {stack_dir} already (pid {pid}); stop it or set another BAGMCP_STACK_DIR")
    if starting:  # its processes would hold the saved ports and the data; a supervisor that was killed left them
        stop_leftovers(stack_dir, lambda text: print(f"bagmcp stack: {text}", file=sys.stderr, flush=True))
    stack_dir.mkdir(mode=0o700, parents=True, exist_ok=True)
    saved = read_saved(stack_dir / SAVED)
    ports = choose_ports(env, saved, starting=starting)
    chosen = choose_secrets(env, saved)
    if starting:
        write_saved(stack_dir / SAVED, {**{k: str(v) for k, v in ports.items()}, **chosen})
    return derived(stack_dir, ports, chosen, env)


def exports(values: Mapping[str, str]) -> Iterable[str]:
    return (f"export {key}={shlex.quote(value)}" for key, value in values.items())


def main(argv: list[str]) -> int:
    try:
        values = stack_settings(Env(), starting=argv[1:] == ["start"])
    except SettingsError as err:
        print(f"bagmcp stack: {err}", file=sys.stderr)
        return 1
    print("\n".join(exports(values)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
