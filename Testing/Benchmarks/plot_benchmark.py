"""Draw the plots of a volillum-benchmark or volillum-unstructured-benchmark JSON file as PNGs
(Debian's python3-matplotlib).

- fig10.png: the Fig. 10 replica of the selective-light-updates paper: full-update time
  against the number of lights from one direction, coherent against sequential
  propagation, and the time of a one-light state change (selective update).
- per_voxel.png: full-update time per voxel of the first light and of each added light,
  for directional, point and spot lights (multi-light propagation, 256^3, scale 1).
- unstructured.png: per-vertex error against a brute-force march of the two-level solver,
  its level 0 alone and resampling + multi-light propagation, against the level-0
  resolution, per mesh (volillum-unstructured-benchmark --json).

Usage: /usr/bin/python3 plot_benchmark.py RESULTS.json OUTPUT_DIR
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the non-interactive backend)


def plot_fig10(fig10, path):
    rows = fig10["rows"]
    lights = [r["lights"] for r in rows]
    figure, axes = plt.subplots(figsize=(5.5, 4))
    axes.plot(lights, [r["sequential_full_s"] for r in rows], "o-",
              label="full update, one light per pass")
    axes.plot(lights, [r["coherent_full_s"] for r in rows], "s-",
              label="full update, coherent")
    axes.plot(lights, [r["state_change_s"] for r in rows], "^-",
              label="one light moved (selective)")
    axes.set_xlabel("lights")
    axes.set_ylabel("seconds")
    axes.set_title("Multi-light propagation (Fig. 10 replica)")
    axes.grid(True, alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def plot_per_voxel(rows, path):
    kinds = [r["light"] for r in rows]
    x = range(len(kinds))
    figure, axes = plt.subplots(figsize=(5.5, 4))
    axes.bar([i - 0.2 for i in x], [r["first_light_ns_per_voxel"] for r in rows], 0.4,
             label="first light")
    axes.bar([i + 0.2 for i in x], [r["added_light_ns_per_voxel"] for r in rows], 0.4,
             label="each added light")
    axes.set_xticks(list(x))
    axes.set_xticklabels(kinds)
    axes.set_ylabel("ns per voxel (wall time)")
    axes.set_title("Full update at scale 1, oblique lights")
    axes.grid(True, axis="y", alpha=0.3)
    # One line of legend in room left above the tallest bar.
    tallest = max(max(r["first_light_ns_per_voxel"], r["added_light_ns_per_voxel"]) for r in rows)
    axes.set_ylim(0, 1.2 * tallest)
    axes.legend(loc="upper center", ncol=2)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def plot_unstructured(rows, path):
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    figure, panels = plt.subplots(1, len(meshes), figsize=(4.5 * len(meshes), 4), squeeze=False)
    for mesh, axes in zip(meshes, panels[0]):
        own = [r for r in rows if r["mesh"] == mesh]
        resolutions = [r["level0"] for r in own]
        for key, label, marker in (("two_level", "two-level", "o-"),
                                   ("level0_only", "level 0 alone", "s--"),
                                   ("resample", "resample + propagation", "^:")):
            axes.plot(resolutions, [100 * r[key + "_rms"] for r in own], marker,
                      label="%s (%.2f s at %d^3)" % (label, own[-1][key + "_s"],
                                                     resolutions[-1]))
        axes.set_xscale("log", base=2)
        axes.set_xticks(resolutions)
        axes.set_xticklabels(["%d^3" % n for n in resolutions])
        axes.set_ylim(bottom=0)
        axes.set_xlabel("level-0 (and resampling) grid")
        axes.set_ylabel("per-vertex RMS vs brute force (%)")
        axes.set_title(mesh)
        axes.grid(True, alpha=0.3)
        axes.legend(fontsize="small")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def main():
    results_path, out = sys.argv[1:3]
    with open(results_path) as f:
        results = json.load(f)
    os.makedirs(out, exist_ok=True)
    written = []
    if "fig10" in results:
        written.append(os.path.join(out, "fig10.png"))
        plot_fig10(results["fig10"], written[-1])
    if "per_voxel" in results:
        written.append(os.path.join(out, "per_voxel.png"))
        plot_per_voxel(results["per_voxel"], written[-1])
    if "unstructured_comparison" in results:
        written.append(os.path.join(out, "unstructured.png"))
        plot_unstructured(results["unstructured_comparison"], written[-1])
    for path in written:
        print("wrote", path)
    return 0 if written else 1


if __name__ == "__main__":
    sys.exit(main())
