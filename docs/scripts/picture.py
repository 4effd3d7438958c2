"""Render the last frame of a run (blocks coloured by displacement) to PNG with PyVista.

    python docs/scripts/picture.py OUT_DIR PICTURE.png

The same view as opening OUT_DIR/result.pvd in ParaView, going to the last time and colouring
by `displacement` (magnitude). Needs PyVista (`pip install pyvista`) and off-screen rendering.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pyvista as pv


def main(run: Path, png: Path) -> None:
    last = sorted((run / "frames").glob("blocks_*.vtu"))[-1]
    mesh = pv.read(last)
    plotter = pv.Plotter(off_screen=True, window_size=(1000, 700))
    plotter.add_mesh(mesh, scalars="displacement", show_edges=False, cmap="viridis",
                     scalar_bar_args={"title": "displacement [m]"})
    plotter.add_mesh(mesh.extract_feature_edges(), color="black", line_width=1)
    plotter.view_isometric()
    plotter.add_text(f"{run.name}: {last.name}", font_size=10)
    plotter.screenshot(png)


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
