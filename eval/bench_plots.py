#!/usr/bin/python3
"""The figures of `aslam bench` (eval/bench.h), from the files it wrote in OUT.

With --set, once per setting: curves.csv's rows of --setting, into OUT/settings/<label>/.

fig3.png: mean edge D-optimality over time per method (the paper's Fig. 3),
          one panel per world, mean over the runs with a ±1 std band.
fig4.png: coverage over time per method (Fig. 4), mean ± std band, one panel
          per world.
fig5_<world>.png: one run's final map and pose graph over the ground truth
          (Fig. 5).
Only the Python standard library and matplotlib (Debian's python3-matplotlib).
"""

import argparse
import csv
import math
import os
import tempfile
from collections import defaultdict

import matplotlib
import numpy as np  # matplotlib's own dependency

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"fd": "tab:blue", "ags": "tab:orange", "ours": "tab:green", "ideal": "tab:gray"}
LABELS = {"fd": "FD", "ags": "AGS", "ours": "Ours", "ideal": "Ideal"}


def number(text):
    return float(text) if text not in ("", None) else math.nan


def read_curves(path, setting):
    """{world: {method: columns}} from curves.csv's rows of `setting` (a sweep's column)."""
    curves = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row.get("setting", "") != setting:
                continue
            columns = curves[row["world"]][row["method"]]
            for key in ("t_s", "coverage_mean", "coverage_std", "d_opt_mean", "d_opt_std"):
                columns[key].append(number(row[key]))
            columns["runs"].append(int(row["runs"]))
    return curves


def save_figure(fig, path):
    """Writes `fig` as PNG atomically, as the C++ side writes every file (common/atomic_file.h):
    a temporary file in the same folder, fsync, rename over `path`, fsync of the folder."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, temp = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".tmp.")
    try:
        with os.fdopen(fd, "wb") as f:
            fig.savefig(f, format="png", dpi=120)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(temp, 0o644)
        os.replace(temp, path)
    except BaseException:
        if os.path.exists(temp):
            os.unlink(temp)
        raise
    folder_fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(folder_fd)
    finally:
        os.close(folder_fd)
    plt.close(fig)


def band_plot(curves, worlds, methods, mean_key, std_key, ylabel, title, path, scale=1.0, setting=""):
    worlds = [w for w in worlds if w in curves] + [w for w in curves if w not in worlds]
    fig, axes = plt.subplots(1, max(1, len(worlds)), figsize=(6.5 * max(1, len(worlds)), 4.2), squeeze=False)
    for ax, world in zip(axes[0], worlds):
        for method in methods:
            c = curves[world].get(method)
            if not c:
                continue
            t = c["t_s"]
            mean = [scale * v for v in c[mean_key]]
            std = [scale * v if not math.isnan(v) else 0.0 for v in c[std_key]]
            runs = max(c["runs"]) if c["runs"] else 0
            colour = COLOURS.get(method)
            ax.plot(t, mean, color=colour, label=f"{LABELS.get(method, method)} ({runs} runs)")
            ax.fill_between(t, [m - s for m, s in zip(mean, std)], [m + s for m, s in zip(mean, std)],
                            color=colour, alpha=0.2, linewidth=0)
        ax.set_title(f"{title}: {world}" + (f"\n{setting}" if setting else ""))
        ax.set_xlabel("time (s)")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best")
    fig.tight_layout()
    save_figure(fig, path)


def fig5(out, world, setting):
    prefix = os.path.join(out, f"fig5_{world}")
    with open(prefix + "_extent.csv", newline="") as f:
        extent_row = next(csv.DictReader(f))
    extent = [float(extent_row[k]) for k in ("x_min_m", "x_max_m", "y_min_m", "y_max_m")]
    truth = plt.imread(prefix + "_truth.png")
    slam = plt.imread(prefix + "_map.png")
    width_m = extent[1] - extent[0]
    height_m = extent[3] - extent[2]
    fig, ax = plt.subplots(figsize=(10, max(3.0, 10 * height_m / max(width_m, 1e-6)) + 0.6))
    # Truth underneath (walls light blue, free space grey); the SLAM map over it (free white, walls black),
    # so grey is free space the robot never mapped.
    truth_rgba = np.zeros(truth.shape[:2] + (4,))
    truth_rgba[truth < 0.1] = (0.55, 0.75, 1.0, 1.0)
    truth_rgba[truth > 0.9] = (0.8, 0.8, 0.8, 1.0)
    ax.imshow(truth_rgba, extent=extent, interpolation="nearest")
    slam_rgba = np.zeros(slam.shape[:2] + (4,))
    slam_rgba[slam > 0.9] = (1.0, 1.0, 1.0, 1.0)
    slam_rgba[slam < 0.1] = (0.0, 0.0, 0.0, 1.0)
    ax.imshow(slam_rgba, extent=extent, interpolation="nearest")
    with open(prefix + "_graph.csv", newline="") as f:
        edges = list(csv.DictReader(f))
    for loop in ("0", "1"):
        xs, ys = [], []
        for e in edges:
            if e["loop_closure"] == loop:
                xs += [float(e["x0_m"]), float(e["x1_m"]), math.nan]
                ys += [float(e["y0_m"]), float(e["y1_m"]), math.nan]
        ax.plot(xs, ys, color="tab:red" if loop == "1" else "tab:blue", linewidth=0.6 if loop == "1" else 0.9,
                alpha=0.7, label="loop closures" if loop == "1" else "odometry edges")
    ax.set_title(f"{world}: {LABELS.get(extent_row['method'], extent_row['method'])}, seed {extent_row['seed']}, "
                 f"coverage {100 * float(extent_row['coverage']):.1f} %" + (f", {setting}" if setting else "")
                 + "\n(truth: walls light blue, unmapped free space grey)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal")
    ax.legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    save_figure(fig, os.path.join(out, f"fig5_{world}.png"))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="the figures' folder (holds Fig. 5's inputs)")
    parser.add_argument("--curves", help="curves.csv (default: OUT/curves.csv)")
    parser.add_argument("--setting", default="", help="a sweep's setting: its rows of curves.csv")
    parser.add_argument("--methods", default="fd,ags,ours,ideal")
    parser.add_argument("--worlds", default="", help="panel order")
    parser.add_argument("--fig5-worlds", default="")
    args = parser.parse_args()
    methods = [m for m in args.methods.split(",") if m]
    curves = read_curves(args.curves or os.path.join(args.out, "curves.csv"), args.setting)
    worlds = [w for w in args.worlds.split(",") if w]
    band_plot(curves, worlds, methods, "d_opt_mean", "d_opt_std", "mean edge D-optimality", "Uncertainty evolution",
              os.path.join(args.out, "fig3.png"), setting=args.setting)
    band_plot(curves, worlds, methods, "coverage_mean", "coverage_std", "coverage (%)", "Map discovered",
              os.path.join(args.out, "fig4.png"), scale=100.0, setting=args.setting)
    for world in [w for w in args.fig5_worlds.split(",") if w]:
        fig5(args.out, world, args.setting)
    print("wrote fig3.png, fig4.png" + "".join(f", fig5_{w}.png" for w in args.fig5_worlds.split(",") if w))


if __name__ == "__main__":
    main()
