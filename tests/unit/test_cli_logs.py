"""A first run is quiet: FFCx's JIT lowers the root logger to INFO (one
``INFO:root:building 'libffcx_...'`` line per compiled form); ``gsi`` shows library log
lines only with ``-v``."""
import subprocess
import sys

import pytest

SCRIPT = """
import logging, sys
import ffcx                       # calls logging.basicConfig() at import
from gsi.run.cli import _library_logs
_library_logs(int(sys.argv[1]))
logging.getLogger().setLevel(logging.INFO)     # what cffi/distutils do during a JIT build
logging.info("building 'libffcx_forms_test'")
logging.warning("a real warning")
"""


@pytest.mark.parametrize("verbose, shown", [(0, False), (1, True)])
def test_library_info_lines_only_with_verbose(verbose, shown):
    r = subprocess.run([sys.executable, "-c", SCRIPT, str(verbose)], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert ("building 'libffcx_forms_test'" in r.stderr) == shown
    assert "a real warning" in r.stderr


def test_verbose_option_on_gsi_and_gsi_run():
    from gsi.run.cli import parser
    assert parser().parse_args(["-v", "info"]).verbose == 1
    assert parser().parse_args(["run", "-vv", "x.toml"]).verbose_run == 2
