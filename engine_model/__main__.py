"""``python -m engine_model``: see ``engine_model.cli``."""

import sys

from engine_model.cli import main

sys.exit(main())
