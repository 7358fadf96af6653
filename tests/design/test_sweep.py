"""Local and Dask sweeps give the same table; bad input to the design tools."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.sweep import _demo_index, fuzzy_minmax, sweep
from imagespace.design.workspace import dexterous_workspace, halfplane_polygon, reachable_workspace

STROKE = [[-np.sqrt(3), np.sqrt(3)]] * 3


@pytest.mark.slow
def test_dask_and_local_sweeps_return_the_same_table():
    distributed = pytest.importorskip("distributed")
    grid = {"alpha": np.array([60, 70, 80]) * np.pi / 180, "r_over_R": np.array([0.4, 0.5])}
    local = sweep(isp.examples.choi_3ppr_indices, grid, processes=0, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        remote = sweep(isp.examples.choi_3ppr_indices, grid, client=client, progress=False)
    assert remote.how.startswith("dask") and local.equals(remote)


def test_design_bad_input():
    with pytest.raises(isp.InputError, match="single design"):
        sweep(_demo_index, {"a": [1.0], "b": [2.0]}, processes=0)
    with pytest.raises(isp.InputError, match="no values"):
        sweep(_demo_index, {"a": [], "b": [2.0]}, processes=0)
    t = sweep(_demo_index, {"a": [1.0, 2.0], "b": [2.0]}, processes=0)
    with pytest.raises(isp.InputError, match="weight"):
        fuzzy_minmax(t, {"sum": (1.5, "max")})
    with pytest.raises(isp.InputError, match="min < max"):
        dexterous_workspace(isp.examples.choi_3ppr(), (0.0, 0.5), [[1, -1]] * 3)
    with pytest.raises(isp.InputError, match="phi_range"):
        reachable_workspace(isp.examples.choi_3ppr(), (0.5, 0.5), STROKE)
    with pytest.raises(isp.InputError, match="b must have"):
        halfplane_polygon([[1, 0]], [1, 2])
