"""``python -m workbench``: serve the workbench page on this machine and open it in the browser."""

from __future__ import annotations

import argparse
import sys
import webbrowser

#: Where the server listens unless told otherwise: this machine only.
LOCAL = "127.0.0.1"


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m workbench",
                                     description="Design, fire, watch and tune a trebuchet in a local web page.")
    parser.add_argument("--port", type=int, default=8765, help="port to listen on (default 8765; 0: any free one)")
    parser.add_argument("--host", default=LOCAL,
                        help=f"address to listen on (default {LOCAL}: this machine only)")
    parser.add_argument("--no-browser", action="store_true", help="do not open the page in a browser")
    return parser


def main(argv: list[str] | None = None) -> int:
    import uvicorn

    from workbench.app import build_app

    args = build_parser().parse_args(argv)
    if not 0 <= args.port <= 65535:
        print(f"--port {args.port}: must be from 0 to 65535", file=sys.stderr)
        return 2
    if args.host != LOCAL:
        print(f"warning: listening on {args.host}: other machines can reach the workbench and make this one "
              f"compute; use the default {LOCAL} unless you mean it", file=sys.stderr)
    config = uvicorn.Config(build_app(), host=args.host, port=args.port, log_level="warning")
    server = uvicorn.Server(config)
    original_startup = server.startup

    async def startup(sockets=None):
        await original_startup(sockets)
        port = server.servers[0].sockets[0].getsockname()[1] if server.servers else args.port
        url = f"http://{args.host}:{port}/"
        print(f"workbench at {url} (Ctrl-C to stop)", flush=True)
        if not args.no_browser:
            webbrowser.open(url)

    server.startup = startup
    server.run()
    return 0


if __name__ == "__main__":
    sys.exit(main())
