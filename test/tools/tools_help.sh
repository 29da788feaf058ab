#!/usr/bin/env bash
# Every command-line tool answers --help with exit code 0 and a malformed command line with exit
# code 2, and its --help lists every flag that the docs, scripts and launch files use with it.
# Usage: tools_help.sh BIN_DIR SOURCE_DIR
set -euo pipefail
bin=${1:?usage: tools_help.sh BIN_DIR SOURCE_DIR}
source_dir=${2:?usage: tools_help.sh BIN_DIR SOURCE_DIR}
tools=(occlusion_render occlusion_soak occlusion_agents occlusion_lod_report occlusion_oracle
       occlusion_eval occlusion_dataset occlusion_train occlusion_dagger
       occlusion_bridge_calibration occlusion_train_ppo)

# The flags written after TOOL's name in the docs, scripts and launch files ("-(-)" in launch
# comments is "--"; a trailing backslash continues a command).
documented_flags() {
  /usr/bin/python3 - "$1" "$source_dir" <<'PY'
import pathlib, re, sys
tool, root = sys.argv[1], pathlib.Path(sys.argv[2])
files = [root / "README.md"] + [p for d in ("doc", "scripts", "launch", "test", "config")
                                 for p in sorted((root / d).rglob("*")) if p.is_file()]
flags = set()
for path in files:
    if path.suffix not in (".md", ".sh", ".py", ".launch", ".yaml", ".txt"):
        continue
    text = path.read_text(errors="replace").replace("-(-)", "--").replace("\\\n", " ")
    for match in re.finditer(r"\b" + tool + r"\b(?!\.)", text):
        segment = re.split(r"[`|;\n]|&&|\bocclusion_\w+", text[match.end():], maxsplit=1)[0]
        flags.update(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", segment))
print("\n".join(sorted(flags)))
PY
}

status=0
for tool in "${tools[@]}"; do
  if ! help=$("$bin/$tool" --help 2>&1); then
    echo "tools_help: $tool --help failed"; status=1; continue
  fi
  count=0
  for flag in $(documented_flags "$tool"); do
    count=$((count + 1))
    grep -qE "(^|[ ,])$flag([ ,=]|$)" <<<"$help" || { echo "tools_help: $tool --help lacks $flag"; status=1; }
  done
  code=0
  "$bin/$tool" --no-such-flag >/dev/null 2>&1 || code=$?
  [[ $code == 2 ]] || { echo "tools_help: $tool --no-such-flag gave exit code $code, not 2"; status=1; }
  echo "tools_help: $tool: --help lists its $count documented flags; a bad flag gives exit code 2"
done
# Flags that only occlusion_train --check reads are refused without it, not silently ignored.
for flag in "--probabilities 0.3" "--versus /nonexistent" "--montage /nonexistent.png"; do
  code=0
  # shellcheck disable=SC2086 # the flag and its value, two words
  said=$("$bin/occlusion_train" --data /nonexistent --out /nonexistent $flag 2>&1) || code=$?
  if [[ $code != 2 || $said != *"${flag%% *} needs --check"* ]]; then
    echo "tools_help: occlusion_train $flag without --check gave exit code $code: $said"; status=1
  fi
done
echo "tools_help: occlusion_train refuses --probabilities, --versus and --montage without --check"
exit $status
