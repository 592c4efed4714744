"""The Dask recipe of docs/python.md, run as the document writes it, on a LocalCluster."""

from __future__ import annotations

import re

import numpy as np
import pytest

import zenosim
from conftest import MODELS, ROOT

distributed = pytest.importorskip("dask.distributed")


def recipe() -> dict:
    """The functions the recipe's first code block defines."""
    text = (ROOT / "docs" / "python.md").read_text()
    marker = text.index("<!-- dask-recipe")
    block = re.search(r"```python\n(.*?)```", text[marker:], re.S).group(1)
    scope: dict = {}
    exec(compile(block, "docs/python.md", "exec"), scope)
    return scope


def test_a_sweep_across_a_local_cluster_equals_the_local_sweep():
    sweep_on_dask = recipe()["sweep_on_dask"]
    model = zenosim.Model.from_file(MODELS / "bouncing-ball.toml")
    values = {"e": np.linspace(0.1, 0.9, 20), "h0": [0.5, 1.0, 2.0]}
    local = zenosim.sweep(model, values, t_end=10.0)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        with distributed.get_task_stream(client) as stream:
            spread = sweep_on_dask(client, model, values, t_end=10.0)
        # Both workers ran parts: 8 (four per worker thread).
        assert len(stream.data) == 8
        assert len({task["worker"] for task in stream.data}) == 2
        # From the path too, with a part count that does not divide the points.
        by_path = sweep_on_dask(client, str(MODELS / "bouncing-ball.toml"), values, parts=7,
                                t_end=10.0)
    assert isinstance(spread, zenosim.SweepTable)
    assert list(spread) == list(local) and spread.rows == local.rows == 60
    for column in local:
        np.testing.assert_array_equal(spread[column], local[column], err_msg=column)
        np.testing.assert_array_equal(by_path[column], local[column], err_msg=column)
