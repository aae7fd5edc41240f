"""Sphinx configuration of the documentation site: ``make docs`` builds it into ``docs/_build/html``.

Pages are MyST Markdown; the API reference comes from the numpydoc docstrings
of the public modules; the notebook is rendered as it is stored (never executed
here: the test suite runs it). No extension fetches anything at build time, so
the build works offline.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

project = "trebuchet-sim"
author = "the trebuchet-sim authors"
copyright = "the trebuchet-sim authors"

extensions = [
    "myst_nb",                      # MyST Markdown pages and the notebook
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
]

exclude_patterns = ["_build", "**/.ipynb_checkpoints"]
source_suffix = {".md": "myst-nb", ".ipynb": "myst-nb"}

# MyST: $...$ and $$...$$ maths (the derivation), heading anchors for links into pages.
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# The notebook is shown as stored; the test suite executes it (tests/test_analytic_notebook.py).
nb_execution_mode = "off"

# Autodoc imports the modules it documents; the signatures keep their annotations as written.
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autosummary_generate = False

# numpydoc renders the sections; no validation checks (see docs/contributing.md).
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "pydata_sphinx_theme"
html_title = "trebuchet-sim"
html_static_path: list[str] = []
# Pages without children of their own get no (empty) section navigation on the left.
html_sidebars = {page: [] for page in ("index", "builders", "derivation", "performance",
                                        "contributing", "dependencies")}
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 7,
}

# Every cross-reference must resolve (a broken one fails the build), except the
# classes of other libraries (no intersphinx: the build stays offline), the
# pieces of generic annotations autodoc splits at their commas, and two internal
# types that appear in public signatures but have no page of their own.
nitpicky = True
nitpick_ignore_regex = [
    ("py:class", r"(numpy|pathlib|collections\.abc|typing)\..*"),
    ("py:class", r"(dict|tuple|list)\[.*"),
    ("py:class", r"analytic\.(parameters\.Params|reference\.ode\.Segment)"),
]
