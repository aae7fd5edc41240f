"""``python -m workbench``: serve the workbench page on this machine and open it in the browser."""

from __future__ import annotations

import argparse
import logging
import sys
import webbrowser

#: Where the server listens unless told otherwise: this machine only.
LOCAL = "127.0.0.1"
#: How long a stop waits for the requests under way, s: a shot answers in tens of ms, and a
#: request that is still open after this (a half-sent body, a page gone quiet) is dropped.
STOP_SECONDS = 2


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m workbench",
                                     description="Design, fire, watch and tune a trebuchet in a local web page.")
    parser.add_argument("--port", type=int, default=8765, help="port to listen on (default 8765; 0: any free one)")
    parser.add_argument("--host", default=LOCAL,
                        help=f"address to listen on (default {LOCAL}: this machine only)")
    parser.add_argument("--no-browser", action="store_true", help="do not open the page in a browser")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Serve until Ctrl-C (or SIGTERM); a stop says so in one line and returns 130 (0 without a signal)."""
    args = build_parser().parse_args(argv)
    if not 0 <= args.port <= 65535:
        print(f"--port {args.port}: must be from 0 to 65535", file=sys.stderr)
        return 2
    if args.host != LOCAL:
        print(f"warning: listening on {args.host}: other machines can reach the workbench and make this one "
              f"compute; use the default {LOCAL} unless you mean it", file=sys.stderr)
    try:
        _serve(args)
    except KeyboardInterrupt:   # uvicorn stops gracefully, then raises the signal it caught again
        print("workbench stopped", file=sys.stderr)
        return 130
    return 0


def _serve(args: argparse.Namespace) -> None:
    import uvicorn

    from workbench.app import build_app

    class Server(uvicorn.Server):
        async def startup(self, sockets=None):
            await super().startup(sockets)
            port = self.servers[0].sockets[0].getsockname()[1] if self.servers else args.port
            url = f"http://{_url_host(args.host)}:{port}/"
            print(f"workbench at {url} (Ctrl-C to stop)", flush=True)
            if not args.no_browser:
                webbrowser.open(url)

        async def shutdown(self, sockets=None):
            # The stop is said in one line (``main``): not uvicorn's count of the requests it dropped.
            logging.getLogger("uvicorn.error").setLevel(logging.CRITICAL)
            await super().shutdown(sockets)

    config = uvicorn.Config(build_app(hosts=(args.host,)), host=args.host, port=args.port, log_level="warning",
                            timeout_graceful_shutdown=STOP_SECONDS)
    Server(config).run()


def _url_host(host: str) -> str:
    """``host`` as a URL names it: an IPv6 address in brackets."""
    return f"[{host}]" if ":" in host and not host.startswith("[") else host


if __name__ == "__main__":
    sys.exit(main())
