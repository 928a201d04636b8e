"""HTML views of results and scenes for Jupyter (``_repr_html_``): small tables, every value
escaped."""

from __future__ import annotations

from html import escape
from typing import Any, Protocol

import numpy as np


class Result(Protocol):
    """What the view reads of a :class:`rustfrac.Result` (structural: ``result.py`` imports
    this module, so it does not import ``result.py`` back)."""

    method: str
    sigma22: float
    cmod: float
    n_dofs: int
    wall_time_s: float
    scalars: dict[str, Any]
    meta: dict[str, Any]
    history: dict[str, Any]
    fields: dict[str, Any]

    @property
    def regions(self) -> dict[str, dict[str, Any]]: ...
    @property
    def probes(self) -> dict[str, tuple[float, float]]: ...
    @property
    def warnings(self) -> list[str]: ...


class Scene(Protocol):
    """What the view reads of a :class:`rustfrac.Scene` (structural, as for :class:`Result`)."""

    method: str
    name: str

    def to_dict(self) -> dict[str, Any]: ...
    def describe(self) -> str: ...


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, np.ndarray):
        return f"array {'x'.join(map(str, v.shape))} {v.dtype}"
    return str(v)


def _table(rows: list[tuple[str, Any]], caption: str = "") -> str:
    cap = f"<caption style='text-align:left'><b>{escape(caption)}</b></caption>" if caption else ""
    body = "".join(
        f"<tr><th style='text-align:left'>{escape(k)}</th>"
        f"<td style='text-align:left'>{escape(_fmt(v))}</td></tr>"
        for k, v in rows
    )
    return f"<table>{cap}{body}</table>"


def result_html(res: Result) -> str:
    """The scalars, status, warnings, history columns and fields of a result."""
    rows: list[tuple[str, Any]] = [
        ("method", res.method),
        ("sigma22", res.sigma22),
        ("CMOD", res.cmod),
        ("unknowns", res.n_dofs),
        ("wall time (s)", res.wall_time_s),
    ]
    for key in ("K_I", "K_II", "J", "gamma", "condition"):
        v = res.scalars.get(key)
        if v is not None:
            rows.append((key, v))
    for key in ("bc", "status", "sla_steps_done"):
        if key in res.meta:
            rows.append((key, res.meta[key]))
    for name, r in res.regions.items():
        f = r["force"]
        rows.append((f"reaction {name}", f"({f[0]:.6g}, {f[1]:.6g})"))
    for name, (a, b) in res.probes.items():
        rows.append((f"probe {name}", f"({a:.6g}, {b:.6g})"))
    if res.history:
        n = len(next(iter(res.history.values())))
        rows.append(("history", f"{n} rows: {', '.join(res.history)}"))
    rows.append(("fields", ", ".join(res.fields) or "none"))
    for w in res.warnings:
        rows.append(("warning", w))
    scene = res.meta.get("scene")
    name = scene.get("name", "") if isinstance(scene, dict) else ""
    return _table(rows, "rustfrac Result" + (f": {name}" if name else ""))


def scene_html(scene: Scene) -> str:
    """The description line and every section's keys of a scene."""
    d = scene.to_dict()
    caption = "rustfrac Scene" + (f": {scene.name}" if scene.name else "")
    parts = [_table([("method", scene.method), ("summary", scene.describe())], caption)]
    for sec, values in d.items():
        tables = (
            [values] if isinstance(values, dict) else values if isinstance(values, list) else []
        )
        for k, t in enumerate(tables):
            title = sec if isinstance(values, dict) else f"{sec}[{k}]"
            parts.append(_table(list(t.items()), title))
    return "".join(parts)
