"""``python -m symbolic.described DESCRIPTION.json MODULE.py``: derive a description into a module."""

import sys

from symbolic.described.module import main

sys.exit(main())
