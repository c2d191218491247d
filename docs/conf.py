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


def _figures_drawn_without_pyplot() -> None:
    """Let the plot directive show the package's figures.

    The directive saves only the figures pyplot manages, and ``dz.plotting`` makes its own
    (``matplotlib.figure.Figure``, no global state), so without this the gallery would be
    code with no pictures. Each figure a snippet makes is handed to pyplot after the snippet
    runs, as ``pyplot.figure`` would have registered it.
    """
    import matplotlib.figure
    import matplotlib.pyplot as plt
    from matplotlib._pylab_helpers import Gcf
    from matplotlib.sphinxext import plot_directive

    run = plot_directive._run_code

    def run_keeping_figures(code, code_path, ns=None, function_name=None):
        made = []
        init = matplotlib.figure.Figure.__init__

        def recording(self, *args, **kwargs):
            init(self, *args, **kwargs)
            made.append(self)

        matplotlib.figure.Figure.__init__ = recording
        try:
            return run(code, code_path, ns, function_name)
        finally:
            matplotlib.figure.Figure.__init__ = init
            for fig in made:
                if fig.canvas.manager is None:
                    number = max(plt.get_fignums(), default=0) + 1
                    # what pyplot.figure does with a new manager (it also wires the close)
                    Gcf._set_new_active_manager(fig.canvas.new_manager(fig, number))

    plot_directive._run_code = run_keeping_figures


_figures_drawn_without_pyplot()

html_theme = "furo"
html_title = f"dzhanibekov {release}"
napoleon_use_ivar = True


def _every_plot_drawn(app, exception) -> None:
    """Fail the build when a page's plots are missing or share one file: MyST parses each
    ``eval-rst`` block apart, so plots without a ``:filename-prefix:`` would all be
    ``<page>-1.png``, each overwriting the last."""
    import re
    from pathlib import Path

    if exception is not None or app.builder.format != "html":
        return
    for page in Path(app.outdir).rglob("*.html"):
        sources = re.findall(r'<img[^>]*class="plot-directive"[^>]*src="([^"]+)"',
                             page.read_text(encoding="utf-8"))
        if len(set(sources)) != len(sources):
            raise RuntimeError(f"{page.name}: plots share an image file: {sorted(sources)}")
        missing = [s for s in sources if not (page.parent / s).is_file()]
        if missing:
            raise RuntimeError(f"{page.name}: plots drew no image: {missing}")


def setup(app):
    app.connect("build-finished", _every_plot_drawn)
