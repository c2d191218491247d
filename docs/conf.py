"""Sphinx configuration of the dzhanibekov documentation (``sphinx-build -W -b html docs OUT``).

The API reference is generated from the docstrings of the installed package (not the source
tree: the Rust core is only in the installed one), the gallery by running its examples.
"""

import dzhanibekov

project = "dzhanibekov"
author = "the dzhanibekov authors"
release = version = dzhanibekov.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_parser",
    "matplotlib.sphinxext.plot_directive",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "make_figures.py"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
# myst.xref_missing: README-style in-page links resolve on GitHub; ref.python: "shape" in a
# docstring names both Body.shape and Sweep.shape
suppress_warnings = ["myst.xref_missing", "ref.python"]

autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False

plot_include_source = True
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 80)]
plot_rcparams = {"figure.max_open_warning": 0}

html_theme = "furo"
html_title = f"dzhanibekov {release}"
napoleon_use_ivar = True
