"""Scenes shared by the PD test files."""

from __future__ import annotations

import rustfrac as rf


def coarse(steps: int = 30, **kw: object) -> rf.Scene:
    """The paper's plate with dx = 0.2 (x2 = 10.5 and x1 = 1.1 lie between nodes) and a PD
    rectangle [0.3, 4.7] x [9.3, 11.7] large enough for the crack to grow in it."""
    args: dict[str, object] = {
        "method": "ccm_pd",
        "dx": 0.2,
        "pd_center": (2.5, 10.5),
        "pd_size": (4.4, 2.4),
        "sla_steps": steps,
    }
    args.update(kw)
    return rf.scenes.edge_crack_plate(**args)  # type: ignore[arg-type]
