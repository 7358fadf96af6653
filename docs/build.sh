#!/bin/sh
# Build the documentation site into docs/_build/html (warnings are errors).
# Needs the docs extra: python -m pip install -e ".[docs]"
# IMAGESPACE_DOCS_EXECUTE=off skips executing the notebooks (quick check of the other pages).
set -eu
cd "$(dirname "$0")/.."
exec python -m sphinx -W --keep-going -b html docs "${1:-docs/_build/html}"
