#!/usr/bin/env bash
# Checks the pages a newcomer reads, README.md and docs/*.md: every repository path they name
# exists, README.md stays at most 300 lines, and no page cites /tmp or tells the project's own
# development history. A path counts when it is a backticked word (inside a command too) whose
# first component is a top-level entry of the repository, or the target of a relative Markdown
# link; build outputs (build/bin/hilrig) and output files (report.json) are not tree paths and are
# left alone. Fewer references than a floor fails too, so a broken extraction cannot pass.
# Usage: docs_references_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"

readonly max_readme_lines=300
readonly min_readme_references=50
readonly min_references=150

failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# Top-level entries of the tree; a folder holding a CMakeCache.txt is a build tree, not source.
declare -A roots=()
for entry in * .[!.]*; do
  [[ -e $entry && $entry != .git ]] || continue
  [[ -d $entry && -f $entry/CMakeCache.txt ]] && continue
  roots[$entry]=1
done

shopt -s nullglob
pages=(README.md docs/*.md)
shopt -u nullglob
[[ -f README.md ]] || fail "README.md is missing"
[[ -d docs ]] || fail "docs/ is missing"

readme_lines=$(wc -l <README.md)
((readme_lines <= max_readme_lines)) || fail "README.md has $readme_lines lines (at most $max_readme_lines)"

# A word from a code span that names something in the tree: a path under a top-level folder, or
# a top-level file. Placeholders (<scene>, $VAR, ...) are not paths.
is_tree_path() {
  local word=$1 first=${1%%/*}
  [[ -n $first && -n ${roots[$first]:-} ]] || return 1
  [[ $word == */* || $word == *.* ]] || return 1
  [[ $word != *[\<\>\$\{\}=\'\"]* && $word != *...* ]]
}

path_exists() {
  local path=$1
  if [[ $path == *'*'* ]]; then
    compgen -G "$path" >/dev/null
  else
    [[ -e $path ]]
  fi
}

# Checks every word of one piece of code text (a code span, or a line of a code block) that
# names a tree path; counts them in `count`.
check_words() {
  local page=$1 line=$2 word
  local -a words
  read -ra words <<<"$3"  # no globbing: rig/emulated_bus.* stays a pattern
  for word in "${words[@]}"; do
    [[ $word != *...* ]] || continue
    while [[ $word == [\(\[\`]* ]]; do word=${word#?}; done
    while [[ $word == *[,.\;:\)\]\`] ]]; do word=${word%?}; done
    is_tree_path "$word" || continue
    count=$((count + 1))
    path_exists "$word" || fail "$page:$line: $word does not exist"
  done
}

total=0
readme_total=0
for page in "${pages[@]}"; do
  [[ -f $page ]] || continue
  count=0
  # A code span must not cross a line break, or the check below would pair the wrong backticks.
  while IFS= read -r odd; do fail "$page:$odd: a code span crosses a line break"; done < <(
    awk '/^```/ { fenced = !fenced; next } !fenced && gsub(/`/, "`") % 2 { print NR }' "$page")
  # Code spans in the prose and tables.
  while IFS=: read -r line span; do
    check_words "$page" "$line" "$span"
  done < <(grep -no '`[^`]*`' "$page")
  # Code blocks: fenced, or indented by four spaces.
  while IFS=: read -r line text; do
    check_words "$page" "$line" "$text"
  done < <(awk '/^```/ { fenced = !fenced; next } fenced || /^    / { print NR ":" $0 }' "$page")
  # Relative Markdown links, resolved from the page's folder.
  while IFS=: read -r line link; do
    target=${link#](}
    target=${target%)}
    target=${target%%#*}
    [[ -n $target && $target != *://* && $target != mailto:* ]] || continue
    count=$((count + 1))
    [[ -e $(dirname "$page")/$target ]] || fail "$page:$line: link target $target does not exist"
  done < <(grep -no '\]([^)]*)' "$page")
  total=$((total + count))
  [[ $page == README.md ]] && readme_total=$count
done

((readme_total >= min_readme_references)) ||
  fail "found $readme_total path references in README.md; expected at least $min_readme_references"
((total >= min_references)) ||
  fail "found $total path references in README.md and docs/; expected at least $min_references"

# The pages describe the rig, not how it was developed.
if history=$(grep -niE '\bsessions?\b [0-9]|\bsession-[0-9]|this session|last session|/tmp/[a-z]|\bissue [0-9]' "${pages[@]}"); then
  while IFS= read -r hit; do fail "development history or a /tmp path: $hit"; done <<<"$history"
fi

echo "checked $total path references ($readme_total in README.md, $readme_lines lines)"
((failures == 0)) || exit 1
echo "PASS"
