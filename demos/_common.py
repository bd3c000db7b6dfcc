"""Shared command line of the demos: ``python demos/<name>.py [--quick] [--out DIR]``."""
from __future__ import annotations

import argparse
import pathlib
import sys

from gsi.config.case import load_case
from gsi.drivers import run_case
from gsi.errors import GsiInputError, GsiRunError


def main(case_file: pathlib.Path, description: str, argv=None):
    """Parse the demo's options, run its case, and return the driver's result."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--quick", action="store_true", help="small version (< 2 minutes)")
    parser.add_argument("--out", default=None, help="output directory (default out/<name>)")
    args = parser.parse_args(argv)
    try:
        case = load_case(case_file)
        out = pathlib.Path(args.out) if args.out else pathlib.Path("out") / case.case.name
        return run_case(case, out=out, quick=args.quick)
    except GsiInputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
    except GsiRunError as exc:
        print(f"run stopped: {exc}", file=sys.stderr)
        sys.exit(3)
