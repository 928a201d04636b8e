"""Typed stubs of the native module ``rustfrac._core`` (PyO3). Prefer the Python API
(:func:`rustfrac.run`); these functions take plain numbers and do only the core's checks."""

import os
from collections.abc import Sequence
from typing import Any, Callable

import numpy as np
import numpy.typing as npt

__version__: str
PROGRESS_INTERVAL_S: float
#: condition estimate above which a result carries a warning (rustfrac_core::solver::COND_WARN)
COND_WARN: float
#: condition estimate above which a solve raises SingularSystemError ("numerically singular",
#: rustfrac_core::solver::COND_SINGULAR)
COND_SINGULAR: float
#: kinds of the (kind, message) warning pairs: "ill_conditioned", "locking", "discretisation"
#: (Python classes: rustfrac.errors.WARNING_CLASSES)
WARNING_KINDS: list[str]

ProgressCallback = Callable[[int, int, str], Any]

def solve_fem_plate(
    *,
    width: float,
    height: float,
    nx: int,
    ny: int,
    e: float,
    nu: float,
    plane: str = "strain",
    thickness: float = 1.0,
    bc: str = "free",
    u0: float = 0.0,
    traction: float = 0.0,
    seam: tuple[float, float] | None = None,
    gauss: int = 2,
    condition: bool = True,
    progress: ProgressCallback | None = None,
) -> dict[str, Any]:
    """The paper's plate with plain Q4 FEM (GIL released). Keys: coords (n,2), elements (m,4)
    int64, u (2n,), reactions (2n,), nodal_stress (n,3), gauss_points (g,2), gauss_stress (g,3)
    as float64 arrays; sigma22, cmod, energy, residual, wall_time_s: float; n_dofs, anchor_node:
    int; seam_y: float | None; bc: str; condition (dimensionless condition estimate of the
    equilibrated stiffness), condition_pivot_ratio: float, both None with ``condition=False``
    (not computed: saves 2 solves); warnings: list[tuple[str, str]] (kind in WARNING_KINDS,
    message: ill conditioning, volumetric locking near nu = 0.5). Raises SingularSystemError
    naming a free rigid-body mode, or when the system is numerically singular."""

def solve_fem_grid(
    *,
    width: float,
    height: float,
    nx: int,
    ny: int,
    e: float,
    nu: float,
    plane: str = "strain",
    thickness: float = 1.0,
    fixed_dofs: list[int] | npt.NDArray[np.integer[Any]],
    fixed_values: list[float] | npt.NDArray[np.floating[Any]],
    forces: list[float] | npt.NDArray[np.floating[Any]] = ...,
) -> dict[str, Any]:
    """A uniform Q4 grid with explicit Dirichlet dofs (2 node + component) and nodal forces.
    Keys: coords, elements, u, reactions, nodal_stress, energy, residual, n_dofs. Raises
    SingularSystemError if the conditions leave a rigid-body mode free (named) or the system is
    numerically singular."""

def solve_xfem_plate(
    *,
    width: float,
    height: float,
    nx: int,
    ny: int,
    e: float,
    nu: float,
    plane: str = "strain",
    thickness: float = 1.0,
    bc: str = "free",
    u0: float = 0.0,
    traction: float = 0.0,
    crack: Sequence[Sequence[float]] | npt.NDArray[np.floating[Any]],
    extra_cracks: Sequence[Sequence[Sequence[float]]] = (),
    nsub: int = 4,
    tip_nsub: int = 0,
    r_i: float = 2.5,
    extra_radii: Sequence[float] = (1.5, 2.0, 3.0, 3.5),
    fixed_area_radius: float | None = None,
    area_threshold: float = 1e-4,
    growth_steps: int = 0,
    g0: float | None = None,
    da: float | None = None,
    a_stop: float | None = None,
    condition: bool = True,
    progress: ProgressCallback | None = None,
) -> dict[str, Any]:
    """The plate with XFEM (GIL released); ``crack`` is a polyline (an end on the boundary is a
    mouth, an end inside a tip), ``extra_cracks`` further polylines (they must neither cross nor
    touch; tips are numbered crack by crack, ``crack`` first); ``tip_nsub = 0`` means nsub; ``r_i``/``extra_radii`` in
    tip-element lengths; ``growth_steps > 0`` runs LEFM growth (needs ``g0``; ``da = None``: one
    element length; ``a_stop = None``: 0.7 width).

    Keys: K_I, K_II, J (from K), J_domain, r_i (absolute), sigma22, cmod, wall_time_s,
    condition (dimensionless condition estimate of the initial solve), condition_pivot_ratio:
    float, both None with ``condition=False``; warnings: list[tuple[str, str]] (kind, message);
    n_dofs, n_std, n_heaviside_nodes, n_tip_nodes, n_dropped_nodes, anchor_node: int;
    status, bc: str; coords (n,2), elements (m,4) int64, u (n_dofs,) (u[:n_std] are the nodal
    displacements), heaviside_nodes, tip_nodes (int64), crack (k,2) final polyline,
    crack_initial (k0,2), radii (r,5) [radius, K_I, K_II, J_from_K, J_domain], radii_factor (r,),
    tips (t,6) [x1, x2, K_I, K_II, J_from_K, J_domain] (every tip), tip_crack (t,) int64 (0 =
    ``crack``, k = ``extra_cracks[k-1]``), cracks (P,2) and cracks_offsets (C+1,) int64 (final
    polylines of all cracks), deformed_cells, deformed_disp (c,4,2); snapshot_cells, snapshot_disp (C,4,2) and
    snapshot_offsets (s+1,) (growth: patch k = rows offsets[k]:offsets[k+1], history row k+1);
    growth history (origin first; empty without growth): history_load_factor, history_sigma22,
    history_cmod, history_u0, history_traction, history_a, history_K_I, history_K_II,
    history_kink_angle, history_tip_x, history_tip_y (the most critical tip), history_condition
    (0 at the origin; None instead of an array with ``condition=False``), and every tip's state
    as (s, t) arrays tip_history_x, tip_history_y,
    tip_history_K_I, tip_history_K_II, tip_history_kink_angle, tip_history_grows (1.0: the tip
    grew after that state)."""

def _progress_demo(steps: int, step_s: float, progress: ProgressCallback | None = None) -> int: ...
def _panic_demo() -> None: ...
def solve_pd_plate(
    *,
    method: str,
    width: float,
    height: float,
    dx: float,
    m: int,
    e: float,
    nu: float,
    plane: str = "strain",
    thickness: float = 1.0,
    g0: float,
    bc: str = "free",
    u0: float = 0.0,
    traction: float = 0.0,
    pd_regions: list[tuple[float, float, float, float]] = ...,
    precrack: list[tuple[float, float]] = ...,
    sla_steps: int = 500,
    stop_crack_length: float | None = None,
    tie_tol: float = 0.0,
    refactor_every: int = 0,
    fast: bool = True,
    damage_at_steps: list[int] = ...,
    checkpoint_every: int = 0,
    checkpoint_path: str | os.PathLike[str] | None = None,
    resume_from: str | os.PathLike[str] | None = None,
    progress: ProgressCallback | None = None,
) -> dict[str, Any]:
    """Pure PD (method "pd") or splice CCM-PD ("ccm_pd": PD in the rectangles (x0, y0, x1, y1),
    FEM elsewhere) plate, then the sequentially linear analysis (GIL released; progress after
    each SLA step; raising from it stops the run, writes a checkpoint when configured, and
    re-raises). ``precrack``: polyline, first point at the
    mouth (empty: uncracked). Keys: scalars sigma22, cmod (reference load, before any break),
    gamma, c, s0, delta, setup_seconds, sla_seconds, wall_time_s: float; n_dofs, n_nodes,
    n_pd_nodes, n_bonds, n_precrack_bonds, n_removed_elements, bytes_per_bond, anchor_node,
    n_refactorisations, max_update_rank, refactor_interval, resumed_steps, n_checkpoints: int;
    peak_memory_bytes: int | None; status ("completed" | "crack_length_reached" | "separated" |
    "no_bond_in_tension" | "cancelled"), solver, bc, method: str; warnings: list[tuple[str, str]]
    ((kind, message): "discretisation": m < 2, detached nodes). Checkpoints every ``checkpoint_every`` steps to
    ``checkpoint_path`` (atomic); ``resume_from`` replays a checkpoint of the same model bit for
    bit (another model's checkpoint: InvalidParameterError; unreadable: CheckpointIOError).
    Arrays: node_xy (n,2), u (2n,), u_final (2n,; empty when separated), pd_nodes (p,) int64,
    pd_node_xy (p,2), damage (p,), broken (b,) bool, bond_nodes (b,2) int64, out_of_balance (2,),
    anchor_xy (2,); one entry per SLA step: history_step, history_bond, history_n_broken,
    history_node_i, history_node_j, history_n_detached (int64), detached_nodes (d,2) int64
    (step, node; step 0 = detached by the pre-crack), history_load_factor, history_sigma22, history_cmod,
    history_u0, history_crack_length (float64); damage_at_steps (k,) int64, damage_at (k,p)."""
