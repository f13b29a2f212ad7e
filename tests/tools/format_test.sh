#!/usr/bin/env bash
# Checks that every C++ source and header of the repository is formatted as its .clang-format
# says (Google base, 100 columns): a file clang-format would change fails, with the first lines
# of the change. Every file, not only those a change touched: the tree is formatted, so this costs
# a few seconds and a file cannot slip through on an unusual change. A sample that is not
# formatted must be flagged too, so a clang-format that checks nothing cannot pass. Skips (77)
# without clang-format (scripts/setup test installs it).
# Usage: format_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"

readonly min_files=400

if ! command -v clang-format >/dev/null; then
  echo "SKIP: clang-format not found (install clang-format, or run scripts/setup test)"
  exit 77
fi
clang-format --version

if printf 'int  main( ){return 0;}\n' |
  clang-format --dry-run --Werror --assume-filename=sample.cc >/dev/null 2>&1; then
  echo "FAIL: clang-format accepted a sample that is not formatted"
  exit 1
fi

# Build trees (a folder holding a CMakeCache.txt) and generated code are not the repository's.
files=()
while IFS= read -r -d '' file; do
  files+=("$file")
done < <(find . \( -name .git -o -exec test -f '{}/CMakeCache.txt' \; \) -prune -o \
  -type f \( -name '*.cc' -o -name '*.h' \) -print0 | sort -z)

if ((${#files[@]} < min_files)); then
  echo "FAIL: found ${#files[@]} C++ files, expected at least $min_files"
  exit 1
fi

# One clang-format for every file (one per file takes ten times as long); it names each file it
# would change in "FILE:LINE:COLUMN: error: code should be clang-formatted" lines.
failing=()
if ! report=$(clang-format --dry-run --Werror "${files[@]}" 2>&1); then
  mapfile -t failing < <(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be.*/\1/p' <<<"$report" |
    sort -u)
  if ((${#failing[@]} == 0)); then
    echo "FAIL: clang-format failed without naming a file:"
    echo "$report" | head -20
    exit 1
  fi
fi
for file in "${failing[@]}"; do
  echo "FAIL: $file is not formatted (clang-format -i $file); the change:"
  diff "$file" <(clang-format "$file") | head -20 || true
done
echo "checked ${#files[@]} files"
if ((${#failing[@]} > 0)); then
  echo "FAIL: ${#failing[@]} files not formatted"
  exit 1
fi
echo PASS
