"""Bad input to imagespace.paths.backlash gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.paths.backlash import MAX_MEMORY, backlash, released_curve


@pytest.fixture(scope="module")
def mq():
    m = isp.examples.stigger_husty()
    return m, m.q_example_float


@pytest.mark.parametrize("call, exc, words", [
    (lambda m, q: isp.backlash(m, q, 0, samples=10**12), isp.InputError,
     r"samples=1000000000000 needs about .* GB .* lower samples \(at most \d+\) or raise max_memory"),
    (lambda m, q: released_curve(m, q, 2, samples=10**12), isp.InputError, "max_memory"),
    (lambda m, q: released_curve(m, q, 2, samples=1000, max_memory=1000), isp.InputError, "lower samples"),
    (lambda m, q: released_curve(m, q, 2, max_memory=float("nan")), isp.InputError, "max_memory must be"),
    (lambda m, q: released_curve(m, q, 2, max_memory="1GB"), TypeError, "max_memory must be a number"),
    (lambda m, q: isp.backlash(m, q, 0, samples=0), isp.InputError, "samples must be at least 100"),
    (lambda m, q: backlash(m, q, 0, samples=2.5e3), TypeError, "samples must be a whole number"),
    (lambda m, q: backlash(m, q, 0, samples=True), TypeError, "samples must be a whole number"),
    (lambda m, q: backlash(m, q, 1.0), TypeError, "leg must be the whole number"),
    (lambda m, q: released_curve(m, q, "0"), TypeError, "leg must be"),
    (lambda m, q: backlash(m, q, 3), isp.InputError, "leg must be 0, 1 or 2"),
    (lambda m, q: backlash(m, q, 0, delta="a"), TypeError, "delta must be numeric"),
    (lambda m, q: backlash(m, q, 0, delta=None), TypeError, "delta must be numeric"),
    (lambda m, q: backlash(m, q, 0, delta=[0.1, 0.2]), isp.InputError, "delta must be a single number"),
    (lambda m, q: backlash(m, q, 0, delta=np.inf), isp.InputError, "delta must be a finite"),
    (lambda m, q: backlash(None, q, 0), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, q: released_curve("m", q, 0), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, q: released_curve(m, "abc", 0), TypeError, "q must be numeric"),
])
def test_bad_input(mq, call, exc, words):
    m, q = mq
    with pytest.raises(exc, match=words):
        call(m, q)


def test_valid_input_still_works(mq):
    m, q = mq
    theta, X = released_curve(m, q, np.int64(2), samples=np.int64(200), max_memory=MAX_MEMORY)
    assert X.shape == (200, 2, 4)
