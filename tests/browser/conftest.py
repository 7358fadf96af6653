"""Fixtures of the browser tests (the harness: browser_harness.py)."""

import pytest

from browser_harness import ARTIFACTS, Timings


@pytest.fixture(scope="session")
def artifacts():
    base = ARTIFACTS / "browser"
    base.mkdir(parents=True, exist_ok=True)
    print(f"\nbrowser screenshots and timings: {base}")
    return base


@pytest.fixture(scope="session")
def timings(artifacts):
    path = artifacts / "timings.json"
    if path.exists():
        path.unlink()
    return Timings(path)
