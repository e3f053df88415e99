#!/usr/bin/env bash
# ctest's test_python: the package's pytest tests with the project's .venv,
# against the command line just built. Skipped (77) when the package is not
# built there (./setup.sh python builds it; ./test.sh always does).
#   run.sh SOURCE_DIR PATH/TO/relief DATA_DIR
set -u
src=$1 cli=$2 data=$3
py=$src/.venv/bin/python
if ! "$py" -c "import relief" 2>/dev/null; then
  echo "$py cannot import relief: run ./setup.sh python; skipped"
  exit 77
fi
cd "$src" && RELIEF=$cli DATA=$data exec "$py" -m pytest -q -p no:cacheprovider tests/python
