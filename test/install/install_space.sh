#!/usr/bin/env bash
# The package from its install space alone (doc/INSTALL.md): this build's install rules, the
# ones `catkin_make install` runs, write the install space into a temporary folder (DESTDIR,
# then moved: the install space must not depend on where it lies); then, in a private mount
# namespace where the source tree, the build and the devel space are empty folders, with a
# clean environment and only the install space's setup.bash sourced, run_installed.sh runs the
# learned agent, an evaluation with its plot and demo.launch.
# Usage: install_space.sh BUILD_DIR SOURCE_DIR DEVEL_PREFIX
# Exits 77 (skipped) where no mount namespace can be made (not root, or a container without
# CAP_SYS_ADMIN): the source tree could not be hidden.
set -euo pipefail
build_dir=${1:?usage: install_space.sh BUILD_DIR SOURCE_DIR DEVEL_PREFIX}
source_dir=$(realpath "${2:?}")
devel_prefix=$(realpath "${3:?}")
build_dir=$(realpath "$build_dir")

if ! unshare -m true 2>/dev/null; then
  echo "install_space: cannot make a mount namespace (unshare -m) to hide the source tree; skipped"
  exit 77
fi

tmp=$(mktemp -d /tmp/occlusion_env_install.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build_dir/CMakeCache.txt")
start=$(date +%s%N)
DESTDIR=$tmp/destdir cmake --install "$build_dir" > "$tmp/install.log"
mv "$tmp/destdir$prefix" "$tmp/install"
rm -rf "$tmp/destdir"
echo "install_space: installed $(find "$tmp/install" -type f | wc -l) files" \
  "($(du -sh "$tmp/install" | cut -f1)) in $((($(date +%s%N) - start) / 1000000)) ms"

# Hidden: the source tree, the build folder and the devel space (each that is not inside one
# already hidden).
cp "$(dirname "$0")/run_installed.sh" "$tmp/run_installed.sh"
status=0
unshare -m env -i PATH=/usr/bin:/bin HOME="$tmp/home" LANG=C.UTF-8 \
  bash "$tmp/run_installed.sh" "$tmp/install" "$tmp/work" "$source_dir" "$build_dir" \
  "$devel_prefix" || status=$?
exit $status
