"""PD extremes and long SLA runs from Python: the m < 2 accuracy warning,
PD regions thinner than two horizons, checkpoints and bit-for-bit resume (scene options and CLI),
refusal of another model's checkpoint, detached-node reporting."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import rustfrac as rf
from pd_scenes import coarse
from rustfrac.cli import main


def test_m1_runs_with_an_accuracy_warning() -> None:
    with pytest.warns(rf.DiscretisationWarning, match="m = 1") as rec:
        res = rf.run(coarse(3, m=1))
    assert len(rec) == 1
    assert res.meta["warnings"] and "m = 1" in res.meta["warnings"][0]
    assert res.warning_kinds == ["discretisation"]
    assert np.isfinite(res.sigma22) and np.isfinite(res.cmod)
    assert len(res.history["step"]) == 4  # the origin + 3 steps
    with warnings.catch_warnings():
        warnings.simplefilter("error", rf.AccuracyWarning)
        res2 = rf.run(coarse(3, m=2))
    assert res2.meta["warnings"] == []
    # m = 1 overestimates the opening (paper grid: CMOD +21 % against XFEM, m = 2..8: +3..5 %;
    # crates/rustfrac-core/tests/suite/pd_extremes_validation.rs)
    assert res.cmod > res2.cmod


def test_pd_region_thinner_than_two_horizons_is_refused() -> None:
    with pytest.raises(rf.InvalidParameterError, match="two horizons") as e:
        coarse(3, pd_size=(4.4, 1.2))  # 2 m dx = 1.6
    assert e.value.param == "pd.size"
    # the same rectangle is fine with m = 2 (2 m dx = 0.8)
    assert rf.run(coarse(1, pd_size=(4.4, 1.2), m=2)).meta["status"] == "completed"


def _same_history(a: rf.Result, b: rf.Result) -> None:
    assert a.history.keys() == b.history.keys()
    for k in a.history:
        np.testing.assert_array_equal(a.history[k], b.history[k], err_msg=k)
    np.testing.assert_array_equal(a.damage, b.damage)
    np.testing.assert_array_equal(a.fields["u_final"], b.fields["u_final"])


def test_checkpoint_interrupt_and_resume_bit_for_bit(tmp_path: Path) -> None:
    n, k = 15, 4
    total = 2 * n + k
    straight = rf.run(coarse(total, refactor_every=10))
    ck = tmp_path / "run.ckpt"

    class Stop(Exception):
        pass

    def stop(done: int, total: int, message: str) -> None:
        if done >= n + 2:
            raise Stop

    # interrupted from the progress callback: the checkpoint of the stop step is written
    with pytest.raises(Stop):
        rf.run(
            coarse(total, refactor_every=10, checkpoint_every=n, checkpoint_path=str(ck)),
            progress=stop,
        )
    assert ck.exists() and not list(tmp_path.glob("*.tmp*"))
    resumed = rf.run(coarse(total, refactor_every=10, resume_from=str(ck)))
    assert n + 2 <= resumed.meta["resumed_steps"] < total
    _same_history(straight, resumed)
    # stopped by the step limit: resume from the periodic checkpoint after step n
    first = rf.run(coarse(n + 3, refactor_every=10, checkpoint_every=n, checkpoint_path=str(ck)))
    assert first.meta["n_checkpoints"] == 1
    resumed = rf.run(coarse(total, refactor_every=10, resume_from=str(ck)))
    assert resumed.meta["resumed_steps"] == n
    _same_history(straight, resumed)


def test_another_models_checkpoint_is_refused(tmp_path: Path) -> None:
    ck = tmp_path / "a.ckpt"
    rf.run(coarse(6, checkpoint_every=5, checkpoint_path=str(ck)))
    with pytest.raises(rf.InvalidParameterError, match="different") as e:
        rf.run(coarse(10, m=3, resume_from=str(ck)))
    assert "resume_from" in str(e.value)
    with pytest.raises(rf.CheckpointIOError, match=r"missing\.ckpt"):
        rf.run(coarse(10, resume_from=str(tmp_path / "missing.ckpt")))
    (tmp_path / "junk.ckpt").write_bytes(b"not a checkpoint, clearly not one at all....")
    with pytest.raises(rf.InvalidParameterError, match="checkpoint file"):
        rf.run(coarse(10, resume_from=str(tmp_path / "junk.ckpt")))


def test_cli_checkpoint_and_resume(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "s.toml"
    scene.write_text(coarse(24, refactor_every=10).to_toml(), encoding="utf-8")
    ck = tmp_path / "s.ckpt"
    assert main(["run", str(scene), "--out", str(tmp_path / "a"), "--checkpoint", str(ck),
                 "--checkpoint-every", "10", "--no-vtu", "-q"]) == 0  # fmt: skip
    assert ck.exists()
    capsys.readouterr()
    assert main(["run", str(scene), "--out", str(tmp_path / "b"), "--resume", str(ck),
                 "--no-vtu"]) == 0  # fmt: skip
    assert "20 steps replayed" in capsys.readouterr().out
    a, b = rf.load(tmp_path / "a"), rf.load(tmp_path / "b")
    assert a.meta["n_checkpoints"] == 2 and b.meta["resumed_steps"] == 20
    for key in a.history:
        np.testing.assert_array_equal(a.history[key], b.history[key], err_msg=key)
    # checkpoint options on a method without an SLA: refused
    xscene = tmp_path / "x.toml"
    xscene.write_text(rf.scenes.edge_crack_plate("xfem").to_toml(), encoding="utf-8")
    assert main(["run", str(xscene), "--out", str(tmp_path / "x"), "--resume", str(ck)]) == 2
