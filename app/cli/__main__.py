"""``python -m app.cli``: the ``trical`` command, as the console script runs it."""

import sys

from app.cli.main import main

sys.exit(main())
