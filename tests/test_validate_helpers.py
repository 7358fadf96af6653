"""The shared validators of ``imagespace._validate``: shapes, empty sides, overflow, indices."""

import numpy as np
import pytest

from imagespace._validate import as_box, as_index, as_joint_vector
from imagespace.exceptions import InputError


def test_joint_vector_shapes():
    assert as_joint_vector([1, 2, 3]).shape == (3,)
    assert as_joint_vector(np.zeros((4, 3)), allow_batch=True).shape == (4, 3)
    with pytest.raises(InputError, match=r"q must have shape \(3,\), got shape \(4, 3\)"):
        as_joint_vector(np.zeros((4, 3)))
    with pytest.raises(InputError, match="q must have shape"):
        as_joint_vector([1, 2])
    with pytest.raises(InputError, match="finite"):
        as_joint_vector([1, np.nan, 2])
    with pytest.raises(TypeError, match="q must be numeric"):
        as_joint_vector("1 2 3")


def test_box_checks_every_side():
    assert as_box([[0, 1], [0, 1], [-2, 2]]).shape == (3, 2)
    assert as_box(None, required=False) is None
    with pytest.raises(InputError, match="needed"):
        as_box(None)
    with pytest.raises(InputError, match=r"empty along axis \[1\]"):
        as_box([[0, 1], [1, 1], [0, 1]])
    with pytest.raises(InputError, match="overflows"):
        as_box([[-1e308, 1e308], [0, 1], [0, 1]])
    with pytest.raises(InputError, match=r"shape \(2, 2\); got shape \(3, 2\)"):
        as_box(np.zeros((3, 2)), dim=2)


def test_index_range():
    assert as_index(0, "mode", 2) == 0
    with pytest.raises(InputError, match=r"mode must be in 0..1, got 2"):
        as_index(2, "mode", 2)
    with pytest.raises(InputError):
        as_index(-1, "mode", 2)
    with pytest.raises(TypeError):
        as_index(1.0, "mode", 2)
