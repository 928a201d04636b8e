"""Out of memory ends in a clean exception, never an abort or a hang. A run
whose estimated need exceeds what the machine or the process's address-space limit leaves is
refused before the model is built (``rf.OutOfMemoryError``, naming the size); under
``ulimit -v`` limits from 300 MB to 1.5 GB the paper's CCM-PD run either completes or fails with
a Python exception (exit 1), never exit 134 (abort) or a hang."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

import rustfrac as rf


def test_an_impossible_pd_grid_is_refused_before_it_is_built() -> None:
    # 1.67e6 PD nodes with m = 12 (about 450 bonds a node): hundreds of GB of bonds; before this
    # was accepted and the process aborted while building the bonds
    scene = rf.scenes.edge_crack_plate("pd", dx=1 / 85, m=12, sla_steps=1)
    with pytest.raises(rf.OutOfMemoryError, match="GiB") as e:
        rf.run(scene)
    assert isinstance(e.value, MemoryError)
    assert "PD nodes" in str(e.value)


_LIMITED = textwrap.dedent(
    """
    import resource, sys
    limit = int(sys.argv[1])
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    from rustfrac.cli import main
    sys.exit(main(["run", sys.argv[2], "--out", sys.argv[3], "-q", "--no-vtu"]))
    """
)


@pytest.mark.parametrize("mb", [300, 600, 1000, 1500])
def test_memory_limits_end_cleanly(tmp_path, mb: int) -> None:
    scene = rf.examples.path("paper_ccm_pd")
    p = subprocess.run(
        [sys.executable, "-c", _LIMITED, str(mb << 20), str(scene), str(tmp_path / "o")],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    tail = p.stderr.strip().splitlines()[-3:]
    print(f"ulimit -v {mb} MB: exit {p.returncode}: {tail}")
    assert p.returncode in (0, 1), p.stderr[-2000:]
    assert "memory allocation of" not in p.stderr
    if p.returncode == 1:
        assert "MemoryError" in p.stderr or "OutOfMemoryError" in p.stderr, p.stderr[-2000:]
