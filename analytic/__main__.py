"""Entry point: ``python -m analytic``."""

import sys

from analytic.cli_shared import run_main
from analytic.cli import main

sys.exit(run_main(main))
