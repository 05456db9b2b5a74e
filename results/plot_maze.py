"""Success rate vs number of kernels on the maze, GGK vs OGK (and PVF where run), 95 % CIs over runs
(Student t): one panel per value of every other swept axis (solver, sigma,
lambda), so that no axis is pooled (ggk_results.plot_metric).

    /usr/bin/python3 results/plot_maze.py results/maze.h5 results/figures [--format pdf]
"""

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
from ggk_results import add_format_argument, plot_metric, read_summary, save  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("out_dir")
    add_format_argument(parser)
    args = parser.parse_args()
    summary = read_summary(args.results, "maze")
    out_dir = Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # plot_metric: a panel per value of every other swept axis, dodged curves,
    # the rate on 0-100 % so that differences read at their size.
    fig, _ = plot_metric(summary, "success_rate", title="maze",
                         ylabel="success rate from all cells (%)")
    fig.tight_layout()
    print(save(fig, out_dir, "maze_success", args.format))
    plt.close(fig)


if __name__ == "__main__":
    main()
