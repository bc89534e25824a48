"""``python -m pipeline.cli ...`` is the ``pipeline`` command."""

import sys

from . import main

sys.exit(main())
