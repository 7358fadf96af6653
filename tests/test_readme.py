"""Every Python code block of README.md runs, in order, in one namespace (as a reader pastes them
into one notebook), in a scratch folder (the blocks write files)."""

import os
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def python_blocks(text):
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_readme_has_python_blocks():
    blocks = python_blocks(README.read_text())
    assert len(blocks) >= 3 and all(b.strip() for b in blocks)


@pytest.mark.slow
def test_every_readme_python_block_runs(tmp_path, monkeypatch):
    pytest.importorskip("ipywidgets")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__readme__"}
    for k, block in enumerate(python_blocks(README.read_text())):
        code = compile(block, f"README.md python block {k + 1}", "exec")
        exec(code, namespace)                       # noqa: S102  (the README's own code)
    # what the blocks promise
    assert len(namespace["modes"]) == 6
    assert namespace["res"].count == 40 and namespace["res"].certified
    assert namespace["batch"].counts.shape == (200,)
    assert os.path.exists("explorer.html")
