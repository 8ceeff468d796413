# testlib.sh: shared by the shell tests. A scratch folder removed on exit,
# pass/fail bookkeeping, the closing "N passed, N failed" line, and checks
# the tests share.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failures=0
pass() { echo "ok   $1"; passed=$((passed + 1)); }
fail() { echo "FAIL $1"; failures=$((failures + 1)); }
check() { if [ "$2" -eq 0 ]; then pass "$1"; else fail "$1"; fi; }  # check NAME STATUS
finish() { echo "$passed passed, $failures failed"; [ "$failures" -eq 0 ]; }

# bad NAME TEXT -- COMMAND...: the command fails as bad input does, exit 2
# with one line on stderr that contains TEXT.
bad() {
  local name=$1 text=$2
  shift 3
  "$@" >"$work/out" 2>"$work/err"
  local rc=$?
  check "$name: exit 2, one line naming the problem" \
    $([ $rc -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -qF -- "$text" "$work/err"; echo $?)
}

# exr_attr FILE NAME: the string attribute NAME of an EXR's header ("" if none).
exr_attr() {
  python3 - "$1" "$2" <<'PY'
import re, sys
head = open(sys.argv[1], 'rb').read(1 << 16)
m = re.search(re.escape(sys.argv[2].encode()) + rb'\x00string\x00(....)', head, re.S)  # the length's bytes may be a newline
n = int.from_bytes(m.group(1), 'little') if m else 0
print(head[m.end():m.end() + n].decode() if m else '')
PY
}
