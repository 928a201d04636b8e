"""The PD surface correction on the paper's case (``pd.surface_correction``).

Runs the Fig. 7 job (``rustfrac.fig7.fig7``, preset ``paper``, free grips) without and with
``surface_correction = "energy"`` into OUT/none and OUT/energy, and the paper's CCM-PD case to a
damage front of 2.0 (``pd.stop_crack_length``, the advance of the audit-convergence study) both
ways; prints, per run: the correction's factors (meta), the initial CMOD and sigma22 against XFEM,
the PD states left of XFEM's peak CMOD against XFEM's elastic line, the peak sigma22 and its CMOD
against XFEM, the curve agreement (``summary.json`` ``agreement.curve``: peaks, lower envelope,
running mean) and the energy audit's G / G0 (``rustfrac.energy.audit``).

Usage: python benches/surface_correction.py [--out DIR]   (about a minute on 2 cores)
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import rustfrac as rf
import rustfrac.energy
from rustfrac.fig7 import fig7

CORRECTIONS = ("none", "energy")


def fig7_lines(out: Path, sc: str) -> list[str]:
    d = out / sc
    fig7(d, preset="paper", surface_correction=None if sc == "none" else sc, log=None)
    s = json.loads((d / "summary.json").read_text())
    res = rf.load(d / "ccm_pd")
    a, o = s["agreement"], s["ours"]
    m = res.meta
    lines = [f"fig7 paper, surface_correction {m['surface_correction']}"]
    if "surface_nodes_corrected" in m:
        lines.append(
            f"  corrected PD nodes {m['surface_nodes_corrected']} of {m['counts']['n_pd_nodes']}, "
            f"node factors {m['surface_node_factor_range']}, bond factors "
            f"{m['surface_bond_factor_range']}"
        )
    lines.append(
        f"  initial CMOD {o['cmod_ccm_pd']:.6g} vs XFEM {o['cmod_xfem']:.6g}: "
        f"{100 * a['initial_cmod_rel_diff']:+.2f} %; sigma22 {100 * a['initial_sigma22_rel_diff']:+.2f} %"
    )
    h = res.history
    sig, cm = np.asarray(h["sigma22"])[1:], np.asarray(h["cmod"])[1:]
    pre = cm < o["cmod_at_peak_xfem"]
    dev = sig[pre] / (o["sigma22_xfem"] / o["cmod_xfem"] * cm[pre]) - 1
    lines.append(
        f"  {int(pre.sum())} PD states left of XFEM's peak CMOD, against XFEM's elastic line "
        f"{100 * dev.min():+.2f} .. {100 * dev.max():+.2f} %"
    )
    lines.append(
        f"  peak sigma22 {o['peak_sigma22_ccm_pd']:.4f} vs XFEM {o['peak_sigma22_xfem']:.4f}: "
        f"{100 * a['peak_sigma22_rel_diff']:+.2f} %; CMOD at the peak "
        f"{100 * a['cmod_at_peak_rel_diff']:+.2f} %"
    )
    for k in ("peaks", "lower_envelope", "running_mean"):
        c = a["curve"][k]
        lines.append(
            f"  curve {k}: {c['n']} points, mean {100 * c['mean_rel_diff']:+.2f} %, RMS "
            f"{100 * c['rms_rel_diff']:.2f} %, min {100 * c['min_rel_diff']:+.2f} %, max "
            f"{100 * c['max_rel_diff']:+.2f} %"
        )
    lines.append(f"  G/G0 {s['energy']['ccm_pd']['ratio']:.4f} (front {h['crack_length'][-1]:.4f})")
    return lines


def front_line(sc: str) -> str:
    kw = {} if sc == "none" else {"surface_correction": sc}
    r = rf.run(rf.scenes.edge_crack_plate("ccm_pd", sla_steps=3000, stop_crack_length=2.0, **kw))
    au = rustfrac.energy.audit(r)
    h = r.history
    return (
        f"front 2.0, surface_correction {sc}: {len(h['sigma22']) - 1} steps, status "
        f"{r.meta['status']}, G/G0 {au['ratio']:.4f}, peak sigma22 {np.max(h['sigma22']):.4f}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("surface_correction"))
    args = ap.parse_args()
    for sc in CORRECTIONS:
        print("\n".join(fig7_lines(args.out, sc)), flush=True)
    for sc in CORRECTIONS:
        print(front_line(sc), flush=True)


if __name__ == "__main__":
    main()
