"""The listening socket the servers serve on gives connections without Nagle's delay: asyncio (under uvicorn)
sets TCP_NODELAY only on sockets whose protocol says TCP, so the socket must name it."""

from __future__ import annotations

import asyncio
import socket

from bagmcp_kit.service_app import bound_socket


async def _nodelay_of_accepted(listening: socket.socket) -> int:
    accepted: asyncio.Future[int] = asyncio.get_running_loop().create_future()

    async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        accepted.set_result(writer.get_extra_info("socket").getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY))
        writer.close()

    server = await asyncio.start_server(handle, sock=listening)
    async with server:
        port = listening.getsockname()[1]
        _, writer = await asyncio.open_connection("127.0.0.1", port)
        nodelay = await asyncio.wait_for(accepted, timeout=10)
        writer.close()
        await writer.wait_closed()
    return nodelay


def test_connections_accepted_on_the_bound_socket_have_nagle_off() -> None:
    listening = bound_socket("127.0.0.1", 0)
    assert listening.proto == socket.IPPROTO_TCP
    assert asyncio.run(_nodelay_of_accepted(listening)) != 0
