// `lockstep certify [--ci] [options]`: the determinism certification of the
// fixed engine (docs/CERTIFICATION.md). Runs vectors/certify/certify.py from
// the source tree with python3: it builds the certification driver under the
// compiler / flags / architecture matrix and checks every build's per-frame
// hashes against vectors/data. The exit status is the script's.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "commands.hpp"
#include "lockstep/vectors/vectors.hpp"

namespace lockstep::cli {
namespace {

int certify_command(const std::vector<std::string>& argv) {
  namespace fs = std::filesystem;
  // The checkout in the current directory first, then the one this binary was built from.
  fs::path script = fs::path("vectors") / "certify" / "certify.py";
  if (!fs::exists(script)) script = fs::path(vectors::source_dir()) / "vectors" / "certify" / "certify.py";
  if (!fs::exists(script))
    throw std::invalid_argument("certify needs the lockstep source tree: " + script.string() +
                                " not found (run `python3 vectors/certify/certify.py` in a checkout)");
  std::vector<std::string> args{"python3", script.string()};
  args.insert(args.end(), argv.begin(), argv.end());
  std::vector<char*> c_args;
  for (std::string& a : args) c_args.push_back(a.data());
  c_args.push_back(nullptr);
  std::fflush(stdout);
  execvp("python3", c_args.data());
  std::fprintf(stderr, "lockstep certify: cannot run python3: %s\n", std::strerror(errno));
  return 2;
}

const bool registered = register_command(
    {"certify", "certify [--ci] [--list] [--builds A,B] [--jobs N] [--report FILE] [--skip-missing]",
     "build the fixed engine under the compiler/flag/architecture matrix; prove identical hashes", certify_command});

}  // namespace
}  // namespace lockstep::cli
