"""``rustfrac run SCENE.toml --out DIR``: one run, its summary lines, its result folder (and
with ``--plot`` its figures), checkpoints and resume of the SLA."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from .._folder import FolderWriter, check_writable, with_fallback, writing
from ..errors import InvalidParameterError, OutputError
from ..progress import ProgressBar
from .common import read_scene

if TYPE_CHECKING:
    from ..result import Result as _Result
    from ..scene import Scene as _Scene


def cmd_run(args: argparse.Namespace) -> int:
    from ..result import JSON_NAME, OWNED_NAMES, PVD_NAME, Result, stage_result
    from ..runner import run

    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, flush=True))
    scene = read_scene(args.scene)
    if scene is None:
        return 2
    scene = _checkpoint_options(scene, args)
    resume = scene.pd.resume_from if scene.method in ("pd", "ccm_pd") else None
    if resume and not Path(resume).is_file():  # an input: refused before computing, exit 2
        what = "missing" if not Path(resume).exists() else "not a regular file"
        print(
            f"rustfrac: error: invalid --resume (pd.resume_from): checkpoint {resume} is {what}",
            file=sys.stderr,
        )
        return 2
    try:
        check_writable(args.out)  # before computing: a bad --out must not cost the run
    except OutputError as e:
        print(f"rustfrac: error: invalid --out: {e}", file=sys.stderr)
        return 2
    log(f"scene   {args.scene}: {scene.describe()}")
    growth = scene.method == "xfem" and scene.xfem.growth_steps > 0
    bar = None if args.quiet else ProgressBar(delay=0.0 if growth else 0.5)
    try:
        res: Result = run(scene, progress=bar)
    except KeyboardInterrupt as e:
        partial = getattr(e, "result", None)
        if isinstance(partial, Result):
            # keep what finished (XFEM growth and the SLA stop with status "cancelled")
            partial.save(args.out, vtu=not args.no_vtu)
            print(
                f"rustfrac: interrupted; the finished part ({partial.summary()}) was written "
                f"to {args.out}",
                file=sys.stderr,
            )
        if scene.method in ("pd", "ccm_pd") and scene.pd.checkpoint_path:
            print(
                f"rustfrac: interrupted; checkpoint written to {scene.pd.checkpoint_path} "
                f"(continue with: rustfrac run {args.scene} --out {args.out} --resume "
                f"{scene.pd.checkpoint_path})",
                file=sys.stderr,
            )
        raise
    finally:
        if bar is not None:
            bar.close()
    anchor = res.meta.get("anchor_node")
    log(
        f"built   {res.n_dofs} unknowns, method {res.method}, bc {res.meta.get('bc')}: "
        f"{res.meta.get('bc_description', '')}"
        + (f"; anchor node {anchor}" if anchor is not None else "")
    )
    enr = res.meta.get("enrichment")
    if enr:
        log(
            f"enrich  {enr['n_std']} standard + {res.n_dofs - enr['n_std']} enriched unknowns: "
            f"{enr['n_heaviside_nodes']} Heaviside nodes, {enr['n_tip_nodes']} tip nodes, "
            f"{enr['n_dropped_nodes']} dropped (small-area rule)"
        )
    log(
        f"result  sigma22 = {res.sigma22:.10g}, CMOD = {res.cmod:.10g}, "
        f"solve {res.wall_time_s:.3f} s"
    )
    if res.K_I is not None:
        log(
            f"sifs    K_I = {res.K_I:.10g}, K_II = {res.K_II:.10g}, J = {res.J:.10g} "
            f"(domain J = {res.scalars.get('J_domain', float('nan')):.10g}, "
            f"r_I = {res.meta.get('r_I', float('nan')):.6g})"
        )
        tips = res.tip_sifs
        if len(tips) > 1:
            for k, t in enumerate(tips):
                log(
                    f"  tip {k} (crack {t['crack']}) at ({t['x1']:.6g}, {t['x2']:.6g}): "
                    f"K_I = {t['K_I']:.10g}, K_II = {t['K_II']:.10g}"
                )
    for name, r in res.regions.items():
        f = r["force"]
        ms = r.get("mean_stress")
        log(
            f"region  {name}: force ({f[0]:.10g}, {f[1]:.10g})"
            + (f", mean stress {ms:.10g}" if ms is not None else "")
        )
    for name, (a, b) in res.probes.items():
        log(f"probe   {name}: ({a:.10g}, {b:.10g})")
    if res.method in ("pd", "ccm_pd"):
        _log_pd(log, res)
    elif "status" in res.meta:
        n = len(res.history.get("a", ()))
        extra = (
            f", {n - 1} critical states, a = {res.history['a'][-1]:.6g} at the last"
            if n > 1
            else ""
        )
        log(f"status  {res.meta['status']}{extra}")
    plots: list[str] = []
    missing: list[str] = []

    def write(d: Path) -> Path:
        plots.clear()
        missing.clear()
        with writing(d, owned=OWNED_NAMES, last=JSON_NAME) as w:
            stage_result(res, w, vtu=not args.no_vtu)
            if args.plot:
                _stage_plots(res, w, plots, missing)
        return d

    try:
        out = with_fallback(args.out, write, "run")
    except OutputError as e:
        print(f"rustfrac: error: {e}", file=sys.stderr)
        return 1
    log(
        f"saved   {out}/ (result.json, fields.npz{'' if args.no_vtu else ', result.vtu'}"
        + (f", {PVD_NAME} + series" if (Path(out) / PVD_NAME).exists() else "")
        + "".join(", " + p for p in plots)
        + ")"
    )
    if missing:
        print(
            f"rustfrac: interrupted while plotting; the result was saved to {out}/ without "
            f"{', '.join(missing)}",
            file=sys.stderr,
        )
        return 130
    return 0


def _stage_plots(res: _Result, w: FolderWriter, plots: list[str], missing: list[str]) -> None:
    """``rustfrac run --plot``: the PNGs of a result, staged into its folder; Ctrl-C drops the
    plot being drawn and lists it and the rest in ``missing`` (the result is still written)."""
    from ..plotting import (
        field_components,
        plot_crack_path,
        plot_damage,
        plot_field,
        plot_load_path,
        plot_tip_deformation,
    )

    component = "s22" if "s22" in field_components(res) else "u2"
    todo: list[tuple[str, Callable[[], Any]]] = [
        (f"{component}.png", lambda: plot_field(res, component)),
        ("crack_path.png", lambda: plot_crack_path(res)),
    ]
    if res.damage is not None:
        todo.append(("damage.png", lambda: plot_damage(res)))
    if "deformed_cells" in res.fields:
        todo.append(("tip_x50.png", lambda: plot_tip_deformation(res, scale=50.0)))
    if res.history:
        todo.append(("load_path.png", lambda: plot_load_path(res)))
    done, _ = w.stage_each(
        (name, lambda p, d=draw: d().figure.savefig(p, format="png", dpi=150, bbox_inches="tight"))
        for name, draw in todo
    )
    plots.extend(done)
    missing.extend(n for n, _ in todo if n not in done)


def _checkpoint_options(scene: _Scene, args: argparse.Namespace) -> _Scene:
    """Applies ``--checkpoint``, ``--checkpoint-every`` and ``--resume`` to a PD scene."""
    if args.checkpoint is None and args.checkpoint_every is None and args.resume is None:
        return scene
    if scene.method not in ("pd", "ccm_pd"):
        raise InvalidParameterError(
            "invalid --checkpoint/--resume: checkpoints are for the SLA of methods 'pd' and "
            f"'ccm_pd', the scene runs {scene.method!r}",
            "resume_from",
        )
    changes: dict[str, Any] = {}
    if args.checkpoint is not None:
        changes["pd__checkpoint_path"] = str(args.checkpoint)
        if args.checkpoint_every is None and scene.pd.checkpoint_every == 0:
            changes["pd__checkpoint_every"] = 100
    if args.checkpoint_every is not None:
        changes["pd__checkpoint_every"] = args.checkpoint_every
    if args.resume is not None:
        changes["pd__resume_from"] = str(args.resume)
    return scene.replace(**changes)


def _log_pd(log: Callable[..., None], res: _Result) -> None:
    """The PD / CCM-PD lines of ``rustfrac run``: model size, gamma, SLA outcome."""
    m, n = res.meta, res.meta.get("counts", {})
    log(
        f"pd      {n.get('n_pd_nodes')} PD nodes of {n.get('n_nodes')} grid nodes, "
        f"{n.get('n_bonds')} bonds ({n.get('bytes_per_bond')} B/bond, "
        f"{n.get('n_precrack_bonds')} pre-broken), {n.get('n_removed_elements')} FEM elements "
        f"removed; gamma = {res.gamma:.15g}, s0 = {res.scalars.get('s0', float('nan')):.6g}"
    )
    h = res.history
    steps = m.get("sla_steps_done", 0)
    last = (
        f"; last step: load factor {h['load_factor'][-1]:.6g}, sigma22 {h['sigma22'][-1]:.6g}, "
        f"crack length {h['crack_length'][-1]:.6g}"
        if steps
        else ""
    )
    t = m.get("timings", {})
    log(
        f"sla     status {m.get('status')} after {steps} steps{last}; solver {m.get('solver')}; "
        f"setup {t.get('setup_s', 0.0):.3f} s, SLA {t.get('sla_s', 0.0):.3f} s"
    )
    if m.get("resumed_steps") or m.get("n_checkpoints"):
        log(
            f"ckpt    {m.get('resumed_steps', 0)} steps replayed from {m.get('resumed_from')}; "
            f"{m.get('n_checkpoints', 0)} checkpoints written to {m.get('checkpoint_path')}"
        )
    for w in m.get("warnings", []):
        log(f"warning {w}")
