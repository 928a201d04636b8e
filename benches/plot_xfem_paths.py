"""Figure of the XFEM path-convergence study: the paths written by the example ``xfem_paths``
(``PATHS_OUT=DIR cargo run --release -p rustfrac-core --example xfem_paths -- all fine``), each
case's grown part, with the vertical deviation from the finest predictor-corrector path
magnified (the paths differ by hundredths of an element).

Usage: python benches/plot_xfem_paths.py DIR [-o xfem_paths.png]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("dir", type=Path)
    ap.add_argument("-o", "--out", type=Path, default=Path("xfem_paths.png"))
    a = ap.parse_args()
    files = sorted(a.dir.glob("*.csv"))
    fig, axes = plt.subplots(len(files), 2, figsize=(12, 4.5 * len(files)), squeeze=False)
    for row, f in zip(axes, files):
        df = pd.read_csv(f)
        runs = list(df.groupby(["mesh", "da", "rule"], sort=False))
        (mesh, da, _), ref = max(
            ((k, g) for k, g in runs if k[2] == "predictor_corrector"),
            key=lambda kg: (kg[0][0], -kg[0][1]),
        )
        rx, ry = ref["x"].to_numpy()[1:], ref["y"].to_numpy()[1:]
        for ax, rule in zip(row, ("hoop", "predictor_corrector")):
            for (m, d, r), g in runs:
                if r != rule:
                    continue
                x, y = g["x"].to_numpy()[1:], g["y"].to_numpy()[1:]
                # deviation from the reference at the same x1 (the paths run left to right)
                dev = y - np.interp(x, rx, ry)
                ax.plot(x, dev, marker=".", label=f"mesh {m}, da = {d:g}")
            ax.set_title(f"{df['case'].iloc[0]}: {rule}")
            ax.set_xlabel("x1")
            ax.set_ylabel(f"x2 - reference x2 (reference: mesh {mesh}, da = {da:g}, pc)")
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
