"""``python -m engine_model``: see ``engine_model.cli``."""

import sys

from analytic.cli_shared import run_main
from engine_model.cli import main

sys.exit(run_main(main))
