"""Entry point: ``python -m crosscheck``."""

import sys

from analytic.cli_shared import run_main
from crosscheck.cli import main

sys.exit(run_main(main))
