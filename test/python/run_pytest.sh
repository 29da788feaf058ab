#!/usr/bin/env bash
# Runs pytest (Debian's python3-pytest, Debian's python3) on test files of test/python in the
# workspace's environment. pytest's exit 5 (nothing collected) is a failure too: every file
# given must hold tests that ran.
# Usage: run_pytest.sh DEVEL_SETUP_BASH TEST_FILE... [-- PYTEST_ARGS]
set -eo pipefail
source "${1:?usage: run_pytest.sh DEVEL_SETUP_BASH TEST_FILE...}"
shift
export PYTHONDONTWRITEBYTECODE=1
exec /usr/bin/python3 -m pytest -q -p no:cacheprovider "$@"
