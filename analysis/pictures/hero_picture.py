#!/usr/bin/env python3
"""The README's first picture: one frame under Z-pass, Z-fail and the exact reference.

Run by scripts/pictures.sh after

  nearcap render SCENE --light 0 --method zpass,zfail --stencil --out WORK/render
  nearcap reference SCENE --light 0 --out WORK/reference

Left and middle: the real GL's lit frames (headless EGL) of Z-pass and Z-fail.
Right: the exact reference's shaded frame (nearcap reference, shadow.png).
Every pixel whose shadow status on the real GL (its stencil, non-zero means
shadowed) differs from the exact reference's (count > 0) is a wrong pixel:
their regions are outlined in each method's panel, and the titles give the
counts, computed here from the two stencils, not written in.

usage: hero_picture.py WORK_DIR OUT_PNG [SCENE_NAME]
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from readme_pictures import read_pgm16  # noqa: E402

NOTHING_SEEN = 65535  # the reference's stencil where the pixel sees no surface


def wrong_pixels(gl_stencil, exact_stencil):
    seen = exact_stencil != NOTHING_SEEN
    return seen & ((gl_stencil != 0) != (exact_stencil > 0))


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    work, out = Path(sys.argv[1]), Path(sys.argv[2])
    scene = sys.argv[3] if len(sys.argv) == 4 else "near_cap_bunny_wall"
    exact = read_pgm16(work / "reference" / "stencil.pgm")
    panels = []
    for method, name in (("zpass", "Z-pass"), ("zfail", "Z-fail")):
        frame = plt.imread(work / "render" / f"frame-{method}.png")
        wrong = wrong_pixels(read_pgm16(work / "render" / f"stencil-{method}-light-0.pgm"), exact)
        panels.append((frame, wrong, f"{name} (real GL)", f"{int(wrong.sum()):,} wrong pixels"))
    seen = int((exact != NOTHING_SEEN).sum())
    panels.append((plt.imread(work / "reference" / "shadow.png"), None, "exact reference (rationals)",
                   f"the truth at all {seen:,} pixels"))

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.0), dpi=110)
    for ax, (image, wrong, title, subtitle) in zip(axes, panels):
        ax.imshow(image, interpolation="nearest")
        if wrong is not None and wrong.any():
            # The outline of every wrong region, drawn twice (dark under bright)
            # so that it reads on the lit wall and in the shadow alike.
            ax.contour(wrong.astype(float), levels=[0.5], colors="black", linewidths=4.5)
            ax.contour(wrong.astype(float), levels=[0.5], colors="#ffe000", linewidths=2.2)
        colour = "#c00000" if wrong is not None and wrong.any() else "#006000"
        ax.text(0.5, 1.11, title, transform=ax.transAxes, ha="center", va="bottom", fontsize=17, fontweight="bold")
        ax.text(0.5, 1.02, subtitle, transform=ax.transAxes, ha="center", va="bottom", fontsize=15, color=colour)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.text(0.5, 0.03,
             f"{scene}: the near plane cuts the bunny's shadow volume; "
             "yellow outlines: pixels whose shadow differs from the exact one",
             ha="center", va="bottom", fontsize=13)
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.1, top=0.82, wspace=0.04)
    fig.savefig(out)
    plt.close(fig)


if __name__ == "__main__":
    main()
