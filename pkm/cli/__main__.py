"""``python -m pkm.cli``: the command line, as the ``pkm`` console script runs it."""

import sys

from pkm.cli import main

if __name__ == "__main__":
    sys.exit(main())
