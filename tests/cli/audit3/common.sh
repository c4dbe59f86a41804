# What every section of the third audit's script shares: counters, checks, fixtures.
# Sourced by hostile_audit_round_three_test.sh, in a fresh temporary directory, with $kincal set.
passed=0
failed=0
# The public datasets (never committed): ../shared/datasets beside the source tree.
datasets=${KINCAL_DATASETS:-$here/../../../shared/datasets}

ok() { passed=$((passed + 1)); }
bad() {
  failed=$((failed + 1))
  echo "FAILED: $*"
}
# check DESCRIPTION EXPECTED_EXIT ACTUAL_EXIT [STDERR_FILE PATTERN]: the exit code, and that
# the pattern (grep -E) is in the file; an exit 2 must be one line.
check() {
  local what=$1 want=$2 got=$3
  if [ "$got" != "$want" ]; then
    bad "$what: exit $got, expected $want${4:+ (stderr: $(head -c 400 "$4"))}"
    return
  fi
  if [ $# -ge 5 ] && ! grep -Eq -- "$5" "$4"; then
    bad "$what: '$4' lacks '$5': $(head -c 400 "$4")"
    return
  fi
  if [ $# -ge 4 ] && [ "$want" = 2 ] && [ "$(wc -l <"$4")" -ne 1 ]; then
    bad "$what: expected one line on stderr, got: $(head -c 400 "$4")"
    return
  fi
  ok
}
# has FILE PATTERN DESCRIPTION / lacks FILE PATTERN DESCRIPTION (grep -E)
has() { if grep -Eq -- "$2" "$1"; then ok; else bad "$3: '$1' lacks '$2': $(head -c 400 "$1")"; fi; }
lacks() { if grep -Eq -- "$2" "$1"; then bad "$3: '$1' has '$2'"; else ok; fi; }
# same FILE HASH DESCRIPTION: the file still has the content it had
hash() { sha256sum <"$1"; }
same() { if [ "$(hash "$1")" != "$2" ]; then bad "$3: $1 was replaced"; else ok; fi; }
no_temporaries() {
  if ls -A | grep -q 'kincal-tmp'; then bad "$1: temporary files left: $(ls -A | grep kincal-tmp)"; else ok; fi
}
# py: Debian's Python (numpy, the module's build) with the module built beside this kincal.
py() { PYTHONPATH="$KINCAL_AUDIT_PYTHONPATH${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 "$@"; }
