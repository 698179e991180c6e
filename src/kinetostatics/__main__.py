"""``python -m kinetostatics``: the command line (as ``python -m kinetostatics.cli``)."""

import sys

from .cli import main

sys.exit(main())
