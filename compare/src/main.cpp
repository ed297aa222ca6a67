// The `lockstep` command: `lockstep run`, `lockstep compare`, `lockstep view`,
// `lockstep vectors`, ... (one cmd_*.cpp per command; `lockstep --help`).
#include <string>
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
  return lockstep::cli::run_command_line(std::vector<std::string>(argv + 1, argv + argc));
}
