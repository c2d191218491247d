"""Regenerates the README's pictures in docs/ from `dzhanibekov paper` and `dzhanibekov map`.

    python docs/make_figures.py

Renders the paper's figures into a temporary folder and keeps a few, reduced to 256 colours
(Pillow) so that each stays well under 200 KB.
"""

import tempfile
from pathlib import Path

from PIL import Image

from dzhanibekov.cli import main

KEEP = {
    "example-phases.png": "fig2-phases.png",
    "fig3.png": "fig3-paths.png",
    "fig3a-omega.png": "fig3a-omega.png",
    "example-polhode.png": "fig2-polhode.png",
    "example-invariants.png": "fig2-invariants.png",
    "stable.png": "stable-paths.png",
    "deployment-shares.png": "deployment-shares.png",
    "deployment-omega.png": "deployment-omega.png",
    "deployment-energy.png": "deployment-energy.png",
    "explorer-1-shares.png": "explorer-1-shares.png",
    "explorer-1-omega.png": "explorer-1-omega.png",
    "explorer-1-energy.png": "explorer-1-energy.png",
}
MAPS = {"map-rates.png": "stability-map.png"}


def run() -> None:
    docs = Path(__file__).parent
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "figures"
        assert main(["paper", "--out", str(out), "--no-progress"]) == 0
        assert main(["map", "--out", str(out), "--kind", "rates", "--no-progress"]) == 0
        for source, target in {**KEEP, **MAPS}.items():
            with Image.open(out / source) as image:
                small = image.convert("RGB").quantize(colors=256, dither=Image.Dither.NONE)
                small.save(docs / target, optimize=True)
            print(f"docs/{target}: {(docs / target).stat().st_size / 1024:.0f} KB")


if __name__ == "__main__":
    run()
