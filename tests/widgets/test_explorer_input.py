"""The explorers refuse bad input at the boundary with an error naming the parameter (issue [16]):
strings are never evaluated (a planted string would create a file), complex numbers and booleans
are refused, absurd magnitudes answered at once."""

import numpy as np
import pytest

pytest.importorskip("ipywidgets")
pytest.importorskip("plotly")

import imagespace as isp  # noqa: E402


@pytest.fixture(scope="module")
def designs():
    gs, L = isp.examples.dietmaier_1998()
    return isp.examples.stigger_husty(), gs, L


def test_planar_explorer_refuses_bad_input(designs):
    m, _, _ = designs
    for kwargs, exc, msg in (({"q": "abc"}, TypeError, "q must be numeric"),
                             ({"q": [np.nan, 1, 1]}, isp.InputError, "q must be finite"),
                             ({"q": [1 + 1j, 1, 1]}, TypeError, "q"),
                             ({"box": [[0, 1]]}, isp.InputError, "box must be"),
                             ({"resolution": 0}, isp.InputError, "resolution must be at least")):
        with pytest.raises(exc, match=msg):
            isp.widgets.explore(m, **kwargs)
    with pytest.raises(TypeError, match="manipulator must be"):
        isp.widgets.explore(object())


def test_spatial_explorer_refuses_bad_input(designs, tmp_path):
    _, gs, L = designs
    planted = tmp_path / "planted"
    for bad, exc, msg in (([1.0] * 5, isp.InputError, r"L must have shape \(6,\)"),
                          ([np.nan] + [1.0] * 5, isp.InputError, "positive finite"),
                          ([f"__import__('pathlib').Path('{planted}').touch()"] * 6, TypeError, "never parsed"),
                          ([1 + 0.5j] * 6, TypeError, "real"),
                          ([True] * 6, TypeError, "booleans"),
                          ([1e300] * 6, isp.InputError, "times the design's size")):
        with pytest.raises(exc, match=msg):
            isp.widgets.explore(gs, bad)
    assert not planted.exists()
    with pytest.raises(isp.InputError, match="box must be"):
        isp.widgets.explore(gs, L, box=[[0, 1]])
