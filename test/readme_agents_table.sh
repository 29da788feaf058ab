#!/usr/bin/env bash
# The README's table of agents is the agent registry's: fails when they differ.
# Usage: readme_agents_table.sh OCCLUSION_AGENTS README
set -euo pipefail
tool=${1:?usage: readme_agents_table.sh OCCLUSION_AGENTS README}
readme=${2:?usage: readme_agents_table.sh OCCLUSION_AGENTS README}
expected=$("$tool" --agents-markdown)
actual=$(sed -n '/<!-- agents-table begin -->/,/<!-- agents-table end -->/p' "$readme" | sed '1d;$d')
if [[ "$expected" != "$actual" ]]; then
  echo "readme_agents_table: the README's table differs from the registry; replace it with:"
  echo "$expected"
  diff <(echo "$actual") <(echo "$expected") || true
  exit 1
fi
echo "readme_agents_table: the README lists the registry's $(($(echo "$expected" | wc -l) - 2)) agents"
