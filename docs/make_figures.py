"""Regenerates the README's pictures in docs/ from `dzhanibekov paper` and `dzhanibekov map`.

    python docs/make_figures.py

Renders the paper's figures into a temporary folder and keeps a few, reduced to 256 colours
(Pillow) so that each stays well under 200 KB.
"""

import tempfile
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from PIL import Image

import dzhanibekov as dz
from dzhanibekov.cli import main
from dzhanibekov.plotting import compute
from dzhanibekov.plotting.figures import _axes3d, _limits, draw_body

KEEP = {
    "example-phases.png": "fig2-phases.png",
    "fig3.png": "fig3-paths.png",
    "fig3a-omega.png": "fig3a-omega.png",
    "example-polhode.png": "fig2-polhode.png",
    "example-invariants.png": "fig2-invariants.png",
    "stable.png": "stable-paths.png",
    "wing-nut-phases.png": "wing-nut-phases.png",
    "wing-nut-omega.png": "wing-nut-omega.png",
    "deployment-shares.png": "deployment-shares.png",
    "deployment-omega.png": "deployment-omega.png",
    "deployment-energy.png": "deployment-energy.png",
    "explorer-1-shares.png": "explorer-1-shares.png",
    "explorer-1-omega.png": "explorer-1-omega.png",
    "explorer-1-energy.png": "explorer-1-energy.png",
}
MAPS = {"map-rates.png": "stability-map.png"}


def wing_nut_picture(path: Path) -> None:
    """The wing nut alone, large, in its body axes (the bolt axis z drawn blue)."""
    scene = dz.SCENES["wing-nut"].replace(draw=dz.scenes.Draw(
        box=True, body_axes=True, figures=("phases",), phases=(0.0,)))
    result = compute(scene)
    fig = Figure(figsize=(4.2, 4.2), layout="constrained")
    ax = _axes3d(fig, 1, 1, 1)
    draw_body(ax, result, 0)
    _limits(ax, 0.75 * float(np.abs(result.at("box", 0)).max()))
    ax.set_axis_off()
    nut = scene.body
    moments = ", ".join(f"{i:.0f}" for i in nut.inertia)
    ax.set_title(f"Body.wing_nut(): {nut.mass:.2f} g; principal moments {moments} g·mm²\n"
                 "body axes x (red), y (green), z (blue: the bolt, the intermediate axis)",
                 fontsize=8)
    fig.savefig(path, dpi=110)


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
        # the wing nut itself (Body.wing_nut), large, with its body axes (x red, y green,
        # z blue: z the bolt axis, the intermediate one)
        wing_nut_picture(out / "wing-nut.png")
        with Image.open(out / "wing-nut.png") as image:
            small = image.convert("RGB").quantize(colors=256, dither=Image.Dither.NONE)
            small.save(docs / "wing-nut.png", optimize=True)
        print(f"docs/wing-nut.png: {(docs / 'wing-nut.png').stat().st_size / 1024:.0f} KB")


if __name__ == "__main__":
    run()
