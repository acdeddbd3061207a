#pragma once
// Runs the real incise binary (INCISE_CLI_PATH, from CMake) as a user would: in a private
// temporary folder, arguments as on a shell line, stdout, stderr and the exit code captured.
// Shared by the CLI tests of sim_cli_tests and sim_mesh_tests.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/temp_dir.h"

namespace incise::sim::test {

struct CliRun {
  int exit_code = -1;  // -1 when the process did not exit normally
  std::string out;
  std::string err;
};

// Whether `text` is exactly one line (a message, an error), newline-terminated.
inline bool one_line(const std::string& text) {
  return !text.empty() && text.back() == '\n' && text.find('\n') == text.size() - 1;
}

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream stream(path);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

class CliFixture : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path) << text;
    return path;
  }

  // Runs incise with the arguments (already shell-quoted where needed) in the temp folder.
  CliRun incise(const std::string& arguments) {
    const std::string command = "cd '" + dir_.string() + "' && '" INCISE_CLI_PATH "' " + arguments +
                                " > out.txt 2> err.txt";
    const int status = std::system(command.c_str());
    CliRun run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = read_file(dir_ / "out.txt");
    run.err = read_file(dir_ / "err.txt");
    return run;
  }

  incise::test::TempDir tmp_{"incise-cli"};
  std::filesystem::path dir_ = tmp_.path();
};

}  // namespace incise::sim::test
