"""Which requests the server answers: those addressed to it by this machine's page, and no others.

A page from elsewhere open in the same browser can send requests to
``http://127.0.0.1:PORT`` (a form's POST needs no permission), and a name
that its owner points at 127.0.0.1 (DNS rebinding) can even read the
answers. So every request must name the server as the browser reached it:
its ``Host`` is ``localhost``, the address it was reached at
(``127.0.0.1``, ``[::1]``) or a name the server was started with
(``--host``), with the port it listens on, and an ``Origin``, where the
browser sends one, is that same place (else 403). A page from elsewhere
cannot send a JSON body without the browser asking the server first (which
it does not allow), so every POST must be ``application/json`` (else 415).
"""

from __future__ import annotations

import ipaddress
import json
from collections.abc import Iterable

#: Methods that change nothing: no body to check.
SAFE_METHODS = {"GET", "HEAD"}
#: The only body a POST may have.
JSON_TYPE = "application/json"
#: The name every browser resolves to this machine itself.
LOCALHOST = "localhost"


def split_host(value: str) -> tuple[str, int | None]:
    """``"127.0.0.1:8765"``, ``"[::1]:8765"``, ``"localhost"`` -> (name, port or None); the name in
    lower case, an IPv6 address without its brackets. ``("", None)`` for a value that is no host."""
    value = value.strip().lower()
    if value.startswith("["):
        name, _, rest = value[1:].partition("]")
        port = rest[1:] if rest.startswith(":") else ("" if not rest else "x")
    else:
        name, _, port = value.partition(":") if value.count(":") <= 1 else (value, "", "")
    if port and not port.isdigit():
        return "", None
    return name, int(port) if port else None


def _same_address(name: str, address: str) -> bool:
    try:
        return ipaddress.ip_address(name) == ipaddress.ip_address(address)
    except ValueError:
        return False


class Guard:
    """ASGI middleware: 403 for a request addressed to another name, 415 for a POST that is not JSON.

    ``hosts``: names besides ``localhost`` and the address reached that the server may be called by
    (the ``--host`` it was started with).
    """

    def __init__(self, app, hosts: Iterable[str] = ()):
        self.app = app
        self.hosts = {split_host(host)[0] for host in hosts}

    def allowed(self, host: str, server: tuple[str, int] | None) -> bool:
        """Whether ``host`` (a ``Host`` header, or an ``Origin``'s host) names this server, reached at ``server``."""
        name, port = split_host(host)
        if server is None:   # not on a network socket: nothing else can reach it
            return True
        address, listening = server[0], server[1]
        if port != listening and not (port is None and listening == 80):
            return False
        return name == LOCALHOST or name in self.hosts or _same_address(name, address)

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        headers = {key.decode("latin-1"): value.decode("latin-1") for key, value in scope["headers"]}
        server = scope.get("server")
        origin = headers.get("origin")
        if not self.allowed(headers.get("host", ""), server):
            return await _refuse(send, 403, "host", f"Host {headers.get('host', '')!r} is not this server's "
                                 "address: open the page at the address the server printed")
        if origin is not None and not (origin.startswith("http://") and self.allowed(origin[7:], server)):
            return await _refuse(send, 403, "origin", f"a page from {origin!r} may not use this server")
        if scope["method"] not in SAFE_METHODS:
            media = headers.get("content-type", "").split(";")[0].strip().lower()
            if media != JSON_TYPE:
                return await _refuse(send, 415, "content-type", f"content-type {media or 'none'!r}: "
                                     f"this server takes only {JSON_TYPE} bodies")
        return await self.app(scope, receive, send)


async def _refuse(send, status: int, field: str, message: str) -> None:
    """Answer ``status`` with the API's error object, ``{"error", "field"}``."""
    body = json.dumps({"error": message, "field": field}).encode()
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]})
    await send({"type": "http.response.body", "body": body})
