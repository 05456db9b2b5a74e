#!/usr/bin/env python3
"""The paper's claims against ggk's results files: one markdown table.

Each row: the claim, what the paper states, what ggk measures (per sweep point,
GGK - OGK paired by run, with the 95 % interval of ggk_results.paired: Student's
t of the mean difference, or Newcombe's paired score interval for a 0/1 success
from A), and a verdict from fixed rules (rows for the third basis, proto-value
functions, where a file holds them: GGK - PVF and PVF - OGK by the same rules,
read as "ahead", "partly ahead", "not ahead"):
  reproduced      GGK significantly ahead at more than half of the points and
                  significantly behind at none;
  partly          GGK significantly ahead at two points or more, and at more
                  points than it is significantly behind;
  not reproduced  otherwise.
A claim that has no number (a figure the paper shows and describes) says so.

  /usr/bin/python3 results/claims.py [--results DIR | FILE ...] [--readme README.md]

Files are recognised by what they hold, not by name: the maze's task (ggk's
addition, the GGK papers' artificial task: rows only where a maze file is given),
the arm's task, the classic continuous tasks (pendulum, mountain car, acrobot:
ggk's additions, rows only where a file is given), and the Khepera's task with its rotation step (khepera.motion.turn_deg: 15 is the
paper's job, 30 and 45 the rotation-step study: one file holds a step per run
configuration, jobs/khepera-study.toml). With --results DIR (default results/)
the paper's files maze.h5, arm-paper.h5, khepera-paper.h5 and khepera-study.h5 are used
where present (khepera-paper.h5 first for 15 degrees), and any other .h5 file there for
a role none of them fills (e.g. out/quick/ of scripts/reproduce.sh --quick);
two files for one role are an error (exit 2) naming both. A file whose job has
not finished contributes its complete runs (said on stderr).

With --readme, the table between the README's "<!-- claims:begin -->" and
"<!-- claims:end -->" lines is replaced; otherwise it is printed. A role with
no file gives a row saying which job makes it.
"""

import argparse
import os
import sys
import tomllib
import warnings
from pathlib import Path

# ggk_results from this checkout (python/), installed or not (python/README.md).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
import ggk_results  # noqa: E402

# The roles of the claims table, the paper's file for each, and the job that makes it.
PAPER_FILES = {
    "maze": ("maze.h5", "jobs/maze.toml"),
    "arm": ("arm-paper.h5", "jobs/arm-paper.toml"),
    "khepera-15": ("khepera-paper.h5", "jobs/khepera-paper.toml"),
    "khepera-30": ("khepera-study.h5", "jobs/khepera-study.toml"),
    "khepera-45": ("khepera-study.h5", "jobs/khepera-study.toml"),
}
# The classic continuous tasks (ggk's additions, jobs/README.md): their file, job,
# the metric their rows compare, how it reads, and its scale and unit.
CONTINUOUS = {
    "pendulum": ("pendulum.h5", "jobs/pendulum.toml", "mean_steps",
                 "balancing steps of the test episodes (at most 3000)", 1, "",
                 "Lagoudakis & Parr's inverted pendulum"),
    "mountain_car": ("mountain-car.h5", "jobs/mountain-car.toml", "success_rate",
                     "success within 200 steps", 100, " %", "the mountain car"),
    "acrobot": ("acrobot.h5", "jobs/acrobot.toml", "success_rate",
                "success within 500 steps", 100, " %", "the acrobot"),
}
PAPER_FILES.update({task: spec[:2] for task, spec in CONTINUOUS.items()})
TURN_AXIS = "khepera.motion.turn_deg"  # the rotation-step study's axis (jobs/khepera-study.toml)
DEFAULT_TURN_DEG = 15.0  # jobs/README.md, [khepera.motion] turn_deg
FIGURE_KERNELS = 128  # the kernel count of Fig. 2 (results/figures/arm_values.png)


class UsageError(Exception):
    pass


def roles_of(results):
    """[(role, summary frame)] of an open_results file: none for another task;
    one per rotation step of a study whose axis it is (jobs/khepera-study.toml),
    each the rows of that step."""
    frame = results.summary()
    if results.task in ("maze", "arm") or results.task in CONTINUOUS:
        return [(results.task, frame)]
    if results.task != "khepera":
        return []
    if TURN_AXIS in frame.columns:
        return [(f"khepera-{turn:g}", frame[frame[TURN_AXIS] == turn])
                for turn in sorted(set(frame[TURN_AXIS]))]
    turn = DEFAULT_TURN_DEG
    if "job_resolved" in results.attrs:
        turn = tomllib.loads(results.attrs["job_resolved"]).get(TURN_AXIS, turn)
    elif "job" in results.attrs:
        job = tomllib.loads(results.attrs["job"])
        turn = job.get("khepera", {}).get("motion", {}).get("turn_deg", turn)
    return [(f"khepera-{turn:g}", frame)]


def load(path):
    """open_results(path), noting on stderr when its job has not finished."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ggk_results.PartialResultsWarning)
        results = ggk_results.open_results(path)
    if not results.complete:
        print(f"claims.py: {path} has no summary yet (its job is not finished): "
              f"{len(results.runs)} complete run(s) used", file=sys.stderr)
    return results


def assign_roles(paths, preferred=()):
    """{role: (path, frame)} of the files; a file in `preferred` (the paper's
    file names in --results DIR) fills its role before any other file."""
    roles, sources = {}, {}
    for path in sorted(paths, key=lambda p: (p not in preferred, str(p))):
        for role, frame in roles_of(load(path)):
            if role in roles:
                if sources[role] in preferred:
                    continue
                raise UsageError(f"{sources[role]} and {path} both hold {role} results: "
                                 "give the files to use (claims.py FILE ...)")
            roles[role], sources[role] = frame, path
    return roles, sources


def tally(points):
    ahead = int((points.low > 0).sum())
    behind = int((points.high < 0).sum())
    return ahead, behind


def verdict(points):
    ahead, behind = tally(points)
    if ahead * 2 > len(points) and behind == 0:
        return "reproduced"
    if ahead >= 2 and ahead > behind:
        return "partly"
    return "not reproduced"


def interval_text(r, scale):
    """'+d ± h' for a t interval (symmetric), 'd, CI [low, high]' for Newcombe's."""
    if r.method == "t":
        return f"{scale * r.difference:+.3g} ± {scale * (r.high - r.difference):.2g}"
    return (f"{scale * r.difference:+.3g}, 95 % CI {scale * r.low:+.2g} to "
            f"{scale * r.high:+.2g}")


def describe(points, scale, unit, ahead_name="GGK"):
    """'GGK ahead at a of n kernel counts, behind at b; e.g. k: x vs y (d +- h)'."""
    ahead, behind = tally(points)
    best = points.loc[points.difference.idxmax()]
    worst = points.loc[points.difference.idxmin()]
    runs = int(points.pairs.iloc[0])

    def point(r):
        return (f"{int(r.kernels)} kernels {scale * r.a:.3g}{unit} vs {scale * r.b:.3g}{unit} "
                f"({interval_text(r, scale)})")

    text = (f"{ahead_name} significantly ahead at {ahead} of {len(points)} kernel counts, "
            f"behind at {behind} ({runs} runs); best for {ahead_name}: {point(best)}")
    if worst.name != best.name:
        text += f"; worst: {point(worst)}"
    return text


def paired_points(frame, metric, solver, a="ggk", b="ogk"):
    return ggk_results.paired(frame[frame.solver == solver], metric, compare="basis", a=a,
                              b=b, by=["kernels"])


# The third basis (jobs/README.md, [pvf]): GGK - PVF and PVF - OGK, paired by run,
# where a file holds "pvf" fits; the paper makes no claim about PVFs.
PVF_PAIRS = (("ggk", "pvf"), ("pvf", "ogk"))


def pvf_rows(frame, task, metric, what, solvers, scale=1, unit=""):
    rows = []
    if not (frame.basis == "pvf").any():
        return rows
    for solver in solvers:
        for a, b in PVF_PAIRS:
            points = paired_points(frame, metric, solver, a, b)
            rows.append((
                f"{task}: {a.upper()} vs {b.upper()} ({solver.upper()}; ggk's third basis, "
                "proto-value functions)",
                "(not in the paper)",
                f"{what}, {a.upper()} - {b.upper()}: " +
                describe(points, scale, unit, a.upper()),
                # The claims' rules, read as "a ahead" (no claim to reproduce).
                {"reproduced": f"{a.upper()} ahead", "partly": f"{a.upper()} partly ahead",
                 "not reproduced": f"{a.upper()} not ahead"}[verdict(points)],
            ))
    return rows


def arm_rows(arm):
    rows = [(
        "Arm: value function keeps the obstacle's discontinuity (Fig. 2)",
        "GGKs give a smooth surface with the obstacle-induced discontinuity sharply "
        "preserved; OGKs smooth it out",
        "figure only (results/figures/arm_values.png, run 0, 128 kernels); no number",
        "shown, not measured",
    )]
    kernels = FIGURE_KERNELS if (arm.kernels == FIGURE_KERNELS).any() else int(arm.kernels.max())
    shown = arm[(arm.run == arm.run.min()) & (arm.kernels == kernels) & (arm.solver == "brm")]
    run = int(arm.run.min())

    def outcome(basis):
        row = shown[shown.basis == basis].iloc[0]
        if row.success_from_A >= 1:
            return f"{basis.upper()} reaches the goal from A in {int(row.steps_from_A)} steps"
        return f"{basis.upper()} does not reach it"

    which = ("the figure's" if kernels == FIGURE_KERNELS and run == 0
             else "this file's; the figure's are run 0, 128 kernels")
    rows.append((
        "Arm: the GGK trajectory from A goes around the obstacle, the OGK one "
        "gets stuck (Fig. 2)",
        "from A the GGK-based policy avoids the obstacle; the OGK-based one moves "
        "the arm through it and gets stuck",
        f"run {run}, {kernels} kernels ({which}): {outcome('ggk')}, {outcome('ogk')}",
        "reproduced" if shown[shown.basis == "ggk"].success_from_A.iloc[0] >= 1
        and shown[shown.basis == "ogk"].success_from_A.iloc[0] < 1 else "not reproduced",
    ))
    from_a = paired_points(arm, "success_from_A", "brm")
    rows.append((
        "Arm: success vs kernels (Fig. 3)",
        "GGKs remarkably outperform OGKs (percentage of successful trials over 30 "
        "runs, tested from A)",
        "success from A, " + describe(from_a, 100, " %"),
        verdict(from_a),
    ))
    everywhere = paired_points(arm, "success_rate", "brm")
    rows.append((
        "Arm: success from every free pose (ggk's addition)",
        "(not in the paper)",
        "success from all free poses, " + describe(everywhere, 100, " %"),
        verdict(everywhere),
    ))
    rows += pvf_rows(arm, "Arm", "success_from_A", "success from A", ["brm"], 100, " %")
    return rows


def solvers_of(frame):
    return [s for s in ("brm", "lstdq") if (frame.solver == s).any()]


def maze_rows(maze):
    rows = []
    for solver in solvers_of(maze):
        points = paired_points(maze, "success_rate", solver)
        rows.append((
            f"Maze: success vs kernels, {solver.upper()} (ggk's addition: the GGK papers' "
            "artificial task, the four-rooms map of jobs/maze.toml)",
            "GGKs outperform OGKs (the GGK papers' maze experiments; not in this paper's text)",
            "success from every free cell, " + describe(points, 100, " %"),
            verdict(points),
        ))
    rows += pvf_rows(maze, "Maze", "success_rate", "success from every free cell",
                     solvers_of(maze), 100, " %")
    return rows


def khepera_rows(khepera):
    rows = [(
        "Khepera: policies differ at region C (Fig. 5)",
        "OGK backs up at C, GGK rotates; OGK shuttles in front of the obstacle",
        "region C is not defined outside the paper's figure: policies per unit in "
        "results/figures/khepera_policies.png; no number",
        "shown, not measured",
    )]
    for solver in solvers_of(khepera):
        points = paired_points(khepera, "mean_return", solver)
        rows.append((
            f"Khepera: exploration vs kernels (Fig. 6), {solver.upper()}, ggk's "
            "default 15-degree rotations",
            "GGK explores more than OGK (average amount of exploration)",
            "mean return of 150 greedy steps, " + describe(points, 1, ""),
            verdict(points),
        ))
    rows += pvf_rows(khepera, "Khepera", "mean_return", "mean return", solvers_of(khepera))
    return rows


def rotation_rows(study, degrees):
    rows = []
    for solver in solvers_of(study):
        points = paired_points(study, "mean_return", solver)
        rows.append((
            f"Khepera, {degrees}-degree rotations (a choice the paper leaves open), "
            f"{solver.upper()}",
            "(the paper gives no rotation step)",
            "mean return, " + describe(points, 1, ""),
            verdict(points),
        ))
    rows += pvf_rows(study, f"Khepera, {degrees}-degree rotations", "mean_return",
                     "mean return", solvers_of(study))
    return rows


def continuous_rows(task, frame):
    """GGK vs OGK per solver on a classic continuous task, with the diagnostics
    that say whether GGK can differ from OGK there (the paper's argument: only
    where shortest paths on the sample graph are much longer than straight
    lines), then the third basis's rows."""
    _, _, metric, what, scale, unit, name = CONTINUOUS[task]
    title = task.replace("_", " ").capitalize()
    kernels = frame[frame.basis == "ggk"]
    diagnostics = (f"median geodesic stretch {kernels.geodesic_stretch.mean():.3g}, mean "
                   f"|K_GGK - K_OGK| {kernels.kernel_gap.mean():.2g}")
    rows = []
    for solver in solvers_of(frame):
        points = paired_points(frame, metric, solver)
        rows.append((
            f"{title}: GGK vs OGK, {solver.upper()} (ggk's addition: {name})",
            f"(not in the paper; its argument predicts a GGK lead only where paths are "
            f"long: {diagnostics})",
            f"{what}, " + describe(points, scale, unit),
            {"reproduced": "GGK ahead", "partly": "GGK partly ahead",
             "not reproduced": "GGK not ahead"}[verdict(points)],
        ))
    rows += pvf_rows(frame, title, metric, what, solvers_of(frame), scale, unit)
    return rows


def claims_table(roles):
    rows = []
    if "maze" in roles:  # not one of the paper's claims: no row when no file gives it
        rows += maze_rows(roles["maze"])
    if "arm" in roles:
        rows += arm_rows(roles["arm"])
    else:
        rows.append(("Arm", "(results/arm-paper.h5 missing: ggk run jobs/arm-paper.toml)", "", ""))
    if "khepera-15" in roles:
        rows += khepera_rows(roles["khepera-15"])
    else:
        rows.append(("Khepera", "(results/khepera-paper.h5 missing: ggk run "
                     "jobs/khepera-paper.toml)", "", ""))
    for degrees in (30, 45):
        if f"khepera-{degrees}" in roles:
            rows += rotation_rows(roles[f"khepera-{degrees}"], degrees)
    for task in CONTINUOUS:  # not the paper's claims: rows only where a file gives them
        if task in roles:
            rows += continuous_rows(task, roles[task])
    lines = [
        "| claim | the paper | ggk measures (GGK - OGK paired by run, 95 % CI) | verdict |",
        "|---|---|---|---|",
    ]
    for claim, paper, measured, result in rows:
        lines.append(f"| {claim} | {paper} | {measured} | {result} |")
    return "\n".join(lines) + "\n"


def files_of(args):
    """(paths, preferred): the files to read and the paper's names among them."""
    if args.files:
        missing = [p for p in args.files if not os.path.exists(p)]
        if missing:
            raise UsageError(f"no such file: {', '.join(missing)}")
        return list(args.files), set()
    folder = Path(args.results)
    if not folder.is_dir():
        raise UsageError(f"{folder}: not a folder of results files")
    paths = sorted(str(p) for p in folder.glob("*.h5"))
    preferred = {str(folder / name) for name, _ in PAPER_FILES.values()}
    return paths, preferred & set(paths)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", help="results files (default: those in --results)")
    parser.add_argument("--results", default="results",
                        help="folder of the results files (default results/)")
    parser.add_argument("--readme", help="replace the claims table in this README")
    args = parser.parse_args()
    try:
        roles, _ = assign_roles(*files_of(args))
        table = claims_table(roles)
    except (UsageError, ValueError, KeyError, OSError) as error:
        print(f"claims.py: {error}", file=sys.stderr)
        return 2
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
