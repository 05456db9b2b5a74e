"""The Khepera claim map (jobs/khepera-claim-map.toml): where, if anywhere, GGK
beats OGK over the choices the paper leaves open.

  khepera_claim_map.png  one panel per solver and kernel count; in each, a row per
                         run configuration (rotation step x sensor noise model)
                         and a column per kernel width. A cell's colour is GGK - OGK
                         mean return, paired by run (ggk_results.paired: Student's t
                         95 % CI over the runs); "+" marks a cell whose CI lies above
                         0 (GGK ahead), "-" one whose CI lies below (OGK ahead).
                         Beside them, per configuration, the graph diagnostics that
                         say whether a geodesic kernel can differ from an ordinary
                         one: the SOM graph's geodesic stretch (shortest paths over
                         straight lines) and the kernel gap (mean |K_GGK - K_OGK|)
                         at each width, means over runs.

    /usr/bin/python3 results/plot_claim_map.py results/khepera-claim-map.h5 results/figures

It prints the count of cells where GGK is ahead, behind and level, per solver.
"""

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import add_format_argument, open_results, paired, save  # noqa: E402

TURN = "khepera.motion.turn_deg"
NOISE = "khepera.sensors.noise_model"


def configurations(frame):
    """The (turn, noise model) pairs of the file, in configuration order."""
    pairs = frame[["configuration", TURN, NOISE]].drop_duplicates().sort_values("configuration")
    return [(float(t), str(n)) for t, n in zip(pairs[TURN], pairs[NOISE])]


def differences(frame, solver, kernels):
    """GGK - OGK mean return per (configuration, width): (difference, low, high)."""
    rows = frame[(frame.solver == solver) & (frame.kernels == kernels)]
    table = paired(rows, "mean_return", by=[TURN, NOISE, "sigma"])
    return {(float(r[TURN]), str(r[NOISE]), float(r["sigma"])): (r["difference"], r["low"], r["high"])
            for r in table.to_dict("records")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("out_dir")
    parser.add_argument("--prefix", default="khepera", help="file name PREFIX_claim_map.png")
    add_format_argument(parser)
    args = parser.parse_args()
    frame = open_results(args.results).summary()
    for column in (TURN, NOISE, "configuration"):
        if column not in frame.columns:
            sys.exit(f"{args.results}: no column {column!r}: not a claim map "
                     "(jobs/khepera-claim-map.toml)")
    configs = configurations(frame)
    widths = sorted(set(frame.sigma.astype(float)))
    kernel_counts = sorted(set(frame.kernels.astype(int)))
    solvers = [s for s in ("brm", "lstdq") if (frame.solver == s).any()]
    runs = frame.run.nunique()

    cells = {(s, k): differences(frame, s, k) for s in solvers for k in kernel_counts}
    largest = max(abs(v[0]) for table in cells.values() for v in table.values()
                  if np.isfinite(v[0]))
    fig, axes = plt.subplots(len(solvers), len(kernel_counts) + 1,
                             figsize=(3.2 * (len(kernel_counts) + 1) + 1.5, 0.42 * len(configs) * len(solvers) + 2.2),
                             squeeze=False, gridspec_kw={"width_ratios": [1] * len(kernel_counts) + [1.1]})
    labels = [f"{t:g} deg, {n}" for t, n in configs]
    image = None
    tally = {}
    for i, solver in enumerate(solvers):
        ahead = behind = level = 0
        for j, kernels in enumerate(kernel_counts):
            ax = axes[i][j]
            table = cells[(solver, kernels)]
            grid = np.full((len(configs), len(widths)), np.nan)
            for r, (turn, noise) in enumerate(configs):
                for c, width in enumerate(widths):
                    difference, low, high = table.get((turn, noise, width), (np.nan,) * 3)
                    grid[r, c] = difference
                    mark = "+" if low > 0 else "-" if high < 0 else ""
                    ahead += mark == "+"
                    behind += mark == "-"
                    level += mark == "" and np.isfinite(difference)
                    if mark:
                        ax.text(c, r, mark, ha="center", va="center", fontsize=11,
                                color="black", fontweight="bold")
            image = ax.imshow(grid, cmap="RdBu", vmin=-largest, vmax=largest, aspect="auto")
            ax.set_xticks(range(len(widths)), [f"{w:g}" for w in widths])
            ax.set_yticks(range(len(configs)), labels if j == 0 else [])
            ax.set_title(f"{solver.upper()}, {kernels} kernels", fontsize=10)
            if i == len(solvers) - 1:
                ax.set_xlabel("kernel width")
        tally[solver] = (ahead, behind, level)
        # The diagnostics of each configuration's graphs (the same for both solvers).
        ax = axes[i][-1]
        stretch = frame.groupby("configuration").geodesic_stretch.mean()
        gap = frame.groupby(["configuration", "sigma"]).kernel_gap.mean()
        for r in range(len(configs)):
            ax.text(0.02, r, f"stretch {stretch.iloc[r]:.2f}", va="center", fontsize=8)
            gaps = " ".join(f"{gap.loc[(r, w)]:.2f}" for w in widths)
            ax.text(0.42, r, f"gap {gaps}", va="center", fontsize=8)
        ax.set_ylim(len(configs) - 0.5, -0.5)
        ax.set_xlim(0, 1)
        ax.axis("off")
        ax.set_title("graph: geodesic stretch; kernel gap per width", fontsize=9)
    fig.colorbar(image, ax=axes[:, :-1].ravel().tolist(), shrink=0.8,
                 label="GGK - OGK mean return (paired by run)")
    fig.suptitle(f"Khepera claim map: GGK - OGK over rotation step, sensor noise, width and "
                 f"kernels ({runs} runs; +/-: 95 % CI above / below 0)", fontsize=11)
    path = save(fig, args.out_dir, f"{args.prefix}_claim_map", args.format)
    print(path)
    for solver, (ahead, behind, level) in tally.items():
        print(f"{solver}: GGK ahead in {ahead}, behind in {behind}, level in {level} of "
              f"{ahead + behind + level} cells")


if __name__ == "__main__":
    main()
