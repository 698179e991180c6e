#!/usr/bin/env bash
# The suite in a new venv with the oldest or the newest supported versions
# (docs/testing.md, "Supported versions"):
#   bash tests/venv_run.sh minimum [PYTEST ARGS...]   # pins of tests/minimum-versions.txt
#   bash tests/venv_run.sh newest  [PYTEST ARGS...]   # the newest the registry serves
# The venv is made in a temporary folder and removed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
which=${1:?usage: tests/venv_run.sh minimum|newest [pytest args]}
shift
venv=$(mktemp -d "${TMPDIR:-/tmp}/kinetostatics-$which.XXXXXX")
trap 'rm -rf "$venv"' EXIT
"${PYTHON:-python3}" -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --upgrade pip
case "$which" in
    minimum) "$venv/bin/python" -m pip install --quiet -e '.[test]' -c tests/minimum-versions.txt ;;
    newest) "$venv/bin/python" -m pip install --quiet --upgrade --upgrade-strategy eager -e '.[test]' ;;
    *) echo "tests/venv_run.sh: minimum or newest, not '$which'" >&2; exit 2 ;;
esac
"$venv/bin/python" -m pip list --format freeze | grep -iE '^(numpy|scipy|matplotlib|pyyaml|pandas|numba|hypothesis|pytest)=='
"$venv/bin/python" -m pytest "$@"
