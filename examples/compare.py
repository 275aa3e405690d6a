#!/usr/bin/env python3
"""Error against steps for three techniques, as the bench measures them, plotted into a PNG.

Each technique traces the primary rays of one view (relief.camera_rays) at several iteration caps
(the parameter whose role is "iteration cap"); relief.compare measures every run against the exact
reference on the same rays. Usage: compare.py OUT.png [--map gen:fbm:256x256] [--size 256]
Run from the build tree with PYTHONPATH=build/python (ctest python_example_compare does).
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import relief  # noqa: E402

TECHNIQUES = ["linear", "relaxed-cone", "cone"]
CAPS = [2, 4, 8, 16, 32, 64]


def cap_parameter(row):
    return next(p["name"] for p in row["parameters"] if p["role"] == "iteration cap")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", help="PNG file to write")
    parser.add_argument("--map", default="gen:fbm:256x256:1", help="heightfield (file or gen:...)")
    parser.add_argument("--size", type=int, default=256, help="image width in rays (height 3/4)")
    parser.add_argument("--elevation", type=float, default=27.8)
    args = parser.parse_args()

    hf = relief.Heightfield.load(args.map)
    origins, directions = relief.camera_rays(hf, elevation=args.elevation,
                                             size=(args.size, args.size * 3 // 4))
    exact = relief.trace(hf, origins, directions, technique="exact")
    fig, (ax_err, ax_wrong) = plt.subplots(1, 2, figsize=(10, 4))
    for name in TECHNIQUES:
        row = next(r for r in relief.techniques() if r["name"] == name)
        maps = relief.bake(hf, name) if row["has_maps"] else None  # built once for every cap
        steps, error, wrong = [], [], []
        for cap in CAPS:
            hits = relief.trace(hf, origins, directions, technique=name, maps=maps,
                                **{cap_parameter(row): cap})
            stats = relief.compare(exact, hits)
            steps.append(stats["covered_steps"]["mean"])
            error.append(stats["error"]["mean"])
            wrong.append(100.0 * stats["covered_wrong_rate"])
        ax_err.plot(steps, np.maximum(error, 1e-7), "o-", label=name)
        ax_wrong.plot(steps, wrong, "o-", label=name)
    ax_err.set(xscale="log", yscale="log", xlabel="mean steps per covered ray",
               ylabel="mean |t - t_exact| (texels, rays both hit)")
    ax_wrong.set(xscale="log", xlabel="mean steps per covered ray", ylabel="wrong rays (%)")
    for ax in (ax_err, ax_wrong):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle(f"{hf.source}, elevation {args.elevation:g} deg, caps {CAPS}")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    fig.savefig(args.output, dpi=100)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
