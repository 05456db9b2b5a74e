"""python3 -m ggk_results plot FILE METRIC [--x AXIS] [--hue AXIS[,AXIS]]
    [--where KEY=VALUE] [-o OUT_DIR] [--name STEM] [--format png|pdf|svg]

Draws any metric of a results file against any axis (plot_metric) and prints the
path written: OUT_DIR/<task>_<metric>_<x>.<format> unless --name says otherwise.
A usage error (an unknown metric or axis, a --where that selects nothing) is one
line on stderr and exit status 2."""

import argparse
import sys
from pathlib import Path

from .figures import FORMATS, save
from .metric_figure import plot_metric
from .tables import task_of


def plot_command(args):
    import matplotlib

    matplotlib.use("Agg")  # files only: no display needed
    import matplotlib.pyplot as plt

    hue = tuple(a.strip() for a in args.hue.split(",") if a.strip())
    try:
        fig, _ = plot_metric(args.file, args.metric, x=args.x, hue=hue, where=args.where,
                             title=task_of(args.file))
    except (ValueError, SystemExit) as error:  # select_where exits with its message
        print(f"ggk_results plot: {args.file}: {error}", file=sys.stderr)
        return 2
    fig.tight_layout()
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    stem = args.name or f"{task_of(args.file)}_{args.metric}_{args.x}"
    print(save(fig, out, stem, args.format))
    plt.close(fig)
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m ggk_results",
                                     description="ggk's results files as figures")
    commands = parser.add_subparsers(dest="command", required=True)
    plot = commands.add_parser("plot", help="a metric against an axis, 95 %% CIs, a panel per "
                                            "value of the other swept axes")
    plot.add_argument("file", help="a ggk results file (.h5)")
    plot.add_argument("metric", help="a summary column after status, e.g. success_rate")
    plot.add_argument("--x", default="kernels", help="the axis on x (default kernels)")
    plot.add_argument("--hue", default="basis",
                      help="the axis (or comma-separated axes) of the curves (default basis)")
    plot.add_argument("--where", action="append", default=[], metavar="KEY=VALUE",
                      help="only the rows with this value (repeatable), e.g. "
                           "khepera.motion.turn_deg=45")
    plot.add_argument("-o", "--out-dir", default=".", help="folder of the figure (default .)")
    plot.add_argument("--name", default=None, help="file name without suffix")
    plot.add_argument("--format", choices=FORMATS, default="png",
                      help="figure file format (default png)")
    args = parser.parse_args(argv)
    return plot_command(args)


if __name__ == "__main__":
    sys.exit(main())
