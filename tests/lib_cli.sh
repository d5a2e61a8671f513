# Helpers for cli_*.sh tests: each check prints "ok" or "FAIL" with its name;
# finish prints "N passed, N failed" and sets the exit status.
PLUMAGE=$(realpath "$1")
SCRATCH=$2
rm -rf "$SCRATCH" && mkdir -p "$SCRATCH" && cd "$SCRATCH" || exit 1
PASSED=0
FAILED=0
pass() { PASSED=$((PASSED + 1)); echo "ok   $1"; }
fail() { FAILED=$((FAILED + 1)); echo "FAIL $1"; }

# expect_ok NAME CMD...: exits 0
expect_ok() { local n=$1; shift; if "$@" >out.txt 2>err.txt; then pass "$n"; else fail "$n (exit $?): $(head -c 400 err.txt)"; fi; }
# expect_fail NAME CMD...: exits non-zero with a message on stderr
expect_fail() {
    local n=$1; shift
    if "$@" >out.txt 2>err.txt </dev/null; then fail "$n (exit 0)";
    elif [ ! -s err.txt ]; then fail "$n (no message on stderr)"; else pass "$n"; fi
}
# expect_output NAME PATTERN CMD...: exits 0 and stdout matches PATTERN (grep -E)
expect_output() {
    local n=$1 p=$2; shift 2
    if "$@" >out.txt 2>err.txt && grep -Eq -- "$p" out.txt; then pass "$n"; else fail "$n: $(head -c 400 out.txt err.txt)"; fi
}
# expect_stderr NAME PATTERN CMD...: exits non-zero and stderr matches PATTERN
expect_stderr() {
    local n=$1 p=$2; shift 2
    if ! "$@" >out.txt 2>err.txt </dev/null && grep -Eq -- "$p" err.txt; then pass "$n"; else fail "$n: $(head -c 400 err.txt)"; fi
}
finish() { echo "$PASSED passed, $FAILED failed"; [ "$FAILED" -eq 0 ]; }
