# The plumage command's front door: help, unknown commands and options.
# usage: bash cli_basic.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

expect_ok "top-level help" "$PLUMAGE" --help
expect_output "help lists probe" "probe" "$PLUMAGE" --help
expect_fail "no command" "$PLUMAGE"
expect_fail "unknown command" "$PLUMAGE" frobnicate
expect_stderr "unknown command is named" "frobnicate" "$PLUMAGE" frobnicate
expect_ok "probe help" "$PLUMAGE" probe --help
expect_fail "unknown probe" "$PLUMAGE" probe nothing
finish
