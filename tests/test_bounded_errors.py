"""The core's bounds on bad input: an integer too large for any key and a scene with
millions of unknown keys end in RustfracError subclasses naming the key, with a bounded
message, quickly."""

from __future__ import annotations

import time

import pytest

import rustfrac as rf


@pytest.mark.parametrize("key", ["checkpoint_every", "sla_steps", "refactor_every"])
def test_huge_integers_name_their_key(key: str) -> None:
    # before: checkpoint_every = 10**30 raised OverflowError
    with pytest.raises(rf.InvalidParameterError, match="bits") as e:
        rf.scenes.edge_crack_plate("pd", **{key: 10**30})
    assert e.value.param == f"pd.{key}"
    assert isinstance(e.value, rf.RustfracError)


def test_millions_of_unknown_keys_give_a_short_message() -> None:
    scene = {"method": "fem", "plate": {f"k{i}": 1 for i in range(3_000_000)}}
    t0 = time.perf_counter()
    with pytest.raises(rf.UnknownParameterError) as e:
        rf.run(scene)
    took = time.perf_counter() - t0
    msg = str(e.value)
    print(f"3e6 unknown keys refused in {took:.2f} s; message of {len(msg)} characters")
    assert len(msg) < 1000
    assert "more" in msg
    assert isinstance(e.value, rf.RustfracError)
