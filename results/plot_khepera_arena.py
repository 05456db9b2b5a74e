"""Paper Fig. 4(a) from a ggk Khepera results file: the arena with its walls and
obstacles, the robot at the evaluation start pose, and its 8 IR sensors' rays
(three per sensor: left, centre, right), each ray drawn to its hit (solid) or to
the end of its range (dotted), with the noiseless reading per sensor.

    /usr/bin/python3 results/plot_khepera_arena.py results/khepera-paper.h5 results/figures \
        [--run R] [--output NAME.png] [--zoom CM]

Reads the run's arena/* and robot/* datasets (written by
engine/tasks/khepera/khepera_task.cpp with every run: arena/box [min x, min y,
max x, max y, walled], arena/segments, arena/rectangles, arena/rotated_rectangles,
arena/discs, arena/start [x, y, heading], robot/radius, robot/sensors [8, 3],
robot/start_rays [24, 5], robot/start_readings [8]). Writes khepera_arena.png:
the whole arena, and an inset of --zoom cm (default 16) around the robot.
"""

import argparse
import sys
import math
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import patches  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import run_group  # noqa: E402


def read_geometry(path, run):
    with h5py.File(path, "r") as f:
        group = run_group(f, "khepera", run, needs=("arena", "robot"))
        g = {f"arena/{k}": np.asarray(group["arena"][k][()]) for k in group["arena"]}
        g.update({f"robot/{k}": np.asarray(group["robot"][k][()]) for k in group["robot"]})
        return g


def draw_arena(ax, g):
    box = g["arena/box"]
    if box[4]:
        ax.add_patch(patches.Rectangle((box[0], box[1]), box[2] - box[0], box[3] - box[1],
                                       fill=False, edgecolor="k", linewidth=2.0))
    style = {"facecolor": "0.6", "edgecolor": "0.25"}
    for r in g["arena/rectangles"].reshape(-1, 4):
        ax.add_patch(patches.Rectangle((r[0], r[1]), r[2] - r[0], r[3] - r[1], **style))
    for c in g["arena/rotated_rectangles"].reshape(-1, 5):
        angle = math.radians(c[4])
        # The corner that maps to (-w/2, -h/2) in the rectangle's own frame.
        dx, dy = -c[2] / 2, -c[3] / 2
        corner = (c[0] + dx * math.cos(angle) - dy * math.sin(angle),
                  c[1] + dx * math.sin(angle) + dy * math.cos(angle))
        ax.add_patch(patches.Rectangle(corner, c[2], c[3], angle=c[4], **style))
    for d in g["arena/discs"].reshape(-1, 3):
        ax.add_patch(patches.Circle((d[0], d[1]), d[2], **style))
    for s in g["arena/segments"].reshape(-1, 4):
        ax.plot([s[0], s[2]], [s[1], s[3]], "k-", linewidth=2.0)


def draw_robot(ax, g, labels):
    x, y, heading = g["arena/start"]
    radius = float(g["robot/radius"][0])
    ax.add_patch(patches.Circle((x, y), radius, facecolor="#9fd39f", edgecolor="darkgreen",
                                zorder=3))
    ax.plot([x, x + radius * math.cos(heading)], [y, y + radius * math.sin(heading)],
            color="darkgreen", linewidth=2.0, zorder=4)
    rays = g["robot/start_rays"].reshape(-1, 3, 5)
    readings = g["robot/start_readings"]
    for i, fan in enumerate(rays):
        for k, ray in enumerate(fan):
            hit = ray[4] > 0
            ax.plot([ray[0], ray[2]], [ray[1], ray[3]], linestyle="-" if hit else ":",
                    color="tab:red" if hit else "tab:orange", linewidth=1.2 if k == 1 else 0.8,
                    zorder=2)
            if hit:
                ax.plot(ray[2], ray[3], ".", color="tab:red", markersize=4, zorder=2)
        ax.plot(fan[1][0], fan[1][1], "o", color="k", markersize=2.5, zorder=5)
        if labels:
            # Label at the centre ray's half-way point.
            cx, cy = fan[1][0], fan[1][1]
            ex, ey = fan[1][2], fan[1][3]
            ax.annotate(f"s{i + 1}\n{readings[i]:.0f}", ((cx + ex) / 2, (cy + ey) / 2),
                        fontsize=7, ha="center", va="center", zorder=6,
                        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none",
                              "alpha": 0.8})


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results")
    parser.add_argument("outdir")
    parser.add_argument("--run", type=int, default=None, help="run number (default: the first)")
    parser.add_argument("--output", default="khepera_arena.png")
    parser.add_argument("--zoom", type=float, default=16.0, help="inset half-width, cm")
    args = parser.parse_args()

    g = read_geometry(args.results, args.run)
    fig, (whole, near) = plt.subplots(1, 2, figsize=(11.5, 5.6),
                                      gridspec_kw={"width_ratios": [1.2, 1.0]})
    for ax, labels in ((whole, False), (near, True)):
        draw_arena(ax, g)
        draw_robot(ax, g, labels)
        ax.set_aspect("equal")
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
    box = g["arena/box"]
    pad = 2.0
    whole.set_xlim(box[0] - pad, box[2] + pad)
    whole.set_ylim(box[1] - pad, box[3] + pad)
    whole.set_title("arena, obstacles (grey) and the robot at its start pose", fontsize=9)
    x, y, heading = g["arena/start"]
    near.set_xlim(x - args.zoom, x + args.zoom)
    near.set_ylim(y - args.zoom, y + args.zoom)
    near.set_title(f"start pose ({x:.1f}, {y:.1f}, {math.degrees(heading):.0f}\u00b0): rays that hit "
                   "solid red, misses dotted to the 10 cm range;\nlabels: the paper's s1..s8 "
                   "(ggk's s0..s7) and the noiseless reading", fontsize=9)
    fig.suptitle("Fig. 4(a): the Khepera and its 8 infra-red sensors", fontsize=11, y=1.03)
    out = Path(args.outdir)
    out.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out / args.output, dpi=150, bbox_inches="tight")
    print(out / args.output)


if __name__ == "__main__":
    main()
