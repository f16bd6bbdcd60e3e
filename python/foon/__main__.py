"""``python -m foon``: the same as the ``foon`` command."""

import sys

from foon.cli import main

sys.exit(main())
