#!/usr/bin/env python3
"""The pictures of the README and docs/, from nearcap's own outputs on bundled scenes.

Run by scripts/pictures.sh, which first runs the nearcap commands into a
work directory; this script turns their outputs into small PNGs:

  near_cap_bunny.png      the exact near-cap counts of near_cap_bunny_silhouettes
                          (nearcap reference ... cap.pgm), coloured by count
  shadow_reference.png    the exact shadow of near_cap_bunny_wall (shadow.png)
  cracks_zpplus_wall.png  published ZP+ on near_cap_bunny_wall (cracks.png), cropped
                          around its cracks and enlarged, with nearcap's legend
  cracks_case_d.png       ZP+ corrected on case_d: its switch to Z-fail with
                          GL_DEPTH_CLAMP (cracks.png), with nearcap's legend
  cracks_raytrace_far.png Embree (float32 ray tracing, fixed shadow epsilon) on
                          far_grazing: shadow acne 10 km from the origin
                          (cracks.png), with nearcap's legend
  cases.png               the side quad Q of a silhouette edge and where the
                          near plane cuts it in cases A, B, C1, C2, D

usage: readme_pictures.py WORK_DIR OUT_DIR
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402


def read_pgm16(path):
    data = Path(path).read_bytes()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval
        while data[pos : pos + 1].isspace():
            pos += 1
        if data[pos : pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end : end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    pos += 1
    width, height = int(fields[1]), int(fields[2])
    return np.frombuffer(data[pos : pos + 2 * width * height], dtype=">u2").reshape(height, width)


def near_cap_picture(work, out):
    cap = read_pgm16(work / "bunny_silhouettes" / "cap.pgm").astype(int)
    top = int(cap.max())
    colours = ["#ffffff"] + [plt.cm.Blues(0.3 + 0.7 * k / max(top, 1)) for k in range(1, top + 1)]
    cmap = ListedColormap(colours)
    norm = BoundaryNorm(np.arange(-0.5, top + 1.5), cmap.N)
    fig, ax = plt.subplots(figsize=(5.2, 3.4), dpi=100)
    im = ax.imshow(cap, cmap=cmap, norm=norm, interpolation="nearest")
    ax.set_title("exact near-cap counts, bunny between light and near plane", fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])
    bar = fig.colorbar(im, ax=ax, ticks=range(top + 1), fraction=0.04)
    bar.set_label("near-cap count (front faces crossed)", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "near_cap_bunny.png")
    plt.close(fig)


def shadow_picture(work, out):
    image = plt.imread(work / "bunny_wall_reference" / "shadow.png")
    fig, ax = plt.subplots(figsize=(4.8, 3.9), dpi=100)
    ax.imshow(image, interpolation="bilinear")
    ax.set_title("exact shadow, near_cap_bunny_wall (dark: stencil > 0)", fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(out / "shadow_reference.png")
    plt.close(fig)


def crack_picture(src, out, name, title, crop):
    image = plt.imread(src)
    fig, ax = plt.subplots(figsize=(5.6, 5.0), dpi=100)
    if crop:
        # The frame part (above the legend) cropped to its marks, enlarged, and
        # the legend below it unchanged.
        x0, y0, x1, y1 = crop
        fig, (top, bottom) = plt.subplots(
            2, 1, figsize=(5.6, 5.6), dpi=100, gridspec_kw={"height_ratios": [3, 1.15]}
        )
        top.imshow(image[y0:y1, x0:x1], interpolation="nearest")
        top.set_title(title, fontsize=9)
        legend_rows = image[480:, :, :]
        bottom.imshow(legend_rows, interpolation="nearest")
        for a in (top, bottom):
            a.set_xticks([])
            a.set_yticks([])
    else:
        ax.imshow(image, interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(out / name)
    plt.close(fig)


def cases_picture(out):
    # Q in a 2-D slice: A, D the silhouette edge E_m (bottom), A_inf, D_inf the
    # edge at infinity E_inf (top), I1 = A A_inf, I2 = D D_inf.
    quad = np.array([[0.0, 0.0], [2.0, 0.0], [2.7, 2.0], [-0.7, 2.0]])
    planes = {
        "A": ([-1.2, 2.6], [3.2, 2.6], "not cut: nothing to do"),
        "B": ([-1.2, 1.0], [3.2, 1.0], "I1 and I2: counterparts"),
        "C1": ([-1.0, 1.2], [1.2, -0.6], "I1 and E_m: + corrective quad"),
        "C2": ([0.9, 2.6], [3.2, 0.8], "I2 and E_inf: + corrective quad"),
        "D": ([0.3, -0.6], [1.6, 2.6], "E_m and E_inf: switch to Z-fail"),
    }
    fig, axes = plt.subplots(1, 5, figsize=(10, 2.4), dpi=100)
    for ax, (name, (p, q, text)) in zip(axes, planes.items()):
        ax.fill(quad[:, 0], quad[:, 1], color="#d9d9d9", zorder=0)
        ax.plot(*np.vstack([quad, quad[:1]]).T, color="black", lw=1)
        ax.plot([p[0], q[0]], [p[1], q[1]], color="#d62728", lw=2, ls="--")
        ax.text(0.0, -0.35, "A", ha="center", fontsize=8)
        ax.text(2.0, -0.35, "D", ha="center", fontsize=8)
        ax.text(1.0, 0.12, "E_m", ha="center", fontsize=7)
        ax.text(1.0, 1.78, "E_inf", ha="center", fontsize=7)
        ax.text(-0.55, 1.0, "I1", ha="center", fontsize=7)
        ax.text(2.55, 1.0, "I2", ha="center", fontsize=7)
        ax.set_title(f"case {name}\n{text}", fontsize=8)
        ax.set_xlim(-1.3, 3.3)
        ax.set_ylim(-0.7, 2.7)
        ax.set_aspect("equal")
        ax.axis("off")
    fig.suptitle("the side quad Q of silhouette edge AD, extruded from the light; red: the camera's near plane",
                 fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "cases.png")
    plt.close(fig)


def bounding_box_of_marks(path, frame_height):
    image = plt.imread(path)[:frame_height]
    rgb = (image[..., :3] * 255).astype(int)
    marked = (
        ((rgb[..., 0] > 200) & (rgb[..., 1] < 80))  # red
        | ((rgb[..., 1] > 200) & (rgb[..., 2] > 200) & (rgb[..., 0] < 80))  # cyan
        | ((rgb[..., 0] > 200) & (rgb[..., 1] > 200) & (rgb[..., 2] < 50))  # yellow
        | ((rgb[..., 0] > 200) & (rgb[..., 2] > 200) & (rgb[..., 1] < 50))  # magenta
    )
    ys, xs = np.nonzero(marked)
    pad = 12
    return (max(xs.min() - pad, 0), max(ys.min() - pad, 0), min(xs.max() + pad, image.shape[1]),
            min(ys.max() + pad, frame_height))


def main():
    work, out = Path(sys.argv[1]), Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    near_cap_picture(work, out)
    shadow_picture(work, out)
    wall = work / "bunny_wall_zpplus" / "cracks.png"
    crack_picture(wall, out, "cracks_zpplus_wall.png",
                  "published ZP+ on near_cap_bunny_wall: its cracks (rings), enlarged", bounding_box_of_marks(wall, 480))
    crack_picture(work / "case_d_corrected" / "cracks.png", out, "cracks_case_d.png",
                  "ZP+ corrected on case_d: the switch to Z-fail with GL_DEPTH_CLAMP", None)
    crack_picture(work / "far_grazing_raytrace" / "cracks.png", out, "cracks_raytrace_far.png",
                  "Embree, float32, fixed shadow epsilon, 10 km from the origin: shadow acne", None)
    cases_picture(out)
    for p in sorted(out.glob("*.png")):
        print(f"{p} ({p.stat().st_size // 1024} KB)")


if __name__ == "__main__":
    main()
