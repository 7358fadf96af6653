"""Bad input to imagespace.design.sweep gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.sweep import _demo_index, fuzzy_minmax, sweep


@pytest.fixture(scope="module")
def table():
    return sweep(_demo_index, {"a": [1.0, 2.0], "b": [2.0]}, processes=0, progress=False)


@pytest.mark.parametrize("call, exc, words", [
    (lambda t: isp.sweep(None, {"a": [1, 2]}), TypeError, "func must be callable"),
    (lambda t: isp.sweep(lambda a: {"v": a}, None), TypeError, "grid must be a dict"),
    (lambda t: sweep(_demo_index, {}), isp.InputError, "grid must be a non-empty dict"),
    (lambda t: sweep(lambda **kw: {"v": 1.0}, {1: [1, 2]}), TypeError, "grid keys must be parameter names"),
    (lambda t: sweep(_demo_index, {"a": [1, 2], "b": [1]}, processes=2.5), TypeError, "processes"),
    (lambda t: sweep(_demo_index, {"a": [1, 2], "b": [1]}, chunksize=1.5), TypeError, "chunksize"),
    (lambda t: sweep(_demo_index, {"a": [1, 2], "b": [1]}, progress="yes"), TypeError, "progress"),
    (lambda t: sweep(_demo_index, {"a": [1, 2], "b": [1]}, on_error=["raise"]), isp.InputError, "on_error"),
    (lambda t: sweep(_demo_index, {"a": [1, 2], "b": [1]}, client="localhost:8786"), TypeError,
     "client must be a dask.distributed.Client"),
    (lambda t: sweep(_demo_index, {"a": [1, 2], "b": [1]}, processes=2**1100), isp.InputError,
     "processes must be at most"),
    (lambda t: t.grid("nope"), isp.InputError, "name must be one of the table's values"),
    (lambda t: t.grid(["sum"]), isp.InputError, "name must be one of"),
    (lambda t: isp.fuzzy_minmax(None, {"sum": (1.0, "max")}), TypeError, "table must be a DesignTable"),
    (lambda t: fuzzy_minmax(t, None), TypeError, "criteria must be a dict"),
    (lambda t: fuzzy_minmax(t, {}), isp.InputError, "criteria must be a non-empty"),
    (lambda t: fuzzy_minmax(t, {"nope": (1.0, "max")}), isp.InputError, "not an index of the table"),
    (lambda t: fuzzy_minmax(t, {"sum": "max"}), isp.InputError, r"criteria\['sum'\] must be \(weight"),
    (lambda t: fuzzy_minmax(t, {"sum": ("0.5", "max")}), TypeError, "weight of 'sum'"),
    (lambda t: fuzzy_minmax(t, {"sum": (True, "max")}), TypeError, "weight of 'sum'"),
    (lambda t: fuzzy_minmax(t, {"sum": (float("nan"), "max")}), isp.InputError, "weight of 'sum'"),
    (lambda t: fuzzy_minmax(t, {"sum": (-0.5, "max")}), isp.InputError, "weight of 'sum'"),
    (lambda t: fuzzy_minmax(t, {"sum": (0.5, "best")}), isp.InputError, "sense must be 'max' or 'min'"),
])
def test_bad_input(table, call, exc, words):
    with pytest.raises(exc, match=words):
        call(table)


def test_valid_input_still_works(table):
    """numpy weights and a list ``[weight, sense]`` are accepted, and the answer is Choi's fuzzy
    min-max worked by hand: rows (a, b) = (1, 2), (2, 2) have sum 3, 4 and product 2, 4; normalised
    u_sum = (0, 1), u_product = (0, 1), so z_sum = 1 + 1 (u - 1) = (0, 1) and z_product ("min":
    1 - u) = 1 + 0.5 ((1, 0) - 1) = (1, 0.5); W = min = (0, 0.5): row 1 is best."""
    res = fuzzy_minmax(table, {"sum": (np.float64(1.0), "max"), "product": [0.5, "min"]})
    assert res.composite.tolist() == [0.0, 0.5]
    assert res.memberships["sum"].tolist() == [0.0, 1.0] and res.memberships["product"].tolist() == [1.0, 0.5]
    assert res.best == [1]
    # equal weights tie the two rows (W = (0, 0)): both are best
    assert fuzzy_minmax(table, {"sum": (np.float64(1.0), "max"), "product": [1, "min"]}).best == [0, 1]
