#include "rig/command_args.h"

#include <algorithm>
#include <numeric>

namespace hilrig::rig {
namespace {

// Levenshtein distance: insertions, deletions and substitutions.
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string DidYouMean(const std::string& word, const std::set<std::string>& candidates) {
  constexpr std::size_t kMaxEdits = 2;
  const std::string* best = nullptr;
  std::size_t best_distance = kMaxEdits + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = EditDistance(word, candidate);
    if (distance < best_distance) {
      best = &candidate;
      best_distance = distance;
    }
  }
  return best == nullptr ? "" : " (did you mean " + *best + "?)";
}

const std::string* CliArgs::Option(const std::string& name) const {
  const auto found = options.find(name);
  return found == options.end() ? nullptr : &found->second;
}

Result<CliArgs> ParseCliArgs(const std::vector<std::string>& args,
                             const std::set<std::string>& allowed_options,
                             const std::set<std::string>& flags) {
  CliArgs parsed;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (!arg.starts_with("--")) {
      parsed.positional.push_back(arg);
      continue;
    }
    if (!allowed_options.contains(arg)) {
      std::set<std::string> known = allowed_options;
      known.insert(flags.begin(), flags.end());
      return MakeError("unknown option " + arg + DidYouMean(arg, known));
    }
    if (i + 1 >= args.size()) return MakeError(arg + " needs a value");
    parsed.options[arg] = args[++i];
  }
  return parsed;
}

}  // namespace hilrig::rig
