"""The documentation's account of the figures and its pictures agree with what the package
draws: the figures guide lists what `dzhanibekov paper` renders, and the work-precision
picture says what its page says."""

from pathlib import Path

from PIL import Image

import dzhanibekov as dz
from dzhanibekov.render import PAPER_RENDER

DOCS = Path(__file__).resolve().parents[3] / "docs"


def test_the_figures_guide_lists_what_paper_renders():
    """It named one animation (`example.gif`) of four, and none of the nine scenes but Fig. 2
    and 3."""
    text = (DOCS / "guide" / "figures.md").read_text(encoding="utf-8")
    animated = [n for n in PAPER_RENDER if dz.SCENES[n].draw.animation]
    assert "simulates nine scenes" in text and "four animations" in text
    assert (len(PAPER_RENDER), len(animated)) == (9, 4)
    figures = sum(len(dz.SCENES[n].draw.figures) for n in PAPER_RENDER)
    assert f"{figures} in all" in text
    for name in PAPER_RENDER:
        scene = dz.SCENES[name]
        gif = f" `{name}.gif` |" if name in animated else " |"
        row = f"| `{name}` | {scene.title} | {', '.join(scene.draw.figures)} |{gif}"
        assert row in text, row
    for option in ("--jobs", "--no-animation", "--no-progress", "--fps", "--gif-size"):
        assert option in text


def test_the_work_precision_picture_says_what_its_page_says():
    """Its subtitle spoke of who shared the machine, long after the page stopped saying so:
    the picture is drawn from the page's tables (benches/replot_work_precision.py) and carries
    the subtitle it was drawn with."""
    page = (DOCS / "work_precision.md").read_text(encoding="utf-8")
    with Image.open(DOCS / "work_precision.png") as image:
        subtitle = image.text.get("Description", "")
    assert subtitle and subtitle in page
    assert "shared" not in subtitle and "engineer" not in subtitle
