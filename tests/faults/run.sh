#!/usr/bin/env bash
# Fault injection: shows that the suites catch what they claim to. Each fault of
# tests/faults/faults.txt (a flipped sign, a dropped term, a mis-lumped link, a wrongly printed
# expression) is applied, one at a time, to a copy of the committed tree; sweepgen_tests is
# rebuilt and the fault's suites run; a fault is caught when at least one of their tests fails.
# A filter `ctest:TARGET:REGEX` rebuilds TARGET instead and runs the ctest tests matching REGEX
# (tests that are scripts, such as the trajectory-optimisation example's).
# Prints one line per fault with the failing suites and exits 1 if any fault went uncaught or a
# sed expression no longer matches its file (the fault list must follow the code).
#   bash tests/faults/run.sh [NAME...]      # all faults, or the named ones; ~3-5 min per fault on 2 cores
set -uo pipefail
source_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=${SWEEPGEN_FAULT_DIR:-/tmp/sweepgen-faults}
mkdir -p "$work"
rm -rf "$work/tree" && mkdir -p "$work/tree"
git -C "$source_dir" archive HEAD | tar -x -C "$work/tree"
cmake -S "$work/tree" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
      -DSWEEPGEN_BUILD_BENCHMARKS=OFF > "$work/configure.log" || { echo "configure failed: $work/configure.log"; exit 2; }
status=0
while IFS='|' read -r name file expression filter; do
  name=$(echo "$name" | xargs); file=$(echo "$file" | xargs); filter=$(echo "$filter" | xargs)
  expression=$(echo "$expression" | sed 's/^ *//; s/ *$//')
  [[ -z "$name" || "$name" == \#* ]] && continue
  if [ $# -gt 0 ] && [[ ! " $* " == *" $name "* ]]; then continue; fi
  target="$work/tree/$file"
  cp "$target" "$work/original"
  sed -i "$expression" "$target"
  if cmp -s "$target" "$work/original"; then
    echo "FAULT $name: the expression no longer matches $file"; status=1; continue
  fi
  build_target=sweepgen_tests
  if [[ "$filter" == ctest:* ]]; then IFS=: read -r _ build_target test_regex <<< "$filter"; fi
  if ! cmake --build "$work/build" --target "$build_target" > "$work/$name.build.log" 2>&1; then
    echo "FAULT $name: caught at build time ($work/$name.build.log)"
  elif [ "$build_target" != sweepgen_tests ]; then
    (cd "$work/build" && timeout 900 ctest -R "$test_regex" --output-on-failure) < /dev/null > "$work/$name.log" 2>&1
    failed=$(grep -E 'Test +#[0-9]+: .*\*\*\*(Failed|Timeout)' "$work/$name.log" | sed -E 's/.*Test +#[0-9]+: ([^ ]+).*/\1/' | tr '\n' ' ')
    ran=$(grep -cE 'Test +#[0-9]+: ' "$work/$name.log")
    if [ -n "$failed" ]; then
      echo "FAULT $name: caught by $failed"
    else
      echo "FAULT $name: NOT CAUGHT by the $ran ctest tests matching $test_regex ($work/$name.log)"; status=1
    fi
  else
    # A fault can make a test run away (a generator printing a graph as a tree): 15 minutes, then
    # the suite is stopped and the fault counted caught by its time-out (a generator that never
    # finishes fails the build or the test that runs it).
    timeout 900 "$work/build/tests/sweepgen_tests" --gtest_filter="$filter" > "$work/$name.log" 2>&1
    timed_out=$?
    failed=$(grep -E '^\[  FAILED  \] [A-Za-z]' "$work/$name.log" | grep -v ' tests\?, listed below' |
             sed -E 's/^\[  FAILED  \] ([^.]*\.[^/ ,(]*).*/\1/' | sort -u | tr '\n' ' ')
    if [ "$timed_out" -eq 124 ]; then failed+="(stopped after 900 s in $(grep '^\[ RUN' "$work/$name.log" | tail -1 | cut -c14-))"; fi
    if [ -n "$failed" ]; then
      echo "FAULT $name: caught by $failed"
    else
      echo "FAULT $name: NOT CAUGHT by $filter ($work/$name.log)"; status=1
    fi
  fi
  cp "$work/original" "$target"
done < "$source_dir/tests/faults/faults.txt"
exit $status
