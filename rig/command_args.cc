#include "rig/command_args.h"

namespace hilrig::rig {

const std::string* CliArgs::Option(const std::string& name) const {
  const auto found = options.find(name);
  return found == options.end() ? nullptr : &found->second;
}

Result<CliArgs> ParseCliArgs(const std::vector<std::string>& args,
                             const std::set<std::string>& allowed_options) {
  CliArgs parsed;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (!arg.starts_with("--")) {
      parsed.positional.push_back(arg);
      continue;
    }
    if (!allowed_options.contains(arg)) return MakeError("unknown option " + arg);
    if (i + 1 >= args.size()) return MakeError(arg + " needs a value");
    parsed.options[arg] = args[++i];
  }
  return parsed;
}

}  // namespace hilrig::rig
