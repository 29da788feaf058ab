#!/usr/bin/env bash
# The table of agents in doc/AGENTS.md is the agent registry's: fails when they differ.
# Usage: doc_agents_table.sh OCCLUSION_AGENTS AGENTS_MD
set -euo pipefail
tool=${1:?usage: doc_agents_table.sh OCCLUSION_AGENTS AGENTS_MD}
page=${2:?usage: doc_agents_table.sh OCCLUSION_AGENTS AGENTS_MD}
expected=$("$tool" --agents-markdown)
actual=$(sed -n '/<!-- agents-table begin -->/,/<!-- agents-table end -->/p' "$page" | sed '1d;$d')
if [[ "$expected" != "$actual" ]]; then
  echo "doc_agents_table: the table in $page differs from the registry; replace it with:"
  echo "$expected"
  diff <(echo "$actual") <(echo "$expected") || true
  exit 1
fi
echo "doc_agents_table: $page lists the registry's $(($(echo "$expected" | wc -l) - 2)) agents"
