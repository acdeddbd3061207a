#pragma once

#include <ostream>
#include <string>
#include <vector>

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

}  // namespace incise::sim
