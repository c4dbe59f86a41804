#!/usr/bin/env bash
# The third hostile audit's cases (issue 35), kept as a regression script: each case runs the
# real kincal binary (or the Python module) the way the audit did and checks the exit code, the
# one-line message, the verdict and that no file was replaced or left behind. One section per
# surface, in audit3/<section>.sh, each a ctest of its own (tests/CMakeLists.txt).
# Prints "N passed, N failed"; exit 1 on a failure.
# Usage: hostile_audit_round_three_test.sh KINCAL SECTION [PYTHONPATH_OF_THE_MODULE]
set -uo pipefail
kincal=$1
[[ $kincal == /* ]] || kincal=$PWD/$kincal  # the cases run in a temporary directory
section=$2
export KINCAL_AUDIT_PYTHONPATH=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
# shellcheck source=tests/cli/audit3/common.sh
source "$here/audit3/common.sh"
# shellcheck disable=SC1090
source "$here/audit3/$section.sh"
echo "$section: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
