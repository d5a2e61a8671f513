# plumage probe layout end to end: the CSV's shape, reproducibility by seed,
# every layout kind, and bad input named on stderr.
# usage: bash cli_layout.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SPECIES=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}/presets/species

expect_ok "help" "$PLUMAGE" probe layout --help
expect_output "probe lists layout" "layout" "$PLUMAGE" probe --help

pelt() { "$PLUMAGE" probe layout --species "$SPECIES/covert_parrot.json" --count 50 "$@"; }
expect_ok "pelt on a plane" pelt --seed 3
rows=$(($(wc -l <out.txt) - 1))
[ "$rows" -eq 50 ] && pass "50 instances" || fail "expected 50 rows, got $rows"
[ "$(head -1 out.txt | tr ',' '\n' | wc -l)" -eq 24 ] && pass "24 columns" || fail "header: $(head -1 out.txt)"
cp out.txt first.csv
pelt --seed 3 >second.csv 2>/dev/null
cmp -s first.csv second.csv && pass "same seed, same CSV" || fail "same seed gave different CSVs"
pelt --seed 4 >third.csv 2>/dev/null
cmp -s first.csv third.csv && fail "another seed gave the same CSV" || pass "another seed, other instances"
# A pelt has no rows (-1), and its order ranks the feathers along the flow (-y here): order 0 is rooted
# furthest down, and each larger order is rooted no lower (m13, the root's y).
if awk -F, 'NR > 1 { if ($5 != -1) bad = 1; y[$6] = $20; seen[$6] = 1 }
            END { for (k = 0; k < NR - 1; ++k) { if (!seen[k] || (k > 0 && y[k] < y[k - 1])) bad = 1 } exit bad }' \
        first.csv; then
    pass "a pelt's row is -1 and its order follows the flow"
else
    fail "pelt row/order: $(cut -d, -f1-6,20 first.csv | head -5)"
fi
expect_output "pelt on a sphere" "^49," pelt --surface sphere --radius 0.5
expect_output "feather ball (496)" "^495," "$PLUMAGE" probe layout --kind ball --species "$SPECIES/covert_parrot.json"
# A wing lists its under-wing coverts (row 9) first: they lie lowest.
expect_output "wing" "^0,[0-9]*,9,[0-9],9,0," "$PLUMAGE" probe layout --kind wing --row "primary=$SPECIES/remex_pigeon.json" \
    --row "secondary=$SPECIES/remex_pigeon.json" --fold 0.5

expect_stderr "no species" "species" "$PLUMAGE" probe layout --count 5
expect_stderr "bad row name" "ROW=FILE" "$PLUMAGE" probe layout --kind wing --row "wingtip=$SPECIES/remex_pigeon.json"
expect_stderr "wing without secondaries" "secondary" "$PLUMAGE" probe layout --kind wing \
    --row "primary=$SPECIES/remex_pigeon.json"
expect_stderr "fold out of range" "--fold" "$PLUMAGE" probe layout --kind wing --fold 2 \
    --row "primary=$SPECIES/remex_pigeon.json" --row "secondary=$SPECIES/remex_pigeon.json"
# The options take the scene file's layout ranges (one table per block).
expect_stderr "overlap range is the pelt table's" "out of range \\[0, 0.95\\]" pelt --overlap 0.96
expect_stderr "missing surface mesh" "nothing.ply" pelt --surface nothing.ply
expect_stderr "missing species file" "nothing.json" "$PLUMAGE" probe layout --species nothing.json
finish
