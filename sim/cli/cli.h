#pragma once

#include <initializer_list>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

// Exit codes of the incise command line.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;  // the run went non-finite (RESULT still written) or crashed
inline constexpr int kExitUsage = 2;   // bad arguments, unreadable or invalid scene or mesh file,
                                       // unwritable out

// The incise command line: `incise --help`, `incise solve SCENE.json --out RESULT.json`,
// `incise mesh-info MESH` (MESH a .msh, .node, .ele or TetGen base name).
//   args  the arguments after the program name
// Writes help to out and each error as one line "incise: ..." to err; returns the exit code.
// Never throws.
int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

// A command's arguments after its name (args[0]): one positional scene file and the file-valued
// options named (e.g. "--out"). `problem` is empty on success, else the usage error: "--out
// needs a file name", "unknown option -x", "more than one scene file".
struct CommandArgs {
  std::optional<std::string> file;
  std::map<std::string, std::string, std::less<>> options;
  std::string problem;
};
CommandArgs parse_command_args(const std::vector<std::string>& args,
                               std::initializer_list<std::string_view> file_options);

// An option's number: the whole text one finite number (from_chars: no locale, no exception),
// else nullopt.
std::optional<Real> parse_real(const std::string& text);

}  // namespace incise::sim
