"""Handbook LEFM formulas (Tada, Paris and Irwin; Anderson) used as independent references.

Each holds only for the geometry it names: the three-point bend beam for :func:`srawley_senb_F`;
for the others a single edge crack of length ``a`` in a long strip of width ``b`` under remote
uniform tension ``sigma`` (ends free to rotate). The paper's plate
(W = 11, L = 21, loaded through grips) is *not* that geometry, so the curve drawn from these
formulas in Fig. 7 is labelled "LEFM handbook (long strip, traction)" and is a guide, not a target.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "brown_srawley_F",
    "e_prime",
    "edge_crack_curve",
    "srawley_senb_F",
    "tada_F",
    "tada_V",
]


def tada_F(x: ArrayLike) -> NDArray[np.float64]:
    """Geometry factor F(a/b) of K_I = sigma sqrt(pi a) F, Tada's formula (0.5 % for any a/b)."""
    x = np.asarray(x, dtype=float)
    t = np.pi * x / 2
    return (
        np.sqrt(2 / (np.pi * x) * np.tan(t))
        * (0.752 + 2.02 * x + 0.37 * (1 - np.sin(t)) ** 3)
        / np.cos(t)
    )


def brown_srawley_F(x: ArrayLike) -> NDArray[np.float64]:
    """Brown-Srawley polynomial for F(a/b), within 0.5 % for a/b <= 0.6 only."""
    x = np.asarray(x, dtype=float)
    return 1.12 - 0.231 * x + 10.55 * x**2 - 21.72 * x**3 + 30.39 * x**4


def tada_V(x: ArrayLike) -> NDArray[np.float64]:
    """CMOD factor V(a/b) of CMOD = 4 sigma a V / E' (Tada)."""
    x = np.asarray(x, dtype=float)
    t = np.pi * x / 2
    return (1.46 + 3.42 * (1 - np.cos(t))) / np.cos(t) ** 2


def e_prime(E: float, nu: float, plane: str = "strain") -> float:
    """E' = E / (1 - nu^2) in plane strain, E in plane stress (eq. 50)."""
    return E / (1 - nu**2) if plane == "strain" else E


def edge_crack_curve(
    a: ArrayLike, width: float, E: float, nu: float, G0: float, plane: str = "strain"
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(CMOD, sigma) at which an edge crack of length ``a`` grows in a long strip of width
    ``width`` under remote tension: sigma_c = K_Ic / (sqrt(pi a) F(a/W)), K_Ic = sqrt(G0 E'),
    and CMOD = 4 sigma_c a V(a/W) / E'. Prepend (0, 0) for the initial linear loading branch."""
    a = np.asarray(a, dtype=float)
    ep = e_prime(E, nu, plane)
    kic = np.sqrt(G0 * ep)
    x = a / width
    sigma = kic / (np.sqrt(np.pi * a) * tada_F(x))
    cmod = 4 * sigma * a * tada_V(x) / ep
    return cmod, sigma


def srawley_senb_F(x: ArrayLike) -> NDArray[np.float64]:
    """Geometry factor of the single-edge notched bend beam with S/W = 4 (three-point bend):
    K_I = P S / (B W^1.5) F(a/W), Srawley (1976), Int. J. Fract. 12, 475-476, as in ASTM E399
    (within 0.5 % for 0 <= a/W <= 1)."""
    a = np.asarray(x, dtype=float)
    return (
        3
        * np.sqrt(a)
        * (1.99 - a * (1 - a) * (2.15 - 3.93 * a + 2.7 * a**2))
        / (2 * (1 + 2 * a) * (1 - a) ** 1.5)
    )
