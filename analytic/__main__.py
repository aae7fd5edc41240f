"""Entry point: ``python -m analytic``."""

import sys

from analytic.cli import main

sys.exit(main())
