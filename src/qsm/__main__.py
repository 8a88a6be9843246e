"""``python -m qsm``: the ``qsm`` command without its installed script."""

import sys

from qsm.app.cli import main

sys.exit(main())
