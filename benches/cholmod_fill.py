"""Fill of CHOLMOD's orderings on the reduced plate matrix of ``bench_fem.py`` (the comparison
for rustfrac's ``plate_phases`` "factor nnz"): analyse + factorise with each ordering and print
the time and nnz(L). The L() copy needs about as much memory again as the factor.

Usage: python benches/cholmod_fill.py [NX NY] [--orderings default,amd,metis,nesdis]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from bench_fem import assemble_numpy, plate_conditions
from sksparse.cholmod import analyze


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("nx", type=int, nargs="?", default=510)
    ap.add_argument("ny", type=int, nargs="?", default=980)
    ap.add_argument("--orderings", default="default,amd,metis,nesdis")
    a = ap.parse_args()
    k = assemble_numpy(a.nx, a.ny)
    fixed, _, _ = plate_conditions(a.nx, a.ny)
    mask = np.ones(k.shape[0], dtype=bool)
    mask[fixed] = False
    free = np.flatnonzero(mask)
    kff = k[:, free][free, :].tocsc()
    print(f"{a.nx} x {a.ny} elements, {kff.shape[0]} free unknowns, nnz(K_ff) {kff.nnz}")
    for method in a.orderings.split(","):
        t0 = time.perf_counter()
        f = analyze(kff, ordering_method=method)
        t1 = time.perf_counter()
        f.cholesky_inplace(kff)
        t2 = time.perf_counter()
        nnz = f.L().nnz
        print(f"{method:>8}: analyze {t1 - t0:.2f} s, numeric {t2 - t1:.2f} s, nnz(L) {nnz}")
        del f


if __name__ == "__main__":
    main()
