#!/usr/bin/env bash
# Builds the libFuzzer targets of test/fuzz with clang (address and undefined-behaviour
# sanitizers) into BUILD_DIR and runs each for RUNS inputs from its seed corpus. Exits 77 (CTest:
# skipped) when clang++ or libFuzzer is not installed.
# Usage: test/fuzz/run_fuzzers.sh SOURCE_DIR BUILD_DIR [RUNS]   e.g. RUNS=10000000 for a long run
set -euo pipefail
source_dir=${1:?usage: run_fuzzers.sh SOURCE_DIR BUILD_DIR [RUNS]}
build_dir=${2:?usage: run_fuzzers.sh SOURCE_DIR BUILD_DIR [RUNS]}
runs=${3:-200000}
compiler=$(command -v clang++ || command -v clang++-14 || true)
if [[ -z "$compiler" ]]; then
  echo "run_fuzzers: clang++ not installed; skipped" >&2
  exit 77
fi
mkdir -p "$build_dir"
flags=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
       -I"$source_dir/include")
fuzzer="$build_dir/java_properties_fuzzer"
if ! "$compiler" "${flags[@]}" "$source_dir/src/scene/catalogs/java_properties.cpp" \
     "$source_dir/test/fuzz/java_properties_fuzzer.cpp" -o "$fuzzer" 2> "$build_dir/build.log"; then
  if grep -q "fuzzer" "$build_dir/build.log"; then
    echo "run_fuzzers: libFuzzer is not available to $compiler; skipped" >&2
    cat "$build_dir/build.log" >&2
    exit 77
  fi
  cat "$build_dir/build.log" >&2
  exit 1
fi
# A scratch copy of the seed corpus: the fuzzer adds the inputs it finds interesting.
corpus="$build_dir/corpus_java_properties"
rm -rf "$corpus" && mkdir -p "$corpus"
cp "$source_dir"/test/fuzz/corpus/java_properties/* "$corpus"/
"$fuzzer" -runs="$runs" -max_len=4096 -seed=1 -print_final_stats=1 "$corpus"
