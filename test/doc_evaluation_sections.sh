#!/usr/bin/env bash
# EVALUATION.md ends with the sections scripts/evaluate.sh appends to the report it writes
# (doc/robustness/*.md.in, each after an empty line), so that regenerating the report keeps what
# the page says: a figure added to EVALUATION.md alone would be lost. Fails naming the first
# differing line.
# Usage: doc_evaluation_sections.sh SOURCE_DIR
set -euo pipefail
root=${1:?usage: doc_evaluation_sections.sh SOURCE_DIR}
expected=$(mktemp)
trap 'rm -f "$expected"' EXIT
for section in "$root"/doc/robustness/*.md.in; do
  [[ -f "$section" ]] || continue
  { echo; cat "$section"; } >> "$expected"
done
lines=$(wc -l < "$expected")
if ! diff <(tail -n "$lines" "$root/EVALUATION.md") "$expected" > /dev/null; then
  echo "EVALUATION.md does not end with doc/robustness/*.md.in (scripts/evaluate.sh appends them);" \
       "edit both alike. First differences (< EVALUATION.md, > the sections):" >&2
  diff <(tail -n "$lines" "$root/EVALUATION.md") "$expected" | head -20 >&2
  exit 1
fi
echo "EVALUATION.md ends with the $(ls "$root"/doc/robustness/*.md.in | wc -l) section(s) of doc/robustness/"
