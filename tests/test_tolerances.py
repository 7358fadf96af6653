"""The deprecated fields of :class:`imagespace.Tolerances` (issue [15]): kept so existing code still
constructs, documented as having no effect, a warning when set, and read by no computation."""

import dataclasses
import warnings
from pathlib import Path

import pytest

from imagespace.tolerances import DEPRECATED, TOLERANCES, Tolerances

ROOT = Path(__file__).resolve().parents[1] / "imagespace"


@pytest.mark.parametrize("name", sorted(DEPRECATED))
def test_setting_a_deprecated_tolerance_warns(name):
    with pytest.warns(FutureWarning, match=f"Tolerances.{name} is deprecated and has no effect"):
        tol = Tolerances(**{name: 0.5})
    assert getattr(tol, name) == 0.5                       # still accepted
    assert "no effect" in Tolerances.__doc__.split(f"{name} : float", 1)[1].split(" : ", 1)[0]


def test_defaults_and_other_fields_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Tolerances()
        dataclasses.replace(TOLERANCES, joint_residual=1e-6, kernel_residual=1e-8)


def test_no_computation_reads_a_deprecated_tolerance():
    allowed = {"tolerances.py"}
    readers = sorted(p.relative_to(ROOT).as_posix() for p in ROOT.rglob("*.py")
                     if p.relative_to(ROOT).as_posix() not in allowed
                     and any(name in p.read_text() for name in DEPRECATED))
    assert readers == []
