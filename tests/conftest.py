from __future__ import annotations

import os
from pathlib import Path

import pytest

import rustfrac as rf

ROOT = Path(__file__).resolve().parents[1]

# The optional families, by file, and the slowest tests, by file and name (all parameters): the
# markers registered in pyproject.toml, so that `pytest -m "not slow and not docs"` is the quick
# loop. CI runs everything.
FAMILIES = {
    "test_docs.py": "docs",
    "test_doc_blocks.py": "docs",
    "test_notebook.py": "notebook",
    "test_packaging.py": "packaging",
}
# slow: 5 s or more in a CI run (pytest --durations=25, two workers on the loaded 2-core machine)
SLOW = {
    "test_docs.py": {"*"},
    "test_doc_blocks.py": {"test_every_python_block_runs"},
    "test_notebook.py": {"test_example_notebook_reproduces_fig7"},
    "test_packaging.py": {"test_core_stub_matches_the_native_module"},
    "test_fig7.py": {
        "test_full_disk_while_staging_a_result_folder_leaves_the_folder_as_it_was",
        "test_the_cpu_parts_benchmark_accounts_for_every_part",
    },
    "test_fault_campaign.py": {
        "test_sigint_at_random_moments",
        "test_sigint_at_random_moments_of_the_fig7_job",
    },
    "test_result_folder.py": {"test_concurrent_writers_never_mix"},
    "test_sweep.py": {"test_dask_cluster_gives_identical_numbers"},
    "test_bounded_errors.py": {"test_millions_of_unknown_keys_give_a_short_message"},
    "test_interrupt.py": {"test_cli_ctrl_c_keeps_the_finished_part"},
    "test_pd.py": {"test_fast_sla_matches_oracle"},
    "test_sweep_scene.py": {"test_xfem_k_i_extrapolates_to_the_handbook"},
}


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for file, names in SLOW.items():  # an entry that names no test is an error, not a no-op
        text = (ROOT / "tests" / file).read_text(encoding="utf-8")
        missing = [n for n in names if n != "*" and f"def {n}(" not in text]
        assert not missing, f"tests/conftest.py SLOW names tests not in {file}: {missing}"
    for item in items:
        file = item.path.name
        if file in FAMILIES:
            item.add_marker(FAMILIES[file])
        names = SLOW.get(file, ())
        if "*" in names or getattr(item, "originalname", item.name) in names:
            item.add_marker("slow")


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def child_env() -> dict[str, str]:
    """The environment of a child Python process that must import the rustfrac this suite
    imports, whatever its working directory (a relative PYTHONPATH, as in ``PYTHONPATH=python
    pytest``, would not reach it from another directory)."""
    return {**os.environ, "PYTHONPATH": str(Path(rf.__file__).resolve().parents[1])}


@pytest.fixture(scope="session")
def uncracked() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="fem", crack="none"))


@pytest.fixture(scope="session")
def seam() -> rf.Result:
    return rf.run(rf.scenes.edge_crack_plate(method="fem", crack="seam"))
