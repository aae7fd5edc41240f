"""``python -m workbench.bench``: the latency from a slider's key press to the redrawn shot, in Debian's chromium.

Starts ``python -m workbench`` on a free port, opens the page headless, and
presses the right arrow on one design field's slider ``--presses`` times,
each after the last shot is drawn; the page records, for each, the time from
the input event to the end of the stage's redraw (``performance.now()``),
so the figure includes the request, the shot with its histories, the JSON
and the drawing. Prints the median and the 90th percentile.
"""

from __future__ import annotations

import argparse
import socket
import subprocess
import sys

import numpy as np

CHROMIUM = "/usr/bin/chromium"


def measure(url: str, field: str, presses: int) -> np.ndarray:
    """Latencies, ms, of ``presses`` key presses on ``field``'s slider at ``url`` to the redrawn
    stage and readouts."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM,
                                             args=["--no-sandbox", "--disable-background-networking"])
        page = browser.new_page(viewport={"width": 1400, "height": 900})
        page.goto(url)
        page.wait_for_function("Number(document.body.dataset.shots || 0) >= 1", timeout=30_000)
        slider = page.locator(f'.field[data-field="{field}"] .slider')
        slider.focus()
        for press in range(presses):
            count = int(page.evaluate("document.body.dataset.shots"))
            page.keyboard.press("ArrowRight" if press % 20 < 10 else "ArrowLeft")
            page.wait_for_function(f"Number(document.body.dataset.shots) > {count}", timeout=30_000)
        redrawn = np.array(page.evaluate("window.workbench.latencies"))
        browser.close()
    return redrawn


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m workbench.bench", description=__doc__.splitlines()[0])
    parser.add_argument("--presses", type=int, default=60, help="key presses to time (default 60)")
    parser.add_argument("--field", default="machine.sling_length", help="the slider to move")
    args = parser.parse_args(argv)
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    server = subprocess.Popen([sys.executable, "-m", "workbench", "--port", str(port), "--no-browser"],
                              stdout=subprocess.PIPE, text=True)
    try:
        url = f"http://127.0.0.1:{port}/"
        assert url in server.stdout.readline()
        redrawn = measure(url, args.field, args.presses)
    finally:
        server.terminate()
        server.wait(timeout=10)
    print(f"slider -> redrawn stage and readouts (the shot with its motion), {len(redrawn)} presses on "
          f"{args.field}: median {np.median(redrawn):.1f} ms, 90th percentile {np.percentile(redrawn, 90):.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
