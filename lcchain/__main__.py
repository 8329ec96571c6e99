"""``python -m lcchain``: the console script."""

import sys

from .cli.main import main

sys.exit(main())
