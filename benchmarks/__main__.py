"""Entry point: ``python -m benchmarks``."""

import sys

from analytic.cli_shared import run_main
from benchmarks.cli import main

if __name__ == "__main__":
    sys.exit(run_main(main))
