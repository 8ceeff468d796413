# testlib.sh: shared by the shell tests. A scratch folder removed on exit,
# pass/fail bookkeeping, and the closing "N passed, N failed" line.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failures=0
pass() { echo "ok   $1"; passed=$((passed + 1)); }
fail() { echo "FAIL $1"; failures=$((failures + 1)); }
check() { if [ "$2" -eq 0 ]; then pass "$1"; else fail "$1"; fi; }  # check NAME STATUS
finish() { echo "$passed passed, $failures failed"; [ "$failures" -eq 0 ]; }
