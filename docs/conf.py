"""Sphinx configuration of the gsi documentation (built by ``make docs`` from Debian's
python3-sphinx, python3-myst-parser and furo; warnings are errors)."""
import os
import pathlib
import sys

DOCS = pathlib.Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))          # this checkout's gsi, not an installed one
sys.path.insert(0, str(DOCS / "_ext"))

import gsi  # noqa: E402

project = "gsi"
author = "the gsi developers"
copyright = "2026, the gsi developers"
release = version = gsi.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "gsi_docs",                 # docs/_ext/gsi_docs.py: generated pages (keys, gallery, ...)
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "_generated/*.md", "_generated/_mathjax"]
templates_path = []

html_theme = "furo"
html_title = f"gsi {release}"
html_static_path = ["_static"]
# MathJax 2.7 from Debian's libjs-mathjax (a dependency of python3-sphinx), copied in part
# into the site by gsi_docs, so the pages need no network; else Sphinx's default CDN
if pathlib.Path("/usr/share/javascript/mathjax/MathJax.js").exists():
    mathjax_path = "mathjax/MathJax.js?config=TeX-AMS_CHTML"
    html_static_path.append("_generated/_mathjax")
    myst_update_mathjax = False          # its settings are MathJax 3's
    mathjax2_config = {"tex2jax": {"inlineMath": [["\\(", "\\)"]],
                                   "displayMath": [["\\[", "\\]"]],
                                   "processEscapes": True, "processEnvironments": True}}

autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_mock_imports = []               # nothing is mocked: every import is installed
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_ivar = True           # "Attributes" as fields: no duplicate attribute entries
napoleon_use_param = False         # parameters as one field (a typed :param: list trips docutils on gsi.dem.Simulation)
autosummary_generate = False
suppress_warnings = ["myst.header"]
nitpicky = False
