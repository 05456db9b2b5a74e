#!/usr/bin/env python3
"""The paper's claims against ggk's results files: one markdown table.

Each row: the claim, what the paper states, what ggk measures (per sweep point,
GGK - OGK paired by run, with the 95 % Student-t interval of the mean
difference), and a verdict from fixed rules:
  reproduced      GGK significantly ahead at more than half of the points and
                  significantly behind at none;
  partly          GGK significantly ahead at two points or more, and at more
                  points than it is significantly behind;
  not reproduced  otherwise.
A claim that has no number (a figure the paper shows and describes) says so.

  /usr/bin/python3 results/claims.py [--results DIR] [--readme README.md]

With --readme, the table between the README's "<!-- claims:begin -->" and
"<!-- claims:end -->" lines is replaced; otherwise it is printed. Files that do
not exist yet give a row saying which job makes them.
"""

import argparse
import math
import os
import sys

import numpy as np
from scipy import stats

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ggk_results  # noqa: E402


def paired(frame, metric, solver):
    """Per kernel count: (kernels, ggk mean, ogk mean, mean diff, half width)."""
    rows = []
    part = frame[frame.solver == solver]
    for kernels, group in part.groupby("kernels"):
        ggk = group[group.basis == "ggk"].set_index("run")[metric]
        ogk = group[group.basis == "ogk"].set_index("run")[metric]
        diff = (ggk - ogk).dropna().to_numpy(dtype=float)
        n = len(diff)
        if n < 2:
            half = math.nan
        else:
            half = stats.t.ppf(0.975, n - 1) * diff.std(ddof=1) / math.sqrt(n)
        rows.append((int(kernels), ggk.mean(), ogk.mean(), diff.mean(), half, n))
    return rows


def tally(rows):
    ahead = sum(1 for r in rows if r[3] - r[4] > 0)
    behind = sum(1 for r in rows if r[3] + r[4] < 0)
    return ahead, behind


def verdict(rows):
    ahead, behind = tally(rows)
    if ahead * 2 > len(rows) and behind == 0:
        return "reproduced"
    if ahead >= 2 and ahead > behind:
        return "partly"
    return "not reproduced"


def describe(rows, scale, unit):
    """'GGK ahead at a of n kernel counts, behind at b; e.g. k: x vs y (d +- h)'."""
    ahead, behind = tally(rows)
    best = max(rows, key=lambda r: r[3])
    worst = min(rows, key=lambda r: r[3])
    runs = rows[0][5]

    def point(r):
        return (f"{r[0]} kernels {scale * r[1]:.3g}{unit} vs {scale * r[2]:.3g}{unit} "
                f"({scale * r[3]:+.3g} ± {scale * r[4]:.2g})")

    text = (f"GGK significantly ahead at {ahead} of {len(rows)} kernel counts, behind at "
            f"{behind} ({runs} runs); best for GGK: {point(best)}")
    if worst is not best:
        text += f"; worst: {point(worst)}"
    return text


def load(results, name):
    """The summary of a results file, or None when the file is missing or its
    job has not finished (no summary yet: ggk run --resume finishes it)."""
    path = os.path.join(results, name)
    if not os.path.exists(path):
        return None
    try:
        return ggk_results.summary_frame(path)
    except KeyError:
        print(f"claims.py: {path} has no summary yet (its job is not finished); left out",
              file=sys.stderr)
        return None


def claims_table(results):
    rows = []
    arm = load(results, "arm-paper.h5")
    if arm is None:
        rows.append(("Arm", "(results/arm-paper.h5 missing: ggk run jobs/arm-paper.toml)", "", ""))
    else:
        rows.append((
            "Arm: value function keeps the obstacle's discontinuity (Fig. 2)",
            "GGKs give a smooth surface with the obstacle-induced discontinuity sharply "
            "preserved; OGKs smooth it out",
            "figure only (results/figures/arm_values.png, run 0, 128 kernels); no number",
            "shown, not measured",
        ))
        shown = arm[(arm.run == 0) & (arm.kernels == 128) & (arm.solver == "brm")]

        def outcome(basis):
            row = shown[shown.basis == basis].iloc[0]
            if row.success_from_A >= 1:
                return f"{basis.upper()} reaches the goal from A in {int(row.steps_from_A)} steps"
            return f"{basis.upper()} does not reach it"

        rows.append((
            "Arm: the GGK trajectory from A goes around the obstacle, the OGK one "
            "gets stuck (Fig. 2)",
            "from A the GGK-based policy avoids the obstacle; the OGK-based one moves "
            "the arm through it and gets stuck",
            f"run 0, 128 kernels (the figure's): {outcome('ggk')}, {outcome('ogk')}",
            "reproduced" if shown[shown.basis == "ggk"].success_from_A.iloc[0] >= 1
            and shown[shown.basis == "ogk"].success_from_A.iloc[0] < 1 else "not reproduced",
        ))
        from_a = paired(arm, "success_from_A", "brm")
        rows.append((
            "Arm: success vs kernels (Fig. 3)",
            "GGKs remarkably outperform OGKs (percentage of successful trials over 30 "
            "runs, tested from A)",
            "success from A, " + describe(from_a, 100, " %"),
            verdict(from_a),
        ))
        everywhere = paired(arm, "success_rate", "brm")
        rows.append((
            "Arm: success from every free pose (ggk's addition)",
            "(not in the paper)",
            "success from all free poses, " + describe(everywhere, 100, " %"),
            verdict(everywhere),
        ))
    khepera = load(results, "khepera-paper.h5")
    if khepera is None:
        rows.append(("Khepera", "(results/khepera-paper.h5 missing: ggk run "
                     "jobs/khepera-paper.toml)", "", ""))
    else:
        rows.append((
            "Khepera: policies differ at region C (Fig. 5)",
            "OGK backs up at C, GGK rotates; OGK shuttles in front of the obstacle",
            "region C is not defined outside the paper's figure: policies per unit in "
            "results/figures/khepera_policies.png; no number",
            "shown, not measured",
        ))
        for solver in ("brm", "lstdq"):
            points = paired(khepera, "mean_return", solver)
            rows.append((
                f"Khepera: exploration vs kernels (Fig. 6), {solver.upper()}, ggk's "
                "default 15-degree rotations",
                "GGK explores more than OGK (average amount of exploration)",
                "mean return of 150 greedy steps, " + describe(points, 1, ""),
                verdict(points),
            ))
    for degrees in (30, 45):
        study = load(results, f"khepera-turn{degrees}.h5")
        if study is None:
            continue
        for solver in ("brm", "lstdq"):
            points = paired(study, "mean_return", solver)
            rows.append((
                f"Khepera, {degrees}-degree rotations (a choice the paper leaves open), "
                f"{solver.upper()}",
                "(the paper gives no rotation step)",
                "mean return, " + describe(points, 1, ""),
                verdict(points),
            ))
    lines = [
        "| claim | the paper | ggk measures (GGK - OGK paired by run, 95 % CI) | verdict |",
        "|---|---|---|---|",
    ]
    for claim, paper, measured, result in rows:
        lines.append(f"| {claim} | {paper} | {measured} | {result} |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", default="results", help="folder of the results files")
    parser.add_argument("--readme", help="replace the claims table in this README")
    args = parser.parse_args()
    table = claims_table(args.results)
    if not args.readme:
        sys.stdout.write(table)
        return 0
    begin, end = "<!-- claims:begin -->", "<!-- claims:end -->"
    with open(args.readme, encoding="utf-8") as f:
        text = f.read()
    if begin not in text or end not in text:
        print(f"claims.py: {args.readme} has no {begin} ... {end} lines", file=sys.stderr)
        return 2
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    text = head + begin + "\n" + table + end + tail
    tmp = args.readme + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, args.readme)
    return 0


if __name__ == "__main__":
    sys.exit(main())
