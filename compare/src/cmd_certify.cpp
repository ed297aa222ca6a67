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
#include <memory>
#include <utility>

#include "commands.hpp"
#include "lockstep/vectors/vectors.hpp"

namespace lockstep::cli {
namespace {

struct CertifyArgs {
  bool ci = false, list = false, skip_missing = false, all_frames = false;
  std::string builds, scenes, work, vectors, report;
  int jobs = 0, timeout = 0;
};

int certify_command(const CertifyArgs& a) {
  namespace fs = std::filesystem;
  // The checkout in the current directory first, then the one this binary was built from.
  fs::path script = fs::path("vectors") / "certify" / "certify.py";
  if (!fs::exists(script)) script = fs::path(vectors::source_dir()) / "vectors" / "certify" / "certify.py";
  if (!fs::exists(script))
    throw std::invalid_argument("certify needs the lockstep source tree: " + script.string() +
                                " not found (run `python3 vectors/certify/certify.py` in a checkout)");
  std::vector<std::string> args{"python3", script.string()};
  for (const auto& [flag, on] : {std::pair{"--ci", a.ci}, {"--list", a.list}, {"--skip-missing", a.skip_missing},
                                 {"--all-frames", a.all_frames}})
    if (on) args.emplace_back(flag);
  for (const auto& [name, value] : {std::pair{"--builds", a.builds}, {"--scenes", a.scenes}, {"--work", a.work},
                                    {"--vectors", a.vectors}, {"--report", a.report}})
    if (!value.empty()) args.insert(args.end(), {name, value});
  if (a.jobs > 0) args.insert(args.end(), {"--jobs", std::to_string(a.jobs)});
  if (a.timeout > 0) args.insert(args.end(), {"--timeout", std::to_string(a.timeout)});
  std::vector<char*> c_args;
  for (std::string& x : args) c_args.push_back(x.data());
  c_args.push_back(nullptr);
  std::fflush(stdout);
  execvp("python3", c_args.data());
  std::fprintf(stderr, "lockstep certify: cannot run python3: %s\n", std::strerror(errno));
  return 2;
}

std::function<int()> define(CLI::App& app) {
  auto a = std::make_shared<CertifyArgs>();
  app.add_flag("--ci", a->ci, "the CI subset of the matrix (docs/CERTIFICATION.md)");
  app.add_flag("--list", a->list, "print the matrix and exit");
  app.add_option("--builds", a->builds, "comma-separated build names (see --list) to run only those");
  app.add_option("--scenes", a->scenes, "comma-separated scenes to certify (default: every built-in scene)");
  app.add_option("--jobs", a->jobs, "parallel builds and runs (default: the CPU count)")->check(integer_in(1, 1024));
  app.add_option("--work", a->work, "where the binaries go (default: build-certify in the checkout)");
  app.add_option("--vectors", a->vectors, "the reference vectors (default: vectors/data)");
  app.add_option("--report", a->report, "also write the report (Markdown) to this file");
  app.add_option("--timeout", a->timeout, "seconds per compile or run (default: 1800)")->check(integer_in(1, 86400));
  app.add_flag("--skip-missing", a->skip_missing, "skip builds whose compiler or qemu is not installed");
  app.add_flag("--all-frames", a->all_frames, "certify every frame on every build (no limit for emulated -O0 builds)");
  return [a] { return certify_command(*a); };
}

const bool registered = register_command(
    {"certify", "build the fixed engine under the compiler/flag/architecture matrix; prove identical hashes",
     "  lockstep certify --ci --jobs 2 --work build-certify-ci\n", define});

}  // namespace
}  // namespace lockstep::cli
