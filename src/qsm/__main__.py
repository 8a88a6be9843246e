"""``python -m qsm``."""

import sys

from qsm.cli import main

sys.exit(main())
