"""The ``gsi`` command (``gsi`` console script, ``python -m gsi.cli``): see :mod:`gsi.run.cli`."""
import sys

from gsi.run.cli import info, main

__all__ = ["info", "main"]

if __name__ == "__main__":
    sys.exit(main())
