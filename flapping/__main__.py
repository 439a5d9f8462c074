"""``python -m flapping``: the command line of :mod:`flapping.cli`."""

import sys

from flapping.cli import main

if __name__ == "__main__":
    sys.exit(main())
