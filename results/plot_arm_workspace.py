"""Paper Fig. 1(a) from a ggk arm results file: the two-joint arm in its
workspace, with the obstacles, the object, the arm at the start pose A and the
16 goal poses (the poses whose end effector touches the object).

    /usr/bin/python3 results/plot_arm_workspace.py results/arm-paper.h5 results/figures \
        [--run R] [--output NAME.png]

Reads the run's workspace/* datasets (written by engine/tasks/arm/arm_task.cpp
with every run: workspace/rectangles [n, 4], workspace/discs [n, 3],
workspace/object [3], workspace/pose_A [3, 2], workspace/pose_A_deg [2],
workspace/goal_poses [g, 6], workspace/goal_poses_deg [g, 2]); the geometry is
the job's, the same in every run. Writes arm_workspace.png.
"""

import argparse
import sys
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


def read_workspace(path, run):
    with h5py.File(path, "r") as f:
        group = run_group(f, "arm", run, needs=("workspace",))
        return {key: np.asarray(group["workspace"][key][()]) for key in group["workspace"]}


def draw_arm(ax, points, **style):
    ax.plot(points[:, 0], points[:, 1], "-", solid_capstyle="round", **style)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results")
    parser.add_argument("outdir")
    parser.add_argument("--run", type=int, default=None, help="run number (default: the first)")
    parser.add_argument("--output", default="arm_workspace.png")
    args = parser.parse_args()

    w = read_workspace(args.results, args.run)
    fig, ax = plt.subplots(figsize=(9.0, 5.2))
    for r in w["rectangles"].reshape(-1, 4):
        ax.add_patch(patches.Rectangle((r[0], r[1]), r[2] - r[0], r[3] - r[1], facecolor="0.55",
                                       edgecolor="0.2", zorder=1))
    for d in w["discs"].reshape(-1, 3):
        ax.add_patch(patches.Circle((d[0], d[1]), d[2], facecolor="0.55", edgecolor="0.2",
                                    zorder=1))
    obj = w["object"]
    ax.add_patch(patches.Circle((obj[0], obj[1]), obj[2], facecolor="gold", edgecolor="darkgoldenrod",
                                zorder=2, label="object"))

    goals = w["goal_poses"].reshape(-1, 3, 2)
    for i, pose in enumerate(goals):
        draw_arm(ax, pose, color="tab:green", alpha=0.35, linewidth=2.0, zorder=3,
                 label=f"goal poses ({len(goals)})" if i == 0 else None)
    pose_a = w["pose_A"].reshape(3, 2)
    draw_arm(ax, pose_a, color="tab:red", linewidth=4.0, zorder=4,
             label="pose A (shoulder %g\u00b0, elbow %g\u00b0)" % tuple(w["pose_A_deg"]))
    ax.plot(pose_a[1:, 0], pose_a[1:, 1], "o", color="tab:red", markersize=5, zorder=5)
    base = pose_a[0]
    ax.plot(base[0], base[1], "ks", markersize=9, zorder=6, label="base (shoulder joint)")
    ax.annotate("A", pose_a[2], textcoords="offset points", xytext=(6, 6), fontsize=13,
                color="tab:red", weight="bold")

    # Frame the links' reach, the obstacles and the object.
    reach = np.linalg.norm(pose_a[1] - pose_a[0]) + np.linalg.norm(pose_a[2] - pose_a[1])
    xs = [base[0] - reach, base[0] + reach, obj[0] - obj[2], obj[0] + obj[2]]
    ys = [base[1] - reach, base[1] + reach, obj[1] - obj[2], obj[1] + obj[2]]
    for r in w["rectangles"].reshape(-1, 4):
        xs += [r[0], r[2]]
        ys += [r[1], r[3]]
    pad = 0.1 * reach
    ax.set_xlim(min(xs) - pad, max(xs) + pad)
    ax.set_ylim(min(ys) - pad, max(ys) + pad)
    ax.add_patch(patches.Circle(base, reach, fill=False, linestyle=":", edgecolor="0.6"))
    ax.set_aspect("equal")
    ax.set_title("Fig. 1(a): the two-joint arm, obstacles (grey), object, pose A, goal poses")
    ax.title.set_fontsize(9)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    out = Path(args.outdir)
    out.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out / args.output, dpi=150, bbox_inches="tight")
    print(out / args.output)


if __name__ == "__main__":
    main()
