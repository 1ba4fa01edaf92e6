#!/usr/bin/env bash
# Builds examples/library (a program of a user's own, find_package(carom)) against a copy of carom
# installed from a build dir, checks that the installed package hands -ffp-contract=off to the
# consumer, and runs the program on the reference cases: its csv must equal the expected files
# byte for byte; then builds every C++ block of docs/library.md the same way and runs the first.
#
#   library_example_test.sh SOURCE_DIR BUILD_DIR SCRATCH_DIR
#
# BUILD_DIR must be fully built (cmake --install copies what is there). SCRATCH_DIR is emptied.
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: $0 SOURCE_DIR BUILD_DIR SCRATCH_DIR" >&2
  exit 2
fi
source_dir=$(cd "$1" && pwd)
build_dir=$(cd "$2" && pwd)
scratch=$3

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

rm -rf "$scratch"
mkdir -p "$scratch"
scratch=$(cd "$scratch" && pwd)
prefix=$scratch/prefix
consumer=$scratch/consumer

# The consumer is built as the library was: same compiler, build type and flags (a sanitizer
# build's library needs the sanitizer at link time too).
cache_value() {
  sed -n "s/^$1:[A-Z]*=//p" "$build_dir/CMakeCache.txt" | head -n 1
}
compiler=$(cache_value CMAKE_CXX_COMPILER)
build_type=$(cache_value CMAKE_BUILD_TYPE)
cxx_flags=$(cache_value CMAKE_CXX_FLAGS)
linker_flags=$(cache_value CMAKE_EXE_LINKER_FLAGS)

echo "== cmake --install $build_dir --prefix $prefix"
cmake --install "$build_dir" --prefix "$prefix" > "$scratch/install.log" 2>&1 ||
  { cat "$scratch/install.log"; fail "cmake --install"; }

# What a consumer needs is installed; what it must not see is not.
for f in include/carom/engine/simulation.hpp include/carom/io/classic_input.hpp include/carom/io/classic_output.hpp \
         include/carom/version.hpp; do
  [[ -f $prefix/$f ]] || fail "$f not installed"
done
[[ ! -e $prefix/include/carom/viewer_html.hpp ]] || fail "viewer_html.hpp (private) installed"
[[ ! -e $prefix/include/carom/version.hpp.in ]] || fail "version.hpp.in installed"
[[ -x $prefix/bin/carom ]] || fail "bin/carom not installed"
targets=$(find "$prefix" -name caromTargets.cmake)
[[ -n $targets ]] || fail "no caromTargets.cmake installed"
config_dir=$(dirname "$targets")
[[ -f $config_dir/caromConfig.cmake && -f $config_dir/caromConfigVersion.cmake ]] ||
  fail "no caromConfig.cmake or caromConfigVersion.cmake beside $targets"
grep -q 'INTERFACE_COMPILE_OPTIONS.*-ffp-contract=off' "$targets" ||
  fail "the exported carom::carom does not carry -ffp-contract=off ($targets)"

echo "== configure and build examples/library against $prefix"
cmake -S "$source_dir/examples/library" -B "$consumer" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_CXX_COMPILER="$compiler" -DCMAKE_BUILD_TYPE="${build_type:-Release}" \
  -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXE_LINKER_FLAGS="$linker_flags" \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > "$scratch/configure.log" 2>&1 ||
  { cat "$scratch/configure.log"; fail "configuring examples/library"; }
cmake --build "$consumer" > "$scratch/build.log" 2>&1 ||
  { cat "$scratch/build.log"; fail "building examples/library"; }

# It found the installed copy, and compiled against it only: not the source tree's headers.
carom_dir=$(sed -n 's/^carom_DIR:[A-Z]*=//p' "$consumer/CMakeCache.txt")
[[ $carom_dir == "$prefix"/* ]] || fail "find_package(carom) found $carom_dir, not the copy in $prefix"
command=$(grep '"command"' "$consumer/compile_commands.json" | grep 'final_state\.cpp' || true)
[[ -n $command ]] || fail "no compile command for final_state.cpp in compile_commands.json"
[[ $command == *-ffp-contract=off* ]] ||
  fail "the consumer's compile command lacks -ffp-contract=off: $command"
[[ $command == *"$prefix/include"* ]] || fail "the consumer does not use $prefix/include: $command"
[[ $command != *"$source_dir/include"* && $command != *"$build_dir/generated"* ]] ||
  fail "the consumer compiles against carom's source or build tree: $command"

program=$consumer/final_state
cases=$source_dir/tests/data/cases
passed=0
failed=0
run_case() {  # INPUT END_TIME EXPECTED
  local out=$scratch/$(basename "$1" .txt).T$2.csv
  if ! "$program" "$cases/$1" "$2" > "$out"; then
    echo "FAIL: final_state $1 $2 exited with $?" >&2
    failed=$((failed + 1))
  elif ! diff -u "$cases/$3" "$out"; then
    echo "FAIL: final_state $1 $2 differs from $3 (diff above: - expected, + got)" >&2
    failed=$((failed + 1))
  else
    echo "ok: final_state $1 $2 = $3"
    passed=$((passed + 1))
  fi
}
run_case normal.txt 20 normal.T20.csv
run_case normal.txt 100 normal.T100.csv
run_case particles1.txt 15 particles1.T15.csv
run_case particles1.txt 100 particles1.T100.csv

# Bad arguments and input: exit code 2 and a message.
expect_usage_error() {  # what ARGS...
  local what=$1
  shift
  local status=0
  "$program" "$@" > /dev/null 2> "$scratch/stderr" || status=$?
  if [[ $status -eq 2 && -s $scratch/stderr ]]; then
    echo "ok: $what: exit 2, $(head -n 1 "$scratch/stderr")"
    passed=$((passed + 1))
  else
    echo "FAIL: $what: exit $status (want 2), stderr: $(cat "$scratch/stderr")" >&2
    failed=$((failed + 1))
  fi
}
expect_usage_error "no arguments"
expect_usage_error "a missing file" "$scratch/no such file.txt" 20
expect_usage_error "an END_TIME that is not a number" "$cases/normal.txt" twenty
expect_usage_error "a negative END_TIME" "$cases/normal.txt" -1
printf '2\n1\n10 10\n5 5 1 0\n5.5 5 0 1\n' > "$scratch/overlap.txt"
expect_usage_error "overlapping disks" "$scratch/overlap.txt" 20

# Every C++ block of docs/library.md, as written: each is a program of its own, built against the
# installed copy; the first (The library) must give carom run's final state, and its frames.
readme=$scratch/readme
mkdir -p "$readme"
awk -v dir="$readme" '
  /^```cpp$/ { n++; file = sprintf("%s/example_%d.cpp", dir, n); inside = 1; next }
  /^```/ { inside = 0 }
  inside { print > file }
' "$source_dir/docs/library.md"
blocks=$(find "$readme" -name 'example_*.cpp' | sort)
if [[ -z $blocks ]]; then
  echo "FAIL: no C++ block in docs/library.md" >&2
  failed=$((failed + 1))
fi
{
  echo 'cmake_minimum_required(VERSION 3.25)'
  echo 'project(carom_readme_examples LANGUAGES CXX)'
  echo 'find_package(carom 1 REQUIRED)'
  for block in $blocks; do
    name=$(basename "$block" .cpp)
    echo "add_executable($name $name.cpp)"
    echo "target_link_libraries($name PRIVATE carom::carom)"
  done
} > "$readme/CMakeLists.txt"
if cmake -S "$readme" -B "$readme/build" -DCMAKE_PREFIX_PATH="$prefix" \
     -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_CXX_COMPILER="$compiler" \
     -DCMAKE_BUILD_TYPE="${build_type:-Release}" -DCMAKE_CXX_FLAGS="$cxx_flags" \
     -DCMAKE_EXE_LINKER_FLAGS="$linker_flags" > "$readme/configure.log" 2>&1 &&
   cmake --build "$readme/build" > "$readme/build.log" 2>&1; then
  echo "ok: docs/library.md's $(echo "$blocks" | wc -l) C++ block(s) compile against the installed copy"
  passed=$((passed + 1))
else
  cat "$readme/configure.log" "$readme/build.log" >&2
  echo "FAIL: a C++ block of docs/library.md does not build as written (log above)" >&2
  failed=$((failed + 1))
fi
(
  cd "$scratch"
  "$prefix/bin/carom" init --n 200 --phi 0.4 --boundary periodic -o gas.txt
  "$readme/build/example_1" > measured.txt || true
  "$prefix/bin/carom" run gas.txt 100 --rule elastic --boundary periodic --format csv -q > run.csv
)
if tail -n +2 "$scratch/measured.txt" | diff -q - "$scratch/run.csv" > /dev/null &&
   [[ $(grep -c '^200$' "$scratch/movie.xyz") -eq 201 ]] &&
   head -n 1 "$scratch/measured.txt" | grep -q '^Z = '; then
  echo "ok: docs/library.md's example = carom run, 201 frames"
  passed=$((passed + 1))
else
  echo "FAIL: docs/library.md's example differs from carom run, or its frames are not t = 0, 0.5, ..., 100" >&2
  failed=$((failed + 1))
fi

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
