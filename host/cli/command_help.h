// What `hilrig help`, `hilrig help CMD` and `hilrig CMD --help` print, and the pointer a usage
// error gives instead of the whole text: each command's name, one line for the overview and its
// usage, kept in one table so that the overview, the command's own help and the errors cannot
// disagree.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace hilrig::host {

struct CommandHelp {
  std::string_view name;     // "run"
  std::string_view summary;  // one line for the overview
  std::string_view usage;    // the synopsis and every option, lines indented by two spaces
};

// Every command, in the overview's order. Cannot fail.
std::span<const CommandHelp> Commands();

// The command called `name`, or null.
const CommandHelp* FindCommand(std::string_view name);

// `hilrig help`: every command with its summary, how to get one command's help, the exit codes.
std::string Overview();

// `hilrig help CMD`: "usage:\n" and the command's usage.
std::string CommandUsage(const CommandHelp& command);

// The second line of a usage error: "see `hilrig help CMD`" (or `hilrig help` for no command).
std::string HelpPointer(std::string_view command = "");

// The first line of the error for an unknown command, with the nearest command when one is close.
std::string UnknownCommand(const std::string& name);

}  // namespace hilrig::host
