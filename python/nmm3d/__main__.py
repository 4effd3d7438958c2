"""``python -m nmm3d`` is the ``nmm3d`` command."""

import sys

from nmm3d.cli import main

sys.exit(main())
